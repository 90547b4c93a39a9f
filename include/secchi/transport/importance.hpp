#pragma once
// Depth importance: geometric splitting and Russian roulette between depth levels, the
// standard variance reduction for deep penetration (Spanier & Gelbard 1969; Lux & Koblinger
// 1991, ch. 7), so that deep detectors and the deep photon map keep photons. Below it, two
// directional importances for the scattering direction: BackscatterBias (the light going back
// up, for the upwelling irradiances) and UpwardImportance (the light travelling straight up,
// for the nadir radiance from the map).
//
// Importance I(z) = 2^L(z), with the level
//     L(z) = floor( tau_a(z) / (mu_i ln 2) )                          for z <= z_max,
//     L(z) = L(z_max) - floor( (tau_a(z) - tau_a(z_max)) / (mu_i ln 2) )  below,
// tau_a(z) = int_0^z a dz': I grows like exp(tau_a / mu_i) down to z_max, like the inverse of
// the diffuse light, whose weight decays as exp(-tau_a / mu) along paths of mean cosine mu
// (continuous absorption), and falls again at the same rate below z_max, where nothing is
// measured: photons that sink below the deepest detector are rouletted instead of being
// followed, split, through the deep water that only returns a little light.
//  - A photon of weight w moving into a deeper level (L -> L + k) is split into 2^k photons of
//    weight w / 2^k; moving up (L -> L - k) it survives Russian roulette with probability
//    2^-k at weight w 2^k. Expected weight is conserved: every detector stays unbiased.
//  - The photon map stores a scattering event with probability w I(z) (copies for w I > 1),
//    and a stored photon carries the flux Phi / I(z): expected stored flux w Phi, as
//    without importance, but with I(z) times more photons at depth.
//  - Roulette for low weights acts on w I (the photon's weight relative to its level).
// mu_i = 0 turns it off (I = 1 everywhere): the default, and what problems 1, 2, 6 use.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

/// Backscatter bias, a directional importance for the light going back (up, for the
/// downwelling light; Spanier & Gelbard 1969, importance sampling of the collision kernel): a
/// share eps of the scattering events draws its angle from the phase function's backward part
/// only, so that more photons turn back than the phase function alone sends, and the light
/// going up at depth (Eu, Eou, the map's upwelling events) is carried by more photons.
/// The phase function samples by a monotone inverse CDF, and the uniforms [a, b) of it
/// scatter backward (b - a = B, the backward fraction: backward_uniforms()). The biased draw is
/// importance sampling of that uniform: its density is q(v) = (1 - eps) + eps 1[a <= v < b] / B
/// instead of 1, and the photon's weight is multiplied by 1 / q(v): 1 / (1 - eps) for the
/// forward draws, 1 / (1 - eps + eps / B) for the backward ones. Every expectation is unchanged
/// whatever eps and [a, b). One uniform u serves both choices: u < eps picks the backward
/// part, with u / eps its uniform mapped onto [a, b); otherwise (u - eps) / (1 - eps).
/// In Real = double (PhotonTracer, LaneTracer's double lanes) or float (the float lanes): eps,
/// a and b are rounded to Real and the weights computed from the rounded values, so that they
/// are 1 / q of the draws the lanes make. draw() takes a Real or a SIMD vector of Reals.
template <class Real>
class BackscatterBiasOf {
public:
    BackscatterBiasOf() = default;  ///< off: draw(u) = {u, 1}
    /// share: eps in [0, 1); [begin, end): the backward uniforms, 0 <= begin < end <= 1.
    BackscatterBiasOf(double share, double begin, double end) : given_{share, begin, end} {
        require(std::isfinite(share) && share >= 0.0 && share < 1.0, "backscatter bias", share, "must be in [0, 1) (0 = off)");
        require(begin >= 0.0 && end <= 1.0 && end > begin, "backward fraction of the phase function", end - begin,
                "must be positive: the phase function sends nothing backward");
        share_ = static_cast<Real>(share);
        begin_ = static_cast<Real>(begin);
        end_ = static_cast<Real>(end);
        require(end_ > begin_, "backward fraction of the phase function", end - begin,
                "is below the rounding of its bounds in the lanes' type");
        last_backward_ = std::nextafter(end_, Real(0));
        const double eps = share_, fraction = static_cast<double>(end_) - static_cast<double>(begin_);
        forward_weight_ = static_cast<Real>(1.0 / (1.0 - eps));
        backward_weight_ = static_cast<Real>(1.0 / (1.0 - eps + eps / fraction));
    }

