#pragma once
// A phase function given as a table of (angle, value) nodes (manual section 5.8.2), with an
// optional small-angle power law, under one of two explicit interpolation conventions
// (canonical_problems.md, problem 2). eval() is exactly the density that sample() draws from.
//
// Let f(psi) = 2 pi p(psi) sin(psi) be the density of the scattering angle psi (radians), so
// that int_0^pi f dpsi = 1 (manual eq. 5.25). Nodes theta_0 < ... < theta_N (radians).
//
//  * Below theta_0 (if theta_0 > 0), in both conventions: f(psi) = 2 pi p_0 (theta_0/psi)^k psi,
//    i.e. the power law p = p_0 (theta_0/psi)^k (M93 problem 2, k = 1.346 for Petzold) with
//    sin(psi) taken as psi. That makes the CDF a power of psi, inverted exactly; for Petzold
//    (theta_0 = 0.0022 rad) the relative difference from the exact sin is < theta_0^2/6 = 8e-7.
//    eval = f/(2 pi sin psi) is consistent with it. Without an explicit law, k = 0 (p constant).
//  * TabulatedConvention::trapezoid: f linear in psi between nodes. This is M93's trapezoidal
//    normalisation (the Petzold table integrates to 1.002 under it). Note f(pi) = 0 whatever
//    p(180 deg) is, so the 180-degree value does not enter; eval(-1) is the limit
//    f(theta_{N-1}) / (2 pi (pi - theta_{N-1})).
//  * TabulatedConvention::linear_p: p linear in psi between nodes, times the exact sin(psi)
//    (the Petzold table integrates to 1.020). The CDF within a segment,
//    -a cos psi + b (sin psi - psi cos psi) + const, is inverted from a cubic Hermite guess by
//    Newton's step where a bound proves it within 1e-12 of the segment's width, else by
//    safeguarded Halley steps. Each segment is cut into 16 equal sub-intervals; the guide
//    table finds the sub-interval of u directly, and what the guess and the bound need is one
//    64-byte row per sub-interval (and per segment), which photons in lanes read with one load
//    per lane.
//  * A table ending before 180 deg is extended to 180 deg with its last value.
// Photons in double lanes take the same root in the vectors (cos_psi); photons in float lanes
// take a table of the inverse CDF built with the phase function (float_inverse_table.hpp:
// cos psi within 2^-23 of sample_direction's), or the double lanes' root where that table is
// refused.
// Either way the table is then divided by its exact integral, raw_integral(), so that
// 2 pi int p sin dpsi = 1.
#include "secchi/core/config.hpp"
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/phase/float_inverse_table.hpp"
#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

enum class TabulatedConvention {
    trapezoid,  ///< 2 pi p sin(psi) linear in psi between nodes (M93's trapezoidal rule)
    linear_p,   ///< p linear in psi between nodes, times the exact sin(psi)
};

