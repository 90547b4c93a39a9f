#pragma once
// Analytic shapes and a collection of them with materials: a SceneGeometry (scene/geometry.hpp).
// Each shape is a closed convex solid; intersect(o, d, t_max) returns the distance t in
// [0, t_max) where the ray o + t d (d a unit vector) enters the solid (o outside, or on the
// surface moving in) or leaves it (o inside), and the unit normal there facing the ray, or
// nothing. A ray on the surface moving out, or sliding along a face, does not enter.
//  - AxisBox [lo, hi]: the slab method (Kay & Kajiya 1986): the ray is inside the box for t in
//    [max_k t_near,k, min_k t_far,k], t_near,k and t_far,k the crossings of the two planes of
//    axis k; the hit's normal is that of the plane giving the bound.
//  - Sphere of centre c, radius r: |o + t d - c|^2 = r^2, t^2 + 2 b t + q = 0 with b = d.(o - c)
//    and q = |o - c|^2 - r^2, roots -b -+ sqrt(b^2 - q), the nearer one taken as
//    -(b + sign(b) sqrt(b^2 - q)) and the other as q over it (no cancellation; Press et al.,
//    Numerical Recipes, 3rd ed., sec. 5.6).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/geometry.hpp"
#include <cmath>
#include <cstdint>
#include <optional>
#include <variant>
#include <vector>

namespace secchi::SECCHI_ISA {

/// A shape's hit: distance and the unit normal facing the ray.
struct ShapeHit {
    double t;
    vec3 normal;
};

/// An axis-aligned box [lo, hi] (metres, z positive down).
class AxisBox {
public:
    AxisBox(const vec3& lo, const vec3& hi) : lo_(lo), hi_(hi) {
        for (int k = 0; k < 3; ++k) {
            require(std::isfinite(lo[k]) && std::isfinite(hi[k]), "box corner coordinate", std::isfinite(lo[k]) ? hi[k] : lo[k],
                    "must be finite");
            require(hi[k] > lo[k], "box extent (m)", hi[k] - lo[k], "must be > 0 along every axis");
        }
    }
    [[nodiscard]] const vec3& lo() const { return lo_; }
    [[nodiscard]] const vec3& hi() const { return hi_; }
    [[nodiscard]] Bounds bounds() const { return {lo_, hi_}; }
    [[nodiscard]] bool contains(const vec3& p) const {
        return p.x >= lo_.x && p.x <= hi_.x && p.y >= lo_.y && p.y <= hi_.y && p.z >= lo_.z && p.z <= hi_.z;
    }

    [[nodiscard]] std::optional<ShapeHit> intersect(const vec3& o, const vec3& d, double t_max) const {
        double t_near = -INFINITY, t_far = INFINITY;
        int near_axis = -1, far_axis = -1;
        for (int k = 0; k < 3; ++k) {
            if (d[k] == 0.0) {  // parallel to the planes of axis k: strictly between them, or never in
                if (o[k] <= lo_[k] || o[k] >= hi_[k]) return std::nullopt;
                continue;
            }
            const double ta = (lo_[k] - o[k]) / d[k], tb = (hi_[k] - o[k]) / d[k];
            const double t0 = std::min(ta, tb), t1 = std::max(ta, tb);
            if (t0 > t_near) {
                t_near = t0;
                near_axis = k;
            }
            if (t1 < t_far) {
                t_far = t1;
                far_axis = k;
            }
        }
        // The ray is in the box for t in [t_near, t_far]. Not entered at all: t_near >= t_far
        // (a segment of length 0 is an edge or a corner grazed, or a face slid along).
        if (!(t_near < t_far)) return std::nullopt;
        double t;
        int axis;
        if (t_near >= 0.0) {  // enters at t_near (from outside or from the surface)
            t = t_near;
            axis = near_axis;
        } else if (t_far > 0.0) {  // starts inside: leaves at t_far
            t = t_far;
            axis = far_axis;
        } else {
            return std::nullopt;  // behind the ray, or leaving from the surface
        }
        if (!(t < t_max)) return std::nullopt;
        vec3 n(0.0);
        n[axis] = d[axis] > 0.0 ? -1.0 : 1.0;  // facing the ray
        return ShapeHit{t, n};
    }

private:
    vec3 lo_, hi_;
};

/// A sphere of centre c and radius r (metres).
class Sphere {
public:
    Sphere(const vec3& centre, double radius) : c_(centre), r_(radius) {
        for (int k = 0; k < 3; ++k) require(std::isfinite(centre[k]), "sphere centre coordinate", centre[k], "must be finite");
        require(std::isfinite(radius) && radius > 0.0, "sphere radius (m)", radius, "must be finite and > 0");
    }
    [[nodiscard]] const vec3& centre() const { return c_; }
    [[nodiscard]] double radius() const { return r_; }
    [[nodiscard]] Bounds bounds() const { return {c_ - vec3(r_), c_ + vec3(r_)}; }
    [[nodiscard]] bool contains(const vec3& p) const { return glm::length(p - c_) <= r_; }