    [[nodiscard]] bool enabled() const { return share_ > Real(0); }
    /// The same bias drawn in another type (the float lanes').
    template <class Other>
    [[nodiscard]] BackscatterBiasOf<Other> in() const {
        return enabled() ? BackscatterBiasOf<Other>(given_[0], given_[1], given_[2]) : BackscatterBiasOf<Other>{};
    }

    template <class V>
    struct DrawOf {
        V u;       ///< the uniform for the phase function's inverse CDF
        V weight;  ///< the factor on the photon's weight, 1 / q(u)
    };
    using Draw = DrawOf<Real>;
    template <class V>
    [[nodiscard]] SECCHI_KERNEL DrawOf<V> draw(const V& u) const {
        using std::min;
        if (share_ == Real(0)) return {u, V(Real(1))};
        const V v = select(u < share_, min(V(begin_ + (end_ - begin_) * (u / share_)), V(last_backward_)),
                           V((u - share_) / (Real(1) - share_)));
        return {v, select(v >= begin_ && v < end_, V(backward_weight_), V(forward_weight_))};
    }

private:
    std::array<double, 3> given_{0.0, 0.0, 1.0};  ///< share, begin, end as given
    Real share_ = 0, begin_ = 0, end_ = 1;
    Real last_backward_ = std::nextafter(Real(1), Real(0));  ///< the largest Real below end_
    Real forward_weight_ = 1, backward_weight_ = 1;
};
using BackscatterBias = BackscatterBiasOf<double>;

/// Upward importance, a directional importance for the nadir radiance from the map (Spanier &
/// Gelbard 1969, importance sampling of the collision kernel; as a mixture with the phase
/// function, so that no weight grows by more than 1 / (1 - eps) per event: Hesterberg 1995's
/// defensive importance sampling). Lu at depth is carried by the photons travelling within the
/// phase function's peak about straight up; where the peak is broad and most light absorbed
/// (HG g = 0.9, w0 = 0.2) few photons travel there and the estimate is heavy-tailed
/// (docs/limitations.md).
///  - Sampling: a share eps of the scattering events draws the new direction from a
///    Henyey-Greenstein lobe of asymmetry g about straight up (-z: z is depth),
///    v(mu) = (1 - g^2) / (4 pi (1 + g^2 - 2 g mu)^(3/2)) per steradian, mu the cosine from
///    straight up; the others from the phase function p. The new direction's density is
///    q = (1 - eps) p + eps v, and the photon's weight is multiplied by p / q. The factors
///    compound over a photon's scatterings (p / q = 1 / (1 - eps) away from the lobe), so
///    PhotonTracer draws from the mixture only for a photon whose weight relative to its depth
///    level is at most 1 and from p alone otherwise (the choice depends on the state before
///    the event only): no weight then exceeds 1 / (1 - eps) times its level's, however many
///    times the photon scatters (tests/test_exact_references.cpp, albedo 0.99).
///  - Storage: an event of a photon of weight w arriving with upward cosine mu is stored with
///    probability w D(mu) (copies where that exceeds 1), D(mu) = (1 - eps) + eps 4 pi v(mu),
///    and the record carries Phi / D(mu) (transport/record_flux.hpp): the expected stored flux
///    is w Phi, as without it, with more records of photons travelling up.
/// Every expectation is unchanged for any eps in [0, 1) and g in [0, 1).
class UpwardImportance {
public:
    UpwardImportance() = default;  ///< off: D = 1, no draws from the lobe
    /// share: eps in [0, 1); lobe: g in [0, 1).
    UpwardImportance(double share, double lobe) : share_(checked_share(share)), lobe_(checked_lobe(lobe)) {}

    static double checked_share(double share) {
        require(std::isfinite(share) && share >= 0.0 && share < 1.0, "upward importance", share,
                "must be in [0, 1) (0 = off)");
        return share;
    }
    static double checked_lobe(double lobe) {
        require(std::isfinite(lobe) && lobe >= 0.0 && lobe < 1.0, "upward importance lobe", lobe, "must be in [0, 1)");
        return lobe;
    }

    [[nodiscard]] bool enabled() const { return share_ > 0.0; }
    [[nodiscard]] double share() const { return share_; }
    [[nodiscard]] double lobe() const { return lobe_.g(); }

