// phase_bench: the phase functions' samplers alone (a benchmark, never part of the tests):
// nanoseconds per sampled scattering angle, one photon at a time (sample_direction) and
// photons in double lanes (cos_psi(lanes::Reals), what LaneTracer and its float lanes call),
// on one core, over the same uniforms for every sampler.
//   phase_bench [--samples N] [--rounds R] [--md FILE]
//
// Samplers: M93's Petzold table in the canonical reading (linear_p, with the power law below
// the first node; problems 2, 3 and 6), the same table in the trapezoid reading, and
// Henyey-Greenstein g = 0.9 (problem 1's yardstick), and Fournier-Forand (b_b/b = 0.0183,
// sampled from its table). Each figure is the median [min-max] of
// R rounds over N uniforms (default 2^20, 7 rounds, about 3 s); the sum of the cosines is
// printed as the check that both paths sample the same angles (equal to the printed digits:
// the lanes' cos psi is within a few ulp of one photon's).
#include "bench_timing.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/optics/phase/fournier_forand.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace secchi;
using namespace secchi::bench;

namespace {

#if SECCHI_HAS_LANES
constexpr bool with_lanes = true;
#else
constexpr bool with_lanes = false;
#endif

struct Figures {
    Timing one_photon, lanes;
    double sum_one_photon = 0, sum_lanes = 0;
};

template <class Phase>
Figures time_sampler(const Phase& phase, const std::vector<double>& u, int rounds) {
    Figures f;
    // Four sums, so that the additions' latency does not bound a fast sampler's rate.
    f.one_photon = time_runs(rounds, [&] {
        double sum[4] = {};
        for (std::size_t i = 0; i < u.size(); ++i) sum[i % 4] += phase.sample_direction(u[i], 0.0).cos_psi;
        f.sum_one_photon = (sum[0] + sum[1]) + (sum[2] + sum[3]);
    });
#if SECCHI_HAS_LANES
    f.lanes = time_runs(rounds, [&] {
        constexpr std::size_t w = lanes::lane_width;
        lanes::Reals sum[4] = {lanes::Reals(0.0), lanes::Reals(0.0), lanes::Reals(0.0), lanes::Reals(0.0)};
        for (std::size_t i = 0; i + w <= u.size(); i += w)
            sum[(i / w) % 4] += phase.cos_psi(lanes::Reals(&u[i], lanes::stdx::element_aligned));
        f.sum_lanes = reduce((sum[0] + sum[1]) + (sum[2] + sum[3]));
    });
#endif
    return f;
}

}  // namespace

int main(int argc, char** argv) {
    if (CommandLine::wants_help(argc, argv)) {
        std::cout << "usage: phase_bench [--samples N] [--rounds R] [--md FILE]\n";
        return 0;
    }
    try {
        const CommandLine cl(argc, argv, {"md", "samples", "rounds"}, {});
        const auto samples = static_cast<std::size_t>(cl.number("samples", 1 << 20));
        const int rounds = static_cast<int>(cl.number("rounds", 7));
        require(samples >= 64, "--samples", samples, "must be at least 64");
        require(rounds >= 1, "--rounds", rounds, "must be at least 1");
        std::ofstream md_file;
        if (cl.has("md")) md_file.open(cl.text("md"));
        auto out = [&](const std::string& line) {
            std::cout << line << "\n";
            if (md_file.is_open()) md_file << line << "\n";
        };

        PhotonRng rng(1, 0);
        std::vector<double> u(samples);
        for (double& v : u) v = rng.uniform();
        const double per_ns = 1e9 / static_cast<double>(samples);

#if SECCHI_HAS_LANES
        const std::string lanes_header = std::to_string(lanes::lane_width) + " double lanes";
#else
        const std::string lanes_header = "lanes (not built)";
#endif
        out("| sampler | one photon, ns per sample | " + lanes_header + ", ns per sample | one photon / lanes | sum of cos psi, one photon / lanes |");
        out("|---|---|---|---|---|");
        auto row = [&](const std::string& name, const Figures& f) {
            out("| " + name + " | " + time_cell(f.one_photon, per_ns, "%.2f") + " | " +
                (with_lanes ? time_cell(f.lanes, per_ns, "%.2f") : std::string("-")) + " | " +
                (with_lanes ? fmt("%.2f", f.one_photon.median / f.lanes.median) : std::string("-")) + " | " +
                fmt("%.10g", f.sum_one_photon) + " / " + fmt("%.10g", f.sum_lanes) + " |");
        };
        row("Petzold, canonical reading (linear p, power law below 0.126 deg)", time_sampler(petzold_m93(), u, rounds));
        row("Petzold, trapezoid reading", time_sampler(petzold_m93(PetzoldReading::trapezoid), u, rounds));
        row("Henyey-Greenstein, g = 0.9", time_sampler(HenyeyGreensteinPhase(0.9), u, rounds));
        row("Fournier-Forand, b_b/b = 0.0183 (its table, trapezoid reading)",
            time_sampler(FournierForandPhase::from_backscatter_fraction(0.0183), u, rounds));
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "phase_bench: " << e.what() << "\n";
        return 1;
    }
}
