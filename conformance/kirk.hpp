#pragma once
// Kirk's AOP relations (canonical_problems.md section 7; the manual, section 7.5): the
// relations, the cases `canonical --problem kirk` scores or reports, and the reductions of a
// depth profile of Ed to z1% and of R(0) at several k to the slope C.
//
// The relations (both fits to Monte Carlo runs, not exact results):
//  - Irradiance reflectance just below a level surface, R(0) = C k, k = b_b / (a + b_b)
//    (Gordon et al. 1975; Gordon and Morel 1983), with Kirk's C(mu0) = -0.629 mu0 + 0.975
//    (Kirk 1994, "The relationship between inherent and apparent optical properties", chapter 2,
//    pp. 40-58 of Ocean Optics, Oxford University Press, as the manual cites it; the manual,
//    eq. 7.4), for Petzold-like phase functions; mu0 = cosine of the refracted solar zenith angle.
//  - Mean diffuse attenuation over the euphotic zone, Kd_bar = (1/z1%) int_0^z1% Kd dz
//    = ln(100) / z1%: Kd_bar / a = (1/mu0) (1 + G(mu0) b/a)^(1/2) with
//    G(mu0) = mu0 (2.127/mu_s - 1.895) - 0.618/mu_s + 0.490 (Kirk 1994; the manual, eq. 7.8-7.9),
//    mu_s = mean cosine of the phase function; the 1991 form G'(mu0) = mu0 (2.236/mu_s - 2.447)
//    - 0.849/mu_s + 0.739 (Kirk 1991, Limnol. Oceanogr. 36(3):455-467; the manual, eq. 7.10).
//
// Tolerance and domain. A search of the stored public literature (documentation, web pages and
// code) for Kirk 1984 (Limnol. Oceanogr. 29:350-356), Kirk 1991 and Kirk 1994 found neither a
// stated accuracy of these fits nor a stated range of b/a or mu0 over which they were fitted:
// no citable source gives them. So, as canonical_problems.md section 7 prescribes where the
// source states none, the tolerance is +-5 % (kRelationTolerance). The scored domain is the
// canonical Petzold phase function (petzold_m93(): M93 Table 2, an average of San Diego
// harbour waters, the family the relations were fitted for), sun at nadir (mu0 = 1) below a
// level surface, and b/a from 0.27 to 9.6: the k = b_b/(a + b_b) values 0.005 to 0.15 of the
// manual's check (eq. 7.5), as the project's kirk_aop example read it before this scoring
// existed. Whether that lies inside the range Kirk fitted could not be confirmed from a source.
//
// R(0) is not proportional to k over that range: R(0)/k grows with b/a as multiple scattering
// adds to the single-scattered return (a discrete-ordinate solution for this phase function,
// sun at nadir, without the interface, scripts/kirk_exact_reference.py: R(0)/k = 0.288 at
// k = 0.005, 0.325 at 0.05, 0.388 at 0.15). So C depends on the k range, and on whether R(0) is fitted on k or on b_b/a (Kirk's
// own variable, R(0) = C b_b/a; the two agree within 5 % only for k <= 0.048). Since the range
// of Kirk's fit is not known, C is reported, not scored (choosing a range would choose the
// verdict); canonical prints the slope over sub-ranges and on b_b/a beside it. Kd_bar is scored.
//
// Outside the domain (the manual's Henyey-Greenstein case: mean cosine 0.8, a = 0.1 /m,
// b = 0.9 /m, sun at nadir, no interface) nothing is scored against the relations; secchi's
// z1% and R(0) are checked there against an exact discrete-ordinate solution of the same
// problem (kExactHg*, from scripts/kirk_exact_reference.py).
#include "secchi/core/error.hpp"
#include "secchi/core/stats.hpp"
#include <cmath>
#include <span>
#include <string>
#include <vector>

