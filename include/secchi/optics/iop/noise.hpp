#pragma once
// SIGMA, the optional noise of every IOP model (manual 5.5, e.g. eq. 5.8, 5.11, 5.16):
// value + N(0, sigma), for sensitivity studies.
//
// Reproducible: the Gaussian deviate is a pure function of (run seed, model key, position,
// wavelength), drawn from the counter-based generator of core/rng.hpp. The same point and
// wavelength always give the same value, whatever the thread or the order of queries, so a
// noisy medium is still a function of position (what the transport's depth profiles need).
//
// Never negative: a coefficient or concentration cannot be negative, so a noisy value below
// zero is clamped to zero (documented behaviour, not an error: with sigma comparable to the
// value, clamping is the expected outcome for some points). A negative sigma is rejected.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace secchi::SECCHI_ISA::iop {

class Noise {
public:
    Noise() = default;  ///< sigma = 0: no noise
    /// sigma: standard deviation (the model's units); seed: the run's seed; key: tells the
    /// models of one medium apart (e.g. the model's index in its material file).
    explicit Noise(double sigma, std::uint64_t seed = 1, std::uint64_t key = 0) : sigma_(sigma), seed_(seed), key_(key) {
        require(std::isfinite(sigma) && sigma >= 0.0, "SIGMA", sigma, "must be finite and >= 0");
    }

    [[nodiscard]] double sigma() const { return sigma_; }

    /// value + N(0, sigma) at (x, wavelength), clamped at zero.
    [[nodiscard]] double add(double value, vec3 x, double wavelength_nm) const {
        if (sigma_ == 0.0) return value;
        return std::max(0.0, value + sigma_ * deviate(x, wavelength_nm));
    }

    /// The standard normal deviate used at (x, wavelength): Box-Muller on two uniforms of
    /// the stream keyed by a hash of the point.
    [[nodiscard]] double deviate(vec3 x, double wavelength_nm) const {
        std::uint64_t h = mix(key_ ^ 0x9E3779B97F4A7C15ull);
        for (double v : {x.x, x.y, x.z, wavelength_nm}) h = mix(h ^ std::bit_cast<std::uint64_t>(v + 0.0));
        PhotonRng rng(seed_, h);
        const double u1 = rng.uniform(), u2 = rng.uniform();
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(two_pi * u2);
    }

private:
    /// splitmix64 finaliser: a bijective 64-bit mixer.
    static std::uint64_t mix(std::uint64_t z) {
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }

    double sigma_ = 0.0;
    std::uint64_t seed_ = 1, key_ = 0;
};

}  // namespace secchi::iop
