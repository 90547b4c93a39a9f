// ChordTable: a function of cos psi tabulated uniform in s = sin(psi/2), as the radiance
// estimator evaluates the cone-averaged phase function once per collected photon. Checked
// against its source: exact where the source is linear in s, within the interpolation bound
// for Rayleigh, and within measured bounds for the cone-averaged Petzold function (whose cusp
// at the cone's edge is the hardest place), with the normalisation preserved.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "secchi/core/error.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/optics/phase/chord_table.hpp"
#include "secchi/optics/phase/cone_average.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"

using namespace secchi;

TEST_CASE("chord table: nodes and functions linear in s are exact") {
    const ChordTable iso(IsotropicPhase{}, 64);
    CHECK(iso.intervals() == 64);
    for (double mu : {-1.0, -0.3, 0.0, 0.7, 1.0}) CHECK(iso.eval(mu) == Approx(1.0 / four_pi).epsilon(1e-15));
    struct HalfChord {  // f = s, linear in s: interpolation is exact
        double eval(double mu) const { return std::sqrt(0.5 * (1.0 - mu)); }
    };
    const ChordTable chord(HalfChord{}, 100);
    for (int i = 0; i <= 1000; ++i) {
        const double mu = -1.0 + 2.0 * i / 1000.0;
        CHECK(chord.eval(mu) == Approx(HalfChord{}.eval(mu)).margin(1e-15));
    }
    // Slightly out of [-1, 1] (rounding of a dot product) is clamped, never extrapolated.
    CHECK(chord.eval(1.0 + 1e-15) == Approx(0.0).margin(1e-15));
    CHECK(chord.eval(-1.0 - 1e-15) == Approx(1.0).epsilon(1e-15));
}

TEST_CASE("chord table: Rayleigh within the linear-interpolation bound") {
    // f(s) = 3/(16 pi) (1 + (1 - 2 s^2)^2): |f''| <= 3/(16 pi) 40 and f >= 3/(16 pi), so the
    // relative error of linear interpolation is at most h^2/8 * 40 with h = 1/16384.
    const RayleighPhase r;
    const ChordTable t(r);
    const double h = 1.0 / 16384.0, bound = h * h / 8.0 * 40.0;
    for (int i = 0; i <= 10000; ++i) {
        const double mu = std::cos(pi * (i + 0.5) / 10001.0);
        CHECK(t.eval(mu) == Approx(r.eval(mu)).epsilon(bound));
    }
}

TEST_CASE("chord table of the cone-averaged Petzold function") {
    const ConeAveragedPhase<TabulatedPhase> cone(petzold_m93(), 0.005, ConePeak::averaged);
    const ChordTable t(cone);
    const double alpha = cone.half_angle();
    // Random angles, half of them in the forward 11 degrees where the function is steep. The
    // bounds are the measured worst cases rounded up (2e6 angles: 1.04e-4 away from the cusp,
    // 1.14e-2 within 0.001 rad of the cone's edge alpha = 2.29 deg, where the interpolant cuts
    // the cusp's corner).
    PhotonRng rng(3, 0);
    double worst_far = 0.0, worst_near = 0.0;
    for (int k = 0; k < 200000; ++k) {
        const double psi = k % 2 ? pi * rng.uniform() : 0.2 * rng.uniform();
        const double mu = std::cos(psi);
        const double e = std::abs(t.eval(mu) / cone.eval(mu) - 1.0);
        double& worst = std::abs(psi - alpha) > 1e-3 ? worst_far : worst_near;
        worst = std::max(worst, e);
    }
    CHECK(worst_far < 2e-4);
    CHECK(worst_near < 2e-2);
    // On the axis and straight back the nodes are the source's values.
    CHECK(t.eval(1.0) == cone.eval(1.0));
    CHECK(t.eval(-1.0) == cone.eval(-1.0));
    // Normalisation: 2 pi int pbar sin psi dpsi = 1, as for the source.
    const double norm = integrate_solid_angle([&](double psi) { return t.eval(std::cos(psi)); }, 0.0, pi, cone.breakpoints());
    CHECK(norm == Approx(1.0).epsilon(1e-4));
}

TEST_CASE("chord table of the Petzold function averaged with its peak transmitted") {
    // pbar is 0 on the axis and rises from 0 to 2 alpha; the interpolation error relative to
    // pbar away from those ends, and relative to pbar(alpha) within 0.001 rad of them (measured
    // worst cases over 2e6 angles: 6.7e-5 and 6.4e-5, rounded up).
    const ConeAveragedPhase<TabulatedPhase> cone(petzold_m93(), 0.005);
    const ChordTable t(cone);
    const double alpha = cone.half_angle(), scale = cone.eval(std::cos(alpha));
    PhotonRng rng(4, 0);
    double worst_far = 0.0, worst_ends = 0.0;
    for (int k = 0; k < 200000; ++k) {
        const double psi = k % 2 ? pi * rng.uniform() : 0.2 * rng.uniform();
        const double mu = std::cos(psi), e = std::abs(t.eval(mu) - cone.eval(mu));
        if (psi < 1e-3 || std::abs(psi - 2.0 * alpha) < 1e-3) worst_ends = std::max(worst_ends, e / scale);
        else worst_far = std::max(worst_far, e / cone.eval(mu));
    }
    CHECK(worst_far < 2e-4);
    CHECK(worst_ends < 2e-4);
    CHECK(t.eval(1.0) == 0.0);
}

TEST_CASE("chord table: invalid size names the parameter") {
    CHECK_THROWS_WITH(ChordTable(IsotropicPhase{}, 1), Catch::Contains("n = 1"));
}
