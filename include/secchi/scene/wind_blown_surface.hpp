#pragma once
// A wind-blown air-water surface: capillary waves as a distribution of facet slopes, without
// shadowing (canonical problem 5: M93 section 3; the manual 7.6.5, eq. 7.11-7.13). The slopes
// (z_x, z_y) are isotropic Gaussian,
//     p(z_x, z_y) = exp(-(z_x^2 + z_y^2) / sigma^2) / (pi sigma^2),
// i.e. eq. 7.11 in the facet's polar angles, with sigma^2 = 0.003 + 0.00512 U for a wind speed
// U in m/s (Cox and Munk 1954, the isotropic form; eq. 7.12). Each slope component has
// variance sigma^2 / 2.
//
// Which facet a photon meets. A facet of slopes z covers sec(theta_n) of unit horizontal area;
// a photon of direction d sees its projection cos(omega) sec(theta_n) = |d_z| + d_h . z (linear
// in the slopes, with z measured towards the photon's horizontal travel; omega is the angle of
// incidence on the facet), and nothing of a facet that faces away. So photons meet facets with
// density p(z) max(0, |d_z| + d_h . z) / (its integral over z): M93's weight W (eq. 7.13) on
// draws from p. Here that density is sampled directly, so photons keep their weights (analog
// photons stay unweighted) and the estimates are those of the weighting.
// FacetSampling::redraw is the manual's choice instead (7.6.5: draw from p, draw again while
// the facet faces away; no projected area), which it reports beside M93's.
#include "secchi/core/error.hpp"
#include "secchi/scene/fresnel.hpp"
#include "secchi/scene/surface.hpp"
#include <cmath>
#include <string>

namespace secchi {

enum class FacetSampling {
    projected_area,  ///< p(z) times the facet's area seen by the photon (M93's weighting, eq. 7.13)
    redraw,          ///< p(z) alone, drawn again while the facet faces away (the manual's DIRSIG)
};

inline FacetSampling parse_facets(const std::string& name) {
    if (name == "projected-area") return FacetSampling::projected_area;
    if (name == "redraw") return FacetSampling::redraw;
    reject("facets", name, "must be projected-area or redraw");
}

class WindBlownSurface {
public:
    /// slope_variance: sigma^2 of eq. 7.12 (> 0; canonical problem 5: 0.04).
    explicit WindBlownSurface(double slope_variance, double water_index = 1.34,
                              FacetSampling sampling = FacetSampling::projected_area, double air_index = 1.0)
        : variance_(slope_variance), sigma_(std::sqrt(slope_variance)), n_water_(water_index), n_air_(air_index),
          sampling_(sampling) {
        require(std::isfinite(slope_variance) && slope_variance > 0.0, "slope variance", slope_variance,
                "must be finite and > 0 (a flat surface is FlatSurface)");
        require(std::isfinite(water_index) && water_index >= 1.0, "water index", water_index, "must be >= 1");
        require(std::isfinite(air_index) && air_index >= 1.0, "air index", air_index, "must be >= 1");
    }

    /// The surface of Cox and Munk's isotropic slopes at wind speed U (m/s): sigma^2 = 0.003 +
    /// 0.00512 U (eq. 7.12; U = 7.23 m/s gives sigma = 0.2, problem 5).
    static WindBlownSurface from_wind_speed(double wind_m_per_s, double water_index = 1.34,
                                            FacetSampling sampling = FacetSampling::projected_area) {
        require(std::isfinite(wind_m_per_s) && wind_m_per_s >= 0.0, "wind speed (m/s)", wind_m_per_s, "must be >= 0");
        return WindBlownSurface(0.003 + 0.00512 * wind_m_per_s, water_index, sampling);
    }

    [[nodiscard]] double slope_variance() const { return variance_; }
    [[nodiscard]] double water_index() const { return n_water_; }
    [[nodiscard]] FacetSampling sampling() const { return sampling_; }

