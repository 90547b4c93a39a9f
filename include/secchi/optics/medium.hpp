#pragma once
// A medium answers the inherent optical properties the transport needs (manual 2.7.1):
// absorption a, scattering b and attenuation c = a + b (1/m) at a depth z (metres, positive
// down), and the scattering phase function there. The water is horizontally homogeneous
// (the plane-parallel problems; manual 5.10 restricts concentrations to depth profiles), so
// along a straight flight from depth z with direction cosine uz the optical path
//     tau(s) = int_0^s k(z + uz t) dt        (k = a, b or c)
// depends on depth only. The transport asks for tau over a flight (continuous absorption,
// detectors, attenuation along a ray) and for its inverse, the distance at which a sampled
// optical depth -ln(u) is reached (free-path sampling, manual eq. 3.17 and 3.3.4).
//
// HomogeneousWater is the constant-IOP medium of the canonical problems 1, 2 and 6;
// StratifiedWater (stratified_water.hpp) the depth-varying one of problem 3.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include <cmath>
#include <utility>

namespace secchi::SECCHI_ISA {

/// Which coefficient a depth query is about.
enum class Coefficient { absorption, scattering, attenuation };

template <class M>
concept Medium = requires(const M m, Coefficient k, double z, double uz, double s, double tau, double u1, double u2) {
    { m.coefficient(k, z) } -> std::convertible_to<double>;           // k(z), 1/m
    { m.optical_path(k, z, uz, s) } -> std::convertible_to<double>;   // tau over a flight of length s
    { m.distance_to(k, z, uz, tau) } -> std::convertible_to<double>;  // s such that tau(s) = tau, or +inf
    { m.sample_phase(z, u1, u2) } -> std::same_as<PhaseSample>;       // scattering direction at depth z
};

/// Single-scattering albedo w0 = b / c at depth z.
template <Medium M>
double albedo_at(const M& m, double z) {
    const double c = m.coefficient(Coefficient::attenuation, z);
    return c > 0.0 ? m.coefficient(Coefficient::scattering, z) / c : 0.0;
}

/// The scattering direction sample_phase(z, u1, u2) gives, without the density where the
/// medium can skip it (transport never uses it).
template <Medium M>
PhaseDirection scattering_direction(const M& m, double z, double u1, double u2) {
    if constexpr (requires { { m.sample_direction(z, u1, u2) } -> std::same_as<PhaseDirection>; }) {
        return m.sample_direction(z, u1, u2);
    } else {
        const PhaseSample s = m.sample_phase(z, u1, u2);
        return {s.cos_psi, s.phi};
    }
}

template <PhaseFunction Phase>
class HomogeneousWater {
public:
    using phase_type = Phase;
    HomogeneousWater(double a, double b, Phase phase) : a_(a), b_(b), phase_(std::move(phase)) {
        require(std::isfinite(a) && a >= 0.0, "absorption coefficient a (1/m)", a, "must be finite and >= 0");
        require(std::isfinite(b) && b >= 0.0, "scattering coefficient b (1/m)", b, "must be finite and >= 0");
        require(a + b > 0.0, "attenuation coefficient c (1/m)", a + b, "must be > 0");
    }
    /// From the canonical problems' parameters: attenuation c and single-scattering albedo w0 = b/c.
    static HomogeneousWater from_albedo(double c, double albedo, Phase phase) {
        require(std::isfinite(albedo) && albedo >= 0.0 && albedo <= 1.0, "albedo w0", albedo, "must be in [0, 1]");
        require(std::isfinite(c) && c > 0.0, "attenuation coefficient c (1/m)", c, "must be > 0");
        return HomogeneousWater(c * (1.0 - albedo), c * albedo, std::move(phase));
    }
    [[nodiscard]] double absorption() const { return a_; }
    [[nodiscard]] double scattering() const { return b_; }
    [[nodiscard]] double attenuation() const { return a_ + b_; }
    [[nodiscard]] double albedo() const { return b_ / (a_ + b_); }
    [[nodiscard]] const Phase& phase() const { return phase_; }

    // The Medium interface: constant coefficients, tau = k s (Beer-Lambert).
    [[nodiscard]] double coefficient(Coefficient k, double /*z*/) const {
        return k == Coefficient::absorption ? a_ : k == Coefficient::scattering ? b_ : a_ + b_;
    }
    [[nodiscard]] double optical_path(Coefficient k, double z, double /*uz*/, double s) const {
        return coefficient(k, z) * s;
    }
    [[nodiscard]] double distance_to(Coefficient k, double z, double /*uz*/, double tau) const {
        const double v = coefficient(k, z);
        return v > 0.0 ? tau / v : INFINITY;
    }
    [[nodiscard]] PhaseSample sample_phase(double /*z*/, double u1, double u2) const { return phase_.sample(u1, u2); }
    [[nodiscard]] PhaseDirection sample_direction(double /*z*/, double u1, double u2) const {
        return sample_direction_of(phase_, u1, u2);
    }

private:
    double a_, b_;
    Phase phase_;
};

/// Media whose coefficients do not depend on depth: the transport may evaluate them once.
template <class M>
inline constexpr bool depth_independent = false;
template <class Phase>
inline constexpr bool depth_independent<HomogeneousWater<Phase>> = true;

}  // namespace secchi
