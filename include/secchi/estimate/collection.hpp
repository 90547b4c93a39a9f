#pragma once
// Collection volumes of the second pass: which stored photons contribute to the in-scattered
// radiance along a ray segment, and with what weight (length / volume).
//  - StepSpheres: n spheres of radius r centred at the midpoints of n equal steps (manual
//    eq. 3.18 with V_i = 4/3 pi r^3, eq. 3.20), each searched in the store with `within`.
//    Photon weight dr_i / V_i. Spheres that cross the water's top or bottom plane use the
//    volume inside the water (boundary bias compensation, manual 3.5.1).
//  - VoiCylinder: one `along` search of the cylinder of radius r around the whole segment
//    (manual 3.5, eq. 3.21-3.22): photon weight 1 / (pi r^2), independent of segmentation.
//    Where the cylinder crosses the water's top or bottom plane (a slanted ray near either),
//    a photon's weight is 1 / (the cylinder's cross-section inside the water at the photon's
//    distance t along the ray): the disk minus the circle segments beyond the planes (boundary
//    bias compensation, manual 3.5.1). A vertical ray's cross-section is horizontal, never cut.
//    The segment is meant to lie in the water; where a photon's point on the axis does not, the
//    cross-section is taken at the plane it has crossed, so that no weight grows without bound.
// Each calls visit(record index, distance along the ray, weight); VoiCylinder passes the
// stores' runs of hits whole to a visitor that takes them (ChunkVisitor). Both also gather
// themselves at two radii in one search (gather_nested: the spectral compensation's reuse of
// its core search, manual 3.5.2.3): two coaxial cylinders, or two concentric spheres per step.
// Each volume gathers around a ray inside the store's section, gather(store, ray, r, visit),
// and around any ray in a periodic section, gather(store, ray, r, section, visit) (periodic_ray.hpp:
// the unwrapped ray's volume from the section's photons and their images; distances along the
// unwrapped ray).
#include "secchi/core/config.hpp"
#include "secchi/estimate/periodic_ray.hpp"
#include "secchi/map/brute_force.hpp"
#include "secchi/map/store.hpp"
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