namespace detail {
/// x - sin(x) given sin(x), without cancellation for small x (its series below |x| = 1e-2).
/// For a double, or a vector of them.
template <class Real>
Real x_minus_sin(const Real& x, const Real& sin_x) {
    using std::abs;
    const Real x2 = x * x;
    return select(abs(x) < 1e-2, x * x2 / 6.0 * (1.0 - x2 / 20.0 * (1.0 - x2 / 42.0 * (1.0 - x2 / 72.0))), x - sin_x);
}
/// x - sin(x) without cancellation for small x.
inline double x_minus_sin(double x) { return x_minus_sin(x, std::abs(x) < 1e-2 ? 0.0 : std::sin(x)); }
/// x / sin(x), finite at x = 0.
inline double x_over_sin(double x) { return std::abs(x) < 1e-4 ? 1.0 + x * x / 6.0 : x / std::sin(x); }
/// sin of an angle in [0, pi], exactly 0 at 0 and at pi.
inline double sin_angle(double theta) { return theta <= 0.5 * pi ? std::sin(theta) : std::sin(pi - theta); }

/// Guide table (Chen and Asau 1974) for inverting a cumulative table cum_0 <= ... <= cum_n
/// (n >= 1) at target = u cum_n, u in [0, 1]: the i <= n - 1 with cum_i <= target < cum_{i+1},
/// exactly as min(upper_bound(cum, target) - 1, n - 1), in O(1) on average. Bucket b of u,
/// [b/G, (b+1)/G) with G a power of 2, stores the answer for target (b/G) cum_n. As u >= b/G
/// exactly and rounding is monotone, every target of the bucket has that answer or a later
/// one, and a forward scan over cum finds it. A bucket whose end, target ((b+1)/G) cum_n, has
/// the same answer is marked settled: all its targets have it, and no scan is needed
/// (photons in lanes skip the scan's table reads when every lane's bucket is settled). G is
/// about 16 n (at most 2^16), so most buckets are.
class CumulativeGuide {
public:
    CumulativeGuide() = default;
    explicit CumulativeGuide(const std::vector<double>& cum)
        : start_(std::clamp<std::size_t>(std::bit_ceil(buckets_per_entry * cum.size()), 64, max_buckets)) {
        const double g = static_cast<double>(start_.size());
        for (std::size_t b = 0; b < start_.size(); ++b)
            start_[b] = static_cast<std::uint32_t>(upper_bound_index(cum, (static_cast<double>(b) / g) * cum.back()));
        for (std::size_t b = 0; b + 1 < start_.size(); ++b)  // the next bucket's start is this one's end's answer
            if (start_[b] == start_[b + 1]) start_[b] |= settled;
    }
    /// For target = u * cum.back() >= cum.front() (cum as given to the constructor).
    [[nodiscard]] std::size_t find(const std::vector<double>& cum, double u, double target) const {
        const double g = static_cast<double>(start_.size()), scaled = u * g;  // exact
        const std::uint32_t entry = start_[scaled >= 0.0 ? static_cast<std::size_t>(std::min(scaled, g - 1.0)) : 0];
        std::size_t i = entry & ~settled;
        if (entry & settled) return i;
        while (i + 2 < cum.size() && cum[i + 1] <= target) ++i;
        return i;
    }
#if SECCHI_HAS_LANES
    /// find() per lane (photons in lanes), the indices as doubles: the same bucket and the
    /// same forward scan, a lane's scan ending where its own does.
    [[nodiscard]] lanes::Reals find(const std::vector<double>& cum, const lanes::Reals& u, const lanes::Reals& target) const {
        using lanes::Reals, lanes::stdx::max, lanes::stdx::min;
        const double g = static_cast<double>(start_.size());
        Reals i = lanes::lookup(start_, lanes::stdx::floor(min(max(u * g, Reals(0.0)), Reals(g - 1.0))));
        const auto open = i < double(settled);
        if (none_of(open)) return i - double(settled);
        lanes::stdx::where(!open, i) -= double(settled);
        const double last = static_cast<double>(cum.size()) - 2.0;  // i + 2 < cum.size()
        for (auto more = open && i < last && lanes::lookup(cum, i + 1.0) <= target; any_of(more);
             more = more && i < last && lanes::lookup(cum, i + 1.0) <= target)
            lanes::stdx::where(more, i) += 1.0;
        return i;
    }
#endif
    /// The reference: min(upper_bound(cum, target) - 1, n - 1), 0 below cum_0.
    static std::size_t upper_bound_index(const std::vector<double>& cum, double target) {
        const auto it = std::upper_bound(cum.begin(), cum.end(), target);
        return it == cum.begin() ? 0 : std::min<std::size_t>(static_cast<std::size_t>(it - cum.begin()) - 1, cum.size() - 2);
    }

private:
    static constexpr std::size_t buckets_per_entry = 16, max_buckets = std::size_t{1} << 16;
    static constexpr std::uint32_t settled = 1u << 31;  // flag: every target of the bucket has its start's answer
    std::vector<std::uint32_t> start_;  // per bucket of u: where the scan starts, and the flag
};
}  // namespace detail

class TabulatedPhase : public SampledByDirection<TabulatedPhase> {
public:
    /// angle_deg strictly increasing in [0, 180] (degrees), value > 0 (1/sr, any scale),
    /// at least 2 nodes. power_law_exponent k (< 2) sets p = p_0 (theta_0/psi)^k below the
    /// first node (which must then be above 0); without it p is constant there.
    TabulatedPhase(const std::vector<double>& angle_deg, const std::vector<double>& value,
                   TabulatedConvention convention = TabulatedConvention::trapezoid,
                   std::optional<double> power_law_exponent = std::nullopt, std::string name = "tabulated")
        : convention_(convention), k_(power_law_exponent.value_or(0.0)), name_(std::move(name)) {
        validate(angle_deg, value, power_law_exponent);
        for (std::size_t i = 0; i < angle_deg.size(); ++i) {
            theta_.push_back(angle_deg[i] / 180.0 * pi);  // 180 deg -> pi exactly
            p_.push_back(value[i]);
        }
        if (theta_.back() < pi) {
            theta_.push_back(pi);
            p_.push_back(value.back());
        }
        for (std::size_t i = 0; i < theta_.size(); ++i) {
            sin_.push_back(detail::sin_angle(theta_[i]));
            cos_.push_back(std::cos(theta_[i]));
            f_.push_back(two_pi * p_[i] * sin_.back());
        }
        for (std::size_t i = 0; i + 1 < theta_.size(); ++i) {
            slope_.push_back((f_[i + 1] - f_[i]) / width(i));
            p_slope_.push_back((p_[i + 1] - p_[i]) / width(i));
        }
        cum_.push_back(power_mass(theta_[0]));
        for (std::size_t i = 0; i + 1 < theta_.size(); ++i) cum_.push_back(cum_.back() + segment_mass(i, width(i)));
        raw_ = cum_.back();
        require(std::isfinite(raw_) && raw_ > 0.0, "table integral", raw_,
                "the table has no positive, finite integral under this convention");
        if (convention_ == TabulatedConvention::linear_p) tabulate_sub_nodes();
        guide_ = detail::CumulativeGuide(guided());
        for (std::size_t i = 0; i + 1 < theta_.size(); ++i) narrow_segments_ = narrow_segments_ && width(i) < 0.2;
#if SECCHI_HAS_LANES
        float_inverse_ = std::make_shared<const FloatInverseTable>(*this);  // (sample_direction and eval are ready)
#endif
    }

