#pragma once
// A traced plane-parallel atmosphere above the water (M93 problem 4: "E_perp = 1 applied at
// the top of the atmosphere; sun at 60 deg; aerosol optical thickness 0.264 and Rayleigh
// optical thickness 0.145 at 500 nm (Elterman)"; canonical_problems.md section 2). Photons
// start at the top of the atmosphere along the sun's beam and random-walk down through it
// (exponential free paths in optical depth, manual eq. 3.17) to the surface; light the surface
// sends back up (specular reflection, water-leaving light) random-walks again and either
// leaves through the top or comes back down onto the surface (the coupled atmosphere-ocean
// system of Plass and Kattawar 1972; Gjerstad et al. 2003).
//
// What M93 leave to each model (their s/x of 7-14 % reflects it), chosen and stated here:
//  - Molecules: the Rayleigh phase function p = 3/(16 pi) (1 + cos^2 psi) (unpolarised, M93
//    eq. 3), no absorption (ozone is not part of the problem).
//  - Aerosol: Henyey-Greenstein with g = 0.7 and single-scattering albedo 1 by default (a
//    continental/maritime aerosol's asymmetry at 500 nm is 0.6-0.75; no absorption: none is
//    given). Both are parameters.
//  - Vertical profile: both extinctions fall off exponentially with height,
//    k(z) = (tau_R / H_R) exp(-z / H_R) + (tau_A / H_A) exp(-z / H_A), with the molecular
//    scale height H_R = 8 km (the isothermal scale height R T / (M g) near 273 K; Thomas and
//    Stamnes 2002, sec. 1.3) and an aerosol scale height H_A = 2 km (the exponential aerosol
//    profile of the 6S code, Vermote et al. 1997). The optical depth above height z is then
//    tau(z) = tau_R exp(-z / H_R) + tau_A exp(-z / H_A); the aerosol, concentrated low, sees
//    the sun's beam after most of the molecular scattering. Only the mix of the two at each
//    optical depth matters (the atmosphere is plane-parallel and horizontally homogeneous, so
//    its geometric thickness does not), and that is what the profile sets.
//
// Zero optical thickness is no atmosphere: the sun's beam arrives unscattered, no random
// number is drawn, and light going up leaves (returns_light() is false), so the first pass is
// exactly that of the sun alone at the surface (M93 problem 2) with E_perp at the top.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/scene/source.hpp"
#include "secchi/scene/sun.hpp"
#include <algorithm>
#include <cmath>

namespace secchi::SECCHI_ISA {

/// The parameters of a TracedAtmosphere; the defaults are M93 problem 4's set-up with the
/// choices stated in atmosphere.hpp's header.
struct AtmosphereSpec {
    double sun_zenith_deg = 60.0;
    double sun_azimuth_deg = 0.0;
    double e_perp = 1.0;                   ///< irradiance on a plane perpendicular to the sun's rays, at the top
    double rayleigh_tau = 0.145;           ///< M93 problem 4 (Elterman, 500 nm)
    double aerosol_tau = 0.264;            ///< M93 problem 4 (Elterman, 500 nm)
    double aerosol_g = 0.7;                ///< Henyey-Greenstein asymmetry of the aerosol
    double aerosol_albedo = 1.0;           ///< aerosol single-scattering albedo
    double rayleigh_scale_height_km = 8.0; ///< Thomas and Stamnes 2002, sec. 1.3
    double aerosol_scale_height_km = 2.0;  ///< 6S's exponential aerosol profile (Vermote et al. 1997)
};

class TracedAtmosphere {
public:
    explicit TracedAtmosphere(const AtmosphereSpec& spec = {})
        : spec_(validated(spec)), sun_(spec.sun_zenith_deg, spec.sun_azimuth_deg, spec.e_perp),
          direction_(sun_.direction()), aerosol_phase_(spec.aerosol_g),
          tau_(spec.rayleigh_tau + spec.aerosol_tau) {}

    /// E_perp cos(zenith) at the top of the atmosphere (M93 Table 5's problem 4 is per unit
    /// E_perp there).
    [[nodiscard]] double plane_irradiance() const { return sun_.plane_irradiance(); }
    [[nodiscard]] vec3 beam_direction() const { return direction_; }
    [[nodiscard]] bool returns_light() const { return tau_ > 0.0; }

    /// A photon of the sun's beam from the top of the atmosphere to the surface.
    [[nodiscard]] SourcePhoton emit(PhotonRng& rng) const {
        if (tau_ == 0.0) return {SourceFate::arrives, direction_, true, true};
        return walk(0.0, direction_, false, rng);
    }
    /// Light leaving the surface upward with direction `up` (up.z < 0), followed through the
    /// atmosphere until it comes back down onto the surface, leaves, or is absorbed.
    [[nodiscard]] SourcePhoton reenter(const vec3& up, PhotonRng& rng) const {
        if (tau_ == 0.0) return {SourceFate::to_space, up, false, false};
        return walk(tau_, up, true, rng);
    }

    [[nodiscard]] const AtmosphereSpec& spec() const { return spec_; }
    [[nodiscard]] double optical_thickness() const { return tau_; }
    /// The direct (unscattered) plane irradiance just above the surface: Beer-Lambert along the
    /// slant path, E_perp cos(zenith) exp(-tau / cos(zenith)).
    [[nodiscard]] double direct_irradiance_at_surface() const {
        return sun_.plane_irradiance() * std::exp(-tau_ / direction_.z);
    }

