#pragma once
// Rayleigh scattering (M93 problem 1; manual eq. 5.29 with k1 = 3/(16 pi), k2 = 1):
// p(psi) = 3/(16 pi) (1 + cos^2 psi).
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <string>
#include <type_traits>

#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class RayleighPhase : public SampledByDirection<RayleighPhase> {
public:
    double eval(double cos_psi) const { return 3.0 / (16.0 * pi) * (1.0 + cos_psi * cos_psi); }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// Exact inverse CDF. The CDF in mu is (3/8)(mu + mu^3/3 + 4/3) = u, i.e.
    /// mu^3 + 3 mu - q = 0 with q = 8u - 4, whose one real root is (Cardano)
    /// mu = A - 1/A, A = cbrt(q/2 + sqrt(q^2/4 + 1)). The root is odd in q: solving for |q|
    /// avoids the cancellation in q/2 + sqrt(...) for q near -4.
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density).
    PhaseDirection sample_direction(double u1, double u2) const { return {cos_psi(u1), two_pi * u2}; }

    /// The inverse CDF above, for a double (with std::cbrt) or for a SIMD vector of doubles or
    /// floats (photons in lanes, transport/lane_tracer.hpp; the cube root by cardano_cbrt).
    template <class Real>
    SECCHI_KERNEL Real cos_psi(Real u1) const {
        using std::abs, std::sqrt;
        using T = scalar_t<Real>;
        const Real q = T(8) * u1 - T(4), aq = abs(q);
        const Real A = cardano_cbrt(T(0.5) * aq + sqrt(T(0.25) * aq * aq + T(1)));
        const Real mu = unit_with_sign_of(q) * (A - T(1) / A);
        return clamp_cosine(mu);
    }

    std::string name() const { return "rayleigh"; }

private:
    static double cardano_cbrt(double x) { return std::cbrt(x); }
    /// x^(1/3) for x in [1, 2 + sqrt 5] (Cardano's A^3 above), in SIMD lanes: a cubic guess
    /// (Chebyshev fit, relative error 3.7e-3) and Halley's steps y (y^3 + 2 x) / (2 y^3 + x),
    /// which cube the relative error: two for doubles (5.6e-16 with rounding), one for floats
    /// (float rounding).
    template <class Lanes>
    SECCHI_KERNEL static Lanes cardano_cbrt(const Lanes& x) {
        using T = scalar_t<Lanes>;
        Lanes y = T(0.6375926780988878) + x * (T(0.4331474435553432) + x * (T(-0.07303386606088941) +
                                                                          x * T(0.006028295942161762)));
        for (int step = 0; step < (std::is_same_v<T, float> ? 1 : 2); ++step) {
            const Lanes y3 = y * y * y;
            y = y * (y3 + T(2) * x) / (T(2) * y3 + x);
        }
        return y;
    }
};

}  // namespace secchi