    /// p(psi) in 1/sr, normalised. At mu = 1 inside the power law (where p is infinite for
    /// k > 0) it returns the mean density over the cap psi < 2^-26.5 of directions whose
    /// cosine rounds to 1, so that eval/pdf stay finite for every sample.
    double eval(double cos_psi) const {
        const double mu = std::clamp(cos_psi, -1.0, 1.0);
        const double psi = std::acos(mu);
        if (psi < theta_[0]) {
            if (mu >= 1.0) return power_mass(cap_psi) / (pi * cap_psi * cap_psi) / raw_;
            return p_[0] * std::pow(theta_[0] / psi, k_) * detail::x_over_sin(psi) / raw_;
        }
        return segment_density(segment_of(psi), psi, mu) / raw_;
    }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// u1 picks the segment from the exact cumulative integral and the angle within it by
    /// inverting that segment's CDF; phi = 2 pi u2. The pdf is that of the returned direction,
    /// pdf(cos psi) (at small psi the rounding of cos psi moves the angle by ~1e-16/psi).
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density).
    PhaseDirection sample_direction(double u1, double u2) const {
        const double target = u1 * raw_;
        double psi;
        if (target < cum_[0]) {
            psi = theta_[0] * std::pow(target / cum_[0], 1.0 / (2.0 - k_));
        } else if (convention_ == TabulatedConvention::trapezoid) {
            const std::size_t i = guide_.find(cum_, u1, target);
            psi = std::min(theta_[i] + linear_density_root(f_[i], slope_[i], target - cum_[i], width(i), 0.0), theta_[i + 1]);
        } else {
            const std::size_t j = guide_.find(sub_cum_, u1, target), i = j / sub_nodes;
            return {newton_segment(i, j % sub_nodes, target - cum_[i]).cos_psi, two_pi * u2};
        }
        return {std::cos(psi), two_pi * u2};
    }

#if SECCHI_HAS_LANES
    /// sample_direction's cos psi for a vector of uniforms u1 (photons in double lanes,
    /// transport/lane_tracer.hpp). The segment search (the guide's scan) and the segment's
    /// root run in the vectors, with the same operations as sample_direction, and so does the
    /// power law below the first node (by log and exp); a linear_p table with a segment wider
    /// than 0.2 rad (beyond angles()' series) goes through sample_direction lane by lane.
    /// cos psi as sample_direction's from a linear_p root, else by sin_cos rather than
    /// std::cos: within a few ulp of sample_direction (tests/test_lane_tracer.cpp).
    template <class Lanes>
        requires std::same_as<Lanes, lanes::Reals>
    Lanes cos_psi(const Lanes& u1) const {
        using lanes::Reals, lanes::lookup, lanes::stdx::max, lanes::stdx::min;
        if (convention_ == TabulatedConvention::linear_p && !narrow_segments_)
            return Reals([&](auto l) { return sample_direction(u1[l], 0.0).cos_psi; });
        const Reals target = u1 * raw_;
        Reals psi, cosine(0.0);
        auto from_psi = target == target;  // the lanes whose cos psi is still to be taken of psi
        if (convention_ == TabulatedConvention::trapezoid) {
            const Reals i = guide_.find(cum_, u1, target);
            const Reals theta = lookup(theta_, i), theta_next = lookup(theta_, i + 1.0);
            const Reals d = linear_density_root(lookup(f_, i), lookup(slope_, i), target - lookup(cum_, i),
                                                theta_next - theta, Reals(0.0));
            psi = min(theta + d, theta_next);
        } else {
            const Reals j = guide_.find(sub_cum_, u1, target);      // sub-interval j = sub_nodes i + k
            const Reals i = lanes::stdx::floor(j * (1.0 / sub_nodes));  // exact: sub_nodes is a power of 2
            const auto segment = lanes::lookup_rows(segment_rows_, i);
            const LanesRoot root = newton_segment_lanes(segment, i, j - double(sub_nodes) * i, target - segment[segment_cum]);
            psi = min(segment[segment_theta] + root.d, segment[segment_theta_next]);
            cosine = root.cos_psi;
            from_psi = !root.has_cos;
        }
        if (const auto power = target < cum_[0]; any_of(power)) {
            // The power law below the first node: psi = theta_0 (target / cum_0)^(1 / (2 - k)), as
            // theta_0 exp(ln(target / cum_0) / (2 - k)) (lanes::log and lanes::exp, 2 ulp each:
            // psi within a few tens of ulp of std::pow's wherever cos psi is not 1, and so cos
            // psi, with psi < 0.002 rad, within 1e-19 of it). The ratio is kept normal and the
            // exponent above -700: there psi < 1e-300, whose cos is 1, as for std::pow's 0 at
            // target = 0.
            const Reals ratio = max(target / cum_[0], Reals(std::numeric_limits<double>::min()));
            const Reals x = max(lanes::log(ratio) / (2.0 - k_), Reals(-700.0));
            where(power, psi) = theta_[0] * lanes::exp(x);
            from_psi = from_psi || power;
        }
        if (any_of(from_psi)) where(from_psi, cosine) = sin_cos(psi).cos;
        return cosine;
    }

    /// sample_direction's cos psi for a vector of float uniforms (photons in float lanes): from
    /// the table of the inverse (float_inverse_table.hpp; within 2^-23 of sample_direction's at
    /// the same u), or, where the table is refused, from cos_psi in double lanes.
    template <class Lanes>
        requires std::same_as<Lanes, lanes::Floats>
    Lanes cos_psi(const Lanes& u1) const {
        if (float_inverse_->usable()) return float_inverse_->cos_psi(u1);
        return lanes::through_doubles(u1, [&](const lanes::Reals& u) { return cos_psi(u); });
    }
    /// The float lanes' table of the inverse CDF.
    [[nodiscard]] const FloatInverseTable& float_inverse() const { return *float_inverse_; }
