#pragma once
// The air-water surface as a policy of the first pass: what a photon meets when it reaches
// the mean surface plane z = 0 (z positive down) moving down from the air or up from the
// water. A hit gives the unpolarised Fresnel reflectance at the facet the photon meets and the
// two directions it may go on in; the tracer chooses between them (transport/tracer.hpp) and
// lets the photon meet the surface again while its direction points back across it (a
// wind-blown surface's tilted facets can send light down into the air side or up into the
// water side). Models: FlatSurface (flat_surface.hpp), WindBlownSurface (wind_blown_surface.hpp).
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include <concepts>

namespace secchi::SECCHI_ISA {

/// The side of the surface a photon arrives from.
enum class Side { air, water };

/// One meeting of a photon with the surface, at the facet it hits.
struct SurfaceHit {
    double reflectance;  ///< unpolarised Fresnel reflectance at the facet (1: total internal reflection)
    vec3 reflected;      ///< the direction after reflection
    vec3 transmitted;    ///< after refraction into the other side (unused where reflectance is 1)
};

/// A surface policy: hit(direction, side, rng) for a photon arriving from `side`, and
/// random_facets, false when a hit draws no random numbers (the tracer then computes the sun's
/// photons' hit once).
template <class S>
concept AirWaterSurface = requires(const S& s, const vec3& dir, Side side, PhotonRng& rng) {
    { s.hit(dir, side, rng) } -> std::same_as<SurfaceHit>;
    { s.water_index() } -> std::convertible_to<double>;
    { S::random_facets } -> std::convertible_to<bool>;
};

}  // namespace secchi
