#pragma once
// The light above the surface as a ray ending there sees it (the boundary term of manual
// eq. 3.18 at the surface): the sky's diffuse radiance L_sky(d) of light travelling along d
// (z positive down, d.z > 0), and the direct sun, a delta in direction: E_perp on a plane
// perpendicular to its beam, which travels along sun_direction. The first pass draws photons
// from a light source (scene/source.hpp); this is the same source's light seen by the second
// pass, so a map knows the sky its photons came from:
//  - SunAndSky: the uniform sky's L = E_sky / pi (sky.hpp), the collimated sun;
//  - ParametricSky: its quads' radiance (parametric_sky.hpp), the 0.53 deg disk taken as a
//    delta of plane irradiance `direct` (its rays are within 0.27 deg of the centre);
//  - TracedAtmosphere: the sun's unscattered beam, exp(-tau / mu_s) of E_perp; the diffuse sky
//    is what its photons scattered and is not known in closed form: sky_known() is false, and
//    a ray that needs it is refused (estimate/radiance.hpp).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/any_source.hpp"
#include <cmath>
#include <functional>
#include <utility>

namespace secchi::SECCHI_ISA {

/// A collimated beam: direction of travel and irradiance on a plane perpendicular to it.
struct DirectBeam {
    vec3 direction{0.0, 0.0, 1.0};
    double e_perp = 0.0;
};

class SkyLight {
public:
    /// radiance(d): the sky radiance of light travelling along d (d.z > 0), W m^-2 nm^-1 sr^-1,
    /// in the source's units; empty when not known. sun: the direct beam above the surface.
    SkyLight(std::function<double(const vec3&)> radiance, DirectBeam sun)
        : radiance_(std::move(radiance)), sun_(sun) {
        require(std::isfinite(sun.e_perp) && sun.e_perp >= 0.0, "sun E_perp", sun.e_perp, "must be finite and >= 0");
        require(sun.direction.z > 0.0, "sun direction z", sun.direction.z, "must be > 0 (travelling down)");
    }

    /// The light of the source the first pass drew its photons from.
    static SkyLight of(const AnySource& source) {
        if (const auto* s = source.get_if<SunAndSky>()) {
            const double l = s->sky().radiance();
            const vec3 d = s->beam_direction();
            return {[l](const vec3&) { return l; }, {d, s->sun().plane_irradiance() / d.z}};
        }
        if (const auto* s = source.get_if<ParametricSky>()) {
            const vec3 d = s->beam_direction();
            return {[sky = *s](const vec3& dir) { return sky.sky_radiance(dir); }, {d, s->spec().direct / d.z}};
        }
        const auto* a = source.get_if<TracedAtmosphere>();
        const vec3 d = a->beam_direction();
        return {nullptr, {d, a->direct_irradiance_at_surface() / d.z}};
    }

    [[nodiscard]] bool sky_known() const { return static_cast<bool>(radiance_); }
    /// L_sky of light travelling along d (d.z > 0). Precondition: sky_known().
    [[nodiscard]] double sky_radiance(const vec3& d) const { return radiance_(d); }
    [[nodiscard]] const DirectBeam& sun() const { return sun_; }

private:
    std::function<double(const vec3&)> radiance_;
    DirectBeam sun_;
};

}  // namespace secchi
