#pragma once
// Fournier-Forand phase function (Fournier and Forand 1994; Fournier and Jonasz 1999; in the
// form of Mobley, Sundman and Boss, "Phase function effects on oceanic light fields", Applied
// Optics 41(6):1035-1050, 2002, eqs. 5-7): the anomalous-diffraction phase function of
// particles with real index n (relative to water) and a Junge (hyperbolic) size distribution
// of slope mu,
//   p(psi) = 1 / (4 pi (1 - d)^2 d^nu) [nu (1 - d) - (1 - d^nu)
//                                       + (d (1 - d^nu) - nu (1 - d)) / sin^2(psi/2)]
//          + (1 - d180^nu) / (16 pi (d180 - 1) d180^nu) (3 cos^2 psi - 1),
//   nu = (3 - mu)/2,  d = 4 sin^2(psi/2) / (3 (n - 1)^2),  d180 = d at psi = 180 deg,
// normalised exactly; near psi = 0 it diverges as psi^(mu - 5). Its backscatter fraction is
//   B = 1 - (1 - d90^(nu+1) - (1 - d90^nu)/2) / ((1 - d90) d90^nu),  d90 = d at 90 deg,
// which runs from 0 (mu -> 3) to 1/2 (mu = 5) and is inverted for mu by bisection.
// Mobley et al.: n = 1.10, mu = 3.5835 gives B = 0.0183 (Petzold's).
//
// Sampling: the CDF has no simple inverse, so the object IS a TabulatedPhase of the analytic
// function (trapezoid convention: 2 pi p sin linear in psi between nodes) on a dense grid,
// and eval() is that table, exactly the density sample() draws from. analytic() is the
// closed form. Grid: 400 nodes per decade, log-spaced from 1e-4 to 10 deg, then every 0.05
// deg to 180 deg (5401 nodes); below 1e-4 deg the asymptotic law p ~ psi^-(5 - mu).
// Measured against analytic() (tests/test_phase_models.cpp, b_b/b = 0.0183 and 0.01): the
// table integrates to 1 + 2.6e-6 and 1 + 3.4e-6 before rescaling, and eval() is within
// 6.9e-6 and 8.0e-6 (relative) of the closed form from 1e-4 to 180 deg.
#include "secchi/core/config.hpp"
#include <cmath>
#include <concepts>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include "secchi/optics/phase/tabulated.hpp"

namespace secchi::SECCHI_ISA {

class FournierForandPhase {
public:
    /// n: real refractive index of the particles relative to water, 1 < n <= 1.5 (the closed
    /// forms are singular at d90 = 1, n = 1.82); junge_slope mu: 3 < mu <= 5.
    FournierForandPhase(double n, double junge_slope)
        : n_(checked_n(n)), mu_(checked_mu(junge_slope)), table_(tabulate(n_, mu_)) {}

    /// The Junge slope mu that gives backscatter fraction bb_over_b (0 < B <= 1/2) at index n.
    static FournierForandPhase from_backscatter_fraction(double bb_over_b, double n = 1.10) {
        checked_n(n);
        require(std::isfinite(bb_over_b) && bb_over_b > 0.0 && bb_over_b <= 0.5, "bb_over_b", bb_over_b,
                "the Fournier-Forand backscatter fraction lies in (0, 0.5]");
        return FournierForandPhase(n, solve_slope(bb_over_b, n));
    }

    double eval(double cos_psi) const { return table_.eval(cos_psi); }
    double pdf(double cos_psi) const { return table_.pdf(cos_psi); }
    PhaseSample sample(double u1, double u2) const { return table_.sample(u1, u2); }
    /// The direction of sample(u1, u2) without its density (the table's).
    PhaseDirection sample_direction(double u1, double u2) const { return table_.sample_direction(u1, u2); }
#if SECCHI_HAS_LANES
    /// sample_direction's cos psi for lanes of uniforms (photons in lanes,
    /// transport/event_physics.hpp): the table's, in the vectors for double lanes and from its
    /// inverse CDF's float table for float lanes (TabulatedPhase::cos_psi).
    template <class Lanes>
        requires requires(const TabulatedPhase& t, const Lanes& u) { { t.cos_psi(u) } -> std::same_as<Lanes>; }
    Lanes cos_psi(const Lanes& u1) const {
        return table_.cos_psi(u1);
    }
#endif
    /// The uniforms u1 whose sample_direction scatters backward (the table's), for a
    /// backscatter bias (transport/importance.hpp).
    std::pair<double, double> backward_uniforms() const { return table_.backward_uniforms(); }
    std::vector<double> breakpoints() const { return table_.breakpoints(); }

    /// The closed form (Mobley et al. 2002 eq. 5), 1/sr; infinite at cos_psi = 1.
    double analytic(double cos_psi) const { return analytic(n_, mu_, cos_psi); }
    /// B in closed form (Mobley et al. 2002 eq. 7).
    double backscatter_fraction() const { return backscatter_fraction(n_, mu_); }

