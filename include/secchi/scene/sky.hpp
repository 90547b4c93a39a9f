#pragma once
// A uniform (isotropic) sky: the same radiance L from every direction of the upper hemisphere,
// so its downward plane irradiance just above the surface is E = pi L (the integral of
// L cos(theta) over the hemisphere; Mobley 1994, "Light and Water", sec. 1.4). The light it
// sends through a horizontal plane comes with direction density cos(theta) / pi per
// steradian: cos(theta) = sqrt(u1), azimuth 2 pi u2. An irradiance of 0 is a black sky (M93's
// canonical problems). E is in the units of the sun's E_perp (scene/sun.hpp).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

class UniformSky {
public:
    explicit UniformSky(double plane_irradiance = 0.0) : irradiance_(plane_irradiance) {
        require(std::isfinite(plane_irradiance) && plane_irradiance >= 0.0, "sky irradiance", plane_irradiance,
                "must be finite and >= 0 (0: a black sky)");
    }
    /// Downward plane irradiance just above the surface, E = pi L.
    [[nodiscard]] double plane_irradiance() const { return irradiance_; }
    [[nodiscard]] double radiance() const { return irradiance_ / pi; }
    /// The direction of travel (z positive down) of a photon from the sky, for uniforms u1, u2
    /// in (0, 1): density cos(theta) / pi.
    [[nodiscard]] static vec3 direction(double u1, double u2) {
        const double mu = std::sqrt(u1), sin_t = std::sqrt(1.0 - u1);
        const SinCos phi = sin_cos(two_pi * u2);
        return {sin_t * phi.cos, sin_t * phi.sin, mu};
    }

private:
    double irradiance_;
};

}  // namespace secchi
