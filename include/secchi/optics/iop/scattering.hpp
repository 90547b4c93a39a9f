#pragma once
// The scattering coefficient models built on established forms (manual 5.7.3-5.7.5),
// b(x, lambda) in 1/m, lambda in nm. (The generic "constant" and "specific" scattering
// models are ConstantCoefficient and SpecificCoefficient of coefficient.hpp.)
//
//  - GordonMorelScattering<Conc> ("gordonmorel", eq. 5.22): (lambda0/lambda) k C^q, the
//    form of Gordon & Morel (1983) / Morel (1991) for chlorophyll (eq. 5.21 without water).
//  - KopelevichScattering<Conc> ("kopelevich", eq. 5.24): k C (lambda0/lambda)^q, the
//    general form of one term of Kopelevich (1983) (eq. 5.23); CONCID "none" (the default)
//    means C = 1: Conc = NoConcentration.
//  - BuiteveldScattering ("buiteveld", eq. 5.1): K lambda^Q, the DIRSIG power-law fit to
//    Buiteveld et al. (1994) pure water scattering.
//
// Every model has SIGMA (the Noise: + N(0, sigma) at (x, lambda), clamped at zero). ID and
// CONCID are the composer's business (CONCID is resolved to the Conc model given here).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/iop/concentration.hpp"
#include "secchi/optics/iop/iop_model.hpp"
#include "secchi/optics/iop/noise.hpp"
#include <cmath>
#include <concepts>
#include <utility>

namespace secchi::SECCHI_ISA::iop {

namespace detail {
/// Wavelengths enter as lambda0/lambda or lambda^Q: they must be positive.
inline void check_scattering_wavelength(double wavelength_nm) {
    require(std::isfinite(wavelength_nm) && wavelength_nm > 0.0, "wavelength_nm", wavelength_nm,
            "must be finite and > 0");
}
}  // namespace detail

// ---------------------------------------------------------------------------------------
// 5.7.3 Gordon-Morel (eq. 5.22): b(z, lambda) = (lambda0/lambda) k C(z)^q + N(0, sigma).

struct GordonMorelParams {
    double refwl = 550.0;    ///< REFWL: the reference wavelength lambda0 (nm)
    double k = 0.30;         ///< K: the coefficient k (1/m at C = 1, lambda = lambda0)
    double q = 0.62;         ///< Q: the exponent q of the concentration
    bool exclusive = false;  ///< EXCLUSIVE: 1 = exclude all other scattering models
};

template <ConcentrationModel Conc>
class GordonMorelScattering : public ModelParameters<GordonMorelParams> {
public:
    using Params = GordonMorelParams;
    static constexpr const char* type_name = "gordonmorel";

    /// conc: the model named by CONCID (default "chlorophyll", mg m^-3 in eq. 5.21).
    explicit GordonMorelScattering(Conc conc, const Params& p = {}, Noise noise = {})
        : ModelParameters<GordonMorelParams>(p, noise), conc_(std::move(conc)) {
        require(std::isfinite(p.refwl) && p.refwl > 0.0, "REFWL", p.refwl, "must be finite and > 0 (nm)");
        require(std::isfinite(p.k) && p.k >= 0.0, "K", p.k, "must be finite and >= 0");
        // q < 0 would make b infinite where C = 0 (clear water).
        require(std::isfinite(p.q) && p.q >= 0.0, "Q", p.q, "must be finite and >= 0");
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        detail::check_scattering_wavelength(wavelength_nm);
        const double c = conc_.concentration(x);
        const double b = p_.refwl / wavelength_nm * p_.k * std::pow(c, p_.q);
        return noise_.add(b, x, wavelength_nm);
    }
    /// EXCLUSIVE: when true, the medium's composer must drop every other scattering model of
    /// the medium (this one replaces them, e.g. eq. 5.21 with its own water term); this model
    /// only stores the flag.
    [[nodiscard]] bool exclusive() const { return p_.exclusive; }
    [[nodiscard]] const Conc& concentration_model() const { return conc_; }

private:
    Conc conc_;    ///< CONCID
};

// ---------------------------------------------------------------------------------------
// 5.7.4 Kopelevich (eq. 5.24): b(z, lambda) = k C(z) (lambda0/lambda)^q + N(0, sigma).

struct KopelevichParams {
    double refwl = 550.0;  ///< REFWL: the reference wavelength lambda0 (nm)
    double k = 0.30;       ///< K: the coefficient k
    double q = 0.62;       ///< Q: the spectral exponent q
};

template <ConcentrationModel Conc = NoConcentration>
class KopelevichScattering : public ModelParameters<KopelevichParams> {
public:
    using Params = KopelevichParams;
    static constexpr const char* type_name = "kopelevich";