    /// Whether a scattering event draws its direction from the lobe (u uniform in [0, 1)).
    [[nodiscard]] bool from_lobe(double u) const { return u < share_; }
    /// A direction from the lobe: its cosine from straight up by HG's inverse CDF (u1), its
    /// azimuth 2 pi u2.
    [[nodiscard]] vec3 sample(double u1, double u2) const {
        const double mu = lobe_.cos_psi(u1), s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        const double phi = two_pi * u2;
        return {s * std::cos(phi), s * std::sin(phi), -mu};
    }
    /// The factor p / q on the weight of a photon scattered into a direction of z component dz,
    /// p the phase function's density of that direction (per sr). 1 / (1 - eps + eps v / p),
    /// so that an infinite p (a peak's singular point) gives 1 / (1 - eps).
    [[nodiscard]] double weight(double phase_density, double dz) const {
        if (!enabled()) return 1.0;
        return 1.0 / ((1.0 - share_) + share_ * lobe_.eval(-dz) / phase_density);
    }
    /// The new direction of a photon travelling along `before`, and its weight factor p / q:
    /// from the lobe where u_choice < eps (u_psi, u_phi its uniforms), else turned from
    /// `before` by the phase function's angles, phase_angles(u_psi, u_phi) -> PhaseDirection;
    /// density(cos psi): the phase function's density (per sr) of the new direction.
    struct Scatter {
        vec3 dir;
        double weight;
    };
    template <class PhaseAngles, class Density>
    [[nodiscard]] Scatter scatter(const vec3& before, double u_choice, double u_psi, double u_phi,
                                  PhaseAngles&& phase_angles, Density&& density) const {
        vec3 after;
        if (from_lobe(u_choice)) {
            after = sample(u_psi, u_phi);
        } else {
            const PhaseDirection d = phase_angles(u_psi, u_phi);
            after = rotate_direction(before, d.cos_psi, d.phi);
        }
        return {after, weight(density(std::clamp(glm::dot(before, after), -1.0, 1.0)), after.z)};
    }
    /// D(mu) of a record whose direction of travel has z component dz.
    [[nodiscard]] double storage_factor(double dz) const {
        return enabled() ? (1.0 - share_) + share_ * 4.0 * pi * lobe_.eval(-dz) : 1.0;
    }

private:
    double share_ = 0.0;
    HenyeyGreensteinPhase lobe_{0.0};
};

/// A phase function that names the uniforms of its inverse CDF that scatter backward.
template <class P>
concept BackwardUniforms = requires(const P& p) {
    { p.backward_uniforms() } -> std::convertible_to<std::pair<double, double>>;
};

/// A medium whose scattering angles the backscatter bias can draw: depth-independent, its
/// phase function naming its backward uniforms.
template <class M>
concept BackscatterBiasable = depth_independent<M> && BackwardUniforms<typename M::phase_type>;

struct DepthImportance {
    double cosine = 0.0;     ///< mu_i; 0 = off
    double max_depth = 0.0;  ///< z_max (m): the importance is largest there (the deepest detector)

    [[nodiscard]] bool enabled() const { return cosine > 0.0; }

    void validate() const {
        require(std::isfinite(cosine) && cosine >= 0.0 && cosine <= 1.0, "importance cosine", cosine,
                "must be in [0, 1] (0 = off)");
        require(std::isfinite(max_depth) && max_depth >= 0.0, "importance depth (m)", max_depth, "must be >= 0");
    }
};


/// Depth importance where the caller leaves the choice to the library (slab's default,
/// `--importance-cosine auto`; PlaneParallelConfig::auto_importance): mu_i = 1 down to the
/// deepest detector where the absorption optical depth from the surface to it, tau_a, is at
/// least ln 2, so that photons split at least once on the way down; else none. There the
/// figure of merit 1 / (SE^2 t) of the deep nadir radiance and upwelling irradiances, a run's
/// noisiest entries, was measured to favour it (docs/design-notes.md, "Depth importance by
/// default").
inline constexpr double deep_detector_tau_a = std::numbers::ln2;
template <Medium M>
DepthImportance default_depth_importance(const M& medium, double deepest_detector) {
    const double tau_a = medium.optical_path(Coefficient::absorption, 0.0, 1.0, deepest_detector);
    return tau_a >= deep_detector_tau_a ? DepthImportance{1.0, deepest_detector} : DepthImportance{};
}

