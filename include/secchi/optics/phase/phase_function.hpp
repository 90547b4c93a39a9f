#pragma once
// The phase-function concept and the one numerical integrator over scattering angle that
// every phase-function computation shares (moments, cone averages, test histograms).
//
// A phase function p(psi) (1/sr) is rotationally symmetric about the forward direction
// (manual section 5.8) and normalised so that 2 pi int_0^pi p(psi) sin(psi) dpsi = 1
// (manual eq. 5.25-5.27). Samplers take their uniform numbers as arguments (pbrt style), so
// they are pure functions and testable.
#include "secchi/core/config.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <limits>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "secchi/core/math.hpp"

namespace secchi::SECCHI_ISA {

/// One sampled scattering direction: cos of the scattering angle, azimuth, density per sr.
struct PhaseSample {
    double cos_psi;
    double phi;
    double pdf;
};

template <class P>
concept PhaseFunction = requires(const P p, double mu, double u1, double u2) {
    { p.eval(mu) } -> std::convertible_to<double>;      // p(psi) in 1/sr, mu = cos psi
    { p.pdf(mu) } -> std::convertible_to<double>;       // sampling density per sr
    { p.sample(u1, u2) } -> std::same_as<PhaseSample>;  // u1, u2 uniform in (0, 1)
    { p.name() } -> std::convertible_to<std::string>;
};

/// A sampled scattering direction alone (what transport needs): the first two fields of the
/// PhaseSample the same uniforms give.
struct PhaseDirection {
    double cos_psi;
    double phi;
};

/// A phase function may sample the direction without its density (which costs an acos and a
/// table search for a tabulated function). sample_direction(u1, u2) must return exactly the
/// cos_psi and phi of sample(u1, u2).
template <class P>
concept HasDirectionSampler = requires(const P p, double u1, double u2) {
    { p.sample_direction(u1, u2) } -> std::same_as<PhaseDirection>;
};

/// sample(u1, u2) of a phase function P from its own sample_direction(u1, u2) and pdf(mu): the
/// direction and the density of that direction. P derives from SampledByDirection<P> (CRTP).
template <class P>
struct SampledByDirection {
    PhaseSample sample(double u1, double u2) const {
        const P& p = static_cast<const P&>(*this);
        const PhaseDirection d = p.sample_direction(u1, u2);
        return {d.cos_psi, d.phi, p.pdf(d.cos_psi)};
    }
};

template <class P>
PhaseDirection sample_direction_of(const P& p, double u1, double u2) {
    if constexpr (HasDirectionSampler<P>) {
        return p.sample_direction(u1, u2);
    } else {
        const PhaseSample s = p.sample(u1, u2);
        return {s.cos_psi, s.phi};
    }
}

/// A phase function may list the angles (radians) where it has kinks (table nodes); the
/// integrator then puts panel boundaries there so each panel sees a smooth integrand.
template <class P>
concept HasBreakpoints = requires(const P p) {
    { p.breakpoints() } -> std::convertible_to<std::vector<double>>;
};

template <class P>
std::vector<double> breakpoints_of(const P& p) {
    if constexpr (HasBreakpoints<P>) return p.breakpoints();
    else return {};
}

namespace detail {

/// 16-point Gauss-Legendre rule on [-1, 1]: the positive nodes and their weights.
inline constexpr std::array<double, 8> gl16_x{
    0.0950125098376374401853193, 0.2816035507792589132304605, 0.4580167776572273863424194,
    0.6178762444026437484466718, 0.7554044083550030338951012, 0.8656312023878317438804679,
    0.9445750230732325760779884, 0.9894009349916499325961542};
inline constexpr std::array<double, 8> gl16_w{
    0.1894506104550684962853967, 0.1826034150449235888667637, 0.1691565193950025381893121,
    0.1495959888165767320815017, 0.1246289712555338720524763, 0.0951585116824927848099251,
    0.0622535239386478928628438, 0.0271524594117540948517806};

/// int_a^b f(x) dx on one panel: half times the weighted sum over the nodes, returned as the
/// two factors (integrate_panels adds their product to its sum in one multiply-add). Every
/// value of f goes straight into a mul_add (core/math.hpp), never into a plain sum, which the
/// compiler may fuse with f's last multiply where f is inlined and not where it is called: so
/// an integral rounds alike either way, and two forms of one phase function (a type and its
/// AnyPhaseFunction) give the same bits wherever they are integrated.
template <class F>
std::pair<double, double> gauss_legendre_factors(F&& f, double a, double b) {
    const double half = 0.5 * (b - a), mid = 0.5 * (a + b);
    double sum = 0.0;
    for (std::size_t i = 0; i < gl16_x.size(); ++i) {
        sum = mul_add(gl16_w[i], f(mul_add(-half, gl16_x[i], mid)), sum);
        sum = mul_add(gl16_w[i], f(mul_add(half, gl16_x[i], mid)), sum);
    }
    return {half, sum};
}

/// int_a^b f(x) dx on one panel (16-point Gauss-Legendre).
template <class F>
double gauss_legendre(F&& f, double a, double b) {
    const auto [half, sum] = gauss_legendre_factors(f, a, b);
    return half * sum;
}

/// Composite Gauss-Legendre over consecutive panels [edges[i], edges[i+1]].
template <class F>
double integrate_panels(F&& f, std::span<const double> edges) {
    double sum = 0.0;
    for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
        const auto [half, panel_sum] = gauss_legendre_factors(f, edges[i], edges[i + 1]);
        sum = mul_add(half, panel_sum, sum);
    }
    return sum;
}

// The scattering-angle grid: panels log-spaced from psi_min to psi_log (16 per decade),
// uniform (width <= 0.02 rad) from psi_log to pi, plus pi/2 (the backscatter boundary).
inline constexpr double psi_min = 1e-7;  ///< below this, an analytic power-law tail
inline constexpr double psi_log = 0.1;

inline const std::vector<double>& standard_psi_grid() {
    static const std::vector<double> grid = [] {
        std::vector<double> g;
        const int n_log = 16 * 6;  // 6 decades, 1e-7 .. 0.1 rad
        for (int i = 0; i <= n_log; ++i) g.push_back(psi_min * std::pow(psi_log / psi_min, double(i) / n_log));
        const int n_lin = static_cast<int>(std::ceil((pi - psi_log) / 0.02));
        for (int i = 1; i <= n_lin; ++i) g.push_back(psi_log + (pi - psi_log) * i / n_lin);
        g.push_back(0.5 * pi);
        std::sort(g.begin(), g.end());
        g.back() = pi;
        return g;
    }();
    return grid;
}

/// Panel edges on [a, b]: a, b, the standard grid and the breakpoints strictly inside.
inline std::vector<double> panel_edges(double a, double b, std::span<const double> breakpoints) {
    std::vector<double> e{a, b};
    for (double x : standard_psi_grid())
        if (x > a && x < b) e.push_back(x);
    for (double x : breakpoints)
        if (x > a && x < b) e.push_back(x);
    std::sort(e.begin(), e.end());
    e.erase(std::unique(e.begin(), e.end()), e.end());
    return e;
}

/// 2 pi int_0^c density(psi) sin(psi) dpsi for c <= psi_min, with the density extrapolated
/// as a power law c1 (psi1/psi)^s fitted at psi1 = 1e-6 and 1e-5 rad. There cos(psi) is still
/// resolved in double precision (1 - mu ~ 5e-13), whereas at 1e-7 rad it is not (the spacing
/// of doubles below 1 is 1.1e-16, a 1 % error in psi). Exact for Petzold's small-angle law
/// (M93, p ~ psi^-1.346, which puts 9e-5 of the probability below 1e-7 rad); for a density
/// finite at 0 it gives the O(c^2) term. sin(psi) = psi here (relative error < 2e-15).
template <class Density>
double small_angle_tail(Density&& density, double c) {
    const double psi1 = 1e-6, psi2 = 1e-5;
    const double d1 = density(psi1), d2 = density(psi2);
    if (!(d1 > 0.0) || !(d2 > 0.0)) return 0.0;
    const double s = std::log(d1 / d2) / std::log(psi2 / psi1);
    if (s >= 2.0) return std::numeric_limits<double>::infinity();  // not integrable
    return two_pi * d1 * std::pow(psi1, s) * std::pow(c, 2.0 - s) / (2.0 - s);
}

}  // namespace detail