    static double analytic(double n, double mu, double cos_psi) {
        return analytic_x(n, mu, 0.5 * (1.0 - cos_psi), cos_psi);
    }
    /// The same at an angle psi (radians): sin^2(psi/2) from psi, accurate at small angles.
    static double analytic_at(double n, double mu, double psi) {
        const double s = std::sin(0.5 * psi);
        return analytic_x(n, mu, s * s, std::cos(psi));
    }

    static double backscatter_fraction(double n, double mu) {
        const double d = 2.0 / (3.0 * (n - 1.0) * (n - 1.0)), nu = 0.5 * (3.0 - mu), dn = std::pow(d, nu);
        return 1.0 - (1.0 - d * dn - 0.5 * (1.0 - dn)) / ((1.0 - d) * dn);
    }

    double index() const { return n_; }
    double junge_slope() const { return mu_; }
    const TabulatedPhase& table() const { return table_; }

    std::string name() const {
        std::ostringstream s;
        s << "fournier_forand(n=" << n_ << ", mu=" << mu_ << ")";
        return s.str();
    }

private:
    static double checked_n(double n) {
        require(std::isfinite(n) && n > 1.0 && n <= 1.5, "n", n,
                "the Fournier-Forand relative index needs 1 < n <= 1.5");
        return n;
    }
    static double checked_mu(double mu) {
        require(std::isfinite(mu) && mu > 3.0 && mu <= 5.0, "mu", mu,
                "the Fournier-Forand Junge slope needs 3 < mu <= 5");
        return mu;
    }

    /// Eq. 5 with x = sin^2(psi/2).
    static double analytic_x(double n, double mu, double x, double cos_psi) {
        const double c = 0.75 * (n - 1.0) * (n - 1.0), nu = 0.5 * (3.0 - mu), d180 = 1.0 / c;
        const double forward = x > 0.0 ? core(x / c, c, nu) / four_pi : std::numeric_limits<double>::infinity();
        const double backward = (1.0 - std::pow(d180, nu)) / (4.0 * four_pi * (d180 - 1.0) * std::pow(d180, nu));
        return forward + backward * (3.0 * cos_psi * cos_psi - 1.0);
    }

    /// The forward term without 1/(4 pi), with x = sin^2(psi/2) = c d:
    ///   [(nu (1 - d) - (1 - d^nu)) + ((1 - d^nu) - nu (1 - d)/d) / c] / ((1 - d)^2 d^nu).
    /// Both brackets vanish to second order at d = 1 (psi ~ 10 deg for n = 1.1); for
    /// |ln d| < 1 they are summed as series in t = ln d, without cancellation:
    ///   nu (1 - d) - (1 - d^nu) = sum_{m>=2} (nu^m - nu) t^m / m!,
    ///   (1 - d^nu) - nu (1 - d)/d = -sum_{m>=2} (nu^m + nu (-1)^m) t^m / m!.
    static double core(double d, double c, double nu) {
        const double t = std::log(d), dn = std::exp(nu * t);
        double s1, s2;
        if (std::abs(t) < 1.0) {
            s1 = s2 = 0.0;
            double term = t, num = nu, sign = -1.0;  // term = t^m/m!, num = nu^m, sign = (-1)^m
            for (int m = 2; m <= 30; ++m) {
                term *= t / m;
                num *= nu;
                sign = -sign;
                s1 += (num - nu) * term;
                s2 -= (num + nu * sign) * term;
            }
        } else {
            s1 = nu * (1.0 - d) - (1.0 - dn);
            s2 = (1.0 - dn) - nu * (1.0 - d) / d;
        }
        const double em = std::expm1(t);  // d - 1
        return (s1 + s2 / c) / (em * em * dn);
    }

    /// B(mu) increases from 0 at mu = 3 to 1/2 at mu = 5: bisection to rounding.
    static double solve_slope(double target, double n) {
        double lo = 3.0, hi = 5.0;
        for (int iter = 0; iter < 200 && hi - lo > 4e-16 * hi; ++iter) {
            const double mid = 0.5 * (lo + hi);
            (backscatter_fraction(n, mid) < target ? lo : hi) = mid;
        }
        return hi;
    }

    /// The analytic function on the grid described at the top, as a table with the
    /// small-angle power law p ~ psi^-(5 - mu) below the first node.
    static TabulatedPhase tabulate(double n, double mu) {
        std::vector<double> angle, value;
        const int per_decade = 400;
        for (int i = 0; i < 5 * per_decade; ++i) angle.push_back(1e-4 * std::pow(10.0, double(i) / per_decade));
        for (int i = 0; i <= 3400; ++i) angle.push_back(10.0 + 0.05 * i);
        angle.back() = 180.0;
        for (double a : angle) value.push_back(analytic_at(n, mu, a * deg));
        std::ostringstream s;
        s << "fournier_forand(n=" << n << ", mu=" << mu << ")";
        return TabulatedPhase(angle, value, TabulatedConvention::trapezoid, 5.0 - mu, s.str());
    }

    double n_, mu_;
    TabulatedPhase table_;
};

}  // namespace secchi