namespace secchi::SECCHI_ISA {

/// The visitor signature collection volumes call (used to check the concept).
struct CollectionVisitorArchetype {
    void operator()(std::uint32_t, double, double) const {}
};

/// A visitor that may also take a run of photons at once, all of one weight:
/// v.photons(base, offset, t, n, weight) visits records base + offset[k] at distances t[k],
/// k = 0..n-1, in order, as n calls v(base + offset[k], t[k], weight) would.
template <class V>
concept ChunkVisitor = requires(V v, std::uint32_t index, double distance, double weight, const std::uint32_t* offset,
                                const double* t, std::uint32_t n) {
    { v(index, distance, weight) };
    { v.photons(index, offset, t, n, weight) };
};

template <class V>
concept CollectionVolume = requires(const V v, const BruteForceStore<CompactRecord>& s, Ray ray, Radius r,
                                    PeriodicSection section, CollectionVisitorArchetype visit) {
    { v.gather(s, ray, r, visit) };
    { v.gather(s, ray, r, section, visit) };
    { v.name() } -> std::convertible_to<std::string>;
};

/// The visitor signature of gather_nested: (record index, distance along the ray, weight in
/// the outer volume, weight in the inner one or 0 outside it).
struct NestedVisitorArchetype {
    void operator()(std::uint32_t, double, double, double) const {}
};

/// A collection volume that gathers itself at two radii in one search: the photons of the
/// outer volume, each with its weight there and in the inner one (0 where it lies outside).
/// V::cut_from_longer_search says whether a segment's photons are those of a longer segment
/// (the same origin and direction) with t <= the segment's length, so that segments of several
/// lengths can share the longest one's search (the cylinder), or not (the step spheres, which
/// follow the segment's length).
template <class V>
concept NestedCollectionVolume =
    CollectionVolume<V> && requires(const V v, const BruteForceStore<CompactRecord>& s, Ray ray, Radius r,
                                    PeriodicSection section, NestedVisitorArchetype visit) {
        { v.gather_nested(s, ray, r, r, section, visit) };
        { std::bool_constant<V::cut_from_longer_search>{} };
    };

/// Volume of the part of a sphere (centre depth zc, radius r) between depths top and bottom.
inline double sphere_volume_in_slab(double zc, double r, double top, double bottom) {
    auto cap = [r](double h) {  // volume of a cap of height h (0 <= h <= 2r)
        h = std::clamp(h, 0.0, 2.0 * r);
        return pi * h * h * (3.0 * r - h) / 3.0;
    };
    const double full = 4.0 / 3.0 * pi * r * r * r;
    return full - cap(top - (zc - r)) - cap((zc + r) - bottom);
}

/// Area of the part of a disk of radius r beyond a chord at signed distance h from its centre:
/// r^2 acos(h / r) - h sqrt(r^2 - h^2) (the circle segment; h >= r: none, h <= -r: the disk).
inline double disk_segment_area(double h, double r) {
    const double x = std::clamp(h / r, -1.0, 1.0);
    return r * r * (std::acos(x) - x * std::sqrt(1.0 - x * x));
}

/// sin(theta) of a direction whose vertical component (cos(theta)) is uz.
inline double sin_from_cos(double uz) { return std::sqrt(std::max(0.0, 1.0 - uz * uz)); }

/// The area inside the water (depths between top and bottom) of a disk of radius r centred at
/// depth zc, perpendicular to a ray whose direction has vertical component uz: the cylinder's
/// cross-section there (manual 3.5.1). Across the disk the depth changes by at most
/// sin(theta) = sqrt(1 - uz^2) per metre, so a plane at depth d cuts it along a chord at
/// distance (zc - d) / sin(theta) from its centre, on the side towards d. The two planes' segments
/// never overlap (top < bottom). A horizontal disk (uz = +-1) is not cut: the whole disk.
inline double disk_area_in_slab(double zc, double uz, double r, double top, double bottom) {
    const double full = pi * r * r;
    const double sin_theta = sin_from_cos(uz);
    if (sin_theta == 0.0) return full;
    return full - disk_segment_area((zc - top) / sin_theta, r) - disk_segment_area((bottom - zc) / sin_theta, r);
}

class StepSpheres {
public:
    explicit StepSpheres(unsigned steps, double water_top = 0.0, double water_bottom = INFINITY)
        : steps_(steps), top_(water_top), bottom_(water_bottom) {
        require(steps >= 1, "steps", steps, "must be >= 1");
    }
    [[nodiscard]] std::string name() const { return "spheres(" + std::to_string(steps_) + ")"; }
    [[nodiscard]] unsigned steps() const { return steps_; }

    /// The spheres of a ray inside the section.
    template <class Store, class Visit>
    void gather(const Store& store, const Ray& ray, Radius r, Visit&& visit) const {
        for_each_step(ray, [&](const vec3& centre, double dr) {
            const double weight = dr / sphere_volume_in_slab(centre.z, r.value(), top_, bottom_);
            collect(store, ray, r, centre, vec3(0.0), [&](const Hit& h, double t) { visit(h.index, t, weight); });
        });
    }

    /// The spheres of any ray in a periodic section: the steps along the whole unwrapped ray,
    /// each sphere's centre moved into the section, with its images.
    template <class Store, class Visit>
    void gather(const Store& store, const Ray& ray, Radius r, const PeriodicSection& section, Visit&& visit) const {
        for_each_image(ray, r, section, [&](const vec3& query, const vec3& unwrap, double dr, double depth) {
            const double weight = dr / sphere_volume_in_slab(depth, r.value(), top_, bottom_);
            collect(store, ray, r, query, unwrap, [&](const Hit& h, double t) { visit(h.index, t, weight); });
        });
    }

