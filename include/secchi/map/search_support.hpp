#pragma once
// Search helpers shared by the photon stores (kdtree.hpp, nanoflann_store.hpp,
// voi_octree.hpp): bounding boxes, the traversal stack, the rounding-safe pruning bounds, the
// padded-segment slab test and the k-best list.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/map/store.hpp"
#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {
namespace detail {

inline constexpr double infinity = std::numeric_limits<double>::infinity();

/// Axis-aligned box in double precision (an aggregate, so traversal stacks stay trivial).
struct Box {
    vec3 lo, hi;
};

/// The empty box (grows to the first point).
inline Box empty_box() { return {vec3(infinity), vec3(-infinity)}; }

/// Bounding box of the records' positions.
template <PhotonRecord Record>
Box bounding_box(const std::vector<Record>& records) {
    Box box = empty_box();
    for (const Record& rec : records) {
        box.lo = glm::min(box.lo, rec.position());
        box.hi = glm::max(box.hi, rec.position());
    }
    return box;
}

/// Photon counts are limited by the 32-bit Hit::index.
inline void require_indexable(std::size_t count) {
    require(count <= std::numeric_limits<std::uint32_t>::max(), "photon count", count,
            "exceeds 2^32 - 1 (Hit::index is 32-bit)");
}

/// A stack of at most N entries in automatic storage: the traversal stack of the queries
/// (no recursion, no allocation). Each use proves its depth bound next to its capacity.
template <class T, std::size_t N>
class FixedStack {
public:
    void push(const T& item) {
        assert(size_ < N);
        items_[size_++] = item;
    }
    T pop() { return items_[--size_]; }
    [[nodiscard]] bool empty() const { return size_ == 0; }

private:
    std::array<T, N> items_;
    std::size_t size_ = 0;
};

// Rounding-safe pruning. A store must report exactly the records the brute-force oracle
// accepts, so a subtree is pruned only when rounding cannot make the oracle's exact test
// accept one of its records.

/// Squared radius for sphere pruning: r^2 (1 + 1e-9). Squared distances to a box or plane
/// are rounded by a few ulps (1e-16 relative) and never exceed the rounded squared distance
/// to a record inside, so no record with dot(d, d) <= r^2 is pruned.
inline double pruning_radius2(double r2) { return r2 * (1.0 + 1e-9); }

/// Radius by which to pad boxes for along() pruning. in_cylinder computes dist^2 = |perp|^2
/// with perp = d - t u (store.hpp): each component of perp is off by a few ulp of |d| (d and
/// t u are of that size), where |d| <= t_max + r for an accepted record, so the distance is
/// off by ~1e-15 |d| (with or without fused multiply-adds); and a direction off unit length
/// by delta shifts dist^2 by up to 2 delta t^2 and t by delta t. The pad covers both with a
/// wide margin (1e-13 |d|^2 and 1e-9 |d|), plus the rounding of the slab test itself.
inline double pruning_pad(const Ray& ray, double r2) {
    const double len = ray.t_max + std::sqrt(r2);
    const double off_unit = std::abs(glm::dot(ray.direction, ray.direction) - 1.0);
    const double slack2 = (1e-13 + 4.0 * off_unit) * len * len;
    return std::sqrt(r2 + slack2) + (1e-9 + 2.0 * off_unit) * len;
}

/// A direction component below this is treated as parallel to its axis by the slab tests: it
/// moves a segment by < 1e-300 t_max along that axis, far inside any pruning pad's margin (and
/// its inverse would overflow).
inline constexpr double parallel_below = 1e-300;

/// The slab test along one axis (Kay & Kajiya 1986): the part of the parameter interval
/// [t0, t1] where origin + t direction lies in [low, high] along that axis, given
/// inverse_direction = 1 / direction, or `parallel` (|direction| < parallel_below: then all of
/// [t0, t1] or nothing). Empty: first > second. PaddedSegment (octree, k-d tree, nanoflann
/// adaptor) and the VOI grid's column walk use it.
inline std::pair<double, double> clip_to_slab(double origin, double inverse_direction, bool parallel, double low,
                                              double high, double t0, double t1) {
    if (parallel) return (origin < low || origin > high) ? std::pair{1.0, 0.0} : std::pair{t0, t1};
    double ta = (low - origin) * inverse_direction, tb = (high - origin) * inverse_direction;
    if (ta > tb) std::swap(ta, tb);
    return {std::max(t0, ta), std::min(t1, tb)};
}

/// A query segment origin + t direction, t in [0, t_max], prepared once per along() query
/// for slab tests (Kay & Kajiya 1986) against boxes padded by pruning_pad(ray, r^2): the
/// manual's "volume of influence" (3.5), with the padding applied at query time.
class PaddedSegment {
public:
    PaddedSegment(const Ray& ray, double r2) : origin_(ray.origin), t_max_(ray.t_max), pad_(pruning_pad(ray, r2)) {
        // The segment's bounding box padded by pad: the rounding of the far end point is
        // ~1e-16 of the segment's length, far inside the pad's 1e-9 margin.
        const vec3 end = ray.origin + ray.t_max * ray.direction;
        reach_lo_ = glm::min(ray.origin, end) - vec3(pad_);
        reach_hi_ = glm::max(ray.origin, end) + vec3(pad_);
        for (int a = 0; a < 3; ++a) {
            parallel_[a] = std::abs(ray.direction[a]) < parallel_below;
            inv_dir_[a] = parallel_[a] ? 0.0 : 1.0 / ray.direction[a];
        }
    }

