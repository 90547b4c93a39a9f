#pragma once
// Isotropic (uniform) scattering, manual eq. 5.26: p = 1/(4 pi).
#include "secchi/core/config.hpp"
#include <string>

#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class IsotropicPhase : public SampledByDirection<IsotropicPhase> {
public:
    double eval(double /*cos_psi*/) const { return 1.0 / four_pi; }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// mu uniform in (-1, 1) (dOmega = dmu dphi), phi uniform in (0, 2 pi).
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density).
    PhaseDirection sample_direction(double u1, double u2) const { return {cos_psi(u1), two_pi * u2}; }

    /// mu = 2 u1 - 1, for a double or for a SIMD vector of doubles or floats (photons in
    /// lanes, transport/lane_tracer.hpp); exact for every u1 a multiple of 2^-24 or 2^-53.
    template <class Real>
    Real cos_psi(Real u1) const {
        using T = scalar_t<Real>;
        return T(2) * u1 - T(1);
    }

    std::string name() const { return "isotropic"; }
};

}  // namespace secchi
