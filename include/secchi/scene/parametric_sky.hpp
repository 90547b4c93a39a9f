#pragma once
// A parametric sky just above the surface (what DIRSIG and Hydrolight use): a sun disk of
// finite angular size and a clear-sky radiance distribution, scaled to a given split of the
// downward plane irradiance just above the surface into direct (the disk) and diffuse (the
// sky) parts, e.g. the manual's Gregg-Carder irradiances for problem 4 (manual 7.6.4, table
// "Gregg-Carder atmosphere properties for Problem 4": 0.4158 direct, 0.2729 diffuse,
// W m^-2 nm^-1). No atmosphere is traced: light leaving the surface upward is gone.
//
// Sky radiance: Harrison and Coombes' clear-sky model as Hydrolight evaluates it (its routine
// hcnrad.f, "Harrison and Coombes Normalized RADiances", which cites eqs. 3-5 of Harrison and
// Coombes 1988, Solar Energy 41(4):387-392, the manual's reference; the clear-sky fit is that
// of their companion paper, "Angular distribution of clear sky short wavelength radiance",
// Solar Energy 40:57-63, 1988; neither paper was at hand, the coefficients are hcnrad.f's):
//   N(theta, psi) = (1.63 + 53.7 exp(-5.49 psi) + 2.04 cos^2(psi) cos(theta_s))
//                   (1 - exp(-0.19 / cos(theta))) (1 - exp(-0.53 / cos(theta_s))),
// theta the zenith angle of the sky point, theta_s the sun's, psi (radians) the angle between
// the sky point and the sun. Only its shape is used: the sky is scaled to the diffuse
// irradiance.
//
// Sampling as the manual's section 3.3.3.2 does: the sky dome is cut into quads of equal solid
// angle (zenith_bands bands of equal width in cos(theta), each cut into azimuth_sectors
// sectors), each taken as homogeneous, of the radiance that gives it the flux N carries
// through it (the integral of N cos(theta) over the quad, by 5 x 5 Gauss-Legendre); one
// element, the sun's disk or a quad, is chosen with probability equal to its share of the
// plane irradiance (one-dimensional importance sampling, manual 3.3.3.1), and a direction within
// it with density proportional to cos(theta) in solid angle (within a quad: cos^2(theta)
// uniform and azimuth uniform; in the disk: uniform in the cone, kept with probability
// cos(theta) / its largest value in the cone). So every photon carries the same flux, and
// the pdf is exact for the sky as represented (quad_probability, quad_of): the quads'
// radiance is the sky's, and the sun's disk is of uniform radiance.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/source.hpp"
#include "secchi/scene/sun.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <vector>

namespace secchi::SECCHI_ISA {

/// The parameters of a ParametricSky; the defaults are the manual's problem 4 (7.6.4).
struct ParametricSkySpec {
    double sun_zenith_deg = 60.0;
    double sun_azimuth_deg = 0.0;
    double direct = 0.4158;          ///< plane irradiance from the sun's disk just above the surface
    double diffuse = 0.2729;         ///< plane irradiance from the sky just above the surface
    double sun_diameter_deg = 0.53;  ///< the sun's angular diameter
    unsigned zenith_bands = 64;      ///< equal-solid-angle quads: bands of equal width in cos(theta)
    unsigned azimuth_sectors = 128;  ///< and sectors of equal azimuth in each band
};

class ParametricSky {
public:
    explicit ParametricSky(const ParametricSkySpec& spec = {})
        : spec_(validated(spec)), sun_(spec.sun_zenith_deg, spec.sun_azimuth_deg, 1.0),
          direction_(sun_.direction()), half_angle_(0.5 * spec.sun_diameter_deg * deg),
          cos_half_angle_(std::cos(half_angle_)),
          max_disk_cosine_(spec.sun_zenith_deg * deg > half_angle_ ? std::cos(spec.sun_zenith_deg * deg - half_angle_)
                                                                    : 1.0) {
        const std::size_t n = quad_count();
        flux_.resize(n);
        double total = 0.0;
        for (std::size_t i = 0; i < n; ++i) total += flux_[i] = quad_flux(i);
        // The elements' cumulative probabilities: the disk first, then the quads in order.
        const double e = spec_.direct + spec_.diffuse;
        cdf_.resize(n + 1);
        double cum = spec_.direct / e;
        cdf_[0] = cum;
        for (std::size_t i = 0; i < n; ++i) {
            flux_[i] *= spec_.diffuse / total;  // each quad's plane irradiance
            cum += flux_[i] / e;
            cdf_[i + 1] = cum;
        }
        cdf_[n] = 1.0;
    }

