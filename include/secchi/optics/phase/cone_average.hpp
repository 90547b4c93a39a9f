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
// gamma in [|psi - alpha|, psi + alpha] (plus the full circles below alpha - psi), done with
// the shared integrate_solid_angle. L has square-root ends at |psi - alpha| and psi + alpha;
// panels graded geometrically towards both keep the quadrature accurate there.
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
/// The default grid has about 6,700 angles, each an integral of about a thousand evaluations
/// of the phase function.
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
            transmitted_ = integrate_solid_angle([&](double g) { return static_cast<double>(p.eval(std::cos(g))); },
                                                 0.0, alpha_, bps);
        value_.assign(psi_.size(), 0.0);
        parallel_for(
            psi_.size(), table.threads, [&](std::size_t i) { value_[i] = average(p, bps, psi_[i]); },
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

    /// pbar(psi) = (1/omega) 2 pi int p(gamma) L(gamma)/(2 pi) sin(gamma) dgamma (gamma >= alpha
    /// only, where the peak is transmitted).
    double average(const P& p, const std::vector<double>& phase_bps, double psi) const {
        const double lowest = peak_ == ConePeak::transmitted ? alpha_ : 0.0;
        const double a = std::max({0.0, psi - alpha_, lowest}), b = std::min(pi, psi + alpha_);
        if (a >= b) return 0.0;
        const double k1 = std::abs(psi - alpha_), k2 = std::min(psi + alpha_, two_pi - psi - alpha_);
        std::vector<double> bps = phase_bps;
        bps.insert(bps.end(), {k1, k2});
        for (int j = 1; j <= 30; ++j) {  // geometric grading towards the square-root ends of L
            const double r = (k2 - k1) * std::ldexp(1.0, -j);
            bps.insert(bps.end(), {k1 + r, k2 - r});
        }
        const double sin_psi = std::sin(psi);
        const auto integrand = [&](double gamma) {
            return static_cast<double>(p.eval(std::cos(gamma))) * inside_fraction(psi, sin_psi, gamma);
        };
        return integrate_solid_angle(integrand, a, b, bps) / omega_;
    }

    double omega_;
    ConePeak peak_;
    double alpha_ = 0.0;
    double transmitted_ = 0.0;
    std::string name_;
    std::vector<double> psi_, value_;
};

}  // namespace secchi
