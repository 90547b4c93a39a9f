// slab: one plane-parallel problem (M93's base problem and its variants) from the command
// line. Prints a table of Ed, Eu, Eod, Eou and Lu with standard errors, and writes JSON.
// Run with --help for the options and their defaults.
// The options and their reading: slab_options.hpp.
#include "slab_options.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/io/json_writer.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <cstdio>
#include <fstream>
#include <iostream>
#include <optional>
#include <vector>

namespace {

void print_table(const secchi::PlaneParallelResult& r) {
    std::printf("phase %s: mean cosine %.5f, b_b/b %.5f, normalisation %.6f\n", r.phase_name.c_str(),
                r.moments.mean_cosine, r.moments.backscatter_fraction, r.moments.normalisation);
    std::printf("%llu photons traced, %llu stored, %.2f s\n", static_cast<unsigned long long>(r.photons_traced),
                static_cast<unsigned long long>(r.photons_stored), r.seconds);
    std::printf("%6s  %-21s %-21s %-21s %-21s %-21s\n", "tau", "Ed (se)", "Eu (se)", "Eod (se)", "Eou (se)", "Lu (se)");
    for (const auto& d : r.depths) {
        std::printf("%6.2f", d.depth);
        for (const auto& e : {d.irradiance[0], d.irradiance[1], d.irradiance[2], d.irradiance[3], d.lu})
            std::printf("  %.4e (%.1e)", e.value, e.se);
        std::printf("\n");
    }
    const auto& a = r.above;
    std::printf("source %s: just above the surface Ed(0+) = %.4e (direct %.4e, diffuse %.4e), Eu(0+) = %.4e\n",
                r.source_name.c_str(), a.ed_direct.value + a.ed_diffuse.value, a.ed_direct.value, a.ed_diffuse.value,
                a.eu.value);
}

void write_json(const secchi::PlaneParallelResult& r, secchi::OutputFile& file) {
    secchi::JsonWriter j(file.stream());
    j.begin_object();
    j.value("photons_traced", static_cast<unsigned long long>(r.photons_traced));
    j.value("photons_stored", static_cast<unsigned long long>(r.photons_stored));
    j.value("seconds", r.seconds);
    j.value("source", r.source_name);
    j.begin_object("above_surface")
        .value("Ed_direct", r.above.ed_direct.value)
        .value("Ed_direct_se", r.above.ed_direct.se)
        .value("Ed_diffuse", r.above.ed_diffuse.value)
        .value("Ed_diffuse_se", r.above.ed_diffuse.se)
        .value("Eu", r.above.eu.value)
        .value("Eu_se", r.above.eu.se)
        .end_object();
    j.begin_object("phase")
        .value("name", r.phase_name)
        .value("mean_cosine", r.moments.mean_cosine)
        .value("backscatter_fraction", r.moments.backscatter_fraction)
        .value("normalisation_integral", r.moments.normalisation)
        .end_object();
    j.begin_array("depths");
    const char* names[] = {"Ed", "Eu", "Eod", "Eou"};
    const char* se_names[] = {"Ed_se", "Eu_se", "Eod_se", "Eou_se"};
    for (const auto& d : r.depths) {
        j.begin_object().value("tau", d.depth);
        for (int k = 0; k < 4; ++k) j.value(names[k], d.irradiance[k].value).value(se_names[k], d.irradiance[k].se);
        j.value("Lu", d.lu.value).value("Lu_se", d.lu.se).end_object();
    }
    j.end_array();
    j.end_object();
    file.commit();
}

}  // namespace

int main(int argc, char** argv) {
    namespace slab = secchi::examples::slab;
    return secchi::run_program(argc, argv, "slab", slab::usage(), [&] {
        const secchi::CommandLine cl = slab::command_line(argc, argv);
        const auto cfg = slab::config_from(cl);
        const auto phase = secchi::parse_phase(cl.text("phase", "petzold"));
        std::optional<secchi::OutputFile> json;  // checked before the work
        if (cl.has("json")) json.emplace("--json", cl.text("json"));
        const auto result = std::visit([&](const auto& p) { return secchi::solve_plane_parallel(p, cfg); }, phase);
        print_table(result);
        if (json) write_json(result, *json);
        return 0;
    });
}