    [[nodiscard]] double pad() const { return pad_; }

    /// Parameter interval [t0, t1] of the segment inside the box [lo - pad, hi + pad];
    /// empty (t0 > t1) if the segment misses it.
    [[nodiscard]] std::pair<double, double> clip(const vec3& lo, const vec3& hi) const {
        std::pair<double, double> t{0.0, t_max_};
        for (int a = 0; a < 3; ++a) {
            t = clip_to_slab(origin_[a], inv_dir_[a], parallel_[a], lo[a] - pad_, hi[a] + pad_, t.first, t.second);
            if (t.first > t.second) break;
        }
        return t;
    }

    /// Does the segment meet the box [lo - pad, hi + pad]? First the cheap necessary test
    /// (the box overlaps the padded segment's bounding box: six comparisons, exact for
    /// axis-parallel rays), then the slab test.
    [[nodiscard]] bool meets(const vec3& lo, const vec3& hi) const {
        if (!((lo.x <= reach_hi_.x) & (hi.x >= reach_lo_.x) & (lo.y <= reach_hi_.y) & (hi.y >= reach_lo_.y) &
              (lo.z <= reach_hi_.z) & (hi.z >= reach_lo_.z)))
            return false;
        const auto [t0, t1] = clip(lo, hi);
        return t0 <= t1;
    }

private:
    vec3 origin_;
    double t_max_;
    double pad_;
    vec3 inv_dir_{};
    vec3 reach_lo_{}, reach_hi_{};
    std::array<bool, 3> parallel_{};
};

/// Conservative interior test for along(): does the box [lo, hi] lie inside the flat-capped
/// cylinder of in_cylinder (t in [0, t_max], perpendicular distance <= r) with a margin that
/// covers in_cylinder's rounding? Then every record in the box is accepted by in_cylinder, and
/// a store may report a whole subtree without testing it ("bulk accept").
/// Exact argument: t(p) = (p - o).u is linear and |perp(p)|^2 = |M (p - o)|^2 with
/// M = I - u u^T is convex, for any direction u (unit or not). Over the box, t lies within the
/// corner extremes, and |perp| <= |perp(centre)| + sum_a h_a |M e_a| (triangle inequality,
/// h the half extents). The box is accepted when t_min >= m, t_max' <= t_max - m and
/// |perp(centre)| + sum_a h_a |M e_a| <= r - m, with m = 1e-9 (t_max + r)(1 + |u|): rounding
/// in in_cylinder and in this test is ~1e-15 of those lengths, far inside m.
class CylinderInterior {
public:
    CylinderInterior(const Ray& ray, double r2) : origin_(ray.origin), dir_(ray.direction) {
        const double r = std::sqrt(r2);
        const double u2 = glm::dot(ray.direction, ray.direction);
        const double margin = 1e-9 * (ray.t_max + r) * (1.0 + std::sqrt(u2));
        t_lo_ = margin;
        t_hi_ = ray.t_max - margin;
        inner_ = r - margin;
        usable_ = inner_ > 0.0 && t_lo_ <= t_hi_ && std::isfinite(u2);
        for (int a = 0; a < 3; ++a) {  // |M e_a| = |e_a - u_a u| = sqrt(1 - 2 u_a^2 + u_a^2 |u|^2)
            const double ua = ray.direction[a];
            weight_[a] = std::sqrt(std::max(0.0, 1.0 - 2.0 * ua * ua + ua * ua * u2)) * (1.0 + 1e-12);
        }
    }

