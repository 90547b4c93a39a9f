#pragma once
// The photon physics of the first pass between boundaries (manual 3.3), written once for one
// photon (doubles: PhotonTracer, tracer.hpp) and for photons in lanes (SIMD vectors of doubles
// or floats, one photon per lane: LaneTracer, lane_tracer.hpp). What differs between the two is
// only the schedule: which photon is traced when, and when each uniform is drawn from its
// stream. The rules themselves are these functions:
//   free flight  the free path s = -ln(u) / k (eq. 3.17; k = c, or b with continuous
//                absorption), cut where the photon meets the surface (z = 0) or the floor;
//   absorption   at an interaction, by the albedo w0 = b / c in the settings' mode (3.3.5):
//                analog (absorbed with probability 1 - w0), implicit capture (weight x w0),
//                continuous (none at the interaction: the weight decays as exp(-a s) along
//                every flight instead);
//   storage      equal flux (3.3.6): an event is stored with probability equal to the photon's
//                weight (every record then carries the flux of an unweighted photon), every
//                event of an analog photon; none below the map's depth;
//   angles       a scattering direction from the phase function (cos psi, phi), rotated
//                about the direction of flight;
//   limits       the scattering-order limit and the roulette threshold (3.3.8).
// A `Real` is a double or float, or a SIMD vector of them; its mask (mask_of<Real>) is a bool
// or the vector's mask, and select/any_lane work on both (core/math.hpp).
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/lane_sampling.hpp"
#include "secchi/transport/settings.hpp"
#include "secchi/core/lanes.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>

namespace secchi::SECCHI_ISA {

/// A photon's flight to its next event: path length t to depth z1, and whether it ends on the
/// surface (z1 = the top, 0 exactly for the mean plane) or on the floor (the bottom or the escape depth).
template <class Real>
struct FreeFlight {
    Real t, z1;
    mask_of<Real> to_surface, to_floor;
};

/// The outcome of absorption at an interaction: the weight after it, the weight absorbed
/// (for the energy ledger), and whether the photon ends there.
template <class Real>
struct Absorption {
    Real w, absorbed;
    mask_of<Real> ends;
};

/// The scattering angles of an event: cos psi from the phase function, phi uniform in [0, 2 pi).
template <class Real>
struct ScatteringAngles {
    Real cos_psi, phi;
};

/// The per-event rules of the settings (see the header comment). Holds no photon state:
/// each function maps a photon's (or the lanes') values to the event's outcome.
class EventPhysics {
public:
    /// `top`: the depth where upward flights end, the mean surface plane (0), or the crests of a
    /// surface with geometry (the tracer then ends flights earlier, where they cross it).
    EventPhysics(const TransportSettings& s, double floor_depth, double top = 0.0)
        : mode_(s.absorption), floor_depth_(floor_depth), top_(top), map_depth_(s.map_depth),
          roulette_weight_(s.roulette_weight), max_order_(s.max_order) {}

    [[nodiscard]] AbsorptionMode mode() const { return mode_; }
    [[nodiscard]] bool analog() const { return mode_ == AbsorptionMode::analog; }
    [[nodiscard]] bool continuous() const { return mode_ == AbsorptionMode::continuous; }
    /// The coefficient of the free paths (eq. 3.17): b alone when absorption is continuous, else c.
    [[nodiscard]] Coefficient path_coefficient() const {
        return continuous() ? Coefficient::scattering : Coefficient::attenuation;
    }
    /// Whether absorb() reads its uniform (analog photons only), and keeps() its own.
    [[nodiscard]] bool absorption_draws() const { return analog(); }
    [[nodiscard]] bool storage_draws() const { return !analog(); }

    /// The flight of free path s from depth z with direction cosine uz: to the next event, or
    /// to the surface (ending on z = 0 exactly, so that a detector at depth 0 counts it: the
    /// half-open crossing rule of IrradiancePlanes::record) or the floor if the photon gets
    /// there first. In floats a flight to the floor ends on float(floor depth) exactly (a
    /// detector plane on the floor is the next float shallower: lane_tracer.hpp).
    template <class Real>
    SECCHI_KERNEL FreeFlight<Real> free_flight(const Real& z, const Real& uz, const Real& s) const {
        using T = scalar_t<Real>;
        const Real floor_depth(static_cast<T>(floor_depth_));
        const Real top(static_cast<T>(top_));
        const Real z_free = z + uz * s;
        FreeFlight<Real> f{s, z_free, z_free < top, z_free >= floor_depth};
        if (any_lane(f.to_surface || f.to_floor)) {  // the divisions only where a photon meets a boundary
            f.t = select(f.to_floor, (floor_depth - z) / uz, select(f.to_surface, (top - z) / uz, s));
            f.z1 = select(f.to_surface, top, z + uz * f.t);
            if constexpr (std::is_same_v<T, float>) f.z1 = select(f.to_floor, floor_depth, f.z1);
        }
        return f;
    }

