#pragma once
// A collimated sun (sun.hpp) and a uniform sky (sky.hpp) just above the surface, with no
// atmosphere between them and the water (M93's canonical set-up, section 3: black sky, E_perp =
// 1 at the surface). The photons share the incident plane irradiance E_sun + E_sky: a photon
// comes from the sky with probability E_sky / (E_sun + E_sky) (one uniform, drawn only when the
// sky is lit), else along the sun's beam. Light leaving the surface upward is gone.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/scene/sky.hpp"
#include "secchi/scene/source.hpp"
#include "secchi/scene/sun.hpp"

namespace secchi::SECCHI_ISA {

class SunAndSky {
public:
    explicit SunAndSky(const CollimatedSun& sun, UniformSky sky = UniformSky{})
        : sun_(sun), sky_(sky), direction_(sun.direction()), sky_share_(sky_share(sun, sky)) {}

    /// E_sun cos(zenith) + E_sky, just above the surface.
    [[nodiscard]] double plane_irradiance() const { return sun_.plane_irradiance() + sky_.plane_irradiance(); }
    [[nodiscard]] vec3 beam_direction() const { return direction_; }
    [[nodiscard]] SourcePhoton emit(PhotonRng& rng) const {
        if (sky_share_ > 0.0 && rng.uniform() < sky_share_) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            return {SourceFate::arrives, UniformSky::direction(u1, u2), false, false};
        }
        return {SourceFate::arrives, direction_, true, true};
    }
    [[nodiscard]] static constexpr bool returns_light() { return false; }
    /// Never called (returns_light() is false): light going up leaves for good.
    [[nodiscard]] static SourcePhoton reenter(const vec3& up, PhotonRng& /*unused*/) {
        return {SourceFate::to_space, up, false, false};
    }

    [[nodiscard]] const CollimatedSun& sun() const { return sun_; }
    [[nodiscard]] const UniformSky& sky() const { return sky_; }

private:
    /// The sky's share of the incident plane irradiance (0 for a black sky).
    static double sky_share(const CollimatedSun& sun, const UniformSky& sky) {
        const double total = sun.plane_irradiance() + sky.plane_irradiance();
        require(total > 0.0, "incident irradiance", total, "must be > 0: the sun or the sky must shine");
        return sky.plane_irradiance() / total;
    }

    CollimatedSun sun_;
    UniformSky sky_;
    vec3 direction_;
    double sky_share_;
};

static_assert(LightSource<SunAndSky>);

}  // namespace secchi
