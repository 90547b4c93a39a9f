#pragma once
// Opaque objects in the water, as a policy of the first pass (transport/tracer.hpp). Depth z
// is positive down from the surface, as everywhere in secchi.
//
// SceneGeometry (what PhotonTracer needs):
//   has_objects                    static constexpr bool: false only for NoGeometry (the tracer
//                                  then compiles without any object test: its results are
//                                  bit-identical to a tracer without the policy)
//   closest_hit(o, d, t_max)       the closest point where the ray o + t d (d a unit vector)
//                                  enters or leaves an object's solid for t in [0, t_max), or
//                                  nothing: an ObjectHit (distance t, point, unit normal facing
//                                  the incoming ray, dot(normal, d) <= 0, and material index).
//                                  A ray starting on an object's surface and moving into the
//                                  solid hits it at t = 0; one moving out of it does not.
//   material(index)                the ObjectMaterial of that index (a value, or a reference
//                                  valid while the geometry is)
//   bounds()                       a box holding every object (empty(): no object)
// The objects are given in one horizontal period of the water body, the section [0, W) x
// [0, W) of the slab (scene/slab.hpp), whose periodic copies fill the horizontally infinite
// water as the section's photons do: periodic_closest_hit, below, follows a flight across the
// seams of the section into the neighbouring copies.
//
// A photon meeting an object is reflected by its material, or absorbed: ObjectMaterial is
// Lambertian (f_r = A / pi; A = 0 absorbs everything) with a constant albedo A or an albedo
// map, A(x, y) over the section seen from above (AlbedoMap), plus optionally Ward's glossy
// lobe of albedo rho_s (scene/ward.hpp): f_r = A / pi + f_s, A + rho_s <= 1.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/ward.hpp"
#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

/// Where a ray meets an object.
struct ObjectHit {
    double t;                ///< distance along the ray (m)
    vec3 point;              ///< o + t d
    vec3 normal;             ///< unit normal facing the incoming ray: dot(normal, d) <= 0
    std::uint32_t material;  ///< index into the geometry's materials
};

/// An albedo map seen from above: A in nx x ny equal cells over [0, W) x [0, W), cell (i, j)
/// (index j nx + i) covering [i W / nx, (i + 1) W / nx) x [j W / ny, (j + 1) W / ny), repeating
/// with period W in x and y (W the section's width, so that the periodic copies of an object
/// carry the same map). A point takes the cell under it, whatever face it is on: a planar
/// projection along z, as a texture on a box's top or a terrain.
class AlbedoMap {
public:
    AlbedoMap(unsigned nx, unsigned ny, double width, std::vector<double> albedo)
        : nx_(nx), ny_(ny), width_(width), albedo_(std::move(albedo)) {
        require(nx >= 1 && ny >= 1, "albedo map cells per side", std::min(nx, ny), "must be >= 1");
        require(std::isfinite(width) && width > 0.0, "albedo map width (m)", width, "must be finite and > 0");
        require(albedo_.size() == static_cast<std::size_t>(nx) * ny, "albedo map values", albedo_.size(),
                "must be nx x ny = " + std::to_string(static_cast<std::size_t>(nx) * ny));
        for (std::size_t k = 0; k < albedo_.size(); ++k)
            require(std::isfinite(albedo_[k]) && albedo_[k] >= 0.0 && albedo_[k] <= 1.0, indexed_name("albedo map", k),
                    albedo_[k], "must be in [0, 1]");
    }
    /// The largest A of the map.
    [[nodiscard]] double max() const { return *std::max_element(albedo_.begin(), albedo_.end()); }
    /// A at the point (x, y) (any x, y: the map repeats with period W).
    [[nodiscard]] double at(double x, double y) const {
        const auto cell = [this](double v, unsigned n) {
            return std::min(n - 1, static_cast<unsigned>(periodic_wrap(v, width_) / width_ * n));
        };
        return albedo_[static_cast<std::size_t>(cell(y, ny_)) * nx_ + cell(x, nx_)];
    }

private:
    unsigned nx_, ny_;
    double width_;
    std::vector<double> albedo_;
};