#endif

    /// Probability that the scattering angle is below psi (radians), exact.
    double cumulative(double psi) const {
        if (psi <= theta_[0]) return power_mass(std::max(psi, 0.0)) / raw_;
        const std::size_t i = segment_of(std::min(psi, pi));
        return (cum_[i] + segment_mass(i, std::min(psi, pi) - theta_[i])) / raw_;
    }

    /// The uniforms u1 whose sample_direction scatters backward (psi > 90 deg): [F(90 deg), 1).
    std::pair<double, double> backward_uniforms() const { return {cumulative(0.5 * pi), 1.0}; }

    /// 2 pi int p sin dpsi of the table as given, before normalisation (M93: 1.002 for Petzold).
    double raw_integral() const { return raw_; }
    /// The node angles (radians, including an added 180 deg node): kinks of the density.
    std::vector<double> breakpoints() const { return theta_; }
    TabulatedConvention convention() const { return convention_; }
    double power_law_exponent() const { return k_; }
    std::string name() const { return name_; }

private:
    static constexpr double cap_psi = 1.0536712127723509e-08;  // 2^-26.5: cos(psi) rounds to 1 below

    static void validate(const std::vector<double>& a, const std::vector<double>& v, std::optional<double> k) {
        require(a.size() >= 2, "angle_deg.size()", a.size(), "a table needs at least 2 nodes");
        require(v.size() == a.size(), "value.size()", v.size(), "must equal angle_deg.size()");
        for (std::size_t i = 0; i < a.size(); ++i) {
            require(std::isfinite(a[i]) && a[i] >= 0.0 && a[i] <= 180.0, indexed_name("angle_deg", i), a[i],
                    "angles must lie in [0, 180] degrees");
            require(i == 0 || a[i] > a[i - 1], indexed_name("angle_deg", i), a[i], "angles must be strictly increasing");
            require(std::isfinite(v[i]) && v[i] > 0.0, indexed_name("value", i), v[i], "values must be positive and finite");
        }
        if (k) {
            require(std::isfinite(*k) && *k < 2.0, "power_law_exponent", *k, "must be finite and below 2");
            require(a[0] > 0.0, "power_law_exponent", *k, "needs a first node above 0 degrees");
        }
    }

    double width(std::size_t i) const { return theta_[i + 1] - theta_[i]; }

    /// Segment i with theta_i <= psi < theta_{i+1} (psi >= theta_0).
    std::size_t segment_of(double psi) const {
        const auto it = std::upper_bound(theta_.begin(), theta_.end(), psi);
        return std::min<std::size_t>(static_cast<std::size_t>(it - theta_.begin()) - 1, theta_.size() - 2);
    }

    /// Unnormalised mass of the power-law part below psi <= theta_0:
    /// int_0^psi 2 pi p_0 theta_0^k x^{1-k} dx.
    double power_mass(double psi) const {
        if (theta_[0] <= 0.0) return 0.0;
        return two_pi * p_[0] * theta_[0] * theta_[0] / (2.0 - k_) * std::pow(psi / theta_[0], 2.0 - k_);
    }

    /// Unnormalised mass in [theta_i, theta_i + d].
    double segment_mass(std::size_t i, double d) const {
        if (convention_ == TabulatedConvention::trapezoid) return d * (f_[i] + 0.5 * slope_[i] * d);
        return linear_p_mass(i, d, angles(i, d));
    }

    /// sin(d/2), sin d and the sines and cosines of theta_i + d/2 and psi = theta_i + d, from
    /// one sine and cosine of d/2 and the node's own, sin_i and cos_i (angle addition). For a
    /// double, or a vector of them (photons in lanes: there every d/2 must lie below 0.1).
    template <class Real>
    struct SegmentAngles {
        Real sin_half, sin_d, sin_mid, sin_psi, cos_psi;
    };
    template <class Real>
    static SegmentAngles<Real> angles(const Real& sin_i, const Real& cos_i, const Real& d) {
        const Real x = 0.5 * d, x2 = x * x;
        // Taylor series on [0, 0.1): sin to x^13, cos to x^14 (truncation below 0.1^15 / 15! = 8e-28).
        const auto series = [&] {
            return std::pair{x + x * x2 * (-1.0 / 6 + x2 * (1.0 / 120 + x2 * (-1.0 / 5040 + x2 * (1.0 / 362880 + x2 * (-1.0 / 39916800 + x2 * (1.0 / 6227020800.0)))))),
                             1.0 - 0.5 * x2 + x2 * x2 * (1.0 / 24 + x2 * (-1.0 / 720 + x2 * (1.0 / 40320 + x2 * (-1.0 / 3628800 + x2 * (1.0 / 479001600.0 + x2 * (-1.0 / 87178291200.0))))))};
        };
        Real sh, ch;
        if constexpr (std::is_floating_point_v<Real>) {
            if (x < 0.1) {
                std::tie(sh, ch) = series();
            } else {
                sh = std::sin(x);
                ch = std::cos(x);
            }
        } else {
            std::tie(sh, ch) = series();
        }
        const Real sd = 2.0 * sh * ch, cd = 1.0 - 2.0 * sh * sh;
        return {sh, sd, sin_i * ch + cos_i * sh, sin_i * cd + cos_i * sd, cos_i * cd - sin_i * sd};
    }
    SegmentAngles<double> angles(std::size_t i, double d) const { return angles(sin_[i], cos_[i], d); }

    /// linear_p: int (p_i + t x) sin(theta_i + x) dx over [0, d], written without cancellation:
    /// p_i (cos theta_i - cos psi) + t (sin psi (1 - cos d) - cos psi (d - sin d)), with
    /// cos theta_i - cos psi = 2 sin(theta_i + d/2) sin(d/2) and 1 - cos d = 2 sin^2(d/2).
    template <class Real>
    static Real linear_p_mass(const Real& p_i, const Real& t, const Real& d, const SegmentAngles<Real>& a) {
        const Real x_minus_sin = detail::x_minus_sin(d, a.sin_d);
        return two_pi * (p_i * 2.0 * a.sin_mid * a.sin_half + t * (a.sin_psi * 2.0 * a.sin_half * a.sin_half - a.cos_psi * x_minus_sin));
    }
    double linear_p_mass(std::size_t i, double d, const SegmentAngles<double>& a) const {
        return linear_p_mass(p_[i], p_slope_[i], d, a);
    }

    /// Newton's step r / dens toward the root of mass - m (r: the residual, dens: the mass's
    /// derivative); where dens <= 0, `bracket` (hi - lo: never taken as converged).
    template <class Real>
    static Real newton_step(const Real& r, const Real& dens, const Real& bracket) {
        return select(dens > 0.0, r / dens, bracket);
    }
    /// Halley's step from Newton's: newton / (1 - q), q = newton slope / (2 dens) (slope: the
    /// mass's second derivative), where the quadratic model holds (|q| <= 1/2), else Newton's.
    /// Where dens <= 0 it leaves the bracket (and the iteration bisects).
    template <class Real>
    static Real halley_step(const Real& newton, const Real& dens, const Real& slope) {
        using std::abs;
        const Real q = select(dens > 0.0, 0.5 * newton * slope / dens, Real(1.0));
        return select(abs(q) <= 0.5, newton / (1.0 - q), newton);
    }

    /// Unnormalised density per sr at psi = acos(mu) in segment i. Where sin(psi) -> 0 (a
    /// node at 0 or at pi) the trapezoid f vanishes too and the ratio is taken in the limit
    /// (at pi with pi - psi = acos(-mu), accurate there).
    double segment_density(std::size_t i, double psi, double mu) const {
        const double h = width(i), dl = psi - theta_[i], dr = theta_[i + 1] - psi;
        if (convention_ == TabulatedConvention::linear_p) return (p_[i] * dr + p_[i + 1] * dl) / h;
        if (theta_[i] == 0.0) return f_[i + 1] / (two_pi * h) * detail::x_over_sin(psi);
        if (theta_[i + 1] == pi) return f_[i] / (two_pi * h) * detail::x_over_sin(std::acos(-mu));
        return (f_[i] * dr + f_[i + 1] * dl) / (h * two_pi * std::sin(psi));
    }

    /// Where the mass m is reached from the start of an interval of width w over which the
    /// density is linear, f0 at the start with slope s: f0 d + s d^2 / 2 = m, the root written
    /// without cancellation, d = 2 m / (f0 + sqrt(f0^2 + 2 s m)) (also for s <= 0 or f0 = 0),
    /// clamped to [0, w]; `none` where the denominator vanishes. For a double, or a vector of them.
    template <class Real>
    static Real linear_density_root(const Real& f0, const Real& s, const Real& m, const Real& w, const Real& none) {
        using std::max, std::min, std::sqrt;
        const Real den = f0 + sqrt(max(Real(0.0), f0 * f0 + 2.0 * s * m));
        return select(den > 0.0, min(max(2.0 * m / den, Real(0.0)), w), none);
    }

    /// The cumulative masses the guide searches: per segment (trapezoid), or per sub-interval
    /// (linear_p: segment i's sub-interval k is entry sub_nodes i + k).
    [[nodiscard]] const std::vector<double>& guided() const {
        return convention_ == TabulatedConvention::linear_p ? sub_cum_ : cum_;
    }

    /// linear_p: the exact mass and density (and its inverse) at sub_nodes equal steps across
    /// each segment, and per sub-interval the Newton bound (newton_bound()) and the inverse of
    /// its mass where first_guess interpolates (else 0), in one row per sub-interval
    /// (sub_rows_); the mass below each sub-interval, cum_i + mass_k, with the total last
    /// (sub_cum_, the guide's table); each segment's own values in a row (segment_rows_).
    void tabulate_sub_nodes() {
        for (std::size_t i = 0; i + 1 < theta_.size(); ++i) {
            const double h = width(i);
            std::array<double, sub_nodes + 1> mass{}, density{}, inverse_density{};
            for (int k = 0; k <= sub_nodes; ++k) {
                const double x = sub_node(h, double(k));
                mass[k] = k == 0 ? 0.0 : linear_p_mass(i, x, angles(i, x));
                const double sin_psi = k == sub_nodes ? sin_[i + 1] : detail::sin_angle(theta_[i] + x);
                density[k] = two_pi * (p_[i] + p_slope_[i] * x) * sin_psi;
                inverse_density[k] = density[k] > 0.0 ? 1.0 / density[k] : 0.0;
            }
            for (int k = 0; k < sub_nodes; ++k) {
                const double dm = mass[k + 1] - mass[k];
                const bool hermite = density[k] > 0.0 && density[k + 1] > 0.0 && dm > 0.0;
                Row8 row;
                row.v[sub_mass0] = mass[k];
                row.v[sub_mass1] = mass[k + 1];
                row.v[sub_inverse_mass] = hermite ? 1.0 / dm : 0.0;
                row.v[sub_inverse_density0] = inverse_density[k];
                row.v[sub_inverse_density1] = inverse_density[k + 1];
                row.v[sub_bound] = newton_bound(i, sub_node(h, double(k)), sub_node(h, k + 1.0));
                row.v[sub_density0] = density[k];
                row.v[sub_density1] = density[k + 1];
                sub_rows_.push_back(row);
                sub_cum_.push_back(cum_[i] + mass[k]);
            }
            segment_rows_.push_back({{theta_[i], theta_[i + 1], cum_[i], p_[i], p_slope_[i], sin_[i], cos_[i], 0.0}});
        }
        sub_cum_.push_back(cum_.back());
    }

    /// Offset of sub-node k (0 ... sub_nodes) in a segment of width h; the last is h exactly.
    /// For a double, or a vector of them.
    template <class Real>
    static Real sub_node(const Real& h, const Real& k) {
        return select(k == double(sub_nodes), h, h * k / double(sub_nodes));
    }

    /// For the density f(x) = 2 pi (p_i + t x) sin(theta_i + x) of segment i over [xa, xb]:
    /// c = max|f'| / (2 min f^2), so that one Newton step from d, with d and the root both in
    /// [xa, xb], lands within c r^2 / f(d) of the root (r: the mass's residual at d). Taylor's
    /// theorem: 0 = r + f(d) (root - d) + f'(xi) (root - d)^2 / 2, and |root - d| <= |r| / min f
    /// (mean value theorem). The bounds hold on the whole interval: p is linear (its extremes
    /// at the ends), sin is concave on [0, pi] (its minimum at an end, its maximum at an end or
    /// pi/2), |cos| is largest at an end. Infinite where min f = 0 (a node at 0 or 180 deg).
    double newton_bound(std::size_t i, double xa, double xb) const {
        const double t = p_slope_[i];
        const double pa = p_[i] + t * xa, pb = p_[i] + t * xb;
        const double psi_a = theta_[i] + xa, psi_b = theta_[i] + xb;
        const double sa = detail::sin_angle(std::min(psi_a, pi)), sb = detail::sin_angle(std::min(psi_b, pi));
        const double sin_max = psi_a <= 0.5 * pi && psi_b >= 0.5 * pi ? 1.0 : std::max(sa, sb);
        const double cos_max = std::max(std::abs(std::cos(psi_a)), std::abs(std::cos(psi_b)));
        // Rounding margins (a relative 1e-9) keep the bound on the safe side of its own arithmetic.
        const double f_min = two_pi * std::min(pa, pb) * std::min(sa, sb) * (1.0 - 1e-9);
        const double slope_max = two_pi * (std::abs(t) * sin_max + std::max(pa, pb) * cos_max) * (1.0 + 1e-9);
        return f_min > 0.0 ? slope_max / (2.0 * f_min * f_min) : std::numeric_limits<double>::infinity();
    }

    /// An index into the tables: an integer for a double, the lanes' indices as doubles for a
    /// vector of them.
    template <class Real>
    using IndexOf = std::conditional_t<std::is_floating_point_v<Real>, std::size_t, Real>;

    /// Row j of a table: for an integer index, or per lane for a vector of them (each column
    /// a vector).
    template <class Index>
    static decltype(auto) row_at(const std::vector<Row8>& rows, const Index& j) {
#if SECCHI_HAS_LANES
        if constexpr (!std::is_integral_v<Index>) {
            return lanes::lookup_rows(rows, j);
        } else
#endif
        {
            return (rows[j].v);  // a reference
        }
    }

    /// linear_p: the first guess for the mass m in segment i (width h), with the sub-interval
    /// [x0, x1] that holds the root and that sub-interval's Newton bound.
    template <class Real>
    struct FirstGuess {
        Real d, x0, x1, bound;
    };

    /// In the sub-interval k the guide found (the last with cum_i + mass_k <= the target: the
    /// one that holds the root, except where rounding of that sum puts the target within an ulp
    /// of a sub-node's mass, where the neighbour's guess is as close), the inverse of the mass,
    /// x(mass), by cubic Hermite interpolation between its sub-nodes from their offsets and
    /// slopes dx/dmass = 1/f (exact at both ends; off by about 1e-7 of the width with 16
    /// sub-nodes on Petzold's table), with the inverses tabulated. Where a sub-node's density
    /// is 0 (a node at 0 or 180 deg) the guess is the root for a density linear between the
    /// two. For a double (segment i, sub-interval k), or a vector of them (indices as doubles).
    template <class Real>
    FirstGuess<Real> first_guess(const IndexOf<Real>& i, const IndexOf<Real>& k, const Real& h, const Real& m) const {
        using std::max, std::min;
        using Index = IndexOf<Real>;
        const auto& row = row_at(sub_rows_, i * Index(sub_nodes) + k);
        const Real x0 = sub_node(h, static_cast<Real>(k)), x1 = sub_node(h, static_cast<Real>(k + Index(1)));
        const Real m0 = row[sub_mass0], dm = row[sub_mass1] - m0;
        const Real inverse_dm = row[sub_inverse_mass];
        const auto hermite = inverse_dm > 0.0;  // both densities and the mass positive
        const Real s = (m - m0) * inverse_dm;
        const Real inv0 = row[sub_inverse_density0], inv1 = row[sub_inverse_density1];
        const Real interpolated = x0 + s * s * (3.0 - 2.0 * s) * (x1 - x0) + dm * s * (1.0 - s) * ((1.0 - s) * inv0 - s * inv1);
        Real d = min(max(interpolated, x0), x1);
        bool every_hermite;
        if constexpr (std::is_floating_point_v<Real>) {
            every_hermite = hermite;
        } else {
            every_hermite = all_of(hermite);
        }
        if (!every_hermite) {
            const Real f0 = row[sub_density0], f1 = row[sub_density1];
            d = select(hermite, d, x0 + linear_density_root(f0, (f1 - f0) / (x1 - x0), m - m0, x1 - x0, 0.5 * (x1 - x0)));
        }
        return {d, x0, x1, row[sub_bound]};
    }

    /// Whether d - newton (Newton's step from d, residual r, density dens > 0) lies within
    /// 1e-12 of the width h of the root: by the guess's sub-interval bound (bound r^2 / dens,
    /// newton_bound()) where d lies in that sub-interval, else when Newton's step itself is below
    /// 1e-12 h (near the root, the distance to it). For a double, or a vector of them.
    template <class Real>
    static auto converged(const FirstGuess<Real>& g, const Real& d, const Real& r, const Real& dens, const Real& newton,
                          const Real& h) {
        using std::abs;
        const auto inside = d >= g.x0 && d <= g.x1 && dens > 0.0;
        return (inside && g.bound * r * r <= 1e-12 * h * dens) || abs(newton) <= 1e-12 * h;
    }

    /// cos(x - delta) from the cosine and sine at x (angles()' cos_psi and sin_psi) for the
    /// last Newton step delta, |delta| < small_step: cos x cos delta + sin x sin delta with
    /// cos delta = 1 - delta^2/2 (1 - delta^2/12) and sin delta = delta (1 - delta^2/6)
    /// (truncation below 1e-22). For a double, or a vector of them.
    static constexpr double small_step = 1e-4;
    template <class Real>
    static Real cos_after_step(const SegmentAngles<Real>& a, const Real& delta) {
        const Real delta2 = delta * delta;
        return a.cos_psi * (1.0 - 0.5 * delta2 * (1.0 - delta2 / 12.0)) + a.sin_psi * (delta * (1.0 - delta2 / 6.0));
    }

    /// The root d of a segment's mass and cos psi = cos(theta_i + d).
    struct SegmentRoot {
        double d, cos_psi;
    };

    /// Safeguarded Halley iteration (bisection fallback) on segment_mass(i, d) = m, to 1e-12
    /// of the width. It starts from first_guess, usually close enough for the first Newton
    /// step to end it (converged()); the mass's first and second derivatives, 2 pi (p_i + t d)
    /// sin psi and 2 pi (t sin psi + (p_i + t d) cos psi), come with the mass from one sine and
    /// cosine of d/2, and so does cos psi of the root (cos_after_step(); std::cos where the
    /// last step was not small or the iteration ended by bisection).
    SegmentRoot newton_segment(std::size_t i, std::size_t k, double m) const {
        const double h = width(i), t = p_slope_[i];
        const FirstGuess<double> g = first_guess(i, k, h, m);
        double lo = 0.0, hi = h, d = g.d;
        const auto root_at = [&](double root) { return SegmentRoot{root, std::cos(std::min(theta_[i] + root, theta_[i + 1]))}; };
        for (int iter = 0; iter < 200; ++iter) {
            const SegmentAngles<double> a = angles(i, d);
            const double r = linear_p_mass(i, d, a) - m;
            (r > 0.0 ? hi : lo) = d;
            const double p = p_[i] + t * d, dens = two_pi * p * a.sin_psi;
            const double newton = newton_step(r, dens, hi - lo);
            if (converged(g, d, r, dens, newton, h)) {
                const double root = std::clamp(d - newton, 0.0, h), delta = d - root;
                if (std::abs(delta) < small_step) return {root, cos_after_step(a, delta)};
                return root_at(root);
            }
            d -= halley_step(newton, dens, two_pi * (t * a.sin_psi + p * a.cos_psi));
            // Steps leaving the bracket bisect.
            if (!(d > lo && d < hi)) d = 0.5 * (lo + hi);
            if (hi - lo <= 1e-12 * h) break;
        }
        return root_at(d);
    }