/// L(z) for one medium. The depths where the level changes are found once by the medium's
/// exact inverse of the optical depth: where tau_a crosses multiples of mu_i ln 2 above z_max
/// (the level rises by one at each) and below z_max (it falls by one at each). Between two
/// such depths the level is constant, so level(z) is a table entry: the interval holding z is
/// found from a guide of equal depth buckets, each narrower than the closest two boundaries
/// (the interval at the bucket's shallow edge, plus one where the bucket's boundary lies at or
/// above z: one comparison, no branch) instead of a binary search per event; at a boundary
/// the deeper level applies (z >= boundary), as in the formula.
class ImportanceLevels {
public:
    ImportanceLevels() = default;  ///< off: level 0 everywhere
    template <Medium M>
    ImportanceLevels(const DepthImportance& imp, const M& medium) {
        if (!imp.enabled()) return;
        const double step = imp.cosine * std::numbers::ln2;
        const double tau_max = medium.optical_path(Coefficient::absorption, 0.0, 1.0, imp.max_depth);
        // The formula's z <= z_max keeps the rising levels down to z_max: a boundary the
        // inverse rounds to the other side of z_max takes effect at the next double below it.
        const double below_max = std::nextafter(imp.max_depth, std::numeric_limits<double>::infinity());
        int level = 0;
        levels_.push_back(0);
        for (int l = 1; l * step <= tau_max; ++l)  // rising: tau_a(z) = l step, z <= z_max
            add_boundary(std::min(medium.distance_to(Coefficient::absorption, 0.0, 1.0, l * step), below_max), ++level);
        // Falling: tau_a(z) - tau_a(z_max) = l step below z_max.
        for (int l = 1; l < 64; ++l) {
            const double z = imp.max_depth + medium.distance_to(Coefficient::absorption, imp.max_depth, 1.0, l * step);
            if (!std::isfinite(z)) break;
            add_boundary(std::max(z, below_max), --level);
        }
        build_guide();
        enabled_ = true;
    }

    [[nodiscard]] bool enabled() const { return enabled_; }

    /// L(z), for a finite depth z (m).
    [[nodiscard]] int level(double z) const { return enabled_ ? levels_[interval(z)] : 0; }

    /// I(z) = 2^L(z).
    [[nodiscard]] double factor(double z) const { return enabled_ ? factors_[interval(z)] : 1.0; }

    /// The depths [lo, hi) over which the level is z's (L and 2^L there): every depth y with
    /// lo <= y < hi has level(y) == level and factor(y) == factor (lo may be -inf, hi +inf), so
    /// that a caller can keep it and look again only when a depth leaves it.
    struct Span {
        double lo, hi;
        int level;
        double factor;
    };
    [[nodiscard]] Span span(double z) const { return span_at(enabled_ ? interval(z) : 0); }

    /// The spans by index, from the shallowest (index 0) down: index_of(z) is z's (through
    /// the guide, as span(z)), span_at(j) the span itself, and span_count() how many there are.
    [[nodiscard]] std::uint32_t span_count() const { return enabled_ ? count_ + 1 : 1; }
    [[nodiscard]] std::uint32_t index_of(double z) const { return enabled_ ? interval(z) : 0; }
    [[nodiscard]] Span span_at(std::uint32_t j) const {
        constexpr double inf = std::numeric_limits<double>::infinity();
        if (!enabled_) return {-inf, inf, 0, 1.0};
        return {j > 0 ? boundaries_[j - 1] : -inf, boundaries_[j], levels_[j], factors_[j]};
    }

private:
    /// Appends a boundary (in increasing depth; one that coincides with the previous replaces
    /// its level) and the level from it down to the next.
    void add_boundary(double z, int level) {
        if (!boundaries_.empty() && z <= boundaries_.back()) {
            levels_.back() = level;
            return;
        }
        boundaries_.push_back(z);
        levels_.push_back(level);
    }

