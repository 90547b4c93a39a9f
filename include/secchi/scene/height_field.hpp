#pragma once
// A bottom terrain given as a height field over the periodic section: a SceneGeometry
// (scene/geometry.hpp) whose solid is everything below a piecewise-linear surface.
//
// The terrain: depths h_ij (m, positive down, z down as everywhere in secchi) at the nx x ny
// nodes (x_i, y_j) = (i W / nx, j W / ny) of the section [0, W)^2, index j nx + i, repeating
// with period W in x and y: node (nx, j) is node (0, j) and (i, ny) is (i, 0), so the terrain
// joins its periodic copies without a seam. Cell (i, j) = [x_i, x_i+1] x [y_j, y_j+1], with local
// coordinates u = (x - x_i) / dx, v = (y - y_j) / dy in [0, 1] (dx = W / nx, dy = W / ny), is
// split along its diagonal from node (i, j) to node (i + 1, j + 1) into two triangles:
//   lower (u >= v): nodes (i, j), (i+1, j), (i+1, j+1):  h = h00 + (h10 - h00) u + (h11 - h10) v
//   upper (v >= u): nodes (i, j), (i+1, j+1), (i, j+1):  h = h00 + (h11 - h01) u + (h01 - h00) v
// (hab = h at node (i + a, j + b)), so the surface z = h(x, y) is continuous, linear on each of
// the 2 nx ny triangles. On a triangle of slopes s_x = dh/dx, s_y = dh/dy the unit normal
// pointing out of the solid, up into the water, is n = (s_x, s_y, -1) / sqrt(1 + s_x^2 + s_y^2).
// The solid is z >= h(x, y), down to floor_depth (the slab's floor): bounds() is
// [0, W] x [0, W] x [min h, floor_depth]. One ObjectMaterial, index 0, for the whole terrain
// (an AlbedoMap reads A(x, y) of the point met, as for any object). nx = 1 or ny = 1 is allowed:
// the terrain is then constant along that axis on the grid lines (nx = ny = 1: a flat bottom
// at h_00).
//
// closest_hit(o, d, t_max): the smallest t in [0, t_max) where o + t d (d a unit vector) enters
// the solid through the terrain, over this copy's column [0, W] x [0, W] only (periodic_closest_hit
// asks each copy for the hits in its own cell: geometry.hpp). Along the ray, its height above
// the plane of one triangle is
//     g(t) = h(o_xy + t d_xy) - (o_z + t d_z) = g0 + g1 t,   g1 = s_x d_x + s_y d_y - d_z
// (g > 0 above the plane, in the water), with g1 = sqrt(1 + s_x^2 + s_y^2) n . d: the ray enters the
// solid through the triangle's front (upper) side where g1 < 0, at t = -g0 / g1, if that point
// lies over the triangle. Its underside (g1 >= 0) is never met: photons are always above the
// terrain, in the water. No side walls: since the terrain is periodic, a photon above it is
// above it in every copy too, and never meets the walls of a column from inside the solid; the
// column only bounds which copy answers for a point.
// Algorithm (grid tracing of height fields, Musgrave 1988): the ray is clipped to the column
// and to the depths [min h, max h] of the nodes (which hold every triangle; widened by
// 1e-9 max(1 m, max h) against rounding); the cells it crosses are walked in order (a 2-D DDA,
// Amanatides & Woo 1987, "A fast voxel traversal algorithm for ray tracing", Eurographics '87),
// and each cell's part of the ray is cut where it crosses the diagonal into parts over one
// triangle each. g is evaluated in double precision at the ends of the parts: each sample ends
// one part and starts the next (the value is carried over, not recomputed from the next
// triangle), so the samples along the ray form one sequence, and a ray above the terrain at
// one sample and on or below it at the next enters the solid in between: it cannot slip
// through a shared edge or vertex between two triangles (watertight). The first part where g
// goes from > 0 to <= 0, or that starts at 0 (on the terrain) on a triangle the ray enters
// from its front side (g1 < 0), holds the closest hit, at t = -g0 / g1 on that triangle's plane
// (clamped to the part: it is within it but for rounding). The sign change alone decides: on a
// plane nearly parallel to the ray the rounded samples may fall while the rounded slope g1 is
// >= 0 (as with fused multiply-adds, -ffp-contract=fast on a target with FMA), and the hit is
// then at the part's end. Vertical rays (d_x = d_y = 0) make
// one part in the one cell under them; level rays (d_z = 0) are at the terrain's depths along
// their whole chord of the column, or never.
// Tolerance: where the walk starts (the origin, or where the ray enters the column or the
// depth band), a ray within 1e-12 max(1 m, max h) of the terrain (|g|) is on it: moving into
// the solid it meets the terrain there (t = 0 at the origin) exactly; moving out (or along),
// it does not. (A point on the terrain is computed to a few ulps of the depths; the tracer
// moves a reflected photon 1e-9 m off the surface along the normal, far more than this. At a
// seam the two copies evaluate the terrain at the ray's crossing each from its own frame: the
// tolerance makes a ray crossing the terrain there, to rounding, meet one of them.)
// Cost: one DDA step and one or two plane evaluations per cell crossed.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/geometry.hpp"
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