#if SECCHI_HAS_LANES
    /// newton_segment per lane (segment indices i as doubles): the same first guess and the
    /// same safeguarded Halley steps, a lane keeping its root from the step at which its own
    /// iteration ends, and its cos psi where newton_segment takes it from the last step (has_cos).
    /// Needs narrow_segments_ (angles()' series).
    struct LanesRoot {
        lanes::Reals d, cos_psi;
        lanes::Mask has_cos;
    };
    LanesRoot newton_segment_lanes(const std::array<lanes::Reals, 8>& segment, const lanes::Reals& i,
                                   const lanes::Reals& k, const lanes::Reals& m) const {
        using lanes::Reals, lanes::stdx::max, lanes::stdx::min;
        const Reals h = segment[segment_theta_next] - segment[segment_theta];
        const Reals p_i = segment[segment_p], t = segment[segment_p_slope];
        const Reals sin_i = segment[segment_sin], cos_i = segment[segment_cos];
        const FirstGuess<Reals> g = first_guess(i, k, h, m);
        Reals d = g.d;
        Reals lo(0.0), hi = h, root = d, cosine(0.0);
        auto open = d == d;  // lanes still iterating
        auto has_cos = !open;
        for (int iter = 0; iter < 200 && any_of(open); ++iter) {
            const SegmentAngles<Reals> a = angles(sin_i, cos_i, d);
            const Reals r = linear_p_mass(p_i, t, d, a) - m;
            where(open && r > 0.0, hi) = d;
            where(open && !(r > 0.0), lo) = d;
            const Reals p = p_i + t * d, dens = two_pi * p * a.sin_psi;
            const Reals newton = newton_step(r, dens, hi - lo);
            const auto done = open && converged(g, d, r, dens, newton, h);
            where(done, root) = min(max(d - newton, Reals(0.0)), h);
            const Reals delta = d - root;
            const auto small = done && abs(delta) < small_step;
            where(small, cosine) = cos_after_step(a, delta);
            has_cos = has_cos || small;
            open = open && !done;
            if (none_of(open)) break;
            Reals next = d - halley_step(newton, dens, two_pi * (t * a.sin_psi + p * a.cos_psi));
            where(!(next > lo && next < hi), next) = 0.5 * (lo + hi);
            where(open, d) = next;
            const auto bisected = open && hi - lo <= 1e-12 * h;
            where(bisected, root) = d;
            open = open && !bisected;
        }
        where(open, root) = d;
        return {root, cosine, has_cos};
    }