    [[nodiscard]] std::optional<ShapeHit> intersect(const vec3& o, const vec3& d, double t_max) const {
        const vec3 oc = o - c_;
        const double b = glm::dot(oc, d), q = glm::dot(oc, oc) - r_ * r_;
        const double disc = b * b - q;
        if (!(disc > 0.0)) return std::nullopt;  // misses, or touches at one point (grazes)
        const double s = std::sqrt(disc);
        const double big = -(b + std::copysign(s, b));  // the root of larger magnitude (nonzero: disc > 0)
        const double other = q / big;
        const double t0 = std::min(big, other), t1 = std::max(big, other);
        double t;
        if (t0 >= 0.0 && q >= 0.0) t = t0;  // from outside or the surface, moving in (t0 >= 0)
        else if (t1 > 0.0 && t0 < 0.0) t = t1;  // from inside: leaves at t1
        else return std::nullopt;
        if (!(t < t_max)) return std::nullopt;
        vec3 n = (oc + d * t) / r_;
        n /= glm::length(n);
        if (glm::dot(n, d) > 0.0) n = -n;  // facing the ray (inward when leaving)
        return ShapeHit{t, n};
    }

private:
    vec3 c_;
    double r_;
};

/// A SceneGeometry of shapes, each with a material (ObjectMaterial): the closest hit over
/// all of them (a linear scan: for a few objects; many would want a bounding-volume hierarchy).
class Shapes {
public:
    using Shape = std::variant<AxisBox, Sphere>;
    static constexpr bool has_objects = true;

    /// Adds a shape of material `m`; returns *this.
    Shapes& add(const Shape& shape, ObjectMaterial m) {
        shapes_.push_back(shape);
        materials_.push_back(ObjectMaterial::checked(std::move(m)));  // checked again: built by aggregate init
        bounds_ = bounds_.merged(std::visit([](const auto& s) { return s.bounds(); }, shape));
        return *this;
    }
    [[nodiscard]] std::size_t size() const { return shapes_.size(); }

    [[nodiscard]] std::optional<ObjectHit> closest_hit(const vec3& o, const vec3& d, double t_max) const {
        std::optional<ObjectHit> best;
        for (std::size_t i = 0; i < shapes_.size(); ++i) {
            const double limit = best ? best->t : t_max;
            const auto h = std::visit([&](const auto& s) { return s.intersect(o, d, limit); }, shapes_[i]);
            if (h) best = ObjectHit{h->t, o + d * h->t, h->normal, static_cast<std::uint32_t>(i)};
        }
        return best;
    }
    [[nodiscard]] const ObjectMaterial& material(std::uint32_t index) const { return materials_[index]; }
    [[nodiscard]] Bounds bounds() const { return bounds_; }

private:
    std::vector<Shape> shapes_;
    std::vector<ObjectMaterial> materials_;  ///< one per shape (the material index is the shape's)
    Bounds bounds_;
};

static_assert(SceneGeometry<Shapes>);

}  // namespace secchi