    /// Absorption at an interaction of a photon of weight w, albedo w0 (manual 3.3.5); u is the
    /// event's uniform for the analog choice (read only when absorption_draws()). w0 is one
    /// double for every lane (a depth-independent medium's), or a Real: each lane's own (its
    /// depth's, in depth-varying water).
    template <class Real, class Albedo>
    SECCHI_KERNEL Absorption<Real> absorb(const Real& w, const Real& u, const Albedo& w0) const {
        using T = scalar_t<Real>;
        using Mask = mask_of<Real>;
        Real kept, lost;  // w0 and 1 - w0 (in double where w0 is one double, then rounded to T)
        if constexpr (std::is_same_v<Albedo, double>) {
            kept = Real(static_cast<T>(w0));
            lost = Real(static_cast<T>(1.0 - w0));
        } else {
            kept = w0;
            lost = Real(T(1)) - w0;
        }
        switch (mode_) {
            case AbsorptionMode::analog: {
                const Mask ends = u >= kept;
                return {w, select(ends, w, Real(T(0))), ends};
            }
            case AbsorptionMode::implicit_capture: return {w * kept, w * lost, Mask(false)};
            case AbsorptionMode::continuous: break;  // every interaction scatters
        }
        return {w, Real(T(0)), Mask(false)};
    }

    /// The equal-flux storage rule (manual 3.3.6) for an event at depth z of a photon of weight
    /// w: stored with probability w (u: the event's uniform, read only when storage_draws()),
    /// always for an analog photon (w = 1); never below the map's depth.
    template <class Real>
    SECCHI_KERNEL mask_of<Real> keeps(const Real& w, const Real& u, const Real& z) const {
        mask_of<Real> keep(true);
        if (!analog()) keep = u < w;
        if (std::isfinite(map_depth_)) keep = keep && in_map(z);
        return keep;
    }

    /// Whether an event at depth z is within the map's depth (settings.map_depth).
    template <class Real>
    SECCHI_KERNEL mask_of<Real> in_map(const Real& z) const {
        return z <= static_cast<scalar_t<Real>>(map_depth_);
    }

    /// With depth importance (importance.hpp) the expected number of copies of an event is
    /// w I(z) (`importance` = I(z)): floor(w I + u) copies, each carrying Phi / I(z).
    [[nodiscard]] static double copies(double w, double importance, double u) { return std::floor(w * importance + u); }

    /// Whether a photon that has scattered `order` times stops at this interaction, unstored
    /// (the scattering-order limit of manual 3.3.8; never when the limit is 0).
    template <class Order>
    SECCHI_KERNEL mask_of<Order> beyond_order(const Order& order) const {
        if (max_order_ == 0) return mask_of<Order>(false);
        return order >= static_cast<scalar_t<Order>>(max_order_);
    }

    /// Whether a photon of weight w (relative to its importance level) meets Russian roulette
    /// (its cumulative survival probability fell below the roulette weight; 3.3.8).
    template <class Real>
    SECCHI_KERNEL mask_of<Real> roulette_due(const Real& w) const {
        if (roulette_weight_ == 0.0) return mask_of<Real>(false);
        return w < static_cast<scalar_t<Real>>(roulette_weight_);
    }

