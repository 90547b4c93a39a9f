#pragma once
// The generic coefficient models (manual 5.6.1, 5.6.2, 5.7.1, 5.7.2): each serves as an
// absorption model (ADD_ABSORPTION_MODEL) or a scattering model (ADD_SCATTERING_MODEL); the
// role is the place the composer of a medium gives it, not its type. Coefficients in 1/m,
// wavelengths in nm.
//
//  - ConstantCoefficient ("constant", eq. 5.7/5.8 and 5.19): a or b the same everywhere,
//    a single value (ABS resp. SCAT, default 0.1 1/m both) or a spectrum (FILENAME, which
//    overrides the value).
//  - SpecificCoefficient<Conc> ("specific", eq. 5.11 and 5.20): a*(lambda) C(x), a specific
//    coefficient spectrum (FILENAME) times the local concentration of one constituent
//    (CONCID, default "chlorophyll", resolved by the composer to the Conc model given).
//    No units checking: a* C must come out in 1/m (manual 5.6.2.1).
//  - AnyCoefficient: a type-erased CoefficientModel for the run-time (material-file) path.
//
// SIGMA (all models) is the Noise: value + N(0, sigma) at (x, lambda), clamped at zero.
// ID (the model's name in its file) belongs to the composer and is not stored here.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/iop/concentration.hpp"
#include "secchi/optics/iop/iop_model.hpp"
#include "secchi/optics/iop/noise.hpp"
#include "secchi/optics/iop/spectral_table.hpp"
#include <cmath>
#include <concepts>
#include <cstddef>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>

namespace secchi::SECCHI_ISA::iop {

namespace detail {
/// A coefficient spectrum (FILENAME) must be >= 0 at every node (SpectralTable itself
/// accepts negative values, which other tables need).
inline void require_nonnegative_coefficient_table(const SpectralTable& table) {
    const auto wl = table.wavelengths();
    const auto v = table.values();
    for (std::size_t i = 0; i < v.size(); ++i)
        if (!(v[i] >= 0.0))
            reject("FILENAME value at " + std::to_string(wl[i]) + " nm of table " + table.name(), v[i],
                   "a coefficient must be >= 0");
}
}  // namespace detail

// ---------------------------------------------------------------------------------------
// Constant (eq. 5.7, 5.8, 5.19): a(z, lambda) = a(lambda) + N(0, sigma), or a + N(0, sigma).

class ConstantCoefficient {
public:
    static constexpr const char* type_name = "constant";
    /// ABS (absorption, 5.6.1) and SCAT (scattering, 5.7.1) both default to 0.1 1/m.
    static constexpr double default_value = 0.1;

    ConstantCoefficient() = default;
    /// ABS or SCAT: one coefficient for every wavelength (eq. 5.8, 5.19), 1/m.
    explicit ConstantCoefficient(double value, Noise noise = {}) : value_(value), noise_(noise) {
        require(std::isfinite(value) && value >= 0.0, "ABS/SCAT", value, "must be finite and >= 0 (1/m)");
    }
    /// FILENAME: a spectral coefficient a(lambda) in 1/m (eq. 5.7); it overrides ABS/SCAT.
    explicit ConstantCoefficient(SpectralTable spectrum, Noise noise = {})
        : spectrum_(std::move(spectrum)), noise_(noise) {
        detail::require_nonnegative_coefficient_table(*spectrum_);
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        return noise_.add(noiseless(wavelength_nm), x, wavelength_nm);
    }
    /// The value without noise: the spectrum at lambda if given, else the constant.
    [[nodiscard]] double noiseless(double wavelength_nm) const {
        return spectrum_ ? spectrum_->at(wavelength_nm) : value_;
    }
    [[nodiscard]] bool spectral() const { return spectrum_.has_value(); }
    [[nodiscard]] const Noise& noise() const { return noise_; }

private:
    double value_ = default_value;          ///< ABS / SCAT
    std::optional<SpectralTable> spectrum_;  ///< FILENAME (overrides value_)
    Noise noise_;                            ///< SIGMA
};

// ---------------------------------------------------------------------------------------
// Specific (eq. 5.11, 5.20): a(z, lambda) = a*(lambda) C(z) + N(0, sigma).

template <ConcentrationModel Conc>
class SpecificCoefficient {
public:
    static constexpr const char* type_name = "specific";

    /// specific: FILENAME, a*(lambda) (units such that a* C is in 1/m);
    /// conc: the model named by CONCID.
    SpecificCoefficient(SpectralTable specific, Conc conc, Noise noise = {})
        : specific_(std::move(specific)), conc_(std::move(conc)), noise_(noise) {
        detail::require_nonnegative_coefficient_table(specific_);
    }

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        const double value = specific_.at(wavelength_nm) * conc_.concentration(x);
        return noise_.add(value, x, wavelength_nm);
    }
    [[nodiscard]] const SpectralTable& specific() const { return specific_; }
    [[nodiscard]] const Conc& concentration_model() const { return conc_; }
    [[nodiscard]] const Noise& noise() const { return noise_; }

private:
    SpectralTable specific_;  ///< FILENAME
    Conc conc_;               ///< CONCID
    Noise noise_;             ///< SIGMA
};

// ---------------------------------------------------------------------------------------
// AnyCoefficient: any CoefficientModel behind a shared immutable copy (cheap to copy, safe
// to share between threads, one virtual call per query).

class AnyCoefficient {
public:
    template <class M>
        requires(!std::same_as<std::remove_cvref_t<M>, AnyCoefficient> && CoefficientModel<M>)
    AnyCoefficient(M model)  // NOLINT(google-explicit-constructor): any model converts
        : impl_(std::make_shared<const Impl<M>>(std::move(model))) {}

    [[nodiscard]] double coefficient(vec3 x, double wavelength_nm) const {
        return impl_->coefficient(x, wavelength_nm);
    }
    /// The wrapped model's type_name (its TYPE in the material file), or "" if it has none.
    [[nodiscard]] std::string_view type() const { return impl_->type(); }

private:
    struct Interface {
        virtual ~Interface() = default;
        virtual double coefficient(vec3 x, double wavelength_nm) const = 0;
        virtual std::string_view type() const = 0;
    };
    template <class M>
    struct Impl final : Interface {
        explicit Impl(M m) : model(std::move(m)) {}
        double coefficient(vec3 x, double wavelength_nm) const override {
            return model.coefficient(x, wavelength_nm);
        }
        std::string_view type() const override {
            if constexpr (requires { std::string_view(M::type_name); }) return M::type_name;
            else return {};
        }
        M model;
    };
    std::shared_ptr<const Interface> impl_;
};

static_assert(CoefficientModel<ConstantCoefficient>);
static_assert(CoefficientModel<SpecificCoefficient<ConstantConcentration>>);
static_assert(CoefficientModel<SpecificCoefficient<AnyConcentration>>);
static_assert(CoefficientModel<AnyCoefficient>);

}  // namespace secchi::iop
