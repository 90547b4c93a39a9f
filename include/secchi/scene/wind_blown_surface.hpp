#pragma once
// A wind-blown air-water surface: capillary waves as a distribution of facet slopes, without
// shadowing (Cox and Munk 1954; canonical problem 5: M93 section 3, the manual 7.6.5,
// eq. 7.11-7.13). The slopes are Gaussian, their components along the wind (z_u) and across it
// (z_c) independent with variances s_u^2 and s_c^2:
//     p(z_u, z_c) = exp(-z_u^2 / (2 s_u^2) - z_c^2 / (2 s_c^2)) / (2 pi s_u s_c).
// - Isotropic (M93's problem 5, eq. 7.11): s_u^2 = s_c^2 = sigma^2 / 2 with the mean square
//   slope sigma^2 = 0.003 + 0.00512 U for a wind speed U in m/s (eq. 7.12).
// - Cox and Munk's anisotropic clean-surface fit: s_u^2 = 0.00316 U, s_c^2 = 0.003 + 0.00192 U.
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
//
// Shadowing and hiding (optional; M93's problem 5 ignores them): Smith's (1967) model of a
// random surface of uncorrelated heights, as in microfacet theory (Walter et al. 2007, eq.
// 18-27; Heitz 2014, "Understanding the masking-shadowing function"). Light leaving the surface
// along a direction d (away from the mean plane, on either side) clears the other waves with
// probability
//     G1(d) = 1 / (1 + Lambda(nu)),   Lambda(nu) = (exp(-nu^2) / (nu sqrt(pi)) - erfc(nu)) / 2,
//     nu = |d_z| / (sqrt(2) s_d |d_h|),
// s_d^2 the slope variance along d's azimuth (s_u^2 cos^2 + s_c^2 sin^2 of its angle to the
// wind); 1 + Lambda is the facets' area facing d per unit horizontal area, E[max(0, |d_z| +
// |d_h| t)] / |d_z|. Light that does not clear them (hiding) meets the surface again on the
// side it is on, at a facet drawn by the same projected-area rule (the tracer's walk over the
// surface, transport/tracer.hpp; Heitz et al. 2016's random walk on the microsurface).
// Shadowing of the incident light needs nothing more: in Smith's model G1 of the incident
// direction does not depend on the facet, so the facets it reaches are distributed as the
// projected-area rule already draws them.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/names.hpp"
#include "secchi/scene/fresnel.hpp"
#include "secchi/scene/surface.hpp"
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

enum class FacetSampling {
    projected_area,  ///< p(z) times the facet's area seen by the photon (M93's weighting, eq. 7.13)
    redraw,          ///< p(z) alone, drawn again while the facet faces away (the manual's DIRSIG)
};

/// The --facets names (core/names.hpp), in the order the usage texts list them.
inline const std::vector<NamedValue<FacetSampling>>& facet_sampling_names() {
    static const std::vector<NamedValue<FacetSampling>> names{
        {{"projected-area", {}, "facets met in proportion to the area they show the photon (M93)"},
         FacetSampling::projected_area},
        {{"redraw", {}, "facets facing away drawn again (the manual's DIRSIG, 7.6.5)"}, FacetSampling::redraw},
    };
    return names;
}

inline FacetSampling parse_facets(const std::string& name) { return parse_named(facet_sampling_names(), "facets", name); }

enum class Shadowing {
    none,   ///< every facet's light leaves (M93, problem 5)
    smith,  ///< light leaving a facet clears the other waves with probability G1 (Smith 1967)
};

/// The --shadowing names (core/names.hpp).
inline const std::vector<NamedValue<Shadowing>>& shadowing_names() {
    static const std::vector<NamedValue<Shadowing>> names{
        {{"none", {}, "light leaving a facet always leaves (M93)"}, Shadowing::none},
        {{"smith", {}, "light leaving a facet clears the other waves with Smith's probability G1"}, Shadowing::smith},
    };
    return names;
}

inline Shadowing parse_shadowing(const std::string& name) { return parse_named(shadowing_names(), "shadowing", name); }

/// The variances of a surface's facet slopes along the wind and across it, and the wind's
/// direction (the azimuth it blows towards, degrees from +x towards +y; only its axis matters).
struct FacetSlopes {
    double upwind = 0.0;     ///< s_u^2
    double crosswind = 0.0;  ///< s_c^2
    double wind_azimuth_deg = 0.0;