    /// The spheres of radius `outer` and `inner` (<= outer) of any ray in a periodic section,
    /// in one search per sphere (manual 3.5.2.3, the spectral compensation's reuse of its core
    /// search): visit(index, t, w_outer, w_inner) for every photon image of each outer sphere,
    /// w_inner 0 where it lies outside the concentric inner one. Each radius's photons,
    /// distances and weights are those gather() finds (the inner test is the stores' own,
    /// d^2 <= r^2, on the distance the store reports; an inner sphere's images are among the
    /// outer one's), in the outer search's order. The spheres follow ray.t_max: a shorter
    /// segment's spheres are not a longer one's (cut_from_longer_search).
    template <class Store, class Visit>
    void gather_nested(const Store& store, const Ray& ray, Radius outer, Radius inner, const PeriodicSection& section,
                       Visit&& visit) const {
        require(inner.value() <= outer.value(), "inner radius (m)", inner.value(),
                "must not exceed the outer radius (" + std::to_string(outer.value()) + " m)");
        const double inner2 = inner.squared();
        for_each_image(ray, outer, section, [&](const vec3& query, const vec3& unwrap, double dr, double depth) {
            const double w_outer = dr / sphere_volume_in_slab(depth, outer.value(), top_, bottom_),
                         w_inner = dr / sphere_volume_in_slab(depth, inner.value(), top_, bottom_);
            collect(store, ray, outer, query, unwrap,
                    [&](const Hit& h, double t) { visit(h.index, t, w_outer, h.distance2 > inner2 ? 0.0 : w_inner); });
        });
    }

    /// A segment's photons are not those of a longer segment's search cut at its length (the
    /// spheres' centres and steps follow the segment's length).
    static constexpr bool cut_from_longer_search = false;

private:
    /// Calls f(centre, dr) for each of the n spheres: centred at the midpoints of n equal steps
    /// dr along the ray. A sphere's photons weigh dr / (its volume inside the water).
    template <class F>
    void for_each_step(const Ray& ray, F&& f) const {
        const double dr = ray.t_max / steps_;
        for (unsigned i = 0; i < steps_; ++i) f(ray.origin + ray.direction * ((i + 0.5) * dr), dr);
    }

    /// Calls f(query, unwrap, dr, depth) for each sphere of radius r (for_each_step) and each
    /// of its images in a periodic section: the centre, at `depth`, moved into the section and
    /// shifted to `query`; a record at q lies at q + unwrap in the ray's frame.
    template <class F>
    void for_each_image(const Ray& ray, Radius r, const PeriodicSection& section, F&& f) const {
        for_each_step(ray, [&](const vec3& centre, double dr) {
            const vec3 offset = section.cell_offset(centre), c = centre - offset;
            section.for_each_image(c.x - r.value(), c.x + r.value(), c.y - r.value(), c.y + r.value(),
                                   [&](const vec3& shift) { f(c + shift, offset - shift, dr, centre.z); });
        });
    }

    /// Calls hit(h, t) for the records within r of `query`, a record at q lying at q + unwrap
    /// in the ray's frame (t, the distance along the ray: its projection).
    template <class Store, class Hits>
    static void collect(const Store& store, const Ray& ray, Radius r, const vec3& query, const vec3& unwrap, Hits&& hit) {
        auto each = [&](const Hit& h) {
            hit(h, glm::dot(store.records()[h.index].position() + unwrap - ray.origin, ray.direction));
            return true;
        };
        store.within(query, r, each);
    }

    unsigned steps_;
    double top_, bottom_;
};

class VoiCylinder {
public:
    /// The water lies between depths water_top and water_bottom (as StepSpheres).
    explicit VoiCylinder(double water_top = 0.0, double water_bottom = INFINITY) : top_(water_top), bottom_(water_bottom) {
        require(!std::isnan(water_top) && !std::isnan(water_bottom) && water_top < water_bottom, "water_bottom",
                water_bottom, "must lie below water_top (" + std::to_string(water_top) + ")");
    }
    [[nodiscard]] std::string name() const { return "voi-cylinder"; }

    template <class Store, class Visit>
    void gather(const Store& store, const Ray& ray, Radius r, Visit&& visit) const {
        if (reaches_boundary(ray, r.value())) {
            auto collect = [&](const Hit& h) {
                visit(h.index, h.t, cut_weight(ray, h.t, r));
                return true;
            };
            store.along(ray, r, collect);
            return;
        }
        const double weight = 1.0 / (pi * r.squared());
        if constexpr (ChunkVisitor<Visit>) {
            Chunks<std::remove_reference_t<Visit>> collect{visit, weight};
            store.along(ray, r, collect);
        } else {
            auto collect = [&](const Hit& h) {
                visit(h.index, h.t, weight);
                return true;
            };
            store.along(ray, r, collect);
        }
    }

