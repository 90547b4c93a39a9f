// Upward importance (transport/importance.hpp, UpwardImportance): a share of the scattering
// directions drawn from a lobe about straight up, the weights p / q, and the map's records
// stored by their direction of travel with flux Phi / D(mu). Checked here: the definitions (off
// is the identity; D and p / q at given directions), the lobe's directions follow its
// Henyey-Greenstein distribution about straight up, the weighted directions of the mixture
// follow the phase function (Henyey-Greenstein and Petzold) whatever the incoming direction,
// and what is refused. The whole first and second pass with it is checked against the exact
// (DISORT) irradiances and nadir radiance in test_exact_references.cpp.
#include <catch2/catch.hpp>

#include "weighted_angles.hpp"

#include "secchi/core/rng.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/transport/lane_tracer.hpp"
#include "secchi/transport/tracer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using namespace secchi;
using test::hg_cdf;

namespace {
/// The lobe's density per sr at cosine mu from straight up (HG, written out here).
double hg_density(double g, double mu) { return (1.0 - g * g) / (4.0 * pi * std::pow(1.0 + g * g - 2.0 * g * mu, 1.5)); }
}  // namespace

TEST_CASE("upward importance: off is the identity; D and p / q as defined") {
    const UpwardImportance off;
    CHECK_FALSE(off.enabled());
    CHECK(off.weight(0.3, -1.0) == 1.0);
    CHECK(off.storage_factor(-1.0) == 1.0);
    CHECK(off.storage_factor(0.5) == 1.0);
    const double eps = 0.3, g = 0.9;
    const UpwardImportance up(eps, g);
    CHECK(up.enabled());
    // z is depth: dz = -1 travels straight up (mu = 1), dz = +1 straight down (mu = -1).
    CHECK(up.storage_factor(-1.0) == Approx((1.0 - eps) + eps * (1.0 + g) / ((1.0 - g) * (1.0 - g))).epsilon(1e-12));
    CHECK(up.storage_factor(1.0) == Approx((1.0 - eps) + eps * (1.0 - g) / ((1.0 + g) * (1.0 + g))).epsilon(1e-12));
    for (const double dz : {-1.0, -0.6, 0.0, 0.4, 1.0})
        for (const double p : {1e-3, 0.08, 5.0, 300.0}) {
            INFO("dz " << dz << " p " << p);
            CHECK(up.weight(p, dz) == Approx(p / ((1.0 - eps) * p + eps * hg_density(g, -dz))).epsilon(1e-12));
        }
    // An infinite density (a peak's singular point) gives 1 / (1 - eps), not NaN.
    CHECK(up.weight(std::numeric_limits<double>::infinity(), -1.0) == Approx(1.0 / (1.0 - eps)).epsilon(1e-15));
}

TEST_CASE("upward importance: the lobe's directions follow Henyey-Greenstein about straight up") {
    // 20 bins of mu = -dz against the exact CDF, within 4 SE of a binomial frequency
    // (tolerance fixed before the runs); unit vectors; azimuth uniform (quadrant counts).
    const double g = 0.8;
    const UpwardImportance up(0.5, g);
    PhotonRng rng(5, 0);
    const int n = 400'000, bins = 20;
    std::vector<int> count(bins);
    std::array<int, 4> quadrant{};
    double worst_norm = 0.0;
    for (int k = 0; k < n; ++k) {
        const vec3 d = up.sample(rng.uniform(), rng.uniform());
        worst_norm = std::max(worst_norm, std::abs(glm::length(d) - 1.0));
        ++count[std::min(bins - 1, static_cast<int>((1.0 - d.z) / 2.0 * bins))];
        ++quadrant[(d.x >= 0.0 ? 0 : 1) + (d.y >= 0.0 ? 0 : 2)];
    }
    CHECK(worst_norm < 1e-14);
    for (int i = 0; i < bins; ++i) {
        const double lo = -1.0 + 2.0 * i / bins, hi = -1.0 + 2.0 * (i + 1) / bins;
        const double p = hg_cdf(g, hi) - hg_cdf(g, lo), f = static_cast<double>(count[i]) / n;
        INFO("mu in [" << lo << ", " << hi << "): " << f << " exact " << p);
        CHECK(std::abs(f - p) <= 4.0 * std::sqrt(p * (1.0 - p) / n));
    }
    for (int q : quadrant) CHECK(std::abs(q / double(n) - 0.25) <= 4.0 * std::sqrt(0.25 * 0.75 / n));
}

TEST_CASE("upward importance: the mixture's weighted directions follow the phase function") {
    // A photon travelling along `before` scatters by UpwardImportance::scatter (the tracer's
    // draw): the weighted histogram of cos psi (psi from `before`) in 36 bins of 5 deg against
    // the phase function's exact probability, each within 4 SE of the weighted mean (tolerance
    // fixed before the runs). Incoming directions straight down, oblique and straight up.
    const int n = 400'000, bins = 36;
    const auto check = [&](const auto& phase, const auto& probability, const vec3& before) {
        const UpwardImportance up(0.35, 0.9);
        PhotonRng rng(29, 0);
        test::WeightedAngles histogram(bins);
        const auto sample = [&](double u1, double u2) { return phase.sample_direction(u1, u2); };
        const auto density = [&](double mu) { return phase.pdf(mu); };
        for (int k = 0; k < n; ++k) {
            const double u_psi = rng.uniform(), u_phi = rng.uniform(), u_choice = rng.uniform();
            const UpwardImportance::Scatter s = up.scatter(before, u_choice, u_psi, u_phi, sample, density);
            histogram.add(std::acos(std::clamp(glm::dot(before, s.dir), -1.0, 1.0)), s.weight);
        }
        INFO("before " << before.x << " " << before.y << " " << before.z);
        histogram.check(n, probability);
    };
    const double g = 0.9;
    const HenyeyGreensteinPhase hg(g);
    const auto hg_probability = [&](double lo, double hi) { return hg_cdf(g, std::cos(lo)) - hg_cdf(g, std::cos(hi)); };
    const TabulatedPhase petzold = petzold_m93();
    const auto petzold_probability = [&](double lo, double hi) { return petzold.cumulative(hi) - petzold.cumulative(lo); };
    const double s = std::sqrt(0.5);
    for (const vec3& before : {vec3(0.0, 0.0, 1.0), vec3(s, 0.0, s), vec3(0.0, 0.0, -1.0)}) {
        check(hg, hg_probability, before);
        check(petzold, petzold_probability, before);
    }
}

TEST_CASE("upward importance: refused where it cannot be drawn") {
    TransportSettings s;
    s.photons = 1000;
    s.depths = {1.0};
    s.upward_importance = 1.0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("upward importance"));
    s.upward_importance = 0.3;
    s.upward_lobe = 1.0;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("upward importance lobe"));
    s.upward_lobe = 0.9;
    s.backscatter_bias = 0.2;
    CHECK_THROWS_WITH(s.validate(), Catch::Contains("backscatter bias"));
    s.backscatter_bias = 0.0;
    CHECK_NOTHROW(s.validate());
    using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto water = HgWater::from_albedo(1.0, 0.2, HenyeyGreensteinPhase(0.9));
    const Slab slab(1.0, Bottom{}, 30.0);
    CHECK_NOTHROW(PhotonTracer<HgWater, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s));
#if SECCHI_HAS_LANES
    CHECK_THROWS_WITH((LaneTracer<HgWater, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s)),
                      Catch::Contains("upward importance"));
#endif
}
