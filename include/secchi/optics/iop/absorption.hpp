#pragma once
// Absorption coefficient models of the DIRSIG water manual (Goodenough 2007), section 5.6, plus
// three common ocean-optics models beyond the manual (Bricaud 1995, Bricaud 1998, CDOM).
//
// Every model is an iop::CoefficientModel: coefficient(x, lambda) is a(x, lambda) in 1/m at the
// position x (m, z positive down) and the wavelength lambda (nm). Each model's `type_name` is
// the manual's TYPE, and its parameter struct carries the manual's parameter NAMEs (in
// comments) with the manual's defaults as default member values. Each holds a Noise (SIGMA,
// default 0): the value returned is noise.add(a, x, lambda), i.e. a + N(0, sigma) clamped at 0.
// Parameters are validated in the constructors (input_error naming the parameter).
//
// Tabulated models throw input_error for a wavelength outside their table (no extrapolation);
// see SpectralTable.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/iop/data/phytoplankton.hpp"
#include "secchi/optics/iop/data/pure_water.hpp"
#include "secchi/optics/iop/iop_model.hpp"
#include "secchi/optics/iop/noise.hpp"
#include "secchi/optics/iop/spectral_table.hpp"
#include <cmath>
#include <optional>
#include <utility>

namespace secchi::SECCHI_ISA::iop {

// ---------------------------------------------------------------------------------------------
// Data tables as SpectralTables (names used in error messages)

inline SpectralTable smith_baker_1981_absorption_table() {
    return {"Smith-Baker 1981", data::smith_baker_1981_absorption};
}
inline SpectralTable hybrid_sbpf_absorption_table() {
    return {"Smith-Baker 1981 / Pope-Fry 1997 hybrid (sbpf)", data::hybrid_sbpf_absorption};
}
inline SpectralTable pope_fry_1997_absorption_table() { return {"Pope-Fry 1997", data::pope_fry_1997_absorption}; }
inline SpectralTable morel_prieur_1977_absorption_table() {
    return {"Morel-Prieur 1977", data::morel_prieur_1977_absorption};
}
inline SpectralTable prieur_sathyendranath_achl_table() {
    return {"Prieur-Sathyendranath 1981 a*_c'", data::prieur_sathyendranath_1981_achl_normalized};
}

namespace absorption_detail {

/// Wavelengths of the formula models: finite and positive (nm).
inline void require_wavelength(double wavelength_nm) {
    require(std::isfinite(wavelength_nm) && wavelength_nm > 0.0, "wavelength (nm)", wavelength_nm,
            "must be finite and > 0");
}

inline void require_non_negative(double v, const char* name) {
    require(std::isfinite(v) && v >= 0.0, name, v, "must be finite and >= 0");
}

/// A pure-water model: a(x, lambda) = a_w(lambda) + N(0, sigma), a_w linearly interpolated
/// in a published table (no position dependence).
class PureWaterTable {
public:
    PureWaterTable(SpectralTable table, Noise noise) : table_(std::move(table)), noise_(noise) {}
    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        return noise_.add(table_.at(wavelength_nm), x, wavelength_nm);
    }
    [[nodiscard]] const SpectralTable& table() const { return table_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    SpectralTable table_;
    Noise noise_;
};

}  // namespace absorption_detail

// ---------------------------------------------------------------------------------------------
// Pure-water data models (manual 5.6.5 - 5.6.7; parameters: ID, SIGMA only)

/// TYPE "smithbaker" (manual 5.6.6): Smith & Baker (1981) clearest natural water absorption,
/// 200-800 nm every 10 nm, linearly interpolated. Base medium "sbpurewater" (5.3.4).
class SmithBakerAbsorption : public absorption_detail::PureWaterTable {
public:
    static constexpr const char* type_name = "smithbaker";
    explicit SmithBakerAbsorption(Noise noise = {}) : PureWaterTable(smith_baker_1981_absorption_table(), noise) {}
};

/// TYPE "sbpf" (manual 5.6.5, 5.3.3 Fig. 5.3): the "purewater" base medium's absorption, Pope &
/// Fry (1997) at 380-727.5 nm (2.5 nm) and Smith & Baker (1981) at 200-370 and 730-800 nm.
class HybridPureWaterAbsorption : public absorption_detail::PureWaterTable {
public:
    static constexpr const char* type_name = "sbpf";
    explicit HybridPureWaterAbsorption(Noise noise = {}) : PureWaterTable(hybrid_sbpf_absorption_table(), noise) {}
};

/// TYPE "prieursathy" (manual 5.6.7), base medium "pspurewater" (5.3.4). The manual attributes
/// the data to Prieur & Sathyendranath (1981), but no such pure-water table was found (shared
/// data README, "Not found" 1). The Morel & Prieur (1977) pure-water absorption (380-700 nm,
/// 10 nm) is used instead: the closest candidate, NOT verified to be DIRSIG's data.
class PrieurSathyAbsorption : public absorption_detail::PureWaterTable {
public:
    static constexpr const char* type_name = "prieursathy";
    explicit PrieurSathyAbsorption(Noise noise = {}) : PureWaterTable(morel_prieur_1977_absorption_table(), noise) {}
};

// ---------------------------------------------------------------------------------------------
// Morel (1991) based models (manual 5.6.3): eq. 5.13 a = a_w + a_p + a_y with
// a_p = 0.06 a*_c'(lambda) C^0.65 (eq. 5.14) and a_y = 0.2 a_p(440) e^{-0.014 (lambda - 440)}
// (eq. 5.15). "morelconc" generalises eq. 5.14, "morelcovar" eq. 5.15.

/// Parameters of "morelconc" (manual table of 5.6.3.1) with the manual's defaults.
struct MorelConcentrationParams {
    double abs = 0.1;                         ///< ABS: constant specific absorption, used when `table` is empty
    std::optional<SpectralTable> table =      ///< FILENAME: spectral specific absorption a*(lambda);
        prieur_sathyendranath_achl_table();   ///<   default: Prieur-Sathyendranath 1981 a*_c'
    double refwl = 440.0;                     ///< REFWL: normalising wavelength (nm)
    bool prenorm = false;                     ///< PRENORM: 1 = table already normalised, use as is
    double k = 0.06;                          ///< K
    double q = 0.65;                          ///< Q
};

/// TYPE "morelconc" (manual 5.6.3.1, eq. 5.16): a(x, lambda) = k a*'(lambda) C(x)^q + N(0, sigma).
/// a*' is the table divided by its value at REFWL (PRENORM = 0), or the table as given
/// (PRENORM = 1); with no table, the constant ABS (a constant has no shape to normalise, so it is
/// used as given, else ABS would have no effect). With the defaults this is eq. 5.14,
/// a_p = 0.06 a*_c'(lambda) C^0.65 (C: chlorophyll, mg m^-3; CONCID "chlorophyll").
/// Q must be >= 0 (a negative exponent would make a vanishing concentration absorb infinitely).
template <ConcentrationModel Conc>
class MorelConcentrationAbsorption {
public:
    static constexpr const char* type_name = "morelconc";

