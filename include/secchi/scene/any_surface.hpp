#pragma once
// One of the air-water surfaces on the mean plane (scene/surface.hpp), chosen at run time: flat
// (FlatSurface) or wind-blown facets (WindBlownSurface). An AirWaterSurface itself, each call
// going to the surface it holds (one dispatch per photon meeting the surface, never per
// scattering event), so that a program that lets its user choose compiles each first-pass
// tracer once, not once per surface (solver/plane_parallel.hpp).
#include "secchi/core/config.hpp"
#include "secchi/scene/flat_surface.hpp"
#include "secchi/scene/surface.hpp"
#include "secchi/scene/wind_blown_surface.hpp"
#include <optional>
#include <variant>

namespace secchi::SECCHI_ISA {

class AnySurface {
public:
    AnySurface(FlatSurface s) : surface_(s) {}                   // NOLINT(google-explicit-constructor)
    AnySurface(WindBlownSurface s) : surface_(std::move(s)) {}   // NOLINT(google-explicit-constructor)

    [[nodiscard]] double water_index() const {
        return std::visit([](const auto& s) { return s.water_index(); }, surface_);
    }

    /// The AirWaterSurface policy (surface.hpp). Which surface is held is known only at run
    /// time, so random_facets is true (a hit may draw); fixed_hit says where it does not.
    static constexpr bool random_facets = true;
    [[nodiscard]] SurfaceHit hit(const vec3& dir, Side from, PhotonRng& rng) const {
        return std::visit([&](const auto& s) { return s.hit(dir, from, rng); }, surface_);
    }
    /// The hit of every photon arriving from the air along `dir` where the surface held draws
    /// no random numbers for it (random_facets false: the flat surface), else nothing.
    [[nodiscard]] std::optional<SurfaceHit> fixed_hit(const vec3& dir) const {
        return std::visit([&](const auto& s) { return fixed_hit_from_air(s, dir); }, surface_);
    }

    /// Whether light leaving the surface may be hidden by the other waves (WindBlownSurface's
    /// Shadowing::smith; never for the flat surface).
    [[nodiscard]] bool hides() const {
        const auto* waves = std::get_if<WindBlownSurface>(&surface_);
        return waves && waves->hides();
    }
    /// Whether light leaving the surface along d is hidden (WindBlownSurface::hidden; the flat
    /// surface hides nothing and draws nothing).
    [[nodiscard]] bool hidden(const vec3& d, PhotonRng& rng) const {
        const auto* waves = std::get_if<WindBlownSurface>(&surface_);
        return waves && waves->hidden(d, rng);
    }

    /// The surface held, if it is a T.
    template <class T>
    [[nodiscard]] const T* get_if() const {
        return std::get_if<T>(&surface_);
    }

private:
    std::variant<FlatSurface, WindBlownSurface> surface_;
};

static_assert(AirWaterSurface<AnySurface>);

}  // namespace secchi
