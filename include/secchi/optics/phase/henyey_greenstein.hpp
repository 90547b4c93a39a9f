#pragma once
// Henyey-Greenstein phase function (Henyey and Greenstein 1941; manual section 4.13.1,
// eq. 4.70): p(psi) = (1 - g^2) / (4 pi (1 + g^2 - 2 g cos psi)^{3/2}), mean cosine g.
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class HenyeyGreensteinPhase : public SampledByDirection<HenyeyGreensteinPhase> {
public:
    explicit HenyeyGreensteinPhase(double g) : g_(g) {
        require(std::abs(g) < 1.0, "g", g, "the Henyey-Greenstein asymmetry parameter needs |g| < 1");
    }

    /// 1 + g^2 - 2 g mu written as (1 - g)^2 + 2 g (1 - mu): no cancellation near the peak.
    /// Its sums are mul_adds (core/math.hpp), so that every compilation rounds it alike (a
    /// typed mixture and AnyPhaseFunction's, bit for bit, where multiply-adds fuse too).
    double eval(double cos_psi) const {
        const double d = mul_add(2.0 * g_, 1.0 - cos_psi, (1.0 - g_) * (1.0 - g_));
        return mul_add(-g_, g_, 1.0) / (four_pi * d * std::sqrt(d));
    }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// Exact inverse CDF. With s = 2 u - 1 the usual inversion
    /// mu = (1 + g^2 - ((1 - g^2) / (1 + g s))^2) / (2 g)
    /// is, after expanding and cancelling the factor g analytically,
    /// mu = (s + g (3 + s^2)/2 + g^2 s + g^3 (s^2 - 1)/2) / (1 + g s)^2,
    /// which has no 0/0 as g -> 0 (it gives mu = s, isotropic) and gives mu = +-1 at s = +-1.
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density).
    PhaseDirection sample_direction(double u1, double u2) const { return {cos_psi(u1), two_pi * u2}; }

    /// The inverse CDF above, for a double or for a SIMD vector of doubles or floats (photons
    /// in lanes, transport/lane_tracer.hpp): the same operations in the same order.
    template <class Real>
    Real cos_psi(Real u1) const {
        using T = scalar_t<Real>;
        const Real s = T(2) * u1 - T(1);
        const T g = T(g_);
        const Real num = s + T(0.5) * g * (T(3) + s * s) + g * g * s + T(0.5) * g * g * g * (s * s - T(1));
        const Real den = (T(1) + g * s) * (T(1) + g * s);
        return clamp_cosine(num / den);
    }

    /// The uniforms u1 whose cos_psi is negative (backward): [0, u_0), u_0 = P(mu < 0) =
    /// (1 - g^2) / (2 g) (1 / sqrt(1 + g^2) - 1 / (1 + g)) (the CDF of mu; 1/2 at g = 0).
    std::pair<double, double> backward_uniforms() const {
        if (std::abs(g_) < 1e-6) return {0.0, 0.5};
        return {0.0, (1.0 - g_ * g_) / (2.0 * g_) * (1.0 / std::sqrt(1.0 + g_ * g_) - 1.0 / (1.0 + g_))};
    }

    double g() const { return g_; }

    std::string name() const {
        std::ostringstream s;
        s << "henyey_greenstein(g=" << g_ << ")";
        return s.str();
    }

private:
    double g_;
};

}  // namespace secchi
