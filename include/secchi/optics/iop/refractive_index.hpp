#pragma once
// Refractive index models of the DIRSIG water manual, section 5.9. One per medium (they do not
// add linearly, 5.4). Each is an iop::RefractiveIndexModel: refractive_index(lambda) is the
// real index n relative to vacuum at the vacuum wavelength lambda (nm).
//
// SIGMA (Noise, default 0): n + N(0, sigma). The index has no position argument, so the
// noise is drawn at the origin: a function of wavelength only, the same everywhere.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/iop/iop_model.hpp"
#include "secchi/optics/iop/noise.hpp"
#include <cmath>

namespace secchi::SECCHI_ISA::iop {

/// TYPE "constant" (manual 5.9.1): n(lambda) = IOR at every wavelength (as in Hydrolight).
/// Default IOR 1.0 (the null medium, 5.3.1); the "air" base medium uses 1.0003 (5.3.2).
/// IOR must be finite and >= 1 (an absolute index at optical wavelengths).
class ConstantRefractiveIndex {
public:
    static constexpr const char* type_name = "constant";

    explicit ConstantRefractiveIndex(double ior = 1.0, Noise noise = {}) : ior_(ior), noise_(noise) {
        require(std::isfinite(ior) && ior >= 1.0, "IOR", ior, "must be finite and >= 1");
    }

    [[nodiscard]] double refractive_index(double wavelength_nm) const {
        return noise_.add(ior_, vec3(0.0), wavelength_nm);
    }

    [[nodiscard]] double ior() const { return ior_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    double ior_;
    Noise noise_;
};

/// TYPE "iapws" (manual 5.9.2, 5.3.3): IAPWS R9-97, "Release on the Refractive Index of
/// Ordinary Water Substance as a Function of Wavelength, Temperature and Pressure" (1997);
/// Harvey, Gallagher & Levelt Sengers, J. Phys. Chem. Ref. Data 27, 761-774 (1998). With
/// T* = 273.15 K, rho* = 1000 kg/m^3, lambda* = 0.589 um and reduced T, rho, lambda:
///
///   (n^2 - 1)/(n^2 + 2) / rho = a0 + a1 rho + a2 T + a3 lambda^2 T + a4 / lambda^2
///                               + a5 / (lambda^2 - lambda_UV^2) + a6 / (lambda^2 - lambda_IR^2) + a7 rho^2
///
/// so with A = rho x (right-hand side), n = sqrt((1 + 2A) / (1 - A)). Coefficients from
/// shared/data/iapws_1997_refractive_index_coefficients.csv (data README section 5; read from
/// the PyPI package iapws 1.5.5 and identical in several independent codes).
///
/// Range of validity of the release (enforced, input_error outside): temperature
/// 261.15-773.15 K (-12 to 500 deg C, supercooled liquid included), density 0-1060 kg/m^3,
/// wavelength 200-1100 nm (the release calls extrapolation to 1.9 um "reasonable"; not
/// allowed here). Takes DENSITY, not pressure: get rho(T, p) from an equation of state.
/// Defaults are the manual's: TEMP 273.15 K, DENSITY 1000 kg/m^3.
class IapwsRefractiveIndex {
public:
    static constexpr const char* type_name = "iapws";

    static constexpr double min_temperature_K = 261.15, max_temperature_K = 773.15;
    static constexpr double max_density = 1060.0;  ///< kg/m^3
    static constexpr double min_wavelength_nm = 200.0, max_wavelength_nm = 1100.0;

    explicit IapwsRefractiveIndex(double temperature_K = 273.15, double density_kg_m3 = 1000.0, Noise noise = {})
        : t_(temperature_K), rho_(density_kg_m3), noise_(noise) {
        require(temperature_K >= min_temperature_K && temperature_K <= max_temperature_K, "TEMP (K)", temperature_K,
                "outside the IAPWS R9-97 range 261.15-773.15 K");
        require(density_kg_m3 >= 0.0 && density_kg_m3 <= max_density, "DENSITY (kg/m^3)", density_kg_m3,
                "outside the IAPWS R9-97 range 0-1060 kg/m^3");
    }

    [[nodiscard]] double refractive_index(double wavelength_nm) const {
        require(wavelength_nm >= min_wavelength_nm && wavelength_nm <= max_wavelength_nm, "wavelength (nm)",
                wavelength_nm, "outside the IAPWS R9-97 range 200-1100 nm");
        return noise_.add(formula(t_, rho_, wavelength_nm), vec3(0.0), wavelength_nm);
    }

    /// The bare formula (no range checks, no noise): T in K, rho in kg/m^3, lambda in nm.
    [[nodiscard]] static double formula(double temperature_K, double density_kg_m3, double wavelength_nm) {
        // IAPWS R9-97 coefficients (shared/data/iapws_1997_refractive_index_coefficients.csv)
        constexpr double a0 = 0.244257733, a1 = 9.74634476e-3, a2 = -3.73234996e-3, a3 = 2.68678472e-4;
        constexpr double a4 = 1.58920570e-3, a5 = 2.45934259e-3, a6 = 0.900704920, a7 = -1.66626219e-2;
        constexpr double lambda_uv = 0.2292020, lambda_ir = 5.432937;  // reduced resonance wavelengths
        constexpr double t_star = 273.15, rho_star = 1000.0, lambda_star_nm = 589.0;

        const double t = temperature_K / t_star, rho = density_kg_m3 / rho_star;
        const double l2 = (wavelength_nm / lambda_star_nm) * (wavelength_nm / lambda_star_nm);
        const double rhs = a0 + a1 * rho + a2 * t + a3 * l2 * t + a4 / l2 + a5 / (l2 - lambda_uv * lambda_uv) +
                           a6 / (l2 - lambda_ir * lambda_ir) + a7 * rho * rho;
        const double a = rho * rhs;
        return std::sqrt((1.0 + 2.0 * a) / (1.0 - a));
    }

    [[nodiscard]] double temperature_K() const { return t_; }
    [[nodiscard]] double density() const { return rho_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    double t_, rho_;
    Noise noise_;
};

/// The "purewater" base medium's index (manual 5.3.3, Fig. 5.6): IAPWS at 286 K and one
/// atmosphere, i.e. rho = 999.3989 kg/m^3 (IAPWS-95 density at 286 K, 0.101325 MPa; data README
/// section 5). n(400) = 1.344133, n(500) = 1.337354, n(700) = 1.331060.
inline IapwsRefractiveIndex pure_water_refractive_index(Noise noise = {}) {
    return IapwsRefractiveIndex(286.0, 999.3989, noise);
}

static_assert(RefractiveIndexModel<ConstantRefractiveIndex>);
static_assert(RefractiveIndexModel<IapwsRefractiveIndex>);

}  // namespace secchi::iop
