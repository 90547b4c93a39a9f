#pragma once
// Concentration models (manual 5.10): the local concentration C(x) of one constituent
// (chlorophyll, suspended sediment, CDOM, ...), in the constituent's own units. The specific
// and concentration-driven coefficient models (5.6.2, 5.7.2-5.7.4) multiply or raise it; the
// models of one medium are independent of each other (an aggregate, not a linear sum).
//
// The manual's models vary with depth only: depth d = z - ZLEVEL (metres, positive down),
// where ZLEVEL is the z-coordinate of zero depth. Each model's parameters are a small struct
// whose members carry the DIRSIG material-file name (ADD_CONCENTRATION_MODEL) and default.
// SIGMA (every model) is the Noise, evaluated with wavelength 0 (a concentration has none).
//
// ID (default "chlorophyll" in every table) is the name the composer of a medium gives the
// model so that coefficient models can refer to it (CONCID); it is not stored here.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/iop/iop_model.hpp"
#include "secchi/optics/iop/noise.hpp"
#include <algorithm>
#include <cmath>
#include <concepts>
#include <memory>
#include <string_view>
#include <type_traits>
#include <utility>

namespace secchi::SECCHI_ISA::iop {

/// The noise of a concentration: same Noise as the coefficients, at wavelength 0.
inline constexpr double concentration_noise_wavelength = 0.0;

// ---------------------------------------------------------------------------------------
// 5.10.1 Constant: C(x) = CONC + N(0, sigma).

struct ConstantConcentrationParams {
    double conc = 2.0;  ///< CONC: the concentration at any point of the medium
};

class ConstantConcentration : public ModelParameters<ConstantConcentrationParams> {
public:
    using Params = ConstantConcentrationParams;
    static constexpr const char* type_name = "constant";

    ConstantConcentration() : ConstantConcentration(Params{}) {}
    explicit ConstantConcentration(const Params& p, Noise noise = {}) : ModelParameters<ConstantConcentrationParams>(p, noise) {
        require(std::isfinite(p.conc) && p.conc >= 0.0, "CONC", p.conc, "must be finite and >= 0");
    }

    [[nodiscard]] double concentration(vec3 x) const {
        return noise_.add(p_.conc, x, concentration_noise_wavelength);
    }
};

// ---------------------------------------------------------------------------------------
// 5.10.2 Linear: C(d) = ATZERO + RATE d + N(0, sigma), d = z - ZLEVEL.
// The manual gives no bounds: a negative RATE (the default) reaches zero at depth
// ATZERO / |RATE| (20 m with the defaults); below it the line would be negative, which no
// concentration can be, so C is clamped at 0 there (and likewise above ZLEVEL for a positive
// RATE). The line is otherwise extrapolated on both sides of ZLEVEL.

struct LinearConcentrationParams {
    double atzero = 2.0;  ///< ATZERO: the concentration at zero depth (z = ZLEVEL)
    double zlevel = 0.0;  ///< ZLEVEL: the z-coordinate where the depth is zero (m)
    double rate = -0.1;   ///< RATE: change of concentration per metre of (positive) depth
};

class LinearConcentration : public ModelParameters<LinearConcentrationParams> {
public:
    using Params = LinearConcentrationParams;
    static constexpr const char* type_name = "linear";

    LinearConcentration() : LinearConcentration(Params{}) {}
    explicit LinearConcentration(const Params& p, Noise noise = {}) : ModelParameters<LinearConcentrationParams>(p, noise) {
        require(std::isfinite(p.atzero) && p.atzero >= 0.0, "ATZERO", p.atzero, "must be finite and >= 0");
        require(std::isfinite(p.zlevel), "ZLEVEL", p.zlevel, "must be finite");
        require(std::isfinite(p.rate), "RATE", p.rate, "must be finite");
    }