/// 2 pi int_a^b density(psi) sin(psi) dpsi: the solid-angle integral of a rotationally
/// symmetric density (1/sr) between scattering angles a and b (radians, 0 <= a < b <= pi).
/// Composite 16-point Gauss-Legendre on panels log-spaced near 0 (down to 1e-7 rad),
/// uniform above 0.1 rad, split at pi/2 and at the given breakpoints (kinks of the density);
/// the part below 1e-7 rad is the power-law tail of detail::small_angle_tail.
template <class Density>
double integrate_solid_angle(Density&& density, double a, double b, std::span<const double> breakpoints = {}) {
    double tail = 0.0;
    if (a < detail::psi_min) {
        const double c = std::min(b, detail::psi_min);
        tail = detail::small_angle_tail(density, c) - detail::small_angle_tail(density, a);
        a = c;
    }
    if (a >= b) return tail;
    const auto edges = detail::panel_edges(a, b, breakpoints);
    return tail + detail::integrate_panels([&](double psi) { return two_pi * density(psi) * std::sin(psi); }, edges);
}

struct PhaseMoments {
    double normalisation;         ///< 2 pi int p sin dpsi (1 for a normalised function)
    double mean_cosine;           ///< g = 2 pi int p cos sin dpsi
    double backscatter_fraction;  ///< b_b / b = 2 pi int_{pi/2}^{pi} p sin dpsi
};

/// Moments of a phase function computed numerically from eval() (accurate to ~1e-6
/// relative for strongly peaked functions such as HG g = 0.99 and Petzold).
template <PhaseFunction P>
PhaseMoments phase_moments(const P& p) {
    const auto bps = breakpoints_of(p);
    const auto density = [&](double psi) { return static_cast<double>(p.eval(std::cos(psi))); };
    const auto weighted = [&](double psi) { return density(psi) * std::cos(psi); };
    return {integrate_solid_angle(density, 0.0, pi, bps), integrate_solid_angle(weighted, 0.0, pi, bps),
            integrate_solid_angle(density, 0.5 * pi, pi, bps)};
}

}  // namespace secchi
