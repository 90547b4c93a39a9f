// iop_profile: a medium's inherent optical properties as CSV, over wavelength and depth (the
// data behind the manual's Figures 5.3-5.8). The medium is a DIRSIG material file (manual
// chapter 5) or the built-in composed medium of canonical problem 3.
//
// Columns, at each (lambda, z) with x = (0, 0, z):
//   a = sum_i a_i, b = sum_i b_i, c = a + b                     (manual eq. 5.3, 5.4)
//   b_b/b = sum_i b_i B_i / b, mean cosine = sum_i b_i g_i / b   (the mixture of eq. 5.5-5.6)
// where B_i and g_i are the backscatter fraction and mean cosine of component i's phase
// function. Where b = 0 the mixture is undefined and both are written as nan.
// Run with --help for the options.
#include "../conformance/problem3.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/io/material_medium.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace {

constexpr const char* usage = R"(usage: iop_profile (--material FILE [--material-entry ID|NAME] | --problem3) [--wavelengths 400:700:10]
                   [--depths 0:60:5] [--seed S] [--out FILE]
Prints the medium's IOPs as CSV: wavelength_nm, depth_m, a_per_m, b_per_m, c_per_m,
bb_over_b, mean_cosine (of the mixture phase function; nan where b = 0).
  --material FILE     a DIRSIG material file (BULK_PROPERTIES { IOP_MODEL { ... } }, alone or
                      inside MATERIAL_ENTRY sections)
  --material-entry E  the MATERIAL_ENTRY to read, by ID or NAME (default: the only one with
                      BULK_PROPERTIES)
  --problem3          the composed medium of canonical problem 3 (M93, defined at 500 nm)
  --wavelengths R     nm, as START:STOP:STEP or one value (default 400:700:10)
  --depths R          m, as START:STOP:STEP or one value (default 0:60:5)
  --seed S            seed of SIGMA noise in the material file (default 1)
  --out FILE          write the CSV to FILE instead of stdout
Errors (bad options, bad material files, wavelengths outside a model's table) exit with 2.
)";

/// The phase-function moments of each scattering component, computed once.
template <class Model>
std::vector<secchi::PhaseMoments> component_moments(const Model& m) {
    std::vector<secchi::PhaseMoments> out;
    m.for_each_scatterer([&](const auto& s) { out.push_back(secchi::phase_moments(s.phase)); });
    return out;
}

/// One CSV row: a, b, c and the mixture's b_b/b and mean cosine at (lambda, z).
template <class Model>
void write_row(std::ostream& os, const Model& m, const std::vector<secchi::PhaseMoments>& moments, double wl, double z) {
    const secchi::vec3 x{0.0, 0.0, z};
    const double a = m.absorption(x, wl);
    double b = 0.0, bb = 0.0, g = 0.0;
    std::size_t i = 0;
    m.for_each_scatterer([&](const auto& s) {
        const double bi = s.coefficient.coefficient(x, wl);
        b += bi;
        bb += bi * moments[i].backscatter_fraction;
        g += bi * moments[i].mean_cosine;
        ++i;
    });
    const double nan = std::numeric_limits<double>::quiet_NaN();
    os << wl << ',' << z << ',' << a << ',' << b << ',' << a + b << ',' << (b > 0.0 ? bb / b : nan) << ','
       << (b > 0.0 ? g / b : nan) << '\n';
}

template <class Model>
void write_csv(std::ostream& os, const Model& m, const std::vector<double>& wavelengths, const std::vector<double>& depths) {
    const auto moments = component_moments(m);
    os.precision(10);
    os << "wavelength_nm,depth_m,a_per_m,b_per_m,c_per_m,bb_over_b,mean_cosine\n";
    for (double wl : wavelengths)
        for (double z : depths) write_row(os, m, moments, wl, z);
}

/// Writes the CSV of the chosen medium to os.
void run(const secchi::CommandLine& cl, std::ostream& os) {
    if (cl.has("material") == cl.has("problem3"))
        secchi::reject("medium", "(options)", "give exactly one of --material FILE and --problem3");
    const auto wavelengths = cl.range("wavelengths", "400:700:10");
    const auto depths = cl.range("depths", "0:60:5", 0.0);
    const double rows = static_cast<double>(wavelengths.size()) * static_cast<double>(depths.size());
    if (rows > 1e6) {
        std::string value = cl.text("wavelengths", "400:700:10");
        value.append(" x ").append(cl.text("depths", "0:60:5"));
        secchi::reject("--wavelengths x --depths", value, "gives more than a million rows");
    }
    if (cl.has("problem3") && !cl.has("material-entry"))
        return write_csv(os, secchi::conformance::problem3_model(), wavelengths, depths);
    const auto model = secchi::io::read_iop_model_from_options(cl);
    write_csv(os, model, wavelengths, depths);
}

}  // namespace

int main(int argc, char** argv) {
    return secchi::run_program(argc, argv, "iop_profile", usage, [&] {
        const secchi::CommandLine cl(argc, argv, {"material", "material-entry", "wavelengths", "depths", "seed", "out"}, {"problem3"});
        if (cl.has("out")) {  // checked first; written whole or not at all
            secchi::OutputFile file("--out", cl.text("out"));
            run(cl, file.stream());
            file.commit();
            return 0;
        }
        std::ostringstream csv;  // the whole table first: an error midway leaves no partial output
        run(cl, csv);
        std::cout << csv.str();
        return 0;
    });
}
