#pragma once
// The plane-parallel water body: horizontally infinite, represented by a finite horizontal
// section of width W with periodic wrap of photon positions (a photon leaving one side
// re-enters at the other; stored positions lie in [0, W) x [0, W)). Depth z is positive
// down from the surface at z = 0. The bottom is one of:
//  - none (infinitely deep): without an escape depth (the default) photons are followed at
//    any depth until absorption ends them; with one, photons that go below it moving down are
//    counted as transmitted and stop (an explicit cut-off, whose loss is the caller's to bound);
//  - transparent at `depth`: a finite slab over nothing (photons leaving are transmitted);
//  - Lambertian at `depth` with irradiance reflectance `albedo` (opaque).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

enum class BottomKind { none, transparent, lambertian };

struct Bottom {
    BottomKind kind = BottomKind::none;
    double depth = INFINITY;  ///< metres
    double albedo = 0.0;      ///< irradiance reflectance Eu/Ed of a Lambertian bottom

    static Bottom infinitely_deep() { return {}; }
    static Bottom transparent_at(double depth) {
        require(std::isfinite(depth) && depth > 0.0, "bottom depth", depth, "must be finite and > 0");
        return {BottomKind::transparent, depth, 0.0};
    }
    static Bottom lambertian_at(double depth, double albedo) {
        require(std::isfinite(depth) && depth > 0.0, "bottom depth", depth, "must be finite and > 0");
        require(std::isfinite(albedo) && albedo >= 0.0 && albedo <= 1.0, "bottom albedo", albedo, "must be in [0, 1]");
        return {BottomKind::lambertian, depth, albedo};
    }
};

class Slab {
public:
    Slab(double section_width, Bottom bottom, double escape_depth = INFINITY)
        : width_(section_width), bottom_(bottom), escape_depth_(escape_depth) {
        require(std::isfinite(section_width) && section_width > 0.0, "section width", section_width, "must be > 0");
        require(bottom.kind != BottomKind::none || (escape_depth > 0.0), "escape depth", escape_depth, "must be > 0");
    }
    [[nodiscard]] double width() const { return width_; }
    [[nodiscard]] const Bottom& bottom() const { return bottom_; }
    /// Depth at which a downward photon leaves the water body (bottom or escape depth).
    [[nodiscard]] double floor_depth() const { return bottom_.kind == BottomKind::none ? escape_depth_ : bottom_.depth; }
    /// Periodic wrap of a horizontal coordinate into [0, W).
    /// For a double, or a SIMD vector of doubles or floats (photons in lanes).
    template <class Real>
    [[nodiscard]] Real wrap(Real x) const {
        using std::floor;
        using T = scalar_t<Real>;
        const T width = T(width_);
        const Real w = x - width * floor(x / width);
        return select(w < width, w, Real(T(0)));
    }

private:
    double width_;
    Bottom bottom_;
    double escape_depth_;
};

}  // namespace secchi
