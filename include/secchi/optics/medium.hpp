#pragma once
// A medium answers the inherent optical properties the transport needs (manual 2.7.1):
// absorption a, scattering b, attenuation c = a + b (1/m) and the scattering phase function.
// HomogeneousWater is the constant-IOP medium of the canonical problems 1, 2 and 6.
#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include <cmath>
#include <utility>

namespace secchi {

template <class M>
concept Medium = requires(const M m) {
    typename M::phase_type;
    requires PhaseFunction<typename M::phase_type>;
    { m.absorption() } -> std::convertible_to<double>;
    { m.scattering() } -> std::convertible_to<double>;
    { m.attenuation() } -> std::convertible_to<double>;
    { m.albedo() } -> std::convertible_to<double>;
    { m.phase() } -> std::convertible_to<const typename M::phase_type&>;
};

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

private:
    double a_, b_;
    Phase phase_;
};

}  // namespace secchi