    [[nodiscard]] bool usable() const { return usable_; }

    [[nodiscard]] bool contains(const vec3& lo, const vec3& hi) const {
        const vec3 half = 0.5 * (hi - lo);  // float corners: exact, or within an ulp (covered by the margin)
        const double spread = half.x * weight_[0] + half.y * weight_[1] + half.z * weight_[2];
        const double reach = inner_ - spread;
        if (reach < 0.0) return false;  // too wide to fit: the common quick answer
        const vec3 d = 0.5 * (lo + hi) - origin_;
        const double t = glm::dot(d, dir_);
        const double t_spread = half.x * std::abs(dir_.x) + half.y * std::abs(dir_.y) + half.z * std::abs(dir_.z);
        if (t - t_spread < t_lo_ || t + t_spread > t_hi_) return false;
        const vec3 perp = d - t * dir_;
        return glm::dot(perp, perp) <= reach * reach;
    }

private:
    vec3 origin_, dir_;
    double t_lo_ = 0.0, t_hi_ = -1.0, inner_ = -1.0;
    std::array<double, 3> weight_{};
    bool usable_ = false;
};

/// Conservative interior test for within(): is every point of the box [lo, hi] at squared
/// distance <= r^2 (1 - 1e-9) from p? Then rounding cannot make dot(d, d) exceed r^2 for any
/// record inside (the rounding is ~1e-16 relative), and the subtree is accepted whole.
inline bool box_inside_sphere(const vec3& p, double r2, const vec3& lo, const vec3& hi) {
    const vec3 far = glm::max(glm::abs(p - lo), glm::abs(hi - p));
    return glm::dot(far, far) <= r2 * (1.0 - 1e-9);
}

/// The k best hits by (distance2, index), kept as a bounded max-heap in the caller's vector
/// (ties broken by the smaller index, so the result is deterministic).
class KBest {
public:
    KBest(std::size_t k, std::size_t available, std::vector<Hit>& out) : k_(k), out_(out) {
        out_.clear();
        out_.reserve(std::min(k, available));
    }

    static bool before(const Hit& a, const Hit& b) {
        return a.distance2 < b.distance2 || (a.distance2 == b.distance2 && a.index < b.index);
    }

    /// Squared distance of the current k-th hit; infinity until k hits are held (-infinity
    /// for k = 0: nothing can enter).
    [[nodiscard]] double worst2() const {
        if (k_ == 0) return -infinity;
        return out_.size() < k_ ? infinity : out_.front().distance2;
    }

    /// Could a record at squared distance >= bound2 still enter? (rounding-safe, ties enter)
    [[nodiscard]] bool may_accept(double bound2) const { return bound2 <= pruning_radius2(worst2()); }

    void offer(const Hit& hit) {
        if (out_.size() < k_) {
            out_.push_back(hit);
            std::push_heap(out_.begin(), out_.end(), before);
        } else if (k_ > 0 && before(hit, out_.front())) {
            std::pop_heap(out_.begin(), out_.end(), before);
            out_.back() = hit;
            std::push_heap(out_.begin(), out_.end(), before);
        }
    }

    /// Sorts the hits by (distance2, index).
    void finish() { std::sort_heap(out_.begin(), out_.end(), before); }

private:
    std::size_t k_;
    std::vector<Hit>& out_;
};

}  // namespace detail

}  // namespace secchi