#endif

    TabulatedConvention convention_;
    double k_;
    std::string name_;
    std::vector<double> theta_, p_, f_, cum_;  // nodes (rad), values, 2 pi p sin, mass below node
    std::vector<double> sin_, cos_;            // sin and cos of the nodes (sin exactly 0 at 0 and pi)
    static constexpr int sub_nodes = 16;       // linear_p: sub-segments per segment for first_guess
    static_assert(std::has_single_bit(static_cast<unsigned>(sub_nodes)), "a sub-interval's segment by an exact product");
    // linear_p, per sub-interval: the mass from its segment's start and the density (and its
    // inverse, 0 where 0) at both ends, the inverse of its mass where first_guess interpolates
    // (else 0) and its newton_bound().
    enum SubColumn { sub_mass0, sub_mass1, sub_inverse_mass, sub_inverse_density0, sub_inverse_density1, sub_bound, sub_density0, sub_density1 };
    std::vector<Row8> sub_rows_;
    std::vector<double> sub_cum_;                 // linear_p: mass below each sub-interval, then the total
    // linear_p, per segment: theta_i, theta_{i+1}, cum_i, p_i, p's slope, sin_i, cos_i.
    enum SegmentColumn { segment_theta, segment_theta_next, segment_cum, segment_p, segment_p_slope, segment_sin, segment_cos };
    std::vector<Row8> segment_rows_;
    bool narrow_segments_ = true;                 // every segment narrower than 0.2 rad
    std::vector<double> slope_;                // per segment: f's slope (trapezoid)
    std::vector<double> p_slope_;              // per segment: p's slope (linear_p)
    detail::CumulativeGuide guide_;            // search over guided() for sample()
    double raw_ = 0.0;
#if SECCHI_HAS_LANES
    std::shared_ptr<const FloatInverseTable> float_inverse_;  // float lanes' inverse CDF, shared by copies
#endif
};

}  // namespace secchi
