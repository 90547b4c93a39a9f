// Canonical problem 3's IOP profile (the manual's Fig. 7.30 as numbers): the composed model,
// sampled into the transport's StratifiedWater, against M93's equations evaluated here, at
// every metre from 0 to 60 m, and against hand-computed anchor values; the water that keeps the
// model's phase types against the AnyPhaseFunction one.
#include <catch2/catch.hpp>
#include "../conformance/problem3.hpp"
#include "phase_checks.hpp"
#include "secchi/core/rng.hpp"
#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

using namespace secchi;

namespace {
double chlorophyll(double z) { return 0.2 + 144.0 / (9.0 * std::sqrt(2.0 * pi)) * std::exp(-(z - 17.0) * (z - 17.0) / 162.0); }
}  // namespace

TEST_CASE("problem 3: a, b, c and w0 from 0 to 60 m follow M93's equations") {
    const auto water = iop::stratify(conformance::problem3_model(), 500.0, iop::uniform_depths(100.0, 0.05));
    for (int z = 0; z <= 60; ++z) {
        const double c = chlorophyll(z);
        const double a = 0.0257 + 0.04 * std::pow(c, 0.602), b = 0.0029 + 0.33 * std::pow(c, 0.62);
        INFO("z = " << z << " m");
        CHECK(water.coefficient(Coefficient::absorption, z) == Approx(a).epsilon(1e-12));
        CHECK(water.coefficient(Coefficient::scattering, z) == Approx(b).epsilon(1e-12));
        CHECK(water.coefficient(Coefficient::attenuation, z) == Approx(a + b).epsilon(1e-12));
        CHECK(water.component_scattering(0, z) == Approx(0.0029).epsilon(1e-12));  // water: Rayleigh
        // Between nodes (every 5 cm) the linear interpolation stays within 1e-5 of the model.
        const double zm = z + 0.025, cm = chlorophyll(zm);
        CHECK(water.coefficient(Coefficient::scattering, zm) == Approx(0.0029 + 0.33 * std::pow(cm, 0.62)).epsilon(1e-5));
    }
    // Anchors computed by hand (python) from the same equations, printed to 6 decimals: z, a, b, c, w0.
    const double anchors[][5] = {{0, 0.071938, 0.386020, 0.457958, 0.842916},
                                 {17, 0.150081, 1.064449, 1.214530, 0.876429},
                                 {60, 0.040884, 0.124588, 0.165471, 0.752927}};
    for (const auto& r : anchors) {
        CHECK(water.coefficient(Coefficient::absorption, r[0]) == Approx(r[1]).epsilon(0).margin(1e-6));
        CHECK(water.coefficient(Coefficient::scattering, r[0]) == Approx(r[2]).epsilon(0).margin(1e-6));
        CHECK(water.coefficient(Coefficient::attenuation, r[0]) == Approx(r[3]).epsilon(0).margin(1e-6));
        CHECK(albedo_at(water, r[0]) == Approx(r[4]).epsilon(0).margin(1e-6));
    }
}

TEST_CASE("problem 3: the typed water (Rayleigh + Petzold, no variant) is the AnyPhaseFunction water, bit for bit") {
    const auto depths = iop::uniform_depths(100.0, 0.05);
    const auto typed = iop::stratify_typed(conformance::problem3_model(), 500.0, depths);
    const auto any = iop::stratify(conformance::problem3_model(), 500.0, depths);
    static_assert(std::is_same_v<std::decay_t<decltype(typed)>, StratifiedWater<RayleighPhase, TabulatedPhase>>);
    const auto same = test::same_bits;
    REQUIRE(typed.refractive_index() == any.refractive_index());
    for (double z : {0.0, 3.3, 17.0, 42.025, 60.0, 150.0}) {
        INFO("z = " << z << " m");
        for (auto k : {Coefficient::absorption, Coefficient::scattering, Coefficient::attenuation})
            CHECK(same(typed.coefficient(k, z), any.coefficient(k, z)));
        CHECK(test::phase_mismatches_at(typed, any, z, 3, 5000) == 0);
    }
}