    /// The scattering angles at depth z from the event's uniforms u_psi, u_phi: per photon
    /// through the medium's sampler (scattering_direction), or in the vectors for a phase
    /// function with a lane sampler (cos_psi(Reals): a per-lane inverse CDF, phi = 2 pi u_phi),
    /// in float lanes also one for double lanes only (a table) by groups of double lanes; a
    /// mixture of phase functions (depth-varying water) by its components (mixture_angles); any
    /// other phase function's cos psi lane by lane. In the lanes phi = 2 pi u_phi for every phase
    /// function (computed in the lanes' type: rotational symmetry, manual section 5.8), so that a
    /// phase function gives the same angles whether its type is known or erased (AnyPhaseFunction).
    template <Medium M, class Real>
    SECCHI_KERNEL static ScatteringAngles<Real> angles(const M& medium, const Real& z, const Real& u_psi,
                                                       const Real& u_phi);

private:
    AbsorptionMode mode_;
    double floor_depth_, top_, map_depth_, roulette_weight_;
    unsigned max_order_;
};

#if SECCHI_HAS_LANES

/// A medium of one phase function (phase_type, phase()) sampled in the vectors of Real.
template <class M, class Real>
concept LaneSampledMedium = requires(const M m) {
    typename M::phase_type;
    m.phase();
} && LaneSampled<typename M::phase_type, Real>;

/// A medium whose phase function at depth z is a mixture of components (eq. 5.5-5.6; e.g.
/// StratifiedWater): choose(z, u1) gives the component and the rescaled uniform its own sampler
/// takes, visit_phase(i, f) calls f on component i.
namespace detail {
/// A visitor that takes any component's phase function (for PhaseMixtureMedium's check).
struct AnyPhase {
    template <class P>
    void operator()(const P&) const {}
};
}  // namespace detail
template <class M>
concept PhaseMixtureMedium = requires(const M m, double z, double u, std::size_t i) {
    { m.choose(z, u).index } -> std::convertible_to<std::size_t>;
    { m.choose(z, u).v } -> std::convertible_to<double>;
    { m.components() } -> std::convertible_to<std::size_t>;
    m.visit_phase(i, detail::AnyPhase{});
};

/// The mixture's scattering angles per lane: each lane's component chosen lane by lane at its
/// depth (choose, in double), then each component present sampled in the vectors over all lanes
/// where it is LaneSampled (kept in the lanes that chose it), else lane by lane through its own
/// sampler; phi = 2 pi u_phi in every lane: the angles scattering_direction gives lane by lane,
/// but for the lane samplers' rounding (and in float lanes phi's).
template <PhaseMixtureMedium M, class Real>
ScatteringAngles<Real> mixture_angles(const M& medium, const Real& z, const Real& u_psi, const Real& u_phi) {
    using T = scalar_t<Real>;
    constexpr int width = static_cast<int>(Real::size());
    constexpr T below_one = T(1) - std::numeric_limits<T>::epsilon() / 2;
    alignas(64) T v[width], cos_psi[width];
    std::size_t index[width];
    for (int l = 0; l < width; ++l) {
        const auto c = medium.choose(static_cast<double>(z[l]), static_cast<double>(u_psi[l]));
        index[l] = c.index;
        v[l] = std::min(static_cast<T>(c.v), below_one);  // (in floats v may round up to 1)
    }
    for (std::size_t i = 0; i < medium.components(); ++i) {
        if (std::none_of(index, index + width, [&](std::size_t k) { return k == i; })) continue;
        medium.visit_phase(i, [&](const auto& p) {
            const Real mu = cos_psi_in_lanes(p, Real(v, lanes::aligned), [&](std::size_t l) { return index[l] == i; });
            for (int l = 0; l < width; ++l)
                if (index[l] == i) cos_psi[l] = mu[l];
        });
    }
    return {Real(cos_psi, lanes::aligned), static_cast<T>(two_pi) * u_phi};
}
#endif

template <Medium M, class Real>
SECCHI_KERNEL ScatteringAngles<Real> EventPhysics::angles(const M& medium, const Real& z, const Real& u_psi,
                                                          const Real& u_phi) {
    if constexpr (std::is_floating_point_v<Real>) {
        const PhaseDirection d = scattering_direction(medium, z, u_psi, u_phi);
        return {static_cast<Real>(d.cos_psi), static_cast<Real>(d.phi)};
    } else {
#if SECCHI_HAS_LANES
        using T = scalar_t<Real>;
        constexpr int width = static_cast<int>(Real::size());
        if constexpr (LaneSampledMedium<M, Real>) {
            return {lane_cos_psi(medium.phase(), u_psi), static_cast<T>(two_pi) * u_phi};
        } else if constexpr (PhaseMixtureMedium<M>) {
            return mixture_angles(medium, z, u_psi, u_phi);
        } else {  // (phi = 2 pi u_phi as in the vectors: the same angles whatever the phase's type)
            alignas(64) T cos_psi[width];
            for (int l = 0; l < width; ++l)
                cos_psi[l] = static_cast<T>(scattering_direction(medium, static_cast<double>(z[l]), u_psi[l], u_phi[l]).cos_psi);
            return {Real(cos_psi, lanes::aligned), static_cast<T>(two_pi) * u_phi};
        }
#endif
    }
}

}  // namespace secchi
