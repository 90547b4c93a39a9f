#pragma once
// Isotropic (uniform) scattering, manual eq. 5.26: p = 1/(4 pi).
#include "secchi/core/config.hpp"
#include <string>

#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class IsotropicPhase {
public:
    double eval(double /*cos_psi*/) const { return 1.0 / four_pi; }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// mu uniform in (-1, 1) (dOmega = dmu dphi), phi uniform in (0, 2 pi).
    PhaseSample sample(double u1, double u2) const {
        const PhaseDirection d = sample_direction(u1, u2);
        return {d.cos_psi, d.phi, pdf(d.cos_psi)};
    }
    /// The direction of sample(u1, u2) without its density (what transport needs).
    PhaseDirection sample_direction(double u1, double u2) const { return {2.0 * u1 - 1.0, two_pi * u2}; }

    std::string name() const { return "isotropic"; }
};

}  // namespace secchi
