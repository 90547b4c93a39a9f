#pragma once
// Collection volumes of the second pass: which stored photons contribute to the in-scattered
// radiance along a ray segment, and with what weight (length / volume).
//  - StepSpheres: n spheres of radius r centred at the midpoints of n equal steps (manual
//    eq. 3.18 with V_i = 4/3 pi r^3, eq. 3.20), each searched in the store with `within`.
//    Photon weight dr_i / V_i. Spheres that cross the water's top or bottom plane use the
//    volume inside the water (boundary bias compensation, manual 3.5.1).
//  - VoiCylinder: one `along` search of the cylinder of radius r around the whole segment
//    (manual 3.5, eq. 3.21-3.22): photon weight 1 / (pi r^2), independent of segmentation.
// Each calls visit(record index, distance along the ray, weight); VoiCylinder passes the
// stores' runs of hits whole to a visitor that takes them (ChunkVisitor).
#include "secchi/map/brute_force.hpp"
#include "secchi/map/store.hpp"
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

namespace secchi {

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
                                    CollectionVisitorArchetype visit) {
    { v.gather(s, ray, r, visit) };
    { v.name() } -> std::convertible_to<std::string>;
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

class StepSpheres {
public:
    explicit StepSpheres(unsigned steps, double water_top = 0.0, double water_bottom = INFINITY)
        : steps_(steps), top_(water_top), bottom_(water_bottom) {
        require(steps >= 1, "steps", steps, "must be >= 1");
    }
    [[nodiscard]] std::string name() const { return "spheres(" + std::to_string(steps_) + ")"; }
    [[nodiscard]] unsigned steps() const { return steps_; }

    template <class Store, class Visit>
    void gather(const Store& store, const Ray& ray, Radius r, Visit&& visit) const {
        const double dr = ray.t_max / steps_;
        for (unsigned i = 0; i < steps_; ++i) {
            const vec3 centre = ray.origin + ray.direction * ((i + 0.5) * dr);
            const double weight = dr / sphere_volume_in_slab(centre.z, r.value(), top_, bottom_);
            auto collect = [&](const Hit& h) {
                const double t = glm::dot(store.records()[h.index].position() - ray.origin, ray.direction);
                visit(h.index, t, weight);
                return true;
            };
            store.within(centre, r, collect);
        }
    }

private:
    unsigned steps_;
    double top_, bottom_;
};

class VoiCylinder {
public:
    [[nodiscard]] std::string name() const { return "voi-cylinder"; }

    template <class Store, class Visit>
    void gather(const Store& store, const Ray& ray, Radius r, Visit&& visit) const {
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

private:
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
};

}  // namespace secchi
