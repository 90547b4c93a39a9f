#pragma once
// The phase function averaged over the collection cone (manual eq. 3.5): a photon travelling
// in direction xi' contributes to the radiance seen along xi through
//   pbar = (1/omega) int_omega p(xi' . xi_w) dxi_w,
// the mean of p over a cone of solid angle omega around xi. For Petzold's forward peak this
// differs greatly from the point value p(xi' . xi) when the photon travels nearly along xi.
//
// pbar depends only on psi, the angle between the photon direction and the cone axis. With
// alpha the cone half-angle (omega = 2 pi (1 - cos alpha)), group the cone's points by their
// angle gamma from the photon direction: the circle of radius gamma about the photon
// direction lies inside the cone over an arc of length
//   L(gamma) = 2 acos((cos alpha - cos psi cos gamma) / (sin psi sin gamma))   (clamped),
// so that pbar(psi) = (1/omega) int p(gamma) L(gamma) sin(gamma) dgamma: a 1-D integral over
// gamma in [|psi - alpha|, psi + alpha] (plus the full circles below alpha - psi). L has
// square-root ends at |psi - alpha| and psi + alpha; a change of variable that makes them
// smooth keeps the Gauss-Legendre quadrature accurate there (partial_circles below); the
// full circles are the shared integrate_solid_angle's.
//
// The forward peak within the cone (ConePeak::transmitted, the default). The estimator's
// radiance is the cone average of L; eq. 3.18 gathers it from photons whose scattering toward
// the view carries p. Light scattered by less than the cone's half-angle alpha hardly leaves
// the view: if L is constant over that cone (the same assumption as the cone average itself,
// both correct to O(alpha^2) in L's angular curvature), the in-scattering it brings is
// b f L(xi), with f = 2 pi int_0^alpha p sin dpsi the peak's share of the scattering, and the
// radiative transfer equation along the ray, dL/dt = -c L + b int p L, becomes
//     dL/dt = -(c - b f) L + b int p_> L,      p_> = p with the peak (psi < alpha) removed,
// so that L(0) = int exp(-(c - b f) t) J_>(t) dt + exp(-(c - b f) T) L(T). That is the truncation
// of Wiscombe's delta-M method (J. Atmos. Sci. 34:1408, 1977) applied along one ray: the peak
// is transmitted, not collected. The photon estimate of J_> no longer depends on the rare
// photons travelling within alpha of the view (for Petzold's function a third of the scattering
// lies within 2.3 deg, and the estimate of its share is dominated by a few photons: a heavy-tailed
// sum whose typical value lies below its mean). pbar then averages p_> over the cone, and the
// optics attenuate the ray with c - b f (estimate/path_radiance.hpp). ConePeak::averaged keeps
// the whole of p in the average (eq. 3.5 as the manual writes it).
//
// pbar is tabulated at construction on a psi grid (0; log-spaced from 1e-4 alpha to 10 deg;
// uniform to 180 deg; graded about psi = alpha, where Petzold's singular peak crosses the
// cone's edge and pbar has a cusp) and evaluated by linear interpolation in psi.
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/core/names.hpp"
#include "secchi/core/parallel.hpp"
#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

/// Whether the scattering within the cone's half-angle of the forward direction is averaged
/// with the rest (the manual's eq. 3.5) or transmitted along the ray (see above).
enum class ConePeak { transmitted, averaged };

/// The --cone-peak names (core/names.hpp), in the order the usage texts list them.
inline const std::vector<NamedValue<ConePeak>>& cone_peak_names() {
    static const std::vector<NamedValue<ConePeak>> names{
        {{"transmitted", {}, "the peak within the cone travels on along the ray"}, ConePeak::transmitted},
        {{"averaged", {}, "the peak averaged with the rest of the cone (the manual's eq. 3.5)"}, ConePeak::averaged},
    };
    return names;
}

inline ConePeak parse_cone_peak(const std::string& name) { return parse_named(cone_peak_names(), "cone peak", name); }

/// How ConeAveragedPhase's table of pbar is built: its grid (n_log angles log-spaced up to 10
/// degrees and n_uniform uniform beyond, besides the angles about the cone's edge) and the
/// threads that compute its values (each value its own integral: the same for any count).
/// The default grid has about 6,700 angles, each an integral of about 110 evaluations of the
/// phase function (about 230 with ConePeak::averaged, whose integrals near the forward
/// direction reach into the peak and take its log-spaced panels).
struct ConeTable {
    std::size_t n_log = 2048, n_uniform = 4096;
    unsigned threads = 1;
};