    /// The cylinder of any ray in a periodic section: the cylinders of the ray's pieces and their
    /// images (PeriodicSection::for_each_piece_image), distances along the whole ray. The
    /// pieces' cylinders meet at their flat caps, so each photon image counts once (one lying
    /// exactly on a cap, a set of measure zero, may count in both).
    template <class Store, class Visit>
    void gather(const Store& store, const Ray& ray, Radius r, const PeriodicSection& section, Visit&& visit) const {
        section.for_each_piece_image(ray, r.value(), [&](const Ray& query, double t0) {
            if (t0 == 0.0) {  // the first piece (a vertical ray's only one): its distances are the ray's
                gather(store, query, r, visit);
            } else {  // a later piece: its photons one at a time, their distances moved by t0
                gather(store, query, r, [&](std::uint32_t index, double t, double weight) { visit(index, t0 + t, weight); });
            }
        });
    }

    /// The cylinders of radius `outer` and `inner` (<= outer) of any ray in a periodic section,
    /// in one search (manual 3.5.2.3: "reuse the results from the original, core search" for
    /// the spectral one): visit(index, t, w_outer, w_inner) for every photon image of the outer
    /// cylinder, w_inner 0 where it lies outside the inner one. Each cylinder's photons,
    /// distances and weights are those gather() finds at its radius (the inner test is
    /// in_cylinder's, on the distance the store reports; the images of the inner cylinder are
    /// among the outer one's), in the outer search's order.
    template <class Store, class Visit>
    void gather_nested(const Store& store, const Ray& ray, Radius outer, Radius inner, const PeriodicSection& section,
                       Visit&& visit) const {
        require(inner.value() <= outer.value(), "inner radius (m)", inner.value(),
                "must not exceed the outer radius (" + std::to_string(outer.value()) + " m)");
        section.for_each_piece_image(ray, outer.value(), [&](const Ray& query, double t0) {
            const bool cut_outer = reaches_boundary(query, outer.value()), cut_inner = reaches_boundary(query, inner.value());
            const double inner2 = inner.squared(), uncut_outer = 1.0 / (pi * outer.squared()),
                         uncut_inner = 1.0 / (pi * inner.squared());
            auto collect = [&](const Hit& h) {
                const double w_outer = cut_outer ? cut_weight(query, h.t, outer) : uncut_outer;
                const double w_inner = h.distance2 > inner2 ? 0.0 : cut_inner ? cut_weight(query, h.t, inner) : uncut_inner;
                visit(h.index, t0 == 0.0 ? h.t : t0 + h.t, w_outer, w_inner);
                return true;
            };
            store.along(query, outer, collect);
        });
    }

    /// A segment's photons are those of a longer segment's cylinder with t <= its length.
    static constexpr bool cut_from_longer_search = true;

private:
    /// A photon's weight where the cylinder of radius r is cut by the water's planes: 1 / the
    /// cross-section at the photon's point t on the axis, taken at the plane where that point
    /// lies beyond it (a segment that leaves the water).
    [[nodiscard]] double cut_weight(const Ray& ray, double t, Radius r) const {
        const double zc = std::clamp(ray.origin.z + t * ray.direction.z, top_, bottom_);
        return 1.0 / disk_area_in_slab(zc, ray.direction.z, r.value(), top_, bottom_);
    }

    /// Whether the cylinder's cross-section is cut by the top or bottom plane somewhere along
    /// the segment: the disks reach r sin(theta) above and below the segment's depths.
    [[nodiscard]] bool reaches_boundary(const Ray& ray, double r) const {
        const double uz = ray.direction.z;
        const double reach = r * sin_from_cos(uz);
        if (reach == 0.0) return false;  // vertical: horizontal disks, never cut
        const double z0 = ray.origin.z, z1 = ray.origin.z + ray.t_max * uz;
        return std::min(z0, z1) - reach < top_ || std::max(z0, z1) + reach > bottom_;
    }

    /// The collector for a visitor that takes runs of photons (ChunkVisitor): the store's
    /// chunks of hits pass through whole.
    template <class Visit>
    struct Chunks {
        Visit& visit;
        double weight;
        bool operator()(const Hit& h) {
            visit(h.index, h.t, weight);
            return true;
        }
        bool hits(std::uint32_t base, const std::uint32_t* offset, const double* t, const double*, std::uint32_t n) {
            visit.photons(base, offset, t, n, weight);
            return true;
        }
    };

    double top_, bottom_;
};

}  // namespace secchi
