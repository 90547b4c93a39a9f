#pragma once
// Phase functions sampled in SIMD lanes (the lane tracers, transport/lane_tracer.hpp): a lane
// sampler gives cos psi for a vector of uniforms u1 at once, the per-lane inverse CDF of the
// scalar sampler's u1 (phi = 2 pi u2 in every lane: the phase function is rotationally
// symmetric, manual section 5.8). Float lanes may take a sampler for double lanes, by groups.
#include "secchi/core/config.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/core/math.hpp"
#include <concepts>
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

}  // namespace secchi::SECCHI_ISA
#endif