    /// Optical depth measured down from the top (0 at the top, optical_thickness() at the
    /// surface) at height z (km): the optical depth above z, tau_R exp(-z / H_R) + tau_A
    /// exp(-z / H_A).
    [[nodiscard]] double depth_of_height(double z_km) const { return above(z_km); }
    /// The height (km) at optical depth t from the top (0 < t <= optical_thickness(); t is
    /// taken as at least 1e-12 of the thickness, 220 km up or more). Newton's method on
    /// g(z) = ln tau_above(z) - ln t, which is convex and decreasing (a log-sum-exp of linear
    /// functions of z), from z = 0 where g >= 0: the iterates rise monotonically to the root,
    /// without overshoot.
    [[nodiscard]] double height_at(double t) const {
        if (t >= tau_) return 0.0;
        const double log_target = std::log(std::max(t, 1e-12 * tau_));
        double z = 0.0;
        for (int i = 0; i < 100; ++i) {
            const double a = above(z), k = extinction(z);
            const double step = (std::log(a) - log_target) * a / k;  // g / |g'|, g' = -k / a
            z += step;
            if (!(step > 1e-12 * (1.0 + z))) break;
        }
        return z;
    }
    /// The aerosol's share of the extinction at height z (km).
    [[nodiscard]] double aerosol_share(double z_km) const {
        const double ka = aerosol_extinction(z_km);
        return ka / (rayleigh_extinction(z_km) + ka);
    }

private:
    static AtmosphereSpec validated(const AtmosphereSpec& s) {
        require(std::isfinite(s.rayleigh_tau) && s.rayleigh_tau >= 0.0, "Rayleigh optical thickness", s.rayleigh_tau,
                "must be finite and >= 0");
        require(std::isfinite(s.aerosol_tau) && s.aerosol_tau >= 0.0, "aerosol optical thickness", s.aerosol_tau,
                "must be finite and >= 0");
        require(std::isfinite(s.aerosol_g) && std::abs(s.aerosol_g) < 1.0, "aerosol g", s.aerosol_g,
                "the Henyey-Greenstein asymmetry parameter needs |g| < 1");
        require(std::isfinite(s.aerosol_albedo) && s.aerosol_albedo >= 0.0 && s.aerosol_albedo <= 1.0,
                "aerosol single-scattering albedo", s.aerosol_albedo, "must be in [0, 1]");
        require(std::isfinite(s.rayleigh_scale_height_km) && s.rayleigh_scale_height_km > 0.0,
                "Rayleigh scale height (km)", s.rayleigh_scale_height_km, "must be finite and > 0");
        require(std::isfinite(s.aerosol_scale_height_km) && s.aerosol_scale_height_km > 0.0,
                "aerosol scale height (km)", s.aerosol_scale_height_km, "must be finite and > 0");
        require(std::isfinite(s.e_perp) && s.e_perp > 0.0, "E_perp", s.e_perp, "must be finite and > 0");
        return s;
    }

    double rayleigh_extinction(double z) const {
        return spec_.rayleigh_tau / spec_.rayleigh_scale_height_km * std::exp(-z / spec_.rayleigh_scale_height_km);
    }
    double aerosol_extinction(double z) const {
        return spec_.aerosol_tau / spec_.aerosol_scale_height_km * std::exp(-z / spec_.aerosol_scale_height_km);
    }
    double extinction(double z) const { return rayleigh_extinction(z) + aerosol_extinction(z); }
    /// Optical depth above height z (km).
    double above(double z) const {
        return spec_.rayleigh_tau * std::exp(-z / spec_.rayleigh_scale_height_km) +
               spec_.aerosol_tau * std::exp(-z / spec_.aerosol_scale_height_km);
    }

    /// The random walk from optical depth t (from the top) with direction dir (z positive
    /// down): a free path of optical length -ln u (eq. 3.17), projected on the vertical by
    /// dir.z; past the surface the photon arrives, above the top it leaves; else it interacts
    /// with the aerosol with probability k_A / (k_R + k_A) at its height (absorbed with
    /// probability 1 - albedo) or with the molecules, and scatters by that species' phase
    /// function. `scattered`: whether it has scattered (or met the surface) already.
    SourcePhoton walk(double t, vec3 dir, bool scattered, PhotonRng& rng) const {
        for (;;) {
            const double t1 = t + dir.z * -std::log(rng.uniform());
            if (t1 >= tau_ && dir.z > 0.0) return {SourceFate::arrives, dir, !scattered, !scattered};
            if (t1 <= 0.0 && dir.z < 0.0) return {SourceFate::to_space, dir, false, false};
            t = std::clamp(t1, 0.0, tau_);
            const bool aerosol = rng.uniform() < aerosol_share(height_at(t));
            if (aerosol && spec_.aerosol_albedo < 1.0 && rng.uniform() >= spec_.aerosol_albedo)
                return {SourceFate::absorbed, dir, false, false};
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const PhaseDirection d = aerosol ? aerosol_phase_.sample_direction(u1, u2)
                                             : RayleighPhase{}.sample_direction(u1, u2);
            dir = rotate_direction(dir, d.cos_psi, d.phi);
            scattered = true;
        }
    }

    AtmosphereSpec spec_;
    CollimatedSun sun_;
    vec3 direction_;
    HenyeyGreensteinPhase aerosol_phase_;
    double tau_;  ///< total optical thickness
};

static_assert(LightSource<TracedAtmosphere>);

}  // namespace secchi
