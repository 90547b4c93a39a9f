#pragma once
// A collimated sun in a black sky: irradiance E_perp on a plane perpendicular to its rays,
// so the downward plane irradiance just above the surface is E_perp cos(zenith) (M93 sec. 3).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"

namespace secchi::SECCHI_ISA {

class CollimatedSun {
public:
    explicit CollimatedSun(double zenith_deg = 60.0, double azimuth_deg = 0.0, double e_perp = 1.0)
        : zenith_(zenith_deg * deg), azimuth_(azimuth_deg * deg), e_perp_(e_perp) {
        require(std::isfinite(zenith_deg) && zenith_deg >= 0.0 && zenith_deg < 90.0, "sun zenith (deg)", zenith_deg,
                "must be in [0, 90)");
        require(std::isfinite(e_perp) && e_perp >= 0.0, "E_perp", e_perp, "must be >= 0 (0: no sun, a sky alone)");
    }
    /// Direction of travel of the sun's photons (z positive down).
    [[nodiscard]] vec3 direction() const {
        return {-std::sin(zenith_) * std::cos(azimuth_), -std::sin(zenith_) * std::sin(azimuth_), std::cos(zenith_)};
    }
    /// Downward plane irradiance just above the surface, Ed(0+) = E_perp cos(zenith).
    [[nodiscard]] double plane_irradiance() const { return e_perp_ * std::cos(zenith_); }
    [[nodiscard]] double zenith_deg() const { return zenith_ / deg; }

private:
    double zenith_, azimuth_, e_perp_;
};

}  // namespace secchi
