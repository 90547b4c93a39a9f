#pragma once
// Rayleigh scattering (M93 problem 1; manual eq. 5.29 with k1 = 3/(16 pi), k2 = 1):
// p(psi) = 3/(16 pi) (1 + cos^2 psi).
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <string>

#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class RayleighPhase {
public:
    double eval(double cos_psi) const { return 3.0 / (16.0 * pi) * (1.0 + cos_psi * cos_psi); }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// Exact inverse CDF. The CDF in mu is (3/8)(mu + mu^3/3 + 4/3) = u, i.e.
    /// mu^3 + 3 mu - q = 0 with q = 8u - 4, whose one real root is (Cardano)
    /// mu = A - 1/A, A = cbrt(q/2 + sqrt(q^2/4 + 1)). The root is odd in q: solving for |q|
    /// avoids the cancellation in q/2 + sqrt(...) for q near -4.
    PhaseSample sample(double u1, double u2) const {
        const PhaseDirection d = sample_direction(u1, u2);
        return {d.cos_psi, d.phi, pdf(d.cos_psi)};
    }
    /// The direction of sample(u1, u2) without its density (what transport needs).
    PhaseDirection sample_direction(double u1, double u2) const {
        const double q = 8.0 * u1 - 4.0, aq = std::abs(q);
        const double A = std::cbrt(0.5 * aq + std::sqrt(0.25 * aq * aq + 1.0));
        return {std::clamp(std::copysign(A - 1.0 / A, q), -1.0, 1.0), two_pi * u2};
    }

    std::string name() const { return "rayleigh"; }
};

}  // namespace secchi
