#pragma once
// The IOP model concepts (manual chapter 5): every model takes a position and a wavelength
// and returns a value. Depth is the position's z (metres, positive down, 0 at the surface);
// the manual's models vary with depth only (5.10) but the interface keeps the full position
// (manual 5.4: "we always provide the position and time to the IOP interface").
//
//  - ConcentrationModel (5.10): C(x), in the constituent's units (e.g. mg m^-3 chlorophyll).
//  - CoefficientModel (5.6, 5.7): an absorption or scattering coefficient a(x, lambda) or
//    b(x, lambda) in 1/m. Whether it is an absorption or a scattering model is the role it is
//    given in a linear model, not its type (constant and specific serve both).
//  - RefractiveIndexModel (5.9): n(lambda), one per medium.
//  - Phase functions are the PhaseFunction concept of optics/phase (angle only, 5.8).
//
// Wavelengths are in nanometres throughout.
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/iop/noise.hpp"
#include <concepts>

namespace secchi::SECCHI_ISA::iop {

template <class C>
concept ConcentrationModel = requires(const C c, vec3 x) {
    { c.concentration(x) } -> std::convertible_to<double>;
};

template <class M>
concept CoefficientModel = requires(const M m, vec3 x, double wavelength_nm) {
    { m.coefficient(x, wavelength_nm) } -> std::convertible_to<double>;
};

template <class M>
concept RefractiveIndexModel = requires(const M m, double wavelength_nm) {
    { m.refractive_index(wavelength_nm) } -> std::convertible_to<double>;
};

/// What a parameterised model holds: its parameters (named and defaulted as in the manual's
/// tables) and its SIGMA noise (5.5). Models derive from it.
template <class Params>
class ModelParameters {
public:
    [[nodiscard]] const Params& params() const { return p_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }

protected:
    ModelParameters(const Params& p, Noise noise) : p_(p), noise_(noise) {}
    Params p_;
    Noise noise_;  ///< SIGMA
};

}  // namespace secchi::iop
