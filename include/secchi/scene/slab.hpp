#pragma once
// The plane-parallel water body: horizontally infinite, represented by a finite horizontal
// section of width W with periodic wrap of photon positions (a photon leaving one side
// re-enters at the other; stored positions lie in [0, W) x [0, W)). Depth z is positive
// down from the surface at z = 0. The bottom is a policy (BottomModel, scene/bottom.hpp); the
// default, Bottom, is one of:
//  - none (infinitely deep): without an escape depth (the default) photons are followed at
//    any depth until absorption ends them; with one, photons that go below it moving down are
//    counted as transmitted and stop (an explicit cut-off, whose loss is the caller's to bound);
//  - transparent at `depth`: a finite slab over nothing (photons leaving are transmitted);
//  - Lambertian at `depth` with irradiance reflectance `albedo` (opaque).
// The floor is where a downward photon leaves the water body or meets its bottom: the
// bottom's depth, or without one the escape depth.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/bottom.hpp"
#include <cmath>
#include <utility>

namespace secchi::SECCHI_ISA {

template <BottomModel B = Bottom>
class BasicSlab {
public:
    using bottom_type = B;

    BasicSlab(double section_width, B bottom, double escape_depth = INFINITY)
        : width_(section_width), bottom_(std::move(bottom)), escape_depth_(escape_depth) {
        require(std::isfinite(section_width) && section_width > 0.0, "section width", section_width, "must be > 0");
        require(has_bottom() || (escape_depth > 0.0), "escape depth", escape_depth, "must be > 0");
    }
    [[nodiscard]] double width() const { return width_; }
    [[nodiscard]] const B& bottom() const { return bottom_; }
    /// Whether the water body has a bottom (at a finite depth).
    [[nodiscard]] bool has_bottom() const { return std::isfinite(bottom_.depth()); }
    /// Depth at which a downward photon leaves the water body (bottom or escape depth).
    [[nodiscard]] double floor_depth() const { return has_bottom() ? bottom_.depth() : escape_depth_; }
    /// Periodic wrap of a horizontal coordinate into [0, W).
    /// For a double, or a SIMD vector of doubles or floats (photons in lanes).
    template <class Real>
    [[nodiscard]] Real wrap(Real x) const {
        return periodic_wrap(x, scalar_t<Real>(width_));
    }

private:
    double width_;
    B bottom_;
    double escape_depth_;
};

/// The plane-parallel water body of the default bottom (none, transparent or Lambertian).
using Slab = BasicSlab<Bottom>;

}  // namespace secchi