    /// The AirWaterSurface policy (surface.hpp): the photon meets a facet drawn for its direction.
    static constexpr bool random_facets = true;
    [[nodiscard]] SurfaceHit hit(const vec3& dir, Side from, PhotonRng& rng) const {
        // Facets are drawn in the frame where the photon moves down onto the surface (a photon
        // from the water sees the surface mirrored in z, the same slope distribution).
        const bool from_air = from == Side::air;
        const vec3 down = from_air ? dir : vec3{dir.x, dir.y, -dir.z};
        vec3 m = facet_facing(down, rng);
        if (!from_air) m.z = -m.z;
        const double cos_i = -glm::dot(dir, m);  // > 0: the facet faces the photon
        const double n1 = from_air ? n_air_ : n_water_, n2 = from_air ? n_water_ : n_air_;
        const double r = fresnel_reflectance(cos_i, n1, n2);
        const vec3 reflected = glm::normalize(reflect_about(dir, m, cos_i));
        return {r, reflected, r < 1.0 ? refract_through(dir, m, cos_i, n1, n2) : reflected};
    }

private:
    /// The unit normal, facing the photon, of a facet met by a photon moving down along d
    /// (d.z >= 0): slopes t along the photon's horizontal travel and t_perp across it.
    vec3 facet_facing(const vec3& d, PhotonRng& rng) const {
        const double mu = d.z, h = std::hypot(d.x, d.y);
        const double ex = h > 0.0 ? d.x / h : 1.0, ey = h > 0.0 ? d.y / h : 0.0;
        const double t = sampling_ == FacetSampling::projected_area ? seen_slope(mu, h, rng) : redrawn_slope(mu, h, rng);
        const double t_perp = slope_component(rng);
        const double sx = t * ex - t_perp * ey, sy = t * ey + t_perp * ex;
        // Surface height rising by s per unit length has the upward normal (-s_x, -s_y, 1)/N in
        // z-up axes: (-s_x, -s_y, -1)/N with z positive down. It faces the photon when
        // mu + h t > 0, the projected area above.
        return glm::normalize(vec3{-sx, -sy, -1.0});
    }

    /// One slope component, N(0, sigma^2 / 2) (Box-Muller).
    double slope_component(PhotonRng& rng) const {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return sigma_ * std::sqrt(-std::log(u1)) * std::cos(two_pi * u2);
    }

    /// The slope along the photon's travel with density f(t) ~ max(0, mu + h t) exp(-t^2 / sigma^2),
    /// by rejection from g(t) = (mu + h max(t, 0)) exp(-t^2 / sigma^2) >= f: a mixture of the
    /// Gaussian (mass mu sigma sqrt(pi)) and h t exp(-t^2 / sigma^2) on t > 0 (mass h sigma^2 / 2,
    /// t = sigma sqrt(-ln u)); a draw t < 0 is kept with probability (mu + h t) / mu = f / g.
    /// At least half the draws are kept.
    double seen_slope(double mu, double h, PhotonRng& rng) const {
        const double gauss = mu * std::sqrt(pi), ramp = 0.5 * h * sigma_;  // the masses / sigma
        while (true) {
            if (rng.uniform() * (gauss + ramp) >= gauss) return sigma_ * std::sqrt(-std::log(rng.uniform()));
            const double t = slope_component(rng);
            if (t >= 0.0 || rng.uniform() * mu < mu + h * t) return t;
        }
    }

    /// The manual's facet: from p alone, drawn again while it faces away (mu + h t <= 0).
    double redrawn_slope(double mu, double h, PhotonRng& rng) const {
        while (true) {
            const double t = slope_component(rng);
            if (mu + h * t > 0.0) return t;
        }
    }

    double variance_, sigma_, n_water_, n_air_;
    FacetSampling sampling_;
};

static_assert(AirWaterSurface<WindBlownSurface>);

}  // namespace secchi
