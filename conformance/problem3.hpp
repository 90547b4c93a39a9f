#pragma once
// Canonical problem 3 (M93; canonical_problems.md section 2): stratified water at 500 nm,
// composed at compile time from IOP model policies (manual chapter 5):
//   chlorophyll   C(z) = 0.2 + 144 / (9 sqrt(2 pi)) exp(-(z - 17)^2 / (2 9^2))  "gaussian", eq. 5.30
//   water         a_w = 0.0257, b_w = 0.0029 1/m, Rayleigh phase function (problem 1)
//   particles     a_p = 0.04 C^0.602                "morelconc", eq. 5.16 with a*' = 1
//                 b_p = 0.33 C^0.620                 "gordonmorel", eq. 5.22 at lambda = REFWL
//                 with the Petzold particle phase function of problem 2 (M93 Table 2).
// examples/materials/canonical_problem3.mat is the same medium as a material file.
#include "secchi/optics/iop/absorption.hpp"
#include "secchi/optics/iop/concentration.hpp"
#include "secchi/optics/iop/linear_model.hpp"
#include "secchi/optics/iop/scattering.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"

namespace secchi::conformance {

inline constexpr double problem3_wavelength_nm = 500.0;

/// particle_phase: M93 Table 2 by default (the --petzold variants are for investigation).
inline auto problem3_model(TabulatedPhase particle_phase = petzold_m93()) {
    using namespace iop;
    const GaussianConcentration chlorophyll;  // the manual's defaults are problem 3's profile
    MorelConcentrationParams particle_absorption;
    particle_absorption.table.reset();  // a constant specific absorption ABS = 1 ...
    particle_absorption.abs = 1.0;
    particle_absorption.prenorm = true;  // ... used as given
    particle_absorption.k = 0.04;
    particle_absorption.q = 0.602;
    GordonMorelParams particle_scattering;
    particle_scattering.refwl = problem3_wavelength_nm;  // (lambda0 / lambda) = 1 at 500 nm
    particle_scattering.k = 0.33;
    particle_scattering.q = 0.62;
    return LinearIopModel(
        std::tuple{ConstantCoefficient(0.0257), MorelConcentrationAbsorption(chlorophyll, particle_absorption)},
        std::tuple{Scatterer{ConstantCoefficient(0.0029), RayleighPhase{}},
                   Scatterer{GordonMorelScattering(chlorophyll, particle_scattering), std::move(particle_phase)}},
        [](double) { return 1.34; });
}

}  // namespace secchi::conformance