    /// The noiseless profile, clamped at zero.
    [[nodiscard]] double profile(double z) const {
        return std::max(0.0, p_.atzero + p_.rate * (z - p_.zlevel));
    }
    [[nodiscard]] double concentration(vec3 x) const {
        return noise_.add(profile(x.z), x, concentration_noise_wavelength);
    }
};

// ---------------------------------------------------------------------------------------
// 5.10.3 Gaussian (eq. 5.30, Mobley 1994's fit to the Celtic Sea chlorophyll profile, the
// defaults): C(d) = BG + H / (S sqrt(2 pi)) exp(-(d - DMAX)^2 / (2 S^2)) + N(0, sigma),
// d = z - ZLEVEL. The peak BG + H / (S sqrt(2 pi)) is at depth DMAX; BG is the minimum.

struct GaussianConcentrationParams {
    double zlevel = 0.0;  ///< ZLEVEL: the z-coordinate where the depth is zero (m)
    double dmax = 17.0;   ///< DMAX: depth of the maximum, the Gaussian's mean (m)
    double bg = 0.2;      ///< BG: the background concentration C_0
    double h = 144.0;     ///< H: h of eq. 5.30 (the integral of the peak over depth)
    double s = 9.0;       ///< S: s of eq. 5.30, the peak's standard deviation (m)
};

class GaussianConcentration : public ModelParameters<GaussianConcentrationParams> {
public:
    using Params = GaussianConcentrationParams;
    static constexpr const char* type_name = "gaussian";

    GaussianConcentration() : GaussianConcentration(Params{}) {}
    explicit GaussianConcentration(const Params& p, Noise noise = {}) : ModelParameters<GaussianConcentrationParams>(p, noise) {
        require(std::isfinite(p.zlevel), "ZLEVEL", p.zlevel, "must be finite");
        require(std::isfinite(p.dmax), "DMAX", p.dmax, "must be finite");
        require(std::isfinite(p.bg) && p.bg >= 0.0, "BG", p.bg, "must be finite and >= 0");
        require(std::isfinite(p.h) && p.h >= 0.0, "H", p.h, "must be finite and >= 0 (BG is the minimum)");
        require(std::isfinite(p.s) && p.s > 0.0, "S", p.s, "must be finite and > 0");
    }

    /// The noiseless profile of eq. 5.30.
    [[nodiscard]] double profile(double z) const {
        const double u = (z - p_.zlevel - p_.dmax) / p_.s;
        return p_.bg + p_.h / (p_.s * std::sqrt(two_pi)) * std::exp(-0.5 * u * u);
    }
    [[nodiscard]] double concentration(vec3 x) const {
        return noise_.add(profile(x.z), x, concentration_noise_wavelength);
    }
};

// ---------------------------------------------------------------------------------------
// CONCID = "none" (kopelevich, eq. 5.24): the model is independent of any concentration,
// i.e. C = 1 everywhere. No noise: the coefficient model carries its own SIGMA.

struct NoConcentration {
    static constexpr const char* type_name = "none";
    [[nodiscard]] double concentration(vec3 /*x*/) const { return 1.0; }
};

// ---------------------------------------------------------------------------------------
// AnyConcentration: a type-erased concentration model for the run-time path (models named
// in a material file). Holds an immutable copy of any ConcentrationModel behind a shared
// pointer: cheap to copy, safe to share between threads, one virtual call per query.

class AnyConcentration {
public:
    template <class M>
        requires(!std::same_as<std::remove_cvref_t<M>, AnyConcentration> && ConcentrationModel<M>)
    AnyConcentration(M model)  // NOLINT(google-explicit-constructor): any model converts
        : impl_(std::make_shared<const Impl<M>>(std::move(model))) {}

    [[nodiscard]] double concentration(vec3 x) const { return impl_->concentration(x); }
    /// The wrapped model's type_name (its TYPE in the material file), or "" if it has none.
    [[nodiscard]] std::string_view type() const { return impl_->type(); }

private:
    struct Interface {
        virtual ~Interface() = default;
        virtual double concentration(vec3 x) const = 0;
        virtual std::string_view type() const = 0;
    };
    template <class M>
    struct Impl final : Interface {
        explicit Impl(M m) : model(std::move(m)) {}
        double concentration(vec3 x) const override { return model.concentration(x); }
        std::string_view type() const override {
            if constexpr (requires { std::string_view(M::type_name); }) return M::type_name;
            else return {};
        }
        M model;
    };
    std::shared_ptr<const Interface> impl_;
};

static_assert(ConcentrationModel<ConstantConcentration>);
static_assert(ConcentrationModel<LinearConcentration>);
static_assert(ConcentrationModel<GaussianConcentration>);
static_assert(ConcentrationModel<NoConcentration>);
static_assert(ConcentrationModel<AnyConcentration>);

}  // namespace secchi::iop