    explicit MorelConcentrationAbsorption(Conc concentration, MorelConcentrationParams params = {}, Noise noise = {})
        : conc_(std::move(concentration)), p_(std::move(params)), noise_(noise) {
        absorption_detail::require_non_negative(p_.k, "K");
        absorption_detail::require_non_negative(p_.q, "Q");
        absorption_detail::require_non_negative(p_.abs, "ABS");
        require(std::isfinite(p_.refwl) && p_.refwl > 0.0, "REFWL", p_.refwl, "must be finite and > 0 (nm)");
        if (p_.table) init_table();
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        return noise_.add(p_.k * specific(wavelength_nm) * std::pow(conc_.concentration(x), p_.q), x, wavelength_nm);
    }

    /// a*'(lambda): the normalised specific absorption (or ABS without a table).
    [[nodiscard]] double specific(double wavelength_nm) const {
        if (!p_.table) {
            absorption_detail::require_wavelength(wavelength_nm);
            return p_.abs;
        }
        return p_.table->at(wavelength_nm) * norm_;
    }

    [[nodiscard]] const MorelConcentrationParams& params() const { return p_; }
    [[nodiscard]] const Conc& concentration_model() const { return conc_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    void init_table() {
        for (double v : p_.table->values())
            require(v >= 0.0, "specific absorption of table " + p_.table->name(), v, "must be >= 0");
        if (p_.prenorm) return;
        require(p_.table->covers(p_.refwl), "REFWL", p_.refwl,
                "the normalising wavelength must lie inside table " + p_.table->name());
        const double at_ref = p_.table->at(p_.refwl);
        require(at_ref > 0.0, "value at REFWL of table " + p_.table->name(), at_ref, "must be > 0 to normalise");
        norm_ = 1.0 / at_ref;
    }

    Conc conc_;
    MorelConcentrationParams p_;
    double norm_ = 1.0;
    Noise noise_;
};

/// Parameters of "morelcovar" (manual table of 5.6.3.2) with the manual's defaults.
struct MorelCovariantParams {
    double refwl = 440.0;  ///< REFWL: lambda_0 (nm), where the base is evaluated and the exponential centred
    bool usewl = false;    ///< USEWL: accepted for recognition; no effect here (see the class comment)
    double k = 0.2;        ///< K
    double q = -0.014;     ///< Q (1/nm), the signed exponential slope: see the class comment
};

/// TYPE "morelcovar" (manual 5.6.3.2, eq. 5.17): an absorption covarying with another one,
/// the base model a_0 (ABSID, default "morelconc"):
///
///     a(x, lambda) = k a_0(x, lambda_0) e^{q (lambda - lambda_0)} + N(0, sigma).
///
/// SIGN: eq. 5.17 is printed as e^{-q (lambda - lambda_0)} with the default Q = -0.014, which
/// would GROW as e^{+0.014 (lambda - 440)}, contradicting eq. 5.15 (CDOM-like, decaying), the
/// equation the model is meant to generalise. We read Q as the signed exponent, so that the
/// defaults (K 0.2, Q -0.014, REFWL 440) over a "morelconc" base reproduce eq. 5.15 exactly:
/// a_y = 0.2 a_p(440) e^{-0.014 (lambda - 440)}.
///
/// USEWL ("use the reference wavelength internally or interpolate"): in DIRSIG the base is known
/// at the run's spectral samples, so a_0(lambda_0) is either queried at lambda_0 or interpolated
/// between samples. Here every base is a continuous function of wavelength and is always
/// evaluated at lambda_0 exactly, so both settings give the same value.
template <CoefficientModel Base>
class MorelCovariantAbsorption {
public:
    static constexpr const char* type_name = "morelcovar";