    /// The guide: buckets of equal depth from the first boundary to the last, narrower than
    /// the closest two boundaries (at most max_buckets; beyond that a bucket may hold several
    /// and exact_interval steps over them), each holding the interval at its shallow edge;
    /// bucket 0, which also takes every depth above the first boundary, the interval above it.
    /// boundaries_ then ends with +inf, so that the boundary after any interval can be read.
    void build_guide() {
        for (int l : levels_) factors_.push_back(std::ldexp(1.0, l));
        count_ = static_cast<std::uint32_t>(boundaries_.size());
        if (count_ > 0) {
            first_ = boundaries_.front();
            const double span = boundaries_.back() - first_;
            double closest = span;
            for (std::size_t j = 1; j < boundaries_.size(); ++j) closest = std::min(closest, boundaries_[j] - boundaries_[j - 1]);
            const double buckets = span > 0.0 ? std::min(std::ceil(span / closest) + 1.0, max_buckets) : 1.0;
            bucket_scale_ = span > 0.0 ? buckets / span : 0.0;
            for (std::size_t k = 0; k < static_cast<std::size_t>(buckets); ++k)
                guide_.push_back(k == 0 ? 0 : exact_interval(first_ + static_cast<double>(k) / bucket_scale_, 0));
        } else {
            guide_.push_back(0);
        }
        boundaries_.push_back(std::numeric_limits<double>::infinity());
    }
    static constexpr double max_buckets = 65536.0;

    /// The number of boundaries <= z (the index of z's interval), from a starting guess j:
    /// forward past boundaries <= z, back over boundaries > z.
    [[nodiscard]] std::uint32_t exact_interval(double z, std::uint32_t j) const {
        while (j < count_ && boundaries_[j] <= z) ++j;
        while (j > 0 && boundaries_[j - 1] > z) --j;
        return j;
    }

    /// z's interval: its guide bucket's (the bucket clamped to the guide's range), plus one if
    /// the bucket's boundary lies at or above z; exact_interval then only confirms it, unless
    /// rounding put z into a neighbouring bucket or a bucket holds several boundaries.
    [[nodiscard]] std::uint32_t interval(double z) const {
        const double u = (z - first_) * bucket_scale_;
        const std::size_t k = u > 0.0 ? std::min(static_cast<std::size_t>(std::min(u, 1e18)), guide_.size() - 1) : 0;
        std::uint32_t j = guide_[k];
        j += static_cast<std::uint32_t>((boundaries_[j] <= z) & (j < count_));
        return exact_interval(z, j);
    }

    bool enabled_ = false;
    std::vector<double> boundaries_;  ///< depths where the level changes, increasing; then +inf
    std::uint32_t count_ = 0;         ///< the boundaries before the +inf
    std::vector<int> levels_;         ///< levels_[j]: L on [boundaries_[j-1], boundaries_[j])
    std::vector<double> factors_;     ///< 2^levels_[j]
    std::vector<std::uint32_t> guide_;
    double first_ = 0.0;              ///< the first boundary (m)
    double bucket_scale_ = 0.0;       ///< buckets per metre
};

/// A span's bounds (ImportanceLevels::span) for depths held in Real (float or double),
/// narrowed by a relative `margin`: each bound the smallest Real at or above lo (1 + margin)
/// and hi (1 - margin), so that a depth y of type Real has lo <= y < hi exactly when
/// lo (1 + margin) <= y < hi (1 - margin) (the bounds are depths of positive or infinite
/// size). Then y and every depth within a relative margin / (1 + margin) of it (a record's
/// rounding of y to float: 6e-8) share the span's level, and two comparisons per depth tell
/// whether its level is still the span's (transport/lane_tracer.hpp).
template <class Real>
struct InnerSpan {
    Real lo, hi;
};
template <class Real>
InnerSpan<Real> inner_span(const ImportanceLevels::Span& span, double margin) {
    constexpr Real inf = std::numeric_limits<Real>::infinity();
    InnerSpan<Real> inner{-inf, inf};
    if (std::isfinite(span.lo)) {
        const double lo = span.lo + margin * std::abs(span.lo);
        inner.lo = static_cast<Real>(lo);
        if (inner.lo < lo) inner.lo = std::nextafter(inner.lo, inf);
    }
    if (std::isfinite(span.hi)) {
        const double hi = span.hi - margin * std::abs(span.hi);
        inner.hi = static_cast<Real>(hi);
        if (inner.hi < hi) inner.hi = std::nextafter(inner.hi, inf);
    }
    return inner;
}

/// The importance of a record stored at depth z travelling with z component dz: I(z) D(-dz),
/// the records the first pass stores per unit of photon weight there, each carrying Phi / that
/// (transport/record_flux.hpp). The tracer's storage and the estimator's flux both take it from
/// the record's stored (rounded) depth and direction, through this one product, so that they
/// agree bit for bit.
inline double record_importance(const ImportanceLevels& levels, const UpwardImportance& upward, double z, double dz) {
    return levels.factor(z) * upward.storage_factor(dz);
}

}  // namespace secchi
