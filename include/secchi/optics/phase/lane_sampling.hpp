#pragma once
// Phase functions sampled in SIMD lanes (the lane tracers, transport/lane_tracer.hpp): a lane
// sampler gives cos psi for a vector of uniforms u1 at once, the per-lane inverse CDF of the
// scalar sampler's u1 (phi = 2 pi u2 in every lane: the phase function is rotationally
// symmetric, manual section 5.8). Float lanes may take a sampler for double lanes, by groups.
#include "secchi/core/config.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include <concepts>
#include <cstddef>
#include <type_traits>

#if SECCHI_HAS_LANES
namespace secchi::SECCHI_ISA {

/// A phase function that samples cos psi for a vector of uniforms at once, with phi = 2 pi u2
/// (as its scalar sample_direction does).
template <class P, class Lanes = lanes::Reals>
concept LanePhaseSampler = requires(const P p, Lanes u) {
    { p.cos_psi(u) } -> std::same_as<Lanes>;
};

/// A phase function whose cos psi the lanes of Real sample in the vectors: with its lane
/// sampler for Real, or in float lanes with its sampler for double lanes, by groups of lanes.
template <class P, class Real>
concept LaneSampled = LanePhaseSampler<P, Real> ||
                      (std::is_same_v<scalar_t<Real>, float> && LanePhaseSampler<P, lanes::Reals>);

/// cos psi of phase function p (LaneSampled) for each lane's uniform u.
template <class P, class Real>
    requires LaneSampled<P, Real>
SECCHI_KERNEL Real lane_cos_psi(const P& p, const Real& u) {
    if constexpr (LanePhaseSampler<P, Real>) {
        return p.cos_psi(u);
    } else {
        return lanes::through_doubles(u, [&](const lanes::Reals& v) { return p.cos_psi(v); });
    }
}

/// Every lane: the phase function samples each lane.
struct EveryLane {
    constexpr bool operator()(std::size_t) const { return true; }
};

/// cos psi of any phase function p for each lane's uniform u: in the vectors where p is
/// LaneSampled (lane_cos_psi), else its scalar sampler's (sample_direction(u, u2).cos_psi, the
/// same for every u2) lane by lane, in the lanes l where wanted(l) (the others hold 0).
template <class P, class Real, class Wanted = EveryLane>
Real cos_psi_in_lanes(const P& p, const Real& u, Wanted wanted = {}) {
    if constexpr (LaneSampled<P, Real>) {
        return lane_cos_psi(p, u);
    } else {
        using T = scalar_t<Real>;
        alignas(64) T out[Real::size()] = {};
        for (std::size_t l = 0; l < Real::size(); ++l)
            if (wanted(l)) out[l] = static_cast<T>(sample_direction_of(p, static_cast<double>(u[l]), 0.0).cos_psi);
        return Real(out, lanes::aligned);
    }
}

}  // namespace secchi::SECCHI_ISA
#endif