    explicit MorelCovariantAbsorption(Base base, MorelCovariantParams params = {}, Noise noise = {})
        : base_(std::move(base)), p_(params), noise_(noise) {
        absorption_detail::require_non_negative(p_.k, "K");
        require(std::isfinite(p_.q), "Q", p_.q, "must be finite");
        require(std::isfinite(p_.refwl) && p_.refwl > 0.0, "REFWL", p_.refwl, "must be finite and > 0 (nm)");
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        absorption_detail::require_wavelength(wavelength_nm);
        const double a0 = base_.coefficient(x, p_.refwl);
        return noise_.add(p_.k * a0 * std::exp(p_.q * (wavelength_nm - p_.refwl)), x, wavelength_nm);
    }

    [[nodiscard]] const MorelCovariantParams& params() const { return p_; }
    [[nodiscard]] const Base& base() const { return base_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    Base base_;
    MorelCovariantParams p_;
    Noise noise_;
};

// ---------------------------------------------------------------------------------------------
// Raman "absorption" (manual 5.6.4)

/// Parameters of "raman" with the manual's defaults (Marshall & Smith 1990).
struct RamanParams {
    double refwl = 488.0;     ///< REFWL: lambda_0 (nm)
    double refabs = 0.00026;  ///< REFABS: a_0 (1/m)
    /// q: not in the manual's table (eq. 5.18 has it); Mobley (1994, Light and Water) gives
    /// the Raman coefficient b_r(lambda) = 2.6e-4 (488/lambda)^5.5 1/m, so q = 5.5.
    double q = 5.5;
};

/// TYPE "raman" (manual 5.6.4, eq. 5.18): the loss from the beam by Raman scattering treated
/// as absorption, a(lambda) = a_0 (lambda_0 / lambda)^q + N(0, sigma), at the excitation
/// wavelength lambda. Default: 2.6e-4 1/m at 488 nm, a ~ lambda^-5.5.
class RamanAbsorption {
public:
    static constexpr const char* type_name = "raman";