class HeightField {
public:
    static constexpr bool has_objects = true;
    /// The terrain of depths `depths` (m, index j nx + i) at the nodes (i W / nx, j W / ny) of
    /// the section of width W, above the floor at `floor_depth`, of material `material`.
    HeightField(unsigned nx, unsigned ny, double width, double floor_depth, std::vector<double> depths,
                ObjectMaterial material)
        : nx_(nx), ny_(ny), width_(width), floor_depth_(floor_depth), h_(std::move(depths)),
          material_(ObjectMaterial::checked(std::move(material))) {
        require(nx >= 1 && ny >= 1, "height field nodes per side", std::min(nx, ny), "must be >= 1");
        require(std::isfinite(width) && width > 0.0, "height field width (m)", width, "must be finite and > 0");
        require(std::isfinite(floor_depth) && floor_depth > 0.0, "height field floor depth (m)", floor_depth,
                "must be finite and > 0");
        const std::size_t n = static_cast<std::size_t>(nx) * ny;
        require(h_.size() == n, "height field depths", h_.size(), "must be nx x ny = " + std::to_string(n));
        for (std::size_t k = 0; k < n; ++k) {
            require(std::isfinite(h_[k]) && h_[k] >= 0.0, indexed_name("height field depth", k), h_[k],
                    "must be finite and >= 0 (below the surface)");
            require(h_[k] < floor_depth, indexed_name("height field depth", k), h_[k],
                    "must be above the floor depth, " + std::to_string(floor_depth) + " m");
        }
        dx_ = width_ / nx_;
        dy_ = width_ / ny_;
        min_h_ = *std::min_element(h_.begin(), h_.end());
        max_h_ = *std::max_element(h_.begin(), h_.end());
        on_surface_ = 1e-12 * std::max(1.0, max_h_);
        band_margin_ = 1e-9 * std::max(1.0, max_h_);
    }

    /// The terrain of depths f(x, y) (m) sampled at the nodes (i W / nx, j W / ny).
    template <class F>
    static HeightField from_function(unsigned nx, unsigned ny, double width, double floor_depth, F&& f,
                                     ObjectMaterial material) {
        std::vector<double> depths;
        depths.reserve(static_cast<std::size_t>(nx) * ny);
        for (unsigned j = 0; j < ny; ++j)
            for (unsigned i = 0; i < nx; ++i)
                depths.push_back(f(width * i / nx, width * j / ny));
        return HeightField(nx, ny, width, floor_depth, std::move(depths), std::move(material));
    }

    [[nodiscard]] unsigned nx() const { return nx_; }
    [[nodiscard]] unsigned ny() const { return ny_; }
    [[nodiscard]] double width() const { return width_; }
    [[nodiscard]] double floor_depth() const { return floor_depth_; }
    [[nodiscard]] double min_depth() const { return min_h_; }
    [[nodiscard]] double max_depth() const { return max_h_; }
    /// The depth at node (i, j), i <= nx, j <= ny (node nx is node 0: periodic).
    [[nodiscard]] double node_depth(unsigned i, unsigned j) const {
        return h_[static_cast<std::size_t>(j % ny_) * nx_ + i % nx_];
    }

