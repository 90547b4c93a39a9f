#pragma once
// The bottom of a plane-parallel water body, as a policy. Depth z is positive down from the
// surface; a photon meets the bottom at z = depth() moving down (dir.z > 0).
//
// BottomModel (what the first pass needs, transport/tracer.hpp):
//   depth()                        metres; +infinity: no bottom (infinitely deep water)
//   transmits()                    true: light reaching depth() leaves the water body there
//                                  (a finite slab over nothing, or no bottom); false: opaque
//   reflectance(in)                directional-hemispherical reflectance rho(in) in [0, 1] of an
//                                  opaque bottom for light arriving in direction `in`: the share
//                                  of a photon's weight that leaves it, int f_r(in, out) mu_out
//                                  d omega_out (the rest is absorbed by the bottom)
//   reflected_direction(in, u1, u2) an upward direction (dir.z < 0) drawn with pdf
//                                  f_r(in, out) mu_out / rho(in), from two uniforms in [0, 1)
// A photon of weight w arriving at an opaque bottom leaves it with weight w rho(in) (implicit
// capture) or survives with probability rho(in) (analog), in a direction from
// reflected_direction: an unbiased estimate of the BRDF's reflected flux for any f_r.
//
// IrradianceBottom (what the second pass needs, estimate/radiance.hpp): a BottomModel whose
// reflected radiance follows from the plane irradiance Ed arriving on it,
//   radiance_per_irradiance()      L_leaving / Ed in 1/sr, the same in every upward direction.
// By reciprocity a BRDF that does not depend on the direction of incidence does not depend on
// the direction of reflection either: that is the Lambertian bottom, L = A Ed / pi (M93 eq. 11).
// Any other BRDF needs the incident radiance distribution on the bottom, which the photon map
// does not keep: the second pass accepts IrradianceBottoms only (a map of another bottom does
// not compile), so no ray sees a wrong bottom term.
//
// Bottom, below, is the plane-parallel default (the canonical problems', the CLI's and the
// material files'): no bottom, transparent, or Lambertian, chosen at run time. Another model
// (scene/minnaert_bottom.hpp) is a type of its own, composed at compile time.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include <cmath>
#include <concepts>

namespace secchi::SECCHI_ISA {

template <class B>
concept BottomModel = std::copy_constructible<B> && requires(const B& b, const vec3& in, double u) {
    { b.depth() } -> std::convertible_to<double>;
    { b.transmits() } -> std::convertible_to<bool>;
    { b.reflectance(in) } -> std::convertible_to<double>;
    { b.reflected_direction(in, u, u) } -> std::same_as<vec3>;
};

template <class B>
concept IrradianceBottom = BottomModel<B> && requires(const B& b) {
    { b.radiance_per_irradiance() } -> std::convertible_to<double>;
};

/// The upward direction at cosine mu from the upward normal (-z) and azimuth 2 pi u_phi.
inline vec3 upward_direction(double mu, double u_phi) {
    const double phi = two_pi * u_phi;
    const double sin_t = std::sqrt(1.0 - mu * mu);
    return {sin_t * std::cos(phi), sin_t * std::sin(phi), -mu};
}

enum class BottomKind { none, transparent, lambertian };

/// No bottom, a transparent one at a depth, or a Lambertian one at a depth with irradiance
/// reflectance (albedo) A = Eu / Ed: f_r = A / pi.
class Bottom {
public:
    Bottom() = default;  ///< infinitely deep

    static Bottom infinitely_deep() { return {}; }
    static Bottom transparent_at(double depth) { return {BottomKind::transparent, checked_depth(depth), 0.0}; }
    static Bottom lambertian_at(double depth, double albedo) {
        require(std::isfinite(albedo) && albedo >= 0.0 && albedo <= 1.0, "bottom albedo", albedo, "must be in [0, 1]");
        return {BottomKind::lambertian, checked_depth(depth), albedo};
    }

    [[nodiscard]] BottomKind kind() const { return kind_; }
    [[nodiscard]] double depth() const { return depth_; }
    [[nodiscard]] double albedo() const { return albedo_; }  ///< A of a Lambertian bottom, else 0

    [[nodiscard]] bool transmits() const { return kind_ != BottomKind::lambertian; }
    [[nodiscard]] double reflectance(const vec3&) const { return albedo_; }
    /// Cosine-weighted: mu = sqrt(u1) (pdf mu / pi over the upward hemisphere).
    [[nodiscard]] vec3 reflected_direction(const vec3&, double u1, double u2) const {
        return upward_direction(std::sqrt(u1), u2);
    }
    [[nodiscard]] double radiance_per_irradiance() const { return albedo_ / pi; }

private:
    Bottom(BottomKind kind, double depth, double albedo) : kind_(kind), depth_(depth), albedo_(albedo) {}
    static double checked_depth(double depth) {
        require(std::isfinite(depth) && depth > 0.0, "bottom depth", depth, "must be finite and > 0");
        return depth;
    }

    BottomKind kind_ = BottomKind::none;
    double depth_ = INFINITY;  ///< metres
    double albedo_ = 0.0;
};

static_assert(IrradianceBottom<Bottom>);

}  // namespace secchi