    explicit RamanAbsorption(RamanParams params = {}, Noise noise = {}) : p_(params), noise_(noise) {
        require(std::isfinite(p_.refwl) && p_.refwl > 0.0, "REFWL", p_.refwl, "must be finite and > 0 (nm)");
        absorption_detail::require_non_negative(p_.refabs, "REFABS");
        require(std::isfinite(p_.q), "Q", p_.q, "must be finite");
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        absorption_detail::require_wavelength(wavelength_nm);
        return noise_.add(p_.refabs * std::pow(p_.refwl / wavelength_nm, p_.q), x, wavelength_nm);
    }

    [[nodiscard]] const RamanParams& params() const { return p_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    RamanParams p_;
    Noise noise_;
};

// ---------------------------------------------------------------------------------------------
// Beyond the manual

/// TYPE "bricaud1995" (not in the manual): phytoplankton absorption of Bricaud et al. (1995),
/// a_ph(x, lambda) = C a*_ph(lambda) with a*_ph = A(lambda) C^-B(lambda) (m^2/mg), i.e.
/// a_ph = A(lambda) C^(1 - B(lambda)); C chlorophyll a in mg m^-3. Tables 400-700 nm, 2 nm.
template <ConcentrationModel Conc>
class Bricaud1995Absorption {
public:
    static constexpr const char* type_name = "bricaud1995";

    explicit Bricaud1995Absorption(Conc concentration, Noise noise = {})
        : conc_(std::move(concentration)), a_("Bricaud 1995 A", data::bricaud_1995_A),
          b_("Bricaud 1995 B", data::bricaud_1995_B), noise_(noise) {}

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        const double c = conc_.concentration(x);
        return noise_.add(a_.at(wavelength_nm) * std::pow(c, 1.0 - b_.at(wavelength_nm)), x, wavelength_nm);
    }

    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    Conc conc_;
    SpectralTable a_, b_;
    Noise noise_;
};

/// Which absorption of Bricaud et al. (1998): total particles (a_p) or phytoplankton (a_phi).
enum class Bricaud1998Fraction { particles, phytoplankton };

/// TYPE "bricaud1998" (not in the manual): Bricaud et al. (1998) power laws in chlorophyll,
/// a_p(x, lambda) = A_p(lambda) C^E_p(lambda) (total particles, the default) or
/// a_phi(x, lambda) = A_phi(lambda) C^E_phi(lambda) (phytoplankton only); C in mg m^-3, a in
/// 1/m. Tables 400-700 nm, 2 nm.
template <ConcentrationModel Conc>
class Bricaud1998Absorption {
public:
    static constexpr const char* type_name = "bricaud1998";

    explicit Bricaud1998Absorption(Conc concentration, Bricaud1998Fraction fraction = Bricaud1998Fraction::particles,
                                   Noise noise = {})
        : conc_(std::move(concentration)), fraction_(fraction), a_(table_a(fraction)), e_(table_e(fraction)),
          noise_(noise) {}

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        const double c = conc_.concentration(x);
        return noise_.add(a_.at(wavelength_nm) * std::pow(c, e_.at(wavelength_nm)), x, wavelength_nm);
    }

