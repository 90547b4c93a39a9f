#pragma once
// The flat air-water surface at depth z = 0 (z positive down): unpolarised Fresnel
// reflection and refraction both ways, total internal reflection from below. A water index
// of exactly 1.0 means "no interface": nothing is reflected and directions are unchanged.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/scene/fresnel.hpp"
#include "secchi/scene/surface.hpp"

namespace secchi::SECCHI_ISA {

class FlatSurface {
public:
    explicit FlatSurface(double water_index = 1.34, double air_index = 1.0)
        : n_water_(water_index), n_air_(air_index) {
        require(std::isfinite(water_index) && water_index >= 1.0, "water index", water_index, "must be >= 1");
        require(std::isfinite(air_index) && air_index >= 1.0, "air index", air_index, "must be >= 1");
    }
    [[nodiscard]] double water_index() const { return n_water_; }
    [[nodiscard]] double air_index() const { return n_air_; }
    [[nodiscard]] bool is_interface() const { return n_water_ != n_air_; }

    /// The AirWaterSurface policy (surface.hpp): every photon meets the one horizontal facet.
    static constexpr bool random_facets = false;
    [[nodiscard]] SurfaceHit hit(const vec3& dir, Side from, PhotonRng& /*unused*/) const {
        if (from == Side::air) return {reflectance_from_air(dir), reflect(dir), transmit_into_water(dir)};
        return {reflectance_from_water(dir), reflect(dir), transmit_into_air(dir)};
    }

    /// Reflectance for a downward direction arriving from the air.
    [[nodiscard]] double reflectance_from_air(const vec3& dir) const {
        return is_interface() ? fresnel_reflectance(dir.z, n_air_, n_water_) : 0.0;
    }
    /// Reflectance for an upward direction arriving from the water (1 beyond the critical angle).
    [[nodiscard]] double reflectance_from_water(const vec3& dir) const {
        return is_interface() ? fresnel_reflectance(-dir.z, n_water_, n_air_) : 0.0;
    }
    [[nodiscard]] vec3 transmit_into_water(const vec3& dir) const { return refract_horizontal(dir, n_air_, n_water_); }
    [[nodiscard]] vec3 transmit_into_air(const vec3& dir) const { return refract_horizontal(dir, n_water_, n_air_); }
    static vec3 reflect(const vec3& dir) { return {dir.x, dir.y, -dir.z}; }

private:
    double n_water_;
    double n_air_;
};

static_assert(AirWaterSurface<FlatSurface>);

}  // namespace secchi