    /// M93's isotropic slopes of mean square sigma^2 (eq. 7.11): sigma^2 / 2 along each axis.
    static FacetSlopes isotropic(double mean_square_slope) {
        require(std::isfinite(mean_square_slope) && mean_square_slope > 0.0, "slope variance", mean_square_slope,
                "must be finite and > 0 (a flat surface is FlatSurface)");
        return {mean_square_slope / 2.0, mean_square_slope / 2.0, 0.0};
    }
    /// M93's isotropic slopes at wind speed U (m/s): sigma^2 = 0.003 + 0.00512 U (eq. 7.12;
    /// U = 7.23 m/s gives sigma = 0.2, problem 5).
    static FacetSlopes isotropic_at_wind(double wind_m_per_s) {
        return isotropic(0.003 + 0.00512 * valid_wind(wind_m_per_s));
    }
    /// Cox and Munk's (1954) anisotropic clean-surface slopes at wind speed U (m/s):
    /// s_u^2 = 0.00316 U, s_c^2 = 0.003 + 0.00192 U, the wind blowing towards `azimuth_deg`.
    static FacetSlopes cox_munk(double wind_m_per_s, double azimuth_deg) {
        const double u = valid_wind(wind_m_per_s);
        return {0.00316 * u, 0.003 + 0.00192 * u, azimuth_deg};
    }
    [[nodiscard]] double mean_square_slope() const { return upwind + crosswind; }
    /// No slopes: a flat surface (FlatSurface), which no facet option changes.
    [[nodiscard]] bool flat() const { return upwind == 0.0 && crosswind == 0.0; }

private:
    static double valid_wind(double u) {
        require(std::isfinite(u) && u >= 0.0, "wind speed (m/s)", u, "must be >= 0");
        return u;
    }
};

class WindBlownSurface {
public:
    explicit WindBlownSurface(FacetSlopes slopes, double water_index = 1.34,
                              FacetSampling sampling = FacetSampling::projected_area, double air_index = 1.0,
                              Shadowing shadowing = Shadowing::none)
        : slopes_(slopes), wind_x_(std::cos(slopes.wind_azimuth_deg * deg)),
          wind_y_(std::sin(slopes.wind_azimuth_deg * deg)), n_water_(water_index), n_air_(air_index),
          sampling_(sampling), shadowing_(shadowing) {
        require(std::isfinite(slopes.upwind) && slopes.upwind >= 0.0, "upwind slope variance", slopes.upwind,
                "must be finite and >= 0");
        require(std::isfinite(slopes.crosswind) && slopes.crosswind >= 0.0, "crosswind slope variance",
                slopes.crosswind, "must be finite and >= 0");
        require(slopes.mean_square_slope() > 0.0, "mean square slope", slopes.mean_square_slope(),
                "must be > 0 (a flat surface is FlatSurface)");
        require(std::isfinite(slopes.wind_azimuth_deg), "wind azimuth (deg)", slopes.wind_azimuth_deg, "must be finite");
        require(std::isfinite(water_index) && water_index >= 1.0, "water index", water_index, "must be >= 1");
        require(std::isfinite(air_index) && air_index >= 1.0, "air index", air_index, "must be >= 1");
    }
    /// M93's isotropic surface of mean square slope sigma^2 (eq. 7.11; problem 5: 0.04).
    explicit WindBlownSurface(double mean_square_slope, double water_index = 1.34,
                              FacetSampling sampling = FacetSampling::projected_area)
        : WindBlownSurface(FacetSlopes::isotropic(mean_square_slope), water_index, sampling) {}

    [[nodiscard]] const FacetSlopes& slopes() const { return slopes_; }
    [[nodiscard]] double water_index() const { return n_water_; }
    [[nodiscard]] FacetSampling sampling() const { return sampling_; }
    [[nodiscard]] Shadowing shadowing() const { return shadowing_; }
    /// Whether light leaving the surface may be hidden by the other waves (Shadowing::smith).
    [[nodiscard]] bool hides() const { return shadowing_ != Shadowing::none; }

    /// Smith's Lambda for light leaving along d (header: 1 + Lambda is the facet area facing d
    /// per unit horizontal area); 0 for a vertical d.
    [[nodiscard]] double smith_lambda(const vec3& d) const {
        const double h = std::hypot(d.x, d.y);
        if (h == 0.0) return 0.0;
        const double a = (d.x * wind_x_ + d.y * wind_y_) / h, b = (d.y * wind_x_ - d.x * wind_y_) / h;
        const double sd = std::sqrt(slopes_.upwind * a * a + slopes_.crosswind * b * b);
        if (sd == 0.0) return 0.0;  // no slope along d: nothing rises into its path
        const double nu = std::abs(d.z) / (std::sqrt(2.0) * sd * h);
        if (nu == 0.0) return INFINITY;  // level: every wave is in the way
        return 0.5 * (std::exp(-nu * nu) / (nu * std::sqrt(pi)) - std::erfc(nu));
    }
    /// The probability G1 = 1 / (1 + Lambda) that light leaving along d clears the other waves.
    [[nodiscard]] double clearing_probability(const vec3& d) const { return 1.0 / (1.0 + smith_lambda(d)); }