template <PhaseFunction P>
class ConeAveragedPhase {
public:
    /// omega: the cone's solid angle (sr), in (0, 4 pi).
    ConeAveragedPhase(const P& p, double omega, ConePeak peak = ConePeak::transmitted, ConeTable table = {})
        : omega_(omega), peak_(peak), name_(std::string("cone_average(").append(p.name()).append(")")) {
        require(omega > 0.0 && omega < four_pi, "omega", omega, "the cone's solid angle must lie in (0, 4 pi) sr");
        require(table.n_log >= 2 && table.n_uniform >= 2, "grid size", std::min(table.n_log, table.n_uniform),
                "needs at least 2 points");
        alpha_ = 2.0 * std::asin(std::sqrt(omega / four_pi));  // 1 - cos alpha = omega / (2 pi)
        psi_ = make_grid(table.n_log, table.n_uniform);
        auto bps = breakpoints_of(p);
        bps.push_back(alpha_);
        if (peak_ == ConePeak::transmitted)
            transmitted_ = integrate_solid_angle(density_of(p), 0.0, alpha_, bps);
        const std::vector<double> inner = full_circles(p, bps);
        value_.assign(psi_.size(), 0.0);
        parallel_for(
            psi_.size(), table.threads, [&](std::size_t i) { value_[i] = average(p, bps, psi_[i], inner[i]); },
            LoopProgress::unreported);
    }

    /// pbar at cos_psi (1/sr), linear interpolation in psi.
    double eval(double cos_psi) const {
        const double psi = std::acos(std::clamp(cos_psi, -1.0, 1.0));
        const std::size_t i = segment_of(psi);
        const double w = (psi - psi_[i]) / (psi_[i + 1] - psi_[i]);
        return (1.0 - w) * value_[i] + w * value_[i + 1];
    }

    double omega() const { return omega_; }
    double half_angle() const { return alpha_; }
    ConePeak peak() const { return peak_; }
    /// f: the share of the scattering within the half-angle of the forward direction that the
    /// ray transmits (ConePeak::transmitted), 0 when it is averaged. The optics attenuate the
    /// ray with c - b f; the average integrates to 1 - f.
    double transmitted_fraction() const { return transmitted_; }
    /// The tabulation grid (radians): pbar is piecewise linear in psi between these angles.
    std::vector<double> breakpoints() const { return psi_; }
    std::string name() const { return name_; }

private:
    /// The segment [psi_i, psi_{i+1}] holding psi (the last one at psi = pi). Bisection: this
    /// form is evaluated at construction and as the reference; the estimator's per-photon
    /// lookups go through a ChordTable (chord_table.hpp).
    std::size_t segment_of(double psi) const {
        const auto it = std::upper_bound(psi_.begin(), psi_.end(), psi);
        return std::min<std::size_t>(static_cast<std::size_t>(it - psi_.begin()) - 1, psi_.size() - 2);
    }

    std::vector<double> make_grid(std::size_t n_log, std::size_t n_uniform) const {
        const double lo = 1e-4 * alpha_, mid = 10.0 * deg;
        std::vector<double> g{0.0};
        for (std::size_t i = 0; i < n_log; ++i) g.push_back(lo * std::pow(mid / lo, double(i) / double(n_log - 1)));
        for (std::size_t i = 1; i < n_uniform; ++i) g.push_back(mid + (pi - mid) * double(i) / double(n_uniform - 1));
        for (int j = 0; j <= 288; ++j) {  // 6 decades either side of the cone's edge, 48 per decade
            const double r = alpha_ * std::pow(10.0, -j / 48.0);
            for (double x : {alpha_ - r, alpha_ + r})
                if (x >= 0.0 && x <= pi) g.push_back(x);
        }
        g.push_back(alpha_);
        std::sort(g.begin(), g.end());
        g.erase(std::unique(g.begin(), g.end()), g.end());
        g.back() = pi;
        return g;
    }

    /// Fraction L(gamma) / (2 pi) of the circle at angle gamma from the photon direction that
    /// lies inside the cone whose axis is at angle psi. cos alpha - cos psi cos gamma is written
    /// as sin psi sin gamma - 2 sin((alpha + d)/2) sin((alpha - d)/2), d = psi - gamma.
    /// (sin_psi: sin(psi), the same for every gamma of one psi.)
    double inside_fraction(double psi, double sin_psi, double gamma) const {
        if (gamma <= alpha_ - psi || gamma >= two_pi - psi - alpha_) return 1.0;
        if (gamma >= psi + alpha_ || gamma <= psi - alpha_) return 0.0;
        const double d = psi - gamma;
        const double x = 1.0 - 2.0 * std::sin(0.5 * (alpha_ + d)) * std::sin(0.5 * (alpha_ - d)) /
                                   (sin_psi * std::sin(gamma));
        return std::acos(std::clamp(x, -1.0, 1.0)) / pi;
    }

    /// p as a function of the angle gamma (radians), in double.
    static auto density_of(const P& p) {
        return [&p](double gamma) { return static_cast<double>(p.eval(std::cos(gamma))); };
    }

    /// For each angle psi_i of the grid, 2 pi int p(gamma) sin(gamma) dgamma over the circles
    /// about the photon's direction that lie wholly inside the cone, gamma in [lowest,
    /// alpha - psi_i] (lowest = alpha where the peak is transmitted: then none). One pass
    /// outward from psi = alpha, each integral the one before plus the piece between (about as
    /// many evaluations for the whole grid as one integral from 0 to alpha takes).
    std::vector<double> full_circles(const P& p, const std::vector<double>& phase_bps) const {
        std::vector<double> full(psi_.size(), 0.0);
        if (peak_ == ConePeak::transmitted) return full;
        const auto density = density_of(p);
        double sum = 0.0, from = 0.0;
        for (std::size_t i = psi_.size(); i-- > 0;) {
            if (!(psi_[i] < alpha_)) continue;
            const double to = alpha_ - psi_[i];
            sum += integrate_solid_angle(density, from, to, phase_bps);
            full[i] = sum;
            from = to;
        }
        return full;
    }

