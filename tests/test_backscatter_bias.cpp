// Backscatter bias (transport/importance.hpp, BackscatterBias): importance sampling of the
// uniform that the phase function's inverse CDF turns into a scattering angle. Checked here:
// the weights' mean is 1 exactly, the weighted angles follow the phase function (Petzold and
// Henyey-Greenstein), the phase functions' backward uniforms are the ones that scatter backward,
// and the tracers refuse what they cannot do. The first pass with it is checked against the
// exact (DISORT) irradiances in test_exact_references.cpp.
#include <catch2/catch.hpp>

#include "weighted_angles.hpp"

#include "secchi/core/rng.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/transport/lane_tracer.hpp"
#include "secchi/transport/tracer.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

using namespace secchi;

TEST_CASE("backscatter bias: off is the identity, and the weights average to 1 exactly") {
    const BackscatterBias off;
    CHECK_FALSE(off.enabled());
    for (double u : {0.0, 0.3, 0.999}) {
        CHECK(off.draw(u).u == u);
        CHECK(off.draw(u).weight == 1.0);
    }
    // Over a midpoint grid of u the draw is piecewise constant in weight: the mean of the
    // weights is eps w_b + (1 - eps)(B w_b + (1 - B) w_f) = 1 (importance.hpp).
    for (const auto& [eps, a, b] : std::vector<std::array<double, 3>>{{0.1, 0.98, 1.0}, {0.3, 0.0, 0.25}, {0.5, 0.4, 0.7}}) {
        const BackscatterBias bias(eps, a, b);
        const int n = 1 << 20;
        double sum = 0.0, backward = 0.0;
        int outside = 0;
        for (int k = 0; k < n; ++k) {
            const BackscatterBias::Draw d = bias.draw((k + 0.5) / n);
            outside += d.u >= 0.0 && d.u < 1.0 ? 0 : 1;
            sum += d.weight;
            backward += d.u >= a && d.u < b ? 1.0 : 0.0;
        }
        INFO("eps " << eps << " [" << a << ", " << b << ")");
        CHECK(outside == 0);
        CHECK(sum / n == Approx(1.0).epsilon(1e-5));  // the grid's steps at the branch edges: O(1/n)
        CHECK(backward / n == Approx(eps + (1.0 - eps) * (b - a)).epsilon(1e-5));
    }
    CHECK_THROWS_WITH(BackscatterBias(1.0, 0.9, 1.0), Catch::Contains("backscatter bias"));
    CHECK_THROWS_WITH(BackscatterBias(0.2, 0.5, 0.5), Catch::Contains("backward fraction"));
}

TEST_CASE("backward uniforms: the inverse CDF scatters backward exactly there") {
    const TabulatedPhase petzold = petzold_m93();
    const auto [a, b] = petzold.backward_uniforms();
    CHECK(b == 1.0);
    // B = 2 pi int_{-1}^{0} p dmu by the midpoint rule on eval (independent of cumulative()).
    double quadrature = 0.0;
    const int steps = 200'000;
    for (int k = 0; k < steps; ++k) quadrature += two_pi * petzold.eval(-1.0 + (k + 0.5) / steps) / steps;
    CHECK(1.0 - a == Approx(quadrature).epsilon(1e-6));
    CHECK(petzold.sample_direction(std::nextafter(a, 0.0), 0.0).cos_psi > -1e-12);
    CHECK(petzold.sample_direction(a + 1e-9, 0.0).cos_psi < 0.0);
    for (double g : {-0.5, 0.0, 0.3, 0.9}) {
        const HenyeyGreensteinPhase hg(g);
        const auto [lo, hi] = hg.backward_uniforms();
        INFO("g " << g << ": [" << lo << ", " << hi << ")");
        CHECK(lo == 0.0);
        CHECK(hg.cos_psi(0.5 * hi) < 0.0);
        CHECK(hg.cos_psi(hi - 1e-6) < 0.0);
        CHECK(hg.cos_psi(hi + 1e-6) > 0.0);
    }
}

TEST_CASE("backward uniforms through AnyPhaseFunction: the held function's, or refused by its name") {
    const TabulatedPhase petzold = petzold_m93();
    CHECK(AnyPhaseFunction{petzold}.backward_uniforms() == petzold.backward_uniforms());
    CHECK(AnyPhaseFunction{HenyeyGreensteinPhase(0.8)}.backward_uniforms() == HenyeyGreensteinPhase(0.8).backward_uniforms());
    // Fournier-Forand's are its table's: 1 - F(90 deg) is its backscatter fraction (the closed
    // form's, to the table's accuracy: fournier_forand.hpp).
    const auto ff = FournierForandPhase::from_backscatter_fraction(0.0183);
    CHECK(AnyPhaseFunction{ff}.backward_uniforms() == ff.table().backward_uniforms());
    CHECK(1.0 - ff.backward_uniforms().first == Approx(0.0183).epsilon(1e-4));
    CHECK_THROWS_WITH(AnyPhaseFunction{IsotropicPhase{}}.backward_uniforms(),
                      Catch::Contains("phase") && Catch::Contains("isotropic") && Catch::Contains("backward uniforms"));
}