/// An object's surface: Lambertian, f_r = A / pi, with albedo (directional-hemispherical
/// reflectance, the same for every incidence) A in [0, 1], constant or from a map; A = 0 is a
/// black, absorbing surface. Glossy: Ward's lobe added, of albedo rho_s (`specular`) and
/// roughness alpha (scene/ward.hpp), A + rho_s <= 1.
struct ObjectMaterial {
    double albedo = 0.0;                    ///< A, where there is no map
    std::shared_ptr<const AlbedoMap> map;   ///< if set: A = map->at(x, y) of the point met
    double specular = 0.0;                  ///< rho_s of the glossy lobe (0: Lambertian only)
    WardLobe lobe;                          ///< the glossy lobe's shape (where specular > 0)

    ObjectMaterial() = default;
    /// Unchecked (as an aggregate would be): the geometries check their materials (checked()).
    explicit ObjectMaterial(double a, std::shared_ptr<const AlbedoMap> m = nullptr) : albedo(a), map(std::move(m)) {}

    [[nodiscard]] double albedo_at(const vec3& p) const { return map ? map->at(p.x, p.y) : albedo; }

    static ObjectMaterial absorbing() { return {}; }
    static ObjectMaterial lambertian(double albedo) { return checked(ObjectMaterial(albedo)); }
    static ObjectMaterial mapped(AlbedoMap map) { return ObjectMaterial(0.0, std::make_shared<const AlbedoMap>(std::move(map))); }
    /// Lambertian of albedo `diffuse` plus Ward's glossy lobe of albedo `specular` and
    /// roughness alpha (the microfacets' rms slope: 0.05 polished, 0.3 rough).
    static ObjectMaterial ward(double diffuse, double specular, double roughness) {
        ObjectMaterial m(diffuse);
        m.specular = specular;
        m.lobe = WardLobe(roughness);
        return checked(m);
    }
    /// `m` after the check of its albedos (a map checks its own values, each within 1 - rho_s).
    static ObjectMaterial checked(ObjectMaterial m) {
        require(std::isfinite(m.albedo) && m.albedo >= 0.0 && m.albedo <= 1.0, "object albedo", m.albedo, "must be in [0, 1]");
        require(std::isfinite(m.specular) && m.specular >= 0.0 && m.specular <= 1.0, "object glossy albedo", m.specular,
                "must be in [0, 1]");
        const double diffuse = m.map ? m.map->max() : m.albedo;
        require(diffuse + m.specular <= 1.0, "object glossy albedo", m.specular,
                "must not exceed 1 - the diffuse albedo (" + std::to_string(diffuse) + "): no more light sent back than received");
        return m;
    }
};

/// An axis-aligned box [lo, hi]; empty when any lo > hi.
struct Bounds {
    vec3 lo{INFINITY}, hi{-INFINITY};

    [[nodiscard]] bool empty() const { return lo.x > hi.x || lo.y > hi.y || lo.z > hi.z; }
    /// The smallest box holding this one and `o`.
    [[nodiscard]] Bounds merged(const Bounds& o) const {
        return {{std::min(lo.x, o.lo.x), std::min(lo.y, o.lo.y), std::min(lo.z, o.lo.z)},
                {std::max(hi.x, o.hi.x), std::max(hi.y, o.hi.y), std::max(hi.z, o.hi.z)}};
    }
};

template <class G>
concept SceneGeometry =
    std::copy_constructible<G> && requires(const G& g, const vec3& v, double t, std::uint32_t index) {
        { G::has_objects } -> std::convertible_to<bool>;
        { g.closest_hit(v, v, t) } -> std::same_as<std::optional<ObjectHit>>;
        { g.material(index) } -> std::convertible_to<ObjectMaterial>;
        { g.bounds() } -> std::convertible_to<Bounds>;
    };

