#pragma once
// The photon-store concept: build once from records, then concurrent const queries.
//
// Threading contract (every store): the constructor builds the structure; afterwards every
// const member may be called from any number of threads at once. Results reach the caller
// through a Collector, in an order fixed by the structure (deterministic for a given build).
//
// Queries:
//  - within(point, r, collector): every record at distance <= r from point
//    (Hit::t = 0, Hit::distance2 = squared distance).
//  - along(ray, r, collector): every record inside the cylinder of radius r around the
//    segment [origin, origin + t_max * direction], flat-capped (manual 3.5: each photon's
//    "volume of influence" sphere of radius r_s is intersected by the ray). Hit::t is the
//    distance along the ray of the photon's closest approach, Hit::distance2 the squared
//    distance from the ray.
// A Collector is called with each Hit and returns false to stop the search early
// (nanoflann's result-set idea); the query then returns false.
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/units.hpp"
#include "secchi/map/record.hpp"
#include <cmath>
#include <concepts>
#include <cstdint>
#include <ranges>
#include <vector>

namespace secchi::SECCHI_ISA {

struct Ray {
    vec3 origin;
    vec3 direction;  ///< unit vector
    double t_max;    ///< segment length
};

/// A ray whose direction is (0, 0, +-1) exactly, as every normalised vertical vector is (nadir
/// and zenith views). Along it a point's t is dz uz exactly and its squared distance needs
/// only dx and dy (the leaf scan's vertical kernel, cylinder_scan.hpp), and cos psi is a function
/// of a photon's polar angle alone (the estimator's coded path, path_radiance.hpp). Not dz !=
/// 0 alone: with |dz| tiny, dz cos_theta could underflow to a zero whose sign the azimuth
/// terms decide.
inline bool is_vertical(const Ray& ray) {
    return ray.direction.x == 0.0 && ray.direction.y == 0.0 && std::abs(ray.direction.z) == 1.0;
}

struct Hit {
    std::uint32_t index;  ///< index into the store's records()
    double t;             ///< distance along the ray (along queries), 0 for within queries
    double distance2;     ///< squared distance to the query point / ray
};

template <class C>
concept Collector = requires(C c, const Hit& h) {
    { c(h) } -> std::convertible_to<bool>;
};

/// A collector that may also take a run of hits at once (the VOI stores' leaf scan finds them
/// in chunks): c.hits(base, offset, t, distance2, n) receives hits k = 0..n-1, record
/// base + offset[k] with t[k] and distance2[k], in order, as n calls c(hit) would, and returns
/// false to stop the search. Stores call whichever they like; the hits and their order are
/// the same.
template <class C>
concept ChunkCollector = Collector<C> && requires(C c, std::uint32_t base, const std::uint32_t* offset,
                                                  const double* t, const double* distance2, std::uint32_t n) {
    { c.hits(base, offset, t, distance2, n) } -> std::convertible_to<bool>;
};

/// Collects every hit (never stops early).
struct CollectAll {
    std::vector<Hit> hits;
    bool operator()(const Hit& h) {
        hits.push_back(h);
        return true;
    }
};

/// Counts hits, stopping after `limit` (limit 0 = unbounded).
struct CountHits {
    std::size_t count = 0;
    std::size_t limit = 0;
    bool operator()(const Hit&) {
        ++count;
        return limit == 0 || count < limit;
    }
};

template <class S>
concept PhotonStore = requires(const S s, vec3 p, Ray ray, Radius r, CollectAll c) {
    typename S::record_type;
    requires PhotonRecord<typename S::record_type>;
    requires std::constructible_from<S, std::vector<typename S::record_type>>;
    { s.size() } -> std::convertible_to<std::size_t>;
    // the records in the store's order, Hit::index into them: a std::vector, or a random-access
    // range of values (a store that packs them, e.g. the VOI octree: packed_records.hpp)
    requires std::ranges::random_access_range<decltype(s.records())>;
    requires std::convertible_to<std::ranges::range_reference_t<decltype(s.records())>, typename S::record_type>;
    { s.within(p, r, c) } -> std::convertible_to<bool>;
    { s.along(ray, r, c) } -> std::convertible_to<bool>;
    { s.memory_bytes() } -> std::convertible_to<std::size_t>;
};

/// Exact closest approach of point p to a ray: fills t and distance2; true if inside the
/// flat-capped cylinder of squared radius r2.
inline bool in_cylinder(const Ray& ray, const vec3& p, double r2, Hit& hit) {
    const vec3 d = p - ray.origin;
    const double t = glm::dot(d, ray.direction);
    if (t < 0.0 || t > ray.t_max) return false;
    const vec3 perp = d - t * ray.direction;  // not |d|^2 - t^2: that cancels badly far from the origin
    const double dist2 = glm::dot(perp, perp);
    if (dist2 > r2) return false;
    hit.t = t;
    hit.distance2 = dist2;
    return true;
}

}  // namespace secchi