    /// direct + diffuse, the downward plane irradiance just above the surface.
    [[nodiscard]] double plane_irradiance() const { return spec_.direct + spec_.diffuse; }
    /// The disk's centre (its photons' directions differ: none is marked `beam`).
    [[nodiscard]] vec3 beam_direction() const { return direction_; }
    [[nodiscard]] static constexpr bool returns_light() { return false; }
    [[nodiscard]] static SourcePhoton reenter(const vec3& up, PhotonRng& /*unused*/) {
        return {SourceFate::to_space, up, false, false};
    }

    /// A photon from the disk or the sky: one uniform chooses the element, two more the
    /// direction in a quad, three per try in the disk.
    [[nodiscard]] SourcePhoton emit(PhotonRng& rng) const {
        const double u = rng.uniform();
        if (u < cdf_[0]) return {SourceFate::arrives, sample_disk(rng), false, true};
        const auto it = std::upper_bound(cdf_.begin() + 1, cdf_.end(), u);
        const std::size_t quad = std::min<std::size_t>(static_cast<std::size_t>(it - cdf_.begin()) - 1, quad_count() - 1);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return {SourceFate::arrives, sample_in_quad(quad, u1, u2), false, false};
    }

    // --- the sky as represented, for tests and reports ---

    [[nodiscard]] const ParametricSkySpec& spec() const { return spec_; }
    [[nodiscard]] std::size_t quad_count() const {
        return static_cast<std::size_t>(spec_.zenith_bands) * spec_.azimuth_sectors;
    }
    /// The probability that a photon comes from the sun's disk.
    [[nodiscard]] double disk_probability() const { return cdf_[0]; }
    /// The probability that a photon comes from quad i.
    [[nodiscard]] double quad_probability(std::size_t i) const { return flux_[i] / plane_irradiance(); }
    /// Quad i's range of cos(theta) (theta: zenith angle of the sky point) and of azimuth.
    struct QuadBounds {
        double mu0, mu1, phi0, phi1;
    };
    [[nodiscard]] QuadBounds quad_bounds(std::size_t i) const {
        const std::size_t band = i / spec_.azimuth_sectors, sector = i % spec_.azimuth_sectors;
        const double nb = spec_.zenith_bands, ns = spec_.azimuth_sectors;
        return {band / nb, (band + 1) / nb, two_pi * sector / ns, two_pi * (sector + 1) / ns};
    }
    /// The quad a photon travelling along `dir` (z positive down) comes from.
    [[nodiscard]] std::size_t quad_of(const vec3& dir) const {
        const double mu = std::clamp(dir.z, 0.0, 1.0);
        double phi = std::atan2(-dir.y, -dir.x);
        if (phi < 0.0) phi += two_pi;
        const auto band = std::min<std::size_t>(static_cast<std::size_t>(mu * spec_.zenith_bands), spec_.zenith_bands - 1);
        const auto sector = std::min<std::size_t>(static_cast<std::size_t>(phi / two_pi * spec_.azimuth_sectors),
                                                  spec_.azimuth_sectors - 1);
        return band * spec_.azimuth_sectors + sector;
    }
    /// The direction of travel of a photon from quad i for uniforms u1, u2: cos^2(theta)
    /// uniform over the quad's range (density proportional to cos(theta) per solid angle),
    /// azimuth uniform.
    [[nodiscard]] vec3 sample_in_quad(std::size_t i, double u1, double u2) const {
        const QuadBounds q = quad_bounds(i);
        const double mu = std::sqrt(q.mu0 * q.mu0 + u1 * (q.mu1 * q.mu1 - q.mu0 * q.mu0));
        const double sin_t = std::sqrt(std::max(0.0, 1.0 - mu * mu));
        const SinCos phi = sin_cos(q.phi0 + u2 * (q.phi1 - q.phi0));
        return {-sin_t * phi.cos, -sin_t * phi.sin, mu};
    }
    /// The sky's radiance (W m^-2 nm^-1 sr^-1) seen against the direction of travel `dir`:
    /// its quad's (the disk is not included).
    [[nodiscard]] double sky_radiance(const vec3& dir) const {
        const std::size_t i = quad_of(dir);
        const QuadBounds q = quad_bounds(i);
        return flux_[i] / (0.5 * (q.mu1 * q.mu1 - q.mu0 * q.mu0) * (q.phi1 - q.phi0));
    }
    /// The disk's radiance: direct / (pi sin^2(alpha) cos(theta_s)), alpha its angular radius
    /// (the integral of cos(theta) over a cone of half-angle alpha about zenith angle theta_s is
    /// pi sin^2(alpha) cos(theta_s)).
    [[nodiscard]] double disk_radiance() const {
        return spec_.direct / (pi * std::sin(half_angle_) * std::sin(half_angle_) * direction_.z);
    }
    [[nodiscard]] double disk_half_angle() const { return half_angle_; }