    [[nodiscard]] Bricaud1998Fraction fraction() const { return fraction_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    static SpectralTable table_a(Bricaud1998Fraction f) {
        if (f == Bricaud1998Fraction::phytoplankton) return {"Bricaud 1998 A_phi", data::bricaud_1998_A_phi};
        return {"Bricaud 1998 A_p", data::bricaud_1998_A_p};
    }
    static SpectralTable table_e(Bricaud1998Fraction f) {
        if (f == Bricaud1998Fraction::phytoplankton) return {"Bricaud 1998 E_phi", data::bricaud_1998_E_phi};
        return {"Bricaud 1998 E_p", data::bricaud_1998_E_p};
    }

    Conc conc_;
    Bricaud1998Fraction fraction_;
    SpectralTable a_, e_;
    Noise noise_;
};

/// Parameters of "cdom" (not in the manual).
struct CdomParams {
    /// a_y(lambda_0) in 1/m. Default 0.012: eq. 5.15 at 1 mg m^-3 chlorophyll,
    /// 0.2 a_p(440) = 0.2 x 0.06 x 1^0.65 (Morel 1991 Case-1 water).
    double a_ref = 0.012;
    double refwl = 440.0;  ///< lambda_0 (nm)
    /// S (1/nm): 0.014, the slope of eq. 5.15 (Bricaud, Morel & Prieur 1981). Must be >= 0.
    double slope = 0.014;
};

/// TYPE "cdom" (not in the manual): coloured dissolved organic matter ("yellow substance"),
/// a_y(lambda) = a_y(lambda_0) e^{-S (lambda - lambda_0)} + N(0, sigma), the form of eq. 5.15
/// with a fixed (not covarying) magnitude. Uniform in space.
class CdomAbsorption {
public:
    static constexpr const char* type_name = "cdom";

    explicit CdomAbsorption(CdomParams params = {}, Noise noise = {}) : p_(params), noise_(noise) {
        absorption_detail::require_non_negative(p_.a_ref, "a_ref (CDOM absorption at the reference wavelength)");
        require(std::isfinite(p_.refwl) && p_.refwl > 0.0, "refwl (CDOM)", p_.refwl, "must be finite and > 0 (nm)");
        absorption_detail::require_non_negative(p_.slope, "S (CDOM spectral slope, 1/nm)");
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        absorption_detail::require_wavelength(wavelength_nm);
        return noise_.add(p_.a_ref * std::exp(-p_.slope * (wavelength_nm - p_.refwl)), x, wavelength_nm);
    }

    [[nodiscard]] const CdomParams& params() const { return p_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }
    void set_noise(Noise noise) { noise_ = noise; }

private:
    CdomParams p_;
    Noise noise_;
};

// ---------------------------------------------------------------------------------------------
// Every model is a CoefficientModel.

namespace absorption_detail {
struct UnitConcentration {
    [[nodiscard]] double concentration(vec3) const { return 1.0; }
};
}  // namespace absorption_detail

static_assert(CoefficientModel<SmithBakerAbsorption>);
static_assert(CoefficientModel<HybridPureWaterAbsorption>);
static_assert(CoefficientModel<PrieurSathyAbsorption>);
static_assert(CoefficientModel<MorelConcentrationAbsorption<absorption_detail::UnitConcentration>>);
static_assert(CoefficientModel<MorelCovariantAbsorption<MorelConcentrationAbsorption<absorption_detail::UnitConcentration>>>);
static_assert(CoefficientModel<RamanAbsorption>);
static_assert(CoefficientModel<Bricaud1995Absorption<absorption_detail::UnitConcentration>>);
static_assert(CoefficientModel<Bricaud1998Absorption<absorption_detail::UnitConcentration>>);
static_assert(CoefficientModel<CdomAbsorption>);

}  // namespace secchi::iop
