#pragma once
// The light source as a policy of the first pass (manual 3.3.3, "Generating Source Samples"):
// where the photons come from and, for a source with an atmosphere, what becomes of the light
// the surface sends back up. Every photon the tracer shoots carries the same share of the
// source's flux: plane_irradiance() x section area / photons shot (manual 3.3.3, last step:
// normalise by the photons shot, whatever their fate).
//
// A source answers:
//  - plane_irradiance(): the downward plane irradiance its photons represent on the plane where
//    they start (just above the surface for a sun and sky, the top of the atmosphere for a
//    traced atmosphere: M93 Table 5's problem 4 is per unit E_perp there). The tracer's
//    irradiances are in these units.
//  - emit(rng): a photon from the source to the surface: its direction of travel when it meets
//    the surface from the air, or its fate if it never gets there (scattered back to space,
//    absorbed in the air).
//  - returns_light(): whether light going up from the surface can come back down (a traced
//    atmosphere that scatters); reenter(direction, rng) then follows such light from the
//    surface until it comes back down onto the surface, leaves to space or is absorbed.
//  - beam_direction(): the direction of a collimated beam whose photons arrive with exactly that
//    direction (marked `beam`): the tracer computes their surface hit once.
// Models: SunAndSky (sun_and_sky.hpp), ParametricSky (parametric_sky.hpp), TracedAtmosphere
// (atmosphere.hpp), and AnySource (any_source.hpp), one of them chosen at run time.
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include <concepts>

namespace secchi::SECCHI_ISA {

/// What becomes of a photon the source follows.
enum class SourceFate {
    arrives,   ///< it meets the surface from the air, moving down
    to_space,  ///< it leaves through the top of the atmosphere
    absorbed,  ///< it is absorbed in the atmosphere
};

/// A photon from the source (or back from the atmosphere) at the surface.
struct SourcePhoton {
    SourceFate fate = SourceFate::arrives;
    vec3 dir{0.0, 0.0, 1.0};  ///< direction of travel where it arrives (z positive down: dir.z > 0)
    bool beam = false;        ///< exactly beam_direction(): the unscattered beam of a collimated sun
    bool direct = false;      ///< straight from the sun's disk, never scattered (the direct part of Ed(0+))
};

template <class S>
concept LightSource = requires(const S& s, PhotonRng& rng, const vec3& up) {
    { s.plane_irradiance() } -> std::convertible_to<double>;
    { s.beam_direction() } -> std::same_as<vec3>;
    { s.emit(rng) } -> std::same_as<SourcePhoton>;
    { s.returns_light() } -> std::convertible_to<bool>;
    { s.reenter(up, rng) } -> std::same_as<SourcePhoton>;
};

}  // namespace secchi