    /// CONCID = "none" (the default): no concentration, C = 1.
    KopelevichScattering()
        requires std::same_as<Conc, NoConcentration>
        : KopelevichScattering(NoConcentration{}) {}
    explicit KopelevichScattering(const Params& p, Noise noise = {})
        requires std::same_as<Conc, NoConcentration>
        : KopelevichScattering(NoConcentration{}, p, noise) {}
    /// conc: the model named by CONCID.
    explicit KopelevichScattering(Conc conc, const Params& p = {}, Noise noise = {})
        : ModelParameters<KopelevichParams>(p, noise), conc_(std::move(conc)) {
        require(std::isfinite(p.refwl) && p.refwl > 0.0, "REFWL", p.refwl, "must be finite and > 0 (nm)");
        require(std::isfinite(p.k) && p.k >= 0.0, "K", p.k, "must be finite and >= 0");
        require(std::isfinite(p.q), "Q", p.q, "must be finite");
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        detail::check_scattering_wavelength(wavelength_nm);
        const double b = p_.k * conc_.concentration(x) * std::pow(p_.refwl / wavelength_nm, p_.q);
        return noise_.add(b, x, wavelength_nm);
    }
    [[nodiscard]] const Conc& concentration_model() const { return conc_; }

private:
    Conc conc_;    ///< CONCID
};

// ---------------------------------------------------------------------------------------
// 5.7.5 Buiteveld (eq. 5.1): b(lambda) = K lambda^Q + N(0, sigma), lambda in nm, b in 1/m.
//
// Eq. 5.1 is b = 3.4123664e8 lambda^-4.1537676, a fit to Buiteveld et al. (1994) claimed
// only over 340-750 nm (the converted manual drops the exponent's minus sign; it must be
// negative: b = 2.0997e-3 1/m at 500 nm, see data/README.md section 6). The manual's table
// for "buiteveld" lists K = 0.30 and Q = 0.62, copied from the kopelevich table and giving
// nonsense; here K and Q default to the constants of eq. 5.1 instead.

struct BuiteveldParams {
    double k = 3.4123664e8;  ///< K: the coefficient of eq. 5.1 (1/m at lambda = 1 nm)
    double q = -4.1537676;   ///< Q: the exponent of eq. 5.1 (negative)
};

class BuiteveldScattering : public ModelParameters<BuiteveldParams> {
public:
    using Params = BuiteveldParams;
    static constexpr const char* type_name = "buiteveld";

    BuiteveldScattering() : BuiteveldScattering(Params{}) {}
    explicit BuiteveldScattering(const Params& p, Noise noise = {}) : ModelParameters<BuiteveldParams>(p, noise) {
        require(std::isfinite(p.k) && p.k >= 0.0, "K", p.k, "must be finite and >= 0");
        require(std::isfinite(p.q), "Q", p.q, "must be finite");
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        detail::check_scattering_wavelength(wavelength_nm);
        return noise_.add(p_.k * std::pow(wavelength_nm, p_.q), x, wavelength_nm);
    }
};

static_assert(CoefficientModel<GordonMorelScattering<ConstantConcentration>>);
static_assert(CoefficientModel<GordonMorelScattering<AnyConcentration>>);
static_assert(CoefficientModel<KopelevichScattering<>>);
static_assert(CoefficientModel<KopelevichScattering<GaussianConcentration>>);
static_assert(CoefficientModel<BuiteveldScattering>);

}  // namespace secchi::iop