    /// The terrain's depth h(x, y) (m) at any x, y (periodic with W): the interpolant on the
    /// triangle under the point.
    [[nodiscard]] double depth_at(double x, double y) const {
        const double xw = periodic_wrap(x, width_), yw = periodic_wrap(y, width_);
        const unsigned i = std::min(nx_ - 1, static_cast<unsigned>(xw / dx_));
        const unsigned j = std::min(ny_ - 1, static_cast<unsigned>(yw / dy_));
        const double u = xw / dx_ - i, v = yw / dy_ - j;
        const Plane p = plane(i, j, u >= v);
        return p.h00 + p.a * u + p.b * v;
    }

    [[nodiscard]] std::optional<ObjectHit> closest_hit(const vec3& o, const vec3& d, double t_max) const {
        if (!(t_max > 0.0)) return std::nullopt;
        // The part [t0, t1] of the ray over the column and at the terrain's depths.
        double t0 = 0.0, t1 = t_max;
        for (int k = 0; k < 2; ++k) {
            if (d[k] == 0.0) {
                if (o[k] < 0.0 || o[k] > width_) return std::nullopt;
                continue;
            }
            const double ta = -o[k] / d[k], tb = (width_ - o[k]) / d[k];
            t0 = std::max(t0, std::min(ta, tb));
            t1 = std::min(t1, std::max(ta, tb));
        }
        const double z_lo = min_h_ - band_margin_, z_hi = max_h_ + band_margin_;
        if (d.z == 0.0) {
            if (o.z < z_lo || o.z > z_hi) return std::nullopt;
        } else {
            const double ta = (z_lo - o.z) / d.z, tb = (z_hi - o.z) / d.z;
            t0 = std::max(t0, std::min(ta, tb));
            t1 = std::min(t1, std::max(ta, tb));
        }
        if (!(t0 <= t1)) return std::nullopt;
        // The cells the ray crosses over [t0, t1], in order (2-D DDA), and in each the parts
        // of the ray over its two triangles: the ray's height above the terrain, g, is sampled
        // where it crosses an edge (a cell's side or its diagonal), each sample ending one part
        // and starting the next (watertight: no ray slips between two triangles).
        const auto first_cell = [](double x, double size, unsigned n) {
            const double c = std::floor(x / size);
            return c <= 0.0 ? 0u : (c >= n - 1.0 ? n - 1 : static_cast<unsigned>(c));
        };
        unsigned i = first_cell(o.x + t0 * d.x, dx_, nx_), j = first_cell(o.y + t0 * d.y, dy_, ny_);
        const int step_x = d.x > 0.0 ? 1 : (d.x < 0.0 ? -1 : 0), step_y = d.y > 0.0 ? 1 : (d.y < 0.0 ? -1 : 0);
        double ta = t0;
        double ga = along(i, j, o, d, t0).at(t0);  // g where the walk starts
        if (std::abs(ga) <= on_surface_) ga = 0.0;  // on the terrain (at the origin, or a seam)
        for (unsigned steps = 0; steps <= 2 * (nx_ + ny_); ++steps) {  // at most nx + ny - 1 cells, and corners
            // Where the ray leaves the cell (from the origin each time: no accumulated error).
            const double tx = step_x ? ((i + (step_x > 0 ? 1.0 : 0.0)) * dx_ - o.x) / d.x : INFINITY;
            const double ty = step_y ? ((j + (step_y > 0 ? 1.0 : 0.0)) * dy_ - o.y) / d.y : INFINITY;
            const double t_exit = std::max(ta, std::min({tx, ty, t1}));
            // Where it crosses the diagonal u = v: (u0 - v0) + t (du - dv) = 0.
            const double u0 = (o.x - i * dx_) / dx_, v0 = (o.y - j * dy_) / dy_, du = d.x / dx_, dv = d.y / dy_;
            const double t_diag = du != dv ? (v0 - u0) / (du - dv) : INFINITY;
            const bool split = t_diag > ta && t_diag < t_exit;
            for (int part = 0; part < (split ? 2 : 1); ++part) {
                const double tb = split && part == 0 ? t_diag : t_exit;
                const double tm = 0.5 * (ta + tb);
                const Line g = along(i, j, o, d, tm);  // the plane of the triangle under this part
                const double gb = g.at(tb);
                // Entering the solid in [ta, tb]: from above at ta to on the terrain or below it
                // at tb, or from on it at ta through the triangle's front side.
                if ((ga > 0.0 && gb <= 0.0) || (ga == 0.0 && g.g1 < 0.0)) {
                    const double t = ga == 0.0 ? ta : (g.g1 < 0.0 ? std::clamp(-g.g0 / g.g1, ta, tb) : tb);
                    if (!(t < t_max)) return std::nullopt;
                    return ObjectHit{t, o + d * t, g.normal(dx_, dy_), 0};
                }
                ga = gb;
                ta = tb;
            }
            if (t_exit >= t1) return std::nullopt;
            if (tx <= ty) {
                if ((step_x < 0 && i == 0) || (step_x > 0 && i + 1 == nx_)) return std::nullopt;
                i += step_x;
            } else {
                if ((step_y < 0 && j == 0) || (step_y > 0 && j + 1 == ny_)) return std::nullopt;
                j += step_y;
            }
        }
        return std::nullopt;
    }