    /// pbar(psi) = (1/omega) 2 pi int p(gamma) L(gamma)/(2 pi) sin(gamma) dgamma over gamma >=
    /// `lowest` (alpha where the peak is transmitted, else 0): `inner`, the circles wholly
    /// inside the cone about the photon's direction (full_circles); those wholly inside about
    /// the backward direction, gamma > 2 pi - psi - alpha (where the cone reaches past it), by
    /// integrate_solid_angle; the circles that cross the cone's edge, gamma in [k1, k2] =
    /// [|psi - alpha|, min(psi + alpha, 2 pi - psi - alpha)], by partial_circles.
    double average(const P& p, const std::vector<double>& phase_bps, double psi, double inner) const {
        const double lowest = peak_ == ConePeak::transmitted ? alpha_ : 0.0;
        double sum = inner;
        const double back = two_pi - psi - alpha_;
        if (back < pi)
            sum += integrate_solid_angle(density_of(p), std::max(back, lowest), pi, phase_bps);
        const double k1 = std::abs(psi - alpha_), k2 = std::min(psi + alpha_, back);
        if (k2 > std::max(k1, lowest)) sum += partial_circles(p, phase_bps, psi, k1, k2, lowest);
        return sum / omega_;
    }

    /// 2 pi int p(gamma) L(gamma)/(2 pi) sin(gamma) dgamma over [max(k1, lowest), k2]. L has
    /// square-root ends at k1 and k2 (L^2 is linear in gamma there); with
    ///     gamma = k1 + (k2 - k1) sin^2(u/2),  dgamma = (k2 - k1)/2 sin(u) du,  u in [0, pi],
    /// sqrt(gamma - k1) and sqrt(k2 - gamma) become (k2 - k1)^(1/2) sin(u/2) and cos(u/2): the
    /// integrand is smooth in u, and Gauss-Legendre on panels of u converges fast. The panels'
    /// edges: u_panels equal steps of u, and the images of the phase function's breakpoints
    /// and of the standard angle grid's log-spaced part (below psi_log, where the peak of a
    /// forward-peaked p lies when psi is close to alpha). Accuracy: the exact cap averages of
    /// isotropic and Rayleigh functions (Funk-Hecke) to 5e-11 relative for omega >= 1e-4 sr
    /// (test_phase checks 1e-9); where a power-law peak of p meets the square-root end (psi
    /// within 1e-5 rad of alpha, the peak averaged), a brute-force quadrature to 1e-7 (test_phase).
    double partial_circles(const P& p, const std::vector<double>& phase_bps, double psi, double k1, double k2,
                           double lowest) const {
        const double span = k2 - k1, sin_psi = std::sin(psi);
        const auto u_of = [&](double gamma) {  // the inverse map: sin^2(u/2) = (gamma - k1)/span
            return 2.0 * std::asin(std::sqrt(std::clamp((gamma - k1) / span, 0.0, 1.0)));
        };
        // Below psi_min cos(gamma) no longer resolves gamma: that part (psi within psi_min of
        // alpha) is integrate_solid_angle's power-law tail of p L, as elsewhere.
        double tail = 0.0, from = std::max(k1, lowest);
        if (from < detail::psi_min) {
            const auto density = [&](double gamma) { return density_of(p)(gamma) * inside_fraction(psi, sin_psi, gamma); };
            const double to = std::min(k2, detail::psi_min);
            tail = detail::small_angle_tail(density, to) - detail::small_angle_tail(density, from);
            from = to;
            if (from >= k2) return tail;
        }
        const double u_lo = from > k1 ? u_of(from) : 0.0;
        std::vector<double> edges{u_lo, pi};
        for (int j = 1; j < u_panels; ++j) edges.push_back(pi * j / u_panels);
        for (double x : phase_bps)
            if (x > k1 && x < k2) edges.push_back(u_of(x));
        for (double x : detail::standard_psi_grid())
            if (x > k1 && x < std::min(k2, detail::psi_log)) edges.push_back(u_of(x));
        std::erase_if(edges, [&](double u) { return u < u_lo; });
        std::sort(edges.begin(), edges.end());
        edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
        const auto integrand = [&](double u) {
            const double s = std::sin(0.5 * u), gamma = k1 + span * s * s;
            return two_pi * density_of(p)(gamma) * inside_fraction(psi, sin_psi, gamma) *
                   std::sin(gamma) * 0.5 * span * std::sin(u);
        };
        return tail + detail::integrate_panels(integrand, edges);
    }

    static constexpr int u_panels = 6;

    double omega_;
    ConePeak peak_;
    double alpha_ = 0.0;
    double transmitted_ = 0.0;
    std::string name_;
    std::vector<double> psi_, value_;
};

}  // namespace secchi
