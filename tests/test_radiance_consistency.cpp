// The second pass against the first: the radiance distribution the photon map gives at a depth
// (estimate/radiance.hpp, every direction, with the surface's and the sun's terms), integrated
// over directions (estimate/radiance_distribution.hpp), must reproduce the irradiances the
// first pass counted at its planes (Ed, Eu, Eod, Eou: transport/irradiance_planes.hpp), which
// come from the photons' crossings and share none of the second pass's code. Problems 1a
// (Rayleigh) and 2a (Petzold), w0 = 0.9, sun at 60 deg, black sky, at tau 1 and 5, under M93's
// flat surface (n = 1.34: internal reflection and the sky's refraction enter) and index-matched.
// Tolerance: 3 combined standard errors (the map's, over batches and direction groups, and the
// first pass's, from photons of another seed), fixed before the runs.
#include <catch2/catch.hpp>
#include "secchi/estimate/radiance_distribution.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <cmath>
#include <cstdio>
#include <string>

using namespace secchi;

namespace {
struct Case {
    const char* name;
    const char* phase;
    double water_index;
};

void check_case(const Case& c) {
    constexpr double radius = 0.05;
    constexpr std::array<const char*, 4> names{"Ed", "Eu", "Eod", "Eou"};
    std::visit(
        [&](const auto& phase) {
            PlaneParallelConfig cfg;
            cfg.albedo = 0.9;
            cfg.water_index = c.water_index;
            cfg.transport.depths = {1.0, 5.0};
            cfg.transport.photons = 100000;
            cfg.transport.map_photons = 100000;
            cfg.transport.batches = 16;
            cfg.transport.threads = 2;
            cfg.transport.seed = 23;
            const auto medium = HomogeneousWater<std::decay_t<decltype(phase)>>::from_albedo(1.0, cfg.albedo, phase);
            const HomogeneousRayOptics optics(ConeAveragedPhase(phase, cfg.omega, ConePeak::transmitted), 1.0, 0.9);
            // Rays looking down from tau 5 integrate until their transmittance is 1e-4: the map
            // holds the events that deep, and a collection radius more.
            cfg.transport.map_depth =
                5.0 + length_to_transmittance(optics, Ray{{0.0, 0.0, 5.0}, {0.0, 0.0, 1.0}, INFINITY}, 1e-4) + 2.0 * radius;
            const auto mapped = trace_photon_map<VoiGridStore<CompactRecord>>(medium, cfg, Radius(radius));
            const RadianceEstimator est(mapped.map, VoiCylinder(0.0, INFINITY), optics, Radius(radius));
            // The irradiances from other photons (another seed): independent of the map's, so
            // that the combined SE is the SE of the difference.
            PlaneParallelConfig planes = cfg;
            planes.transport.photons = 400000;
            planes.transport.map_photons = 0;
            planes.transport.seed = 24;
            const PlaneParallelResult first_pass = solve_plane_parallel(phase, planes);
            for (std::size_t i = 0; i < cfg.transport.depths.size(); ++i) {
                const double tau = cfg.transport.depths[i];
                const MapIrradiances from_map = irradiances_from_map(est, tau, DirectionSampling{}, 2);
                for (int k = 0; k < 4; ++k) {
                    const Estimate first = first_pass.depths[i].irradiance[k], second = from_map.irradiance[k];
                    const double combined = std::hypot(first.se, second.se), ratio = second.value / first.value;
                    std::printf("%-22s tau %.0f %-3s  first pass %.5g +- %.2g  map %.5g +- %.2g  ratio %.4f  (%.1f combined SE)\n",
                                c.name, tau, names[k], first.value, first.se, second.value, second.se, ratio,
                                (second.value - first.value) / combined);
                    INFO(c.name << " tau " << tau << " " << names[k] << ": map " << second.value << " +- " << second.se
                                << ", first pass " << first.value << " +- " << first.se);
                    CHECK(second.se < 0.05 * second.value);
                    CHECK(std::abs(second.value - first.value) <= 3.0 * combined);
                }
            }
        },
        parse_phase_among<RayleighPhase, TabulatedPhase>("phase", c.phase, "rayleigh or petzold"));
}
}  // namespace

TEST_CASE("The map's radiance distribution integrates to the first pass's irradiances: problem 1a, flat surface") {
    check_case({"1a flat surface", "rayleigh", 1.34});
}
TEST_CASE("The map's radiance distribution integrates to the first pass's irradiances: problem 1a, index-matched") {
    check_case({"1a index-matched", "rayleigh", 1.0});
}
TEST_CASE("The map's radiance distribution integrates to the first pass's irradiances: problem 2a, flat surface") {
    check_case({"2a flat surface", "petzold", 1.34});
}
TEST_CASE("The map's radiance distribution integrates to the first pass's irradiances: problem 2a, index-matched") {
    check_case({"2a index-matched", "petzold", 1.0});
}
