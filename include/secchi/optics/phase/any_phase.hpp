#pragma once
// Every phase-function type as one run-time variant, and a wrapper that makes the variant a
// PhaseFunction itself (one std::visit per call: for configuration, tests and tools; the
// photon loop instead visits once and runs on the concrete type, see solver/phase_choice.hpp).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <concepts>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

#include "secchi/optics/phase/fournier_forand.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/lane_sampling.hpp"
#include "secchi/optics/phase/mixture.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/optics/phase/rayleigh_like.hpp"
#include "secchi/optics/phase/schlick.hpp"
#include "secchi/optics/phase/tabulated.hpp"

namespace secchi::SECCHI_ISA {

using AnyPhase = std::variant<IsotropicPhase, RayleighPhase, HenyeyGreensteinPhase, TabulatedPhase, SchlickPhase,
                              PhaseMixture<HenyeyGreensteinPhase>, PhaseMixture<SchlickPhase>, RayleighLikePhase,
                              FournierForandPhase>;

/// An AnyPhase as a PhaseFunction (with the breakpoints of the held alternative).
struct AnyPhaseFunction {
    AnyPhase p;

    double eval(double cos_psi) const {
        return std::visit([&](const auto& f) { return static_cast<double>(f.eval(cos_psi)); }, p);
    }
    double pdf(double cos_psi) const {
        return std::visit([&](const auto& f) { return static_cast<double>(f.pdf(cos_psi)); }, p);
    }
    PhaseSample sample(double u1, double u2) const {
        return std::visit([&](const auto& f) { return f.sample(u1, u2); }, p);
    }
    /// The direction of sample(u1, u2) without its density, where the held type can skip it.
    PhaseDirection sample_direction(double u1, double u2) const {
        return std::visit([&](const auto& f) { return sample_direction_of(f, u1, u2); }, p);
    }
#if SECCHI_HAS_LANES
    /// cos psi for lanes of uniforms u1 (the lane tracers: lane_sampling.hpp), one visit per
    /// vector: the held function's own lane sampler where it has one, else its scalar sampler
    /// lane by lane. The same values as the held type gives in the lanes, bit for bit.
    template <class Lanes>
        requires(std::same_as<Lanes, lanes::Reals> || std::same_as<Lanes, lanes::Floats>)
    Lanes cos_psi(const Lanes& u1) const {
        return std::visit([&](const auto& f) { return cos_psi_in_lanes(f, u1); }, p);
    }
#endif
    std::vector<double> breakpoints() const {
        return std::visit([](const auto& f) { return breakpoints_of(f); }, p);
    }
    std::string name() const {
        return std::visit([](const auto& f) { return std::string(f.name()); }, p);
    }
    /// The held function's uniforms of its inverse CDF that scatter backward, for a backscatter
    /// bias (transport/importance.hpp); refused, by the phase's name, for a type that names none.
    std::pair<double, double> backward_uniforms() const {
        return std::visit(
            [&](const auto& f) -> std::pair<double, double> {
                if constexpr (requires { f.backward_uniforms(); }) return f.backward_uniforms();
                else reject("phase", name(), "names no backward uniforms for a backscatter bias (Henyey-Greenstein, tables and Fournier-Forand do)");
            },
            p);
    }
};

static_assert(PhaseFunction<AnyPhaseFunction>);
#if SECCHI_HAS_LANES
static_assert(LanePhaseSampler<AnyPhaseFunction, lanes::Reals> && LanePhaseSampler<AnyPhaseFunction, lanes::Floats>);
#endif
static_assert(PhaseFunction<SchlickPhase> && PhaseFunction<RayleighLikePhase> && PhaseFunction<FournierForandPhase>);
static_assert(PhaseFunction<PhaseMixture<HenyeyGreensteinPhase>> && PhaseFunction<PhaseMixture<SchlickPhase>>);

}  // namespace secchi
