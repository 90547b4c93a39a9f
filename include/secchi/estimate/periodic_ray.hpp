#pragma once
// The pieces of a ray in a periodic section, with their images.
//
// The water body is horizontally periodic (scene/slab.hpp): the photons stored in the section
// [0, W)^2 stand for their images at (x + m W, y + n W, z) for every integer m, n. A ray (any
// origin, direction and length) runs through this unwrapped plane, crossing the seams x = m W
// and y = n W. Its collection volume is gathered from the stored photons in two steps:
//  - pieces: the ray cut at the seams into segments [t0, t1) of the unwrapped ray, each
//    translated by whole widths (its cell's offset (m W, n W, 0)) into the section, where it
//    lies in [0, W]^2 (closed: a piece may end on a seam);
//  - images: a region around a piece or a point that reaches across a section edge holds,
//    beyond that edge, the photons stored near the opposite edge. Each horizontal shift s =
//    (i W, j W, 0), i, j in {-1, 0, 1}, for which the region moved by s meets the section is
//    queried with the region moved by s: a stored photon q found there lies, unwrapped, at
//    q - s + (the piece's cell offset). With the region within W/2 of the section (collection
//    radius r < W/2), these shifts reach every photon in it, each image once.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/map/store.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace secchi::SECCHI_ISA {

/// The horizontal section [0, W)^2 of a periodic water body (scene/slab.hpp: Slab::width()).
class PeriodicSection {
public:
    explicit PeriodicSection(double width) : width_(width) {
        require(std::isfinite(width) && width > 0.0, "section width", width, "must be finite and > 0");
    }
    [[nodiscard]] double width() const { return width_; }

    /// Refuses a collection radius of W/2 or more: a region that wide would need images beyond
    /// the neighbouring sections.
    void require_radius(double r) const {
        require(r < 0.5 * width_, "radius", r,
                "must be < half the section width (W = " + std::to_string(width_) + " m): the collection volume's "
                "images are taken from the neighbouring sections only");
    }

    /// The offset (m W, n W, 0) of the cell of the unwrapped plane that holds p: p minus it lies
    /// in the section (up to rounding).
    [[nodiscard]] vec3 cell_offset(const vec3& p) const {
        return {width_ * std::floor(p.x / width_), width_ * std::floor(p.y / width_), 0.0};
    }

    /// Calls f(shift) for each horizontal shift s = (i W, j W, 0), i, j in {-1, 0, 1}, for which
    /// a region whose horizontal extent is [lo_x, hi_x] x [lo_y, hi_y] (within W/2 of the
    /// section), moved by s, meets the section [0, W)^2: (0, 0, 0) first. A region reaching
    /// below 0 is moved by +W, one reaching above W by -W.
    template <class F>
    void for_each_image(double lo_x, double hi_x, double lo_y, double hi_y, F&& f) const {
        const Shifts sx = shifts(lo_x, hi_x), sy = shifts(lo_y, hi_y);
        for (int i = 0; i < sx.size; ++i)
            for (int j = 0; j < sy.size; ++j) f(vec3(sx.value[i], sy.value[j], 0.0));
    }

    /// Calls f(piece, t0, offset) for each piece of the unwrapped ray, in order along it: piece
    /// is the segment [t0, t0 + piece.t_max] of `ray` moved by -offset (its cell's offset) into
    /// the section. The pieces' lengths sum to ray.t_max; a ray that crosses no seam is one
    /// piece, t0 = 0. A ray through a corner (x and y seams crossed at one computed t) is cut once there.
    template <class F>
    void for_each_piece(const Ray& ray, F&& f) const {
        SeamCrossings x(ray.origin.x, ray.direction.x, width_), y(ray.origin.y, ray.direction.y, width_);
        double t0 = 0.0;
        while (t0 < ray.t_max) {
            const double t1 = std::min({x.next, y.next, ray.t_max});
            if (x.next == t1) x.advance();
            if (y.next == t1) y.advance();
            if (t1 <= t0) continue;  // a crossing at the ray's start
            const vec3 offset = cell_offset(ray.origin + (0.5 * (t0 + t1)) * ray.direction);
            f(Ray{ray.origin + t0 * ray.direction - offset, ray.direction, t1 - t0}, t0, offset);
            t0 = t1;
        }
    }

    /// Calls f(query, t0) for every piece of the ray (for_each_piece) and each of its images
    /// whose cylinder of radius r meets the section (for_each_image): query is the piece moved
    /// by the image's shift. A photon at distance t along a query lies at t0 + t along the ray.
    template <class F>
    void for_each_piece_image(const Ray& ray, double r, F&& f) const {
        for_each_piece(ray, [&](const Ray& piece, double t0, const vec3&) {
            const vec3 a = piece.origin, b = piece.origin + piece.t_max * piece.direction;
            for_each_image(std::min(a.x, b.x) - r, std::max(a.x, b.x) + r, std::min(a.y, b.y) - r,
                           std::max(a.y, b.y) + r, [&](const vec3& shift) {
                               f(Ray{piece.origin + shift, piece.direction, piece.t_max}, t0);
                           });
        });
    }

private:
    /// The shifts along one axis of a region spanning [lo, hi] there: 0, then +W if it reaches
    /// below 0, -W if it reaches above W.
    struct Shifts {
        std::array<double, 3> value{};
        int size = 1;
    };
    [[nodiscard]] Shifts shifts(double lo, double hi) const {
        Shifts s;
        if (lo < 0.0) s.value[s.size++] = width_;
        if (hi > width_) s.value[s.size++] = -width_;
        return s;
    }

    /// The parameters t at which a ray's coordinate o + u t crosses the seams (multiples of
    /// W), in increasing order, from the first one ahead of the origin (a seam at the origin
    /// itself is not a crossing); infinity if u = 0.
    struct SeamCrossings {
        SeamCrossings(double o, double u, double w) : origin(o), direction(u), width(w) {
            if (u == 0.0) return;
            seam = u > 0.0 ? std::floor(o / w) + 1.0 : std::ceil(o / w) - 1.0;
            next = (seam * w - o) / u;
        }
        void advance() {
            seam += direction > 0.0 ? 1.0 : -1.0;
            next = (seam * width - origin) / direction;
        }
        double origin, direction, width;
        double seam = 0.0;
        double next = std::numeric_limits<double>::infinity();
    };

    double width_;
};

}  // namespace secchi