    /// Whether light leaving the surface along d is hidden by the other waves and meets the
    /// surface again (Shadowing::smith: one uniform drawn; none: never, nothing drawn).
    [[nodiscard]] bool hidden(const vec3& d, PhotonRng& rng) const {
        return shadowing_ == Shadowing::smith && rng.uniform() >= clearing_probability(d);
    }

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
    /// The unit normal, facing the photon, of a facet met by a photon moving along d in the
    /// frame where the surface lies below it (d.z >= 0 for light arriving at the mean plane,
    /// d.z < 0 for light hidden on its way out): the slope t along the photon's horizontal
    /// travel e, then the slope q across it (along e_perp = z x e) given t.
    vec3 facet_facing(const vec3& d, PhotonRng& rng) const {
        const double mu = d.z, h = std::hypot(d.x, d.y);
        const double ex = h > 0.0 ? d.x / h : 1.0, ey = h > 0.0 ? d.y / h : 0.0;
        // t = a z_u + b z_c and q = -b z_u + a z_c, with a = e . wind, b = e . (z x wind):
        // a bivariate Gaussian of these variances and covariance.
        const double a = ex * wind_x_ + ey * wind_y_, b = ey * wind_x_ - ex * wind_y_;
        const double vu = slopes_.upwind, vc = slopes_.crosswind;
        const double var_t = vu * a * a + vc * b * b, var_q = vu * b * b + vc * a * a, cov = a * b * (vc - vu);
        const double sd_t = std::sqrt(var_t);
        const double t = sampling_ == FacetSampling::projected_area ? seen_slope(mu, h, sd_t, rng)
                                                                   : redrawn_slope(mu, h, sd_t, rng);
        const double q_mean = var_t > 0.0 ? t * cov / var_t : 0.0;
        const double q_sd = std::sqrt(std::max(0.0, var_t > 0.0 ? var_q - cov * cov / var_t : var_q));
        const double q = q_mean + q_sd * standard_normal(rng);
        const double sx = t * ex - q * ey, sy = t * ey + q * ex;
        // Surface height rising by s per unit length has the upward normal (-s_x, -s_y, 1)/N in
        // z-up axes: (-s_x, -s_y, -1)/N with z positive down. It faces the photon when
        // mu + h t > 0, the projected area above.
        return glm::normalize(vec3{-sx, -sy, -1.0});
    }

    /// A standard normal deviate (Box-Muller).
    static double standard_normal(PhotonRng& rng) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(two_pi * u2);
    }

    /// The slope along the photon's travel with density f(t) ~ max(0, mu + h t) exp(-t^2 / (2 sd^2)).
    /// mu >= 0: by rejection from g(t) = (mu + h max(t, 0)) exp(-t^2 / (2 sd^2)) >= f: a mixture
    /// of the Gaussian (mass mu sd sqrt(2 pi)) and h t exp(-t^2 / (2 sd^2)) on t > 0 (mass h sd^2,
    /// t = sd sqrt(-2 ln u)); a draw t < 0 is kept with probability (mu + h t) / mu = f / g.
    /// At least half the draws are kept. mu < 0 (hidden light, moving away from the surface):
    /// f lives on t > t0 = -mu / h; from g(t) = h t exp(-t^2 / (2 sd^2)) on t > t0 (drawn as
    /// t = sqrt(t0^2 - 2 sd^2 ln u)), kept with probability (mu + h t) / (h t) = f / g.
    static double seen_slope(double mu, double h, double sd, PhotonRng& rng) {
        if (mu < 0.0) {
            if (h == 0.0 || sd == 0.0) return 0.0;  // unreachable by hidden light (G1 = 1): a level facet
            const double t0 = -mu / h;
            while (true) {
                const double t = std::sqrt(t0 * t0 - 2.0 * sd * sd * std::log(rng.uniform()));
                if (rng.uniform() * h * t < mu + h * t) return t;
            }
        }
        const double gauss = mu * std::sqrt(two_pi), ramp = h * sd;  // the masses / sd
        while (true) {
            if (rng.uniform() * (gauss + ramp) >= gauss) return sd * std::sqrt(-2.0 * std::log(rng.uniform()));
            const double t = sd * standard_normal(rng);
            if (t >= 0.0 || rng.uniform() * mu < mu + h * t) return t;
        }
    }

    /// The manual's facet: from p alone, drawn again while it faces away (mu + h t <= 0).
    static double redrawn_slope(double mu, double h, double sd, PhotonRng& rng) {
        if (sd == 0.0) return 0.0;  // no slope along the travel (a calm axis): only level facets
        if (mu < 0.0 && h == 0.0) return 0.0;  // unreachable by hidden light (G1 = 1)
        while (true) {
            const double t = sd * standard_normal(rng);
            if (mu + h * t > 0.0) return t;
        }
    }

    FacetSlopes slopes_;
    double wind_x_, wind_y_;  ///< the wind's unit direction
    double n_water_, n_air_;
    FacetSampling sampling_;
    Shadowing shadowing_;
};

static_assert(AirWaterSurface<WindBlownSurface>);

}  // namespace secchi