/// No objects: the plane-parallel water body alone (PhotonTracer's default).
struct NoGeometry {
    static constexpr bool has_objects = false;
    [[nodiscard]] std::optional<ObjectHit> closest_hit(const vec3&, const vec3&, double) const { return std::nullopt; }
    [[nodiscard]] ObjectMaterial material(std::uint32_t) const { return ObjectMaterial::absorbing(); }
    [[nodiscard]] Bounds bounds() const { return {}; }
};

static_assert(SceneGeometry<NoGeometry>);

/// A direction reflected by a Lambertian surface of unit normal n (pointing to the side the
/// light leaves on): cosine-weighted about n, cos theta = sqrt(u1) (pdf cos theta / pi over
/// the hemisphere of n), azimuth 2 pi u2 about n; as Bottom's upward_direction about -z.
inline vec3 lambertian_direction(const vec3& n, double u1, double u2) {
    return rotate_direction(n, std::sqrt(u1), two_pi * u2);
}

/// A level flight (d.z = 0, parallel to the surface) of unbounded length is followed for this
/// many section widths: it may pass between the copies for ever. (The tracer's flights end at an
/// interaction or a boundary: finite.)
inline constexpr double max_level_flight = 1e6;

/// The closest hit of the ray o + t d, t in [0, t_max), with the periodic copies of `g`'s
/// objects, which lie in the section [0, W] x [0, W] (W = width) and repeat with period W in
/// x and y. The origin is wrapped into the section and the flight walks the cells of the
/// copies it crosses in order (a 2-D DDA, Amanatides & Woo 1987), from the first at the
/// objects' depths; since each copy lies in its own cell, the first cell with a hit holds the
/// closest one. The hit's point is in the frame of `o` (not wrapped). Each cell costs one
/// closest_hit, so a flight costs about 1 + (|d.x| + |d.y|) t / W of them.
template <SceneGeometry G>
std::optional<ObjectHit> periodic_closest_hit(const G& g, double width, const vec3& o, const vec3& d, double t_max) {
    const Bounds b = g.bounds();  // empty for NoGeometry
    if (b.empty() || !(t_max > 0.0)) return std::nullopt;
    // The part [t_lo, t_hi] of the flight at the objects' depths.
    double t_lo = 0.0, t_hi = t_max;
    if (d.z == 0.0) {  // level: at the objects' depths all along, or never
        if (o.z < b.lo.z || o.z > b.hi.z) return std::nullopt;
        t_hi = std::min(t_hi, max_level_flight * width);
    } else {
        const double ta = (b.lo.z - o.z) / d.z, tb = (b.hi.z - o.z) / d.z;
        t_lo = std::max(t_lo, std::min(ta, tb));
        t_hi = std::min(t_hi, std::max(ta, tb));
        if (t_lo > t_hi) return std::nullopt;
    }
    const vec3 start{periodic_wrap(o.x, width), periodic_wrap(o.y, width), o.z};  // in cell (0, 0)
    const int step_x = d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0), step_y = d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0);
    // The distances to the next cell boundary in x and y, and between boundaries.
    double next_x = step_x > 0 ? (width - start.x) / d.x : (step_x < 0 ? -start.x / d.x : INFINITY);
    double next_y = step_y > 0 ? (width - start.y) / d.y : (step_y < 0 ? -start.y / d.y : INFINITY);
    const double dt_x = step_x ? width / std::abs(d.x) : INFINITY, dt_y = step_y ? width / std::abs(d.y) : INFINITY;
    double ci = 0.0, cj = 0.0;  // the cell, as the copy's offset in periods
    while (true) {
        const double cell_end = std::min(next_x, next_y);
        if (cell_end >= t_lo) {
            const vec3 shift{ci * width, cj * width, 0.0};
            if (auto hit = g.closest_hit(start - shift, d, t_max)) {
                hit->point += shift + (o - start);
                return hit;
            }
        }
        if (cell_end >= t_hi) return std::nullopt;
        if (next_x <= next_y) {
            next_x += dt_x;
            ci += step_x;
        } else {
            next_y += dt_y;
            cj += step_y;
        }
    }
}

}  // namespace secchi