namespace secchi::conformance::kirk {

/// The relations' tolerance: no source states one (see above), so canonical_problems.md
/// section 7's default.
inline constexpr double kRelationTolerance = 0.05;
/// A scored relation entry must also have a relative SE at most this, so that a noisy run cannot
/// pass (not with --quick, which checks bias only, as for M93 Table 5).
inline constexpr double kMaxRelativeSe = kRelationTolerance / 5.0;
/// The exact checks pass when |secchi - exact| <= kExactSeMultiple SE (the exact solution's own
/// error, < 1e-6 relative, and the depth interpolation's, < 1e-6, are negligible beside it)...
inline constexpr double kExactSeMultiple = 4.0;
/// ... and secchi's relative SE is at most this, so that the check can tell 1 % apart (not with
/// --quick).
inline constexpr double kExactMaxRelativeSe = 0.0025;

/// Kirk 1994's C(mu0) (the manual, eq. 7.4).
inline double reflectance_c(double mu0) { return -0.629 * mu0 + 0.975; }

/// Kirk 1994's G(mu0, mu_s) (the manual, eq. 7.9).
inline double g_1994(double mu0, double mu_s) { return mu0 * (2.127 / mu_s - 1.895) - 0.618 / mu_s + 0.490; }

/// Kirk 1991's G'(mu0, mu_s) (the manual, eq. 7.10).
inline double g_1991(double mu0, double mu_s) { return mu0 * (2.236 / mu_s - 2.447) - 0.849 / mu_s + 0.739; }

/// Kd_bar = (a / mu0) (1 + G b/a)^(1/2) (the manual, eq. 7.8), for G from g_1994 or g_1991.
inline double kd_bar_relation(double a, double b, double mu0, double g) {
    require(a > 0.0, "absorption a", a, "must be > 0");
    require(b >= 0.0, "scattering b", b, "must be >= 0");
    require(mu0 > 0.0 && mu0 <= 1.0, "mu0", mu0, "must be in (0, 1]");
    const double radicand = 1.0 + g * b / a;
    require(radicand > 0.0, "1 + G b/a", radicand, "must be > 0");
    return a / mu0 * std::sqrt(radicand);
}

/// z1% = ln(100) / Kd_bar.
inline double euphotic_depth(double kd_bar) { return std::log(100.0) / kd_bar; }

/// b for a given k = b_b / (a + b_b) with b_b = bb_fraction b (the manual, eq. 7.5).
inline double scattering_for_k(double k, double a, double bb_fraction) {
    require(k > 0.0 && k < 1.0, "k", k, "must be in (0, 1)");
    require(bb_fraction > 0.0 && bb_fraction <= 1.0, "b_b/b", bb_fraction, "must be in (0, 1]");
    return k * a / ((1.0 - k) * bb_fraction);
}

/// The in-domain cases: k = b_b/(a + b_b) of the manual's check (see the header comment).
inline const std::vector<double>& domain_k() {
    static const std::vector<double> k = {0.005, 0.01, 0.02, 0.05, 0.1, 0.15};
    return k;
}

/// The manual's out-of-domain case (section 7.5.4).
struct HgCase {
    double a = 0.1, b = 0.9, mean_cosine = 0.8;
};

/// The exact solution of the HG case (discrete ordinates, PythonicDISORT, NQuad = 256, one
/// layer of optical depth 400, converged to all printed digits from NQuad = 64), printed by
///     /tmp/venv/bin/python scripts/kirk_exact_reference.py
inline constexpr double kExactHgZ1 = 18.790557;    ///< m
inline constexpr double kExactHgR0 = 0.13620802;   ///< Eu(0) / Ed(0)
/// The same case from the literature (canonical_problems.md section 7): an independent Monte
/// Carlo and the manual's DIRSIG photon mapping (its section 7.5.4).
inline constexpr double kIndependentMcHgZ1 = 18.78;  ///< m
inline constexpr double kDirsigHgZ1 = 19.3;          ///< m

/// Detector depths for finding z1% near `z_guess`: the surface and 81 planes from 0.6 z_guess
/// to 1.4 z_guess, z_guess / 100 apart. Log-linear interpolation between planes h apart errs
/// by at most h^2 max|d^2 ln Ed/dz^2| / (8 Kd) in depth; for the HG case (z_guess = 19.94 m,
/// h = 0.2 m) the exact solution puts that below 1e-6 relative (scripts/kirk_exact_reference.py).
inline std::vector<double> euphotic_grid(double z_guess) {
    require(z_guess > 0.0, "z1% guess", z_guess, "must be > 0");
    std::vector<double> depths = {0.0};
    for (int i = 0; i <= 80; ++i) depths.push_back(z_guess * (0.6 + 0.01 * i));
    return depths;
}

/// The depth where Ed falls to `fraction` of Ed at depths[0] (which must be 0: just below the
/// surface), by linear interpolation of ln Ed between the bracketing detector depths.
/// Its SE by the delta method from the relative SEs r_lo, r_hi of Ed at the bracketing depths
/// and r_0 at the surface: dz = ((1 - u) dln Ed_lo + u dln Ed_hi - dln Ed_0) / s, with u the
/// interpolation fraction and s the local log slope; the SE returned,
/// ((1 - u) r_lo + u r_hi + r_0) / s, bounds that from above whatever the correlations between
/// the three (the batch values themselves are not kept by the transport).
/// Throws if Ed does not fall that far within the depths.
inline Estimate depth_of_fraction(std::span<const double> depths, std::span<const Estimate> ed, double fraction) {
    require(depths.size() == ed.size() && depths.size() >= 2, "detector depths", depths.size(),
            "must match the Ed profile and be at least 2");
    require(depths[0] == 0.0, "first detector depth", depths[0], "must be 0 (just below the surface)");
    require(fraction > 0.0 && fraction < 1.0, "fraction", fraction, "must be in (0, 1)");
    const Estimate& e0 = ed[0];
    require(e0.value > 0.0, "Ed(0)", e0.value, "must be > 0");
    const double target = std::log(fraction * e0.value);
    for (std::size_t i = 2; i < depths.size(); ++i) {
        const Estimate& lo = ed[i - 1];
        const Estimate& hi = ed[i];
        if (!(hi.value > 0.0) || std::log(hi.value) > target) continue;
        require(lo.value > 0.0 && std::log(lo.value) > target, "Ed profile", depths[i - 1],
                "(depth in m) does not bracket the target: the first grid plane below the surface is already too deep");
        const double l0 = std::log(lo.value), l1 = std::log(hi.value);
        const double h = depths[i] - depths[i - 1];
        const double slope = (l0 - l1) / h;
        const double u = (l0 - target) / (l0 - l1);
        const double se = ((1.0 - u) * lo.relative_se() + u * hi.relative_se() + e0.relative_se()) / slope;
        return {depths[i - 1] + u * h, se};
    }
    reject("Ed profile", depths.back(), "(deepest detector, m) is above the depth where Ed falls to the fraction");
}

/// x / y with an SE bound |x/y| (r_x + r_y) whatever the correlation of x and y.
inline Estimate ratio(const Estimate& x, const Estimate& y) {
    require(y.value != 0.0, "denominator", y.value, "must not be 0");
    const double r = x.value / y.value;
    return {r, std::abs(r) * (x.relative_se() + y.relative_se())};
}

/// Least-squares slope through the origin of y_i against x_i, sum x y / sum x^2, with the SE
/// of independent y_i: sqrt(sum x^2 SE_i^2) / sum x^2.
inline Estimate slope_through_origin(std::span<const double> x, std::span<const Estimate> y) {
    require(x.size() == y.size() && !x.empty(), "points", x.size(), "must be as many x as y, at least one");
    double sxx = 0.0, sxy = 0.0, var = 0.0;
    for (std::size_t i = 0; i < x.size(); ++i) {
        sxx += x[i] * x[i];
        sxy += x[i] * y[i].value;
        var += x[i] * x[i] * y[i].se * y[i].se;
    }
    require(sxx > 0.0, "sum of x^2", sxx, "must be > 0");
    return {sxy / sxx, std::sqrt(var) / sxx};
}

}  // namespace secchi::conformance::kirk
