#pragma once
// An opaque bottom with Minnaert's reciprocal BRDF (M. Minnaert, "The reciprocity principle
// in lunar photometry", Astrophys. J. 93, 403-410, 1941), a BottomModel (scene/bottom.hpp):
//
//   f_r(in, out) = (A' / pi) (mu_in mu_out)^(k - 1),     mu = cosine from the bottom's normal,
//
// symmetric in in and out (reciprocal). Its directional-hemispherical reflectance is
//
//   rho(mu_in) = int f_r mu_out d omega_out = (2 A' / (k + 1)) mu_in^(k - 1) = A0 mu_in^(k - 1),
//
// with A0 = rho(1), the reflectance at normal incidence, the parameter here. k = 1 is the
// Lambertian bottom of albedo A0; k > 1 sends light back closer to the normal and reflects
// less of slanting light (rho <= A0 <= 1 for every incidence). k < 1 is refused: rho grows
// without bound towards grazing incidence, so the model would create energy. Reflected
// directions are drawn with pdf f_r mu_out / rho proportional to mu_out^k:
// mu_out = u1^(1 / (k + 1)) (sqrt(u1) for k = 1, as Bottom's Lambertian draws).
//
// Its reflected radiance depends on the light's direction of incidence, not only on the
// irradiance, so it is not an IrradianceBottom: the first pass (irradiances, the energy
// ledger) takes it; a photon map's second pass does not.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/bottom.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA {

class MinnaertBottom {
public:
    /// depth in metres (finite, > 0); normal_reflectance A0 in [0, 1]; exponent k >= 1.
    MinnaertBottom(double depth, double normal_reflectance, double k)
        : depth_(depth), a0_(normal_reflectance), k_(k), inverse_k1_(1.0 / (k + 1.0)) {
        require(std::isfinite(depth) && depth > 0.0, "bottom depth", depth, "must be finite and > 0");
        require(std::isfinite(normal_reflectance) && normal_reflectance >= 0.0 && normal_reflectance <= 1.0,
                "Minnaert normal reflectance", normal_reflectance, "must be in [0, 1]");
        require(std::isfinite(k) && k >= 1.0, "Minnaert exponent k", k,
                "must be >= 1 (k < 1 reflects more than it receives near grazing incidence)");
    }

    [[nodiscard]] double depth() const { return depth_; }
    [[nodiscard]] double normal_reflectance() const { return a0_; }
    [[nodiscard]] double exponent() const { return k_; }

    [[nodiscard]] bool transmits() const { return false; }
    /// rho(mu_in) = A0 mu_in^(k - 1), `in` moving down onto the bottom.
    [[nodiscard]] double reflectance(const vec3& in) const { return a0_ * std::pow(std::abs(in.z), k_ - 1.0); }
    /// The BRDF itself, in 1/sr (for checks and for renderers): A0 (k + 1) / (2 pi) (mu_in mu_out)^(k - 1).
    [[nodiscard]] double brdf(const vec3& in, const vec3& out) const {
        return a0_ * (k_ + 1.0) / two_pi * std::pow(std::abs(in.z) * std::abs(out.z), k_ - 1.0);
    }
    [[nodiscard]] vec3 reflected_direction(const vec3&, double u1, double u2) const {
        const double mu = k_ == 1.0 ? std::sqrt(u1) : std::pow(u1, inverse_k1_);
        return upward_direction(mu, u2);
    }

private:
    double depth_, a0_, k_, inverse_k1_;
};

static_assert(BottomModel<MinnaertBottom> && !IrradianceBottom<MinnaertBottom>);

}  // namespace secchi