    [[nodiscard]] const ObjectMaterial& material(std::uint32_t) const { return material_; }
    [[nodiscard]] Bounds bounds() const { return {{0.0, 0.0, min_h_}, {width_, width_, floor_depth_}}; }

private:
    /// A triangle's plane over its cell: h = h00 + a u + b v (u, v the cell's local coordinates).
    struct Plane {
        double h00, a, b;
    };

    [[nodiscard]] Plane plane(unsigned i, unsigned j, bool lower) const {
        const double h00 = node_depth(i, j), h11 = node_depth(i + 1, j + 1);
        if (lower) {
            const double h10 = node_depth(i + 1, j);
            return {h00, h10 - h00, h11 - h10};
        }
        const double h01 = node_depth(i, j + 1);
        return {h00, h11 - h01, h01 - h00};
    }

    /// The ray's height above the plane of one triangle, g(t) = g0 + g1 t (m), with its slopes.
    struct Line {
        double g0, g1, a, b;  ///< a, b: the plane's dh/du, dh/dv
        [[nodiscard]] double at(double t) const { return g0 + g1 * t; }
        /// The plane's unit normal out of the solid (up): (s_x, s_y, -1) / sqrt(1 + s_x^2 + s_y^2).
        [[nodiscard]] vec3 normal(double dx, double dy) const {
            const double sx = a / dx, sy = b / dy;
            return vec3(sx, sy, -1.0) / std::sqrt(1.0 + sx * sx + sy * sy);
        }
    };

    /// g(t) of the ray on the plane of the triangle of cell (i, j) under the ray at t (the lower
    /// one where u >= v): g0 = h00 + a u0 + b v0 - o_z, g1 = a du + b dv - d_z, (u0, v0) the
    /// origin and (du, dv) the direction in the cell's units.
    [[nodiscard]] Line along(unsigned i, unsigned j, const vec3& o, const vec3& d, double t) const {
        const double u0 = (o.x - i * dx_) / dx_, v0 = (o.y - j * dy_) / dy_, du = d.x / dx_, dv = d.y / dy_;
        const Plane p = plane(i, j, u0 + t * du >= v0 + t * dv);
        return {p.h00 + p.a * u0 + p.b * v0 - o.z, p.a * du + p.b * dv - d.z, p.a, p.b};
    }

    unsigned nx_, ny_;
    double width_, floor_depth_;
    std::vector<double> h_;  ///< m, at node (i, j): index j nx + i
    ObjectMaterial material_;
    double dx_ = 0.0, dy_ = 0.0, min_h_ = 0.0, max_h_ = 0.0;
    double on_surface_ = 0.0;   ///< m: a walk starting this close to the terrain starts on it
    double band_margin_ = 0.0;  ///< m: the walk's depth band reaches this far beyond the nodes' depths
};

static_assert(SceneGeometry<HeightField>);

}  // namespace secchi