    /// Harrison and Coombes' clear-sky relative radiance (see the header) at the sky point of
    /// zenith cosine mu, psi radians from a sun of zenith cosine mu_s.
    [[nodiscard]] static double harrison_coombes(double mu, double psi, double mu_s) {
        const double c = std::cos(psi);
        return (1.63 + 53.7 * std::exp(-5.49 * psi) + 2.04 * c * c * mu_s) * (1.0 - std::exp(-0.19 / mu)) *
               (1.0 - std::exp(-0.53 / mu_s));
    }
    /// The same for the sky point seen against the direction of travel `dir`.
    [[nodiscard]] double harrison_coombes(const vec3& dir) const {
        const double cos_psi = std::clamp(glm::dot(dir, direction_), -1.0, 1.0);
        return harrison_coombes(dir.z, std::acos(cos_psi), direction_.z);
    }

private:
    static ParametricSkySpec validated(const ParametricSkySpec& s) {
        require(std::isfinite(s.direct) && s.direct >= 0.0, "direct irradiance", s.direct, "must be finite and >= 0");
        require(std::isfinite(s.diffuse) && s.diffuse >= 0.0, "diffuse irradiance", s.diffuse,
                "must be finite and >= 0");
        require(s.direct + s.diffuse > 0.0, "direct + diffuse irradiance", s.direct + s.diffuse,
                "must be > 0: the sun or the sky must shine");
        require(std::isfinite(s.sun_diameter_deg) && s.sun_diameter_deg > 0.0 && s.sun_diameter_deg <= 10.0,
                "sun diameter (deg)", s.sun_diameter_deg, "must be in (0, 10]");
        require(s.zenith_bands >= 1 && s.zenith_bands <= 4096, "zenith bands", s.zenith_bands, "must be in [1, 4096]");
        require(s.azimuth_sectors >= 1 && s.azimuth_sectors <= 4096, "azimuth sectors", s.azimuth_sectors,
                "must be in [1, 4096]");
        return s;
    }

    /// The integral of N cos(theta) over quad i in (cos(theta), azimuth), 5 x 5 Gauss-Legendre.
    double quad_flux(std::size_t i) const {
        static constexpr std::array<double, 5> x{-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                                 0.9061798459386640};
        static constexpr std::array<double, 5> w{0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                                 0.4786286704993665, 0.2369268850561891};
        const QuadBounds q = quad_bounds(i);
        const double hm = 0.5 * (q.mu1 - q.mu0), cm = 0.5 * (q.mu1 + q.mu0);
        const double hp = 0.5 * (q.phi1 - q.phi0), cp = 0.5 * (q.phi1 + q.phi0);
        double sum = 0.0;
        for (int a = 0; a < 5; ++a) {
            const double mu = cm + hm * x[a], sin_t = std::sqrt(1.0 - mu * mu);
            for (int b = 0; b < 5; ++b) {
                const SinCos phi = sin_cos(cp + hp * x[b]);
                const vec3 dir{-sin_t * phi.cos, -sin_t * phi.sin, mu};
                sum += w[a] * w[b] * harrison_coombes(dir) * mu;
            }
        }
        return sum * hm * hp;
    }

    /// A direction in the disk with density proportional to cos(theta): uniform in the cone
    /// of half-angle alpha about the sun's beam, kept with probability cos(theta) / its
    /// largest value in the cone.
    vec3 sample_disk(PhotonRng& rng) const {
        for (;;) {
            const double cos_gamma = 1.0 - rng.uniform() * (1.0 - cos_half_angle_);
            const double beta = two_pi * rng.uniform();
            const vec3 d = rotate_direction(direction_, cos_gamma, beta);
            if (rng.uniform() * max_disk_cosine_ < d.z) return d;
        }
    }

    ParametricSkySpec spec_;
    CollimatedSun sun_;
    vec3 direction_;  ///< the travel direction of the disk's centre (z positive down)
    double half_angle_, cos_half_angle_, max_disk_cosine_;
    std::vector<double> flux_;  ///< each quad's plane irradiance just above the surface
    std::vector<double> cdf_;   ///< cumulative probabilities: the disk, then the quads
};

static_assert(LightSource<ParametricSky>);

}  // namespace secchi