TEST_CASE("backscatter bias: the weighted angles follow the phase function") {
    // Weighted histogram of psi in 36 bins of 5 deg: each bin's weighted frequency against the
    // exact probability (TabulatedPhase::cumulative; HG's CDF of mu), within 4 SE of the
    // weighted mean (tolerance fixed before the runs).
    const int n = 400'000, bins = 36;
    const auto check = [&](const auto& phase, const auto& probability, double eps) {
        const auto [a, b] = phase.backward_uniforms();
        const BackscatterBias bias(eps, a, b);
        PhotonRng rng(23, 0);
        test::WeightedAngles histogram(bins);
        for (int k = 0; k < n; ++k) {
            const BackscatterBias::Draw d = bias.draw(rng.uniform());
            histogram.add(std::acos(std::clamp(phase.sample_direction(d.u, 0.0).cos_psi, -1.0, 1.0)), d.weight);
        }
        histogram.check(n, probability);
    };
    const TabulatedPhase petzold = petzold_m93();
    check(petzold, [&](double lo, double hi) { return petzold.cumulative(hi) - petzold.cumulative(lo); }, 0.2);
    const double g = 0.9;
    const HenyeyGreensteinPhase hg(g);
    check(hg, [&](double lo, double hi) { return test::hg_cdf(g, std::cos(lo)) - test::hg_cdf(g, std::cos(hi)); }, 0.3);
}

TEST_CASE("backscatter bias: refused where it cannot be drawn") {
    TransportSettings s;
    s.photons = 1000;
    s.depths = {1.0};
    s.backscatter_bias = 1.0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("backscatter bias"));
    s.backscatter_bias = 0.2;
    using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto water = HgWater::from_albedo(1.0, 0.2, HenyeyGreensteinPhase(0.9));
    const Slab slab(1.0, Bottom{}, 30.0);
    CHECK_NOTHROW(PhotonTracer<HgWater, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s));
    // Isotropic scattering names no backward uniforms (nothing to gain from it either).
    using IsoWater = HomogeneousWater<IsotropicPhase>;
    const auto iso = IsoWater::from_albedo(1.0, 0.2, IsotropicPhase{});
    CHECK_THROWS_WITH((PhotonTracer<IsoWater, CompactRecord>(iso, slab, FlatSurface(1.34), CollimatedSun(30.0), s)),
                      Catch::Contains("backscatter bias"));
#if SECCHI_HAS_LANES
    CHECK_NOTHROW(LaneTracer<HgWater, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s));
    CHECK_THROWS_WITH((FloatLaneTracer<IsoWater, CompactRecord>(iso, slab, FlatSurface(1.34), CollimatedSun(30.0), s)),
                      Catch::Contains("backscatter bias"));
#endif
    // Analog photons store every event whatever its weight: the bias's weights would be lost.
    s.absorption = AbsorptionMode::analog;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("backscatter bias") && Catch::Contains("analog"));
}

TEST_CASE("backscatter bias in floats (the float lanes'): the weights are 1 / q of the float draws") {
    // The bounds and eps rounded to float, the weights from the rounded values: over a midpoint
    // grid of float uniforms the weights average to 1 and the backward draws stay in [a, b).
    for (const auto& [eps, a, b] : std::vector<std::array<double, 3>>{{0.2, 0.981718, 1.0}, {0.3, 0.0, 0.25}}) {
        const BackscatterBiasOf<float> bias(eps, a, b);
        const float fa = static_cast<float>(a), fb = static_cast<float>(b);
        const int n = 1 << 20;
        double sum = 0.0;
        int outside = 0;
        for (int k = 0; k < n; ++k) {
            const auto d = bias.draw(static_cast<float>((k + 0.5) / n));
            outside += d.u >= 0.0f && d.u < 1.0f ? 0 : 1;
            sum += d.weight;
            if (static_cast<float>((k + 0.5) / n) < static_cast<float>(eps)) outside += d.u >= fa && d.u < fb ? 0 : 1;
        }
        INFO("eps " << eps << " [" << a << ", " << b << ")");
        CHECK(outside == 0);
        CHECK(sum / n == Approx(1.0).epsilon(1e-5));
    }
    CHECK_THROWS_WITH(BackscatterBiasOf<float>(0.2, 0.5, 0.5 + 1e-9), Catch::Contains("backward fraction"));
}
