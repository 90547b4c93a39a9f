#pragma once
// The linear model of IOPs (manual 5.4): a base medium plus added components,
//   a(x, lambda) = sum_i a_i(x, lambda)                        (eq. 5.3)
//   b(x, lambda) = sum_i b_i(x, lambda)                        (eq. 5.4)
//   p(x, psi)    = sum_i (b_i / b) p_i(psi)                    (eq. 5.5, 5.6)
// where every scattering model carries its own phase function (SCATID, manual 5.8; a
// scattering model without one gets the uniform phase function).
//
// Two ways to build one, one interface:
//  - LinearIopModel<std::tuple<A...>, std::tuple<Scatterer<B, P>...>>: composed at compile time
//    from model types (no virtual calls anywhere);
//  - RuntimeIopModel: vectors of type-erased models, built from a material file
//    (io/material_medium.hpp).
// Both expose absorption(x, lambda), for_each_scatterer(f) and refractive_index(lambda), and
// stratify() turns either into the transport's StratifiedWater at one wavelength (the
// manual's concentrations vary with depth only, 5.10), so both forms give identical values;
// stratify_typed() does the same for a compile-time model and keeps its phase types.
#include "secchi/core/config.hpp"
#include "secchi/optics/iop/coefficient.hpp"
#include "secchi/optics/iop/iop_model.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/stratified_water.hpp"
#include <functional>
#include <span>
#include <tuple>
#include <vector>

namespace secchi::SECCHI_ISA::iop {

/// A scattering-coefficient model and the phase function tied to it (SCATID).
template <CoefficientModel B, PhaseFunction P>
struct Scatterer {
    B coefficient;
    P phase;
};
template <class B, class P>
Scatterer(B, P) -> Scatterer<B, P>;  // (aggregate deduction, for compilers without C++20's: clang < 17)

/// The medium's single refractive index n(lambda) (manual 5.9; not part of the linear sums).
using RefractiveIndexFunction = std::function<double(double)>;

template <class Absorbers, class Scatterers>
class LinearIopModel {
public:
    LinearIopModel(Absorbers absorbers, Scatterers scatterers, RefractiveIndexFunction n = [](double) { return 1.0; })
        : absorbers_(std::move(absorbers)), scatterers_(std::move(scatterers)), n_(std::move(n)) {}

    /// a(x, lambda), eq. 5.3.
    [[nodiscard]] double absorption(vec3 x, double wavelength_nm) const {
        return std::apply([&](const auto&... m) { return (0.0 + ... + m.coefficient(x, wavelength_nm)); }, absorbers_);
    }
    /// Calls f(scatterer) for each scattering component in order.
    template <class F>
    void for_each_scatterer(F&& f) const {
        std::apply([&](const auto&... s) { (f(s), ...); }, scatterers_);
    }
    [[nodiscard]] double refractive_index(double wavelength_nm) const { return n_(wavelength_nm); }
    [[nodiscard]] const Scatterers& scatterers() const { return scatterers_; }

private:
    Absorbers absorbers_;
    Scatterers scatterers_;
    RefractiveIndexFunction n_;
};

/// The run-time form: type-erased models (virtual calls here are fine: stratify() samples the
/// model once per depth node; the transport runs on the resulting StratifiedWater).
struct RuntimeIopModel {
    std::vector<AnyCoefficient> absorbers;
    std::vector<Scatterer<AnyCoefficient, AnyPhaseFunction>> scatterers;
    RefractiveIndexFunction n = [](double) { return 1.0; };

    [[nodiscard]] double absorption(vec3 x, double wavelength_nm) const {
        double a = 0.0;
        for (const auto& m : absorbers) a += m.coefficient(x, wavelength_nm);
        return a;
    }
    template <class F>
    void for_each_scatterer(F&& f) const {
        for (const auto& s : scatterers) f(s);
    }
    [[nodiscard]] double refractive_index(double wavelength_nm) const { return n(wavelength_nm); }
};

/// b(x, lambda), eq. 5.4.
template <class Model>
double scattering(const Model& m, vec3 x, double wavelength_nm) {
    double b = 0.0;
    m.for_each_scatterer([&](const auto& s) { b += s.coefficient.coefficient(x, wavelength_nm); });
    return b;
}

template <class P>
AnyPhaseFunction to_any_phase(const P& p) {
    if constexpr (std::is_same_v<P, AnyPhaseFunction>) return p;
    else return AnyPhaseFunction{AnyPhase{p}};
}

/// Depth nodes 0, h, 2h, ..., max_depth (m).
inline std::vector<double> uniform_depths(double max_depth, double spacing) {
    require(spacing > 0.0 && max_depth > 0.0, "depth node spacing (m)", spacing, "must be > 0 (and max_depth > 0)");
    const auto n = static_cast<std::size_t>(std::ceil(max_depth / spacing - 1e-9));
    std::vector<double> z(n + 1);
    for (std::size_t k = 0; k <= n; ++k) z[k] = std::min(max_depth, static_cast<double>(k) * spacing);
    return z;
}

namespace detail {

/// a and every b_i of the model at one wavelength, sampled at the depth nodes (x = (0, 0, z)).
template <class Model>
DepthProfile sample_profile(const Model& m, double wavelength_nm, std::span<const double> depths) {
    DepthProfile profile;
    profile.depth.assign(depths.begin(), depths.end());
    for (double z : depths) profile.absorption.push_back(m.absorption({0.0, 0.0, z}, wavelength_nm));
    m.for_each_scatterer([&](const auto& s) {
        std::vector<double> b;
        b.reserve(depths.size());
        for (double z : depths) b.push_back(s.coefficient.coefficient({0.0, 0.0, z}, wavelength_nm));
        profile.scattering.push_back(std::move(b));
    });
    return profile;
}

}  // namespace detail

/// The model at one wavelength as the transport's depth profile: a and every b_i sampled at
/// the depth nodes (x = (0, 0, z)), linear in between (stratified_water.hpp), and the water's
/// refractive index at that wavelength (which the surface then takes). The phase functions
/// as AnyPhaseFunction: one water type for either model form (a material file's types are
/// known at run time only).
template <class Model>
StratifiedWater<AnyPhaseFunction> stratify(const Model& m, double wavelength_nm, std::span<const double> depths) {
    std::vector<AnyPhaseFunction> phases;
    m.for_each_scatterer([&](const auto& s) { phases.push_back(to_any_phase(s.phase)); });
    return StratifiedWater<AnyPhaseFunction>(detail::sample_profile(m, wavelength_nm, depths), std::move(phases),
                                             m.refractive_index(wavelength_nm));
}

/// stratify() of a model composed at compile time, keeping its scatterers' phase types:
/// StratifiedWater<P0, P1, ...> (StratifiedWater<P0> for one scatterer), whose transport calls
/// each phase function on its own type. Same profile and phase functions as stratify(), so the
/// same numbers.
template <class Absorbers, class... B, class... P>
StratifiedWater<P...> stratify_typed(const LinearIopModel<Absorbers, std::tuple<Scatterer<B, P>...>>& m,
                                     double wavelength_nm, std::span<const double> depths) {
    auto phases = [&] {
        if constexpr (sizeof...(P) == 1) return std::vector<P...>{std::get<0>(m.scatterers()).phase};
        else return std::apply([](const auto&... s) { return std::tuple<P...>{s.phase...}; }, m.scatterers());
    }();
    return StratifiedWater<P...>(detail::sample_profile(m, wavelength_nm, depths), std::move(phases),
                                 m.refractive_index(wavelength_nm));
}

}  // namespace secchi::iop
