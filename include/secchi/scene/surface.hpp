#pragma once
// The air-water surface as a policy of the first pass: what a photon meets when it reaches
// the mean surface plane z = 0 (z positive down) moving down from the air or up from the
// water. A hit gives the unpolarised Fresnel reflectance at the facet the photon meets and the
// two directions it may go on in; the tracer chooses between them (transport/tracer.hpp) and
// lets the photon meet the surface again while its direction points back across it (a
// wind-blown surface's tilted facets can send light down into the air side or up into the
// water side). Models: FlatSurface (flat_surface.hpp), WindBlownSurface (wind_blown_surface.hpp).
// A surface with geometry (GeometricSurface: SinusoidalWave, wave_surface.hpp; WaveSum,
// wave_sum.hpp) is met where a photon's path crosses it, at its local normal, instead of on the
// mean plane. AnySurface (any_surface.hpp) holds a flat or wind-blown surface chosen at run time.
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include <concepts>
#include <optional>

namespace secchi::SECCHI_ISA {

/// The side of the surface a photon arrives from.
enum class Side { air, water };

/// One meeting of a photon with the surface, at the facet it hits.
struct SurfaceHit {
    double reflectance;  ///< unpolarised Fresnel reflectance at the facet (1: total internal reflection)
    vec3 reflected;      ///< the direction after reflection
    vec3 transmitted;    ///< after refraction into the other side (unused where reflectance is 1)

    /// The direction after the Fresnel choice. Chosen component by component: selecting the
    /// whole vector made GCC 12 load it across the two stores that wrote it (a failed store
    /// forward, about 20 cycles, once per photon crossing the surface).
    [[nodiscard]] vec3 direction(bool reflect) const {
        return {reflect ? reflected.x : transmitted.x, reflect ? reflected.y : transmitted.y,
                reflect ? reflected.z : transmitted.z};
    }
};

/// A surface policy: hit(direction, side, rng) for a photon arriving from `side`, and
/// random_facets, false when a hit draws no random numbers (the tracer then computes the sun's
/// photons' hit once). A surface whose kind is known only at run time (AnySurface,
/// any_surface.hpp) has random_facets true and may say by fixed_hit(direction), an optional
/// SurfaceHit, where a hit from the air draws nothing after all.
template <class S>
concept AirWaterSurface = requires(const S& s, const vec3& dir, Side side, PhotonRng& rng) {
    { s.hit(dir, side, rng) } -> std::same_as<SurfaceHit>;
    { s.water_index() } -> std::convertible_to<double>;
    { S::random_facets } -> std::convertible_to<bool>;
};

/// The hit of every photon arriving from the air along `dir` where the surface draws no random
/// numbers for it (random_facets false, or a run-time surface's fixed_hit says so), computed
/// once; nothing where each photon meets its own facet.
template <AirWaterSurface S>
std::optional<SurfaceHit> fixed_hit_from_air(const S& surface, const vec3& dir) {
    if constexpr (requires { surface.fixed_hit(dir); }) return surface.fixed_hit(dir);
    else if constexpr (S::random_facets) return std::nullopt;
    else {
        PhotonRng unused(0, 0);
        return surface.hit(dir, Side::air, unused);
    }
}

/// A surface policy with geometry, lying between depths crest_depth() (<= 0) and
/// trough_depth() (>= 0): first_crossing(o, d, side, t_max) is the first distance t in
/// (0, t_max] at which the ray o + t d, starting on `side`, reaches the surface (or nothing);
/// hit_at(p, d, side) the meeting at surface point p; normal_into_water(x, y) the unit normal
/// pointing into the water; periodic_in(W) whether it repeats over a section of width W.
template <class S>
concept GeometricSurface = requires(const S& s, const vec3& p, const vec3& d, Side side, double t) {
    { s.first_crossing(p, d, side, t) } -> std::same_as<std::optional<double>>;
    { s.hit_at(p, d, side) } -> std::same_as<SurfaceHit>;
    { s.normal_into_water(t, t) } -> std::same_as<vec3>;
    { s.crest_depth() } -> std::convertible_to<double>;
    { s.trough_depth() } -> std::convertible_to<double>;
    { s.periodic_in(t) } -> std::convertible_to<bool>;
    { s.water_index() } -> std::convertible_to<double>;
};

/// What the first pass (PhotonTracer) accepts: a facet policy or a surface with geometry.
template <class S>
concept SurfacePolicy = AirWaterSurface<S> || GeometricSurface<S>;

}  // namespace secchi
