#pragma once
// Irradiance detectors of the first pass: virtual horizontal planes at given depths that
// span the whole (periodic) section, like the manual's virtual disks (Fig. 7.27). Every
// quantity is a surface-crossing estimate at the plane itself (Lux & Koblinger 1991, sec. 5.1;
// the F2 tally of MCNP), so a plane on a boundary (the surface, the bottom) sees the radiance
// exactly there, however steeply it changes below the boundary:
//  - Plane irradiances Ed, Eu: the weight of every photon crossing the plane downward /
//    upward (flux per area; no cosine weighting needed).
//  - Scalar irradiances Eod, Eou: the weight of every crossing times 1/|mu|, mu = the photon's
//    direction cosine (E_o = int L dOmega, and L |mu| dOmega is the flux that crosses). For
//    grazing crossings, |mu| < mu_c (the grazing cosine), 1/|mu| is replaced by its mean over
//    a radiance constant across the band, 2/mu_c: the score stays bounded (the plain
//    estimator's variance diverges logarithmically at mu = 0), and the bias is
//    int_0^mu_c (2 mu/mu_c - 1) L(mu) dmu = L'(0) mu_c^2 / 6 per hemisphere, a relative
//    ~mu_c^2 / 12 times |L'(0)| / L (< 2e-4 for mu_c = 0.05 and a radiance slope |L'(0)| <= L).
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/medium.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <vector>

namespace secchi::SECCHI_ISA {

enum IrradianceKind : int { Ed = 0, Eu = 1, Eod = 2, Eou = 3 };
using IrradianceTally = std::array<double, 4>;  ///< indexed by IrradianceKind

/// One straight flight: from depth z0 to z1, direction cosine uz, path length s, weight w at
/// the start.
struct Flight {
    double z0, z1, uz, s, w;
};

/// The absorption policy of a flight whose weight does not decay (analog and implicit
/// capture: absorption happens at interactions). Satisfies the Medium queries used here.
struct NoAbsorption {
    [[nodiscard]] double coefficient(Coefficient, double) const { return 0.0; }
    [[nodiscard]] double optical_path(Coefficient, double, double, double) const { return 0.0; }
};

/// The first pass's detector policy: built from the detector depths (m), the grazing cosine
/// mu_c and the floor's depth; `record` tallies a straight flight into one IrradianceTally per
/// depth (Ed, Eu, Eod, Eou), its weight decaying along the flight by the absorber's absorption
/// (a Medium, or NoAbsorption). PhotonTracer takes one (IrradiancePlanes by default);
/// LaneTracer also needs record_lanes, for flights in SIMD lanes.
template <class D>
concept IrradianceDetector =
    std::constructible_from<D, std::vector<double>, double, double> &&
    requires(const D& d, const Flight& f, IrradianceTally* tally) {
        { d.size() } -> std::convertible_to<std::size_t>;
        { d.depths() } -> std::convertible_to<const std::vector<double>&>;
        d.record(f, NoAbsorption{}, tally);
    };

/// Horizontal planes across the whole section (see the header comment).
class IrradiancePlanes {
public:
    /// depths: the detector planes (m); grazing_cosine: mu_c in (0, 1); floor_depth: the
    /// bottom's depth (or +inf).
    IrradiancePlanes(std::vector<double> depths, double grazing_cosine, double floor_depth)
        : depths_(std::move(depths)), grazing_(grazing_cosine), grazing_score_(2.0 / grazing_cosine) {
        require(grazing_cosine > 0.0 && grazing_cosine < 1.0, "grazing cosine", grazing_cosine, "must be in (0, 1)");
        for (double z : depths_) {
            // A plane on the bottom itself counts the flux arriving at and leaving the bottom:
            // it sits a rounding margin above it, so flights ending or starting there cross it.
            planes_.push_back(std::isfinite(floor_depth) ? std::min(z, floor_depth * (1.0 - 1e-12) - 1e-12) : z);
            // In float lanes the flights to the floor end on float(floor depth) exactly
            // (transport/lane_tracer.hpp): the plane is the next float shallower than that, or the
            // depth's own float if shallower still.
            float plane = static_cast<float>(planes_.back());
            if (std::isfinite(floor_depth) && plane >= static_cast<float>(floor_depth))
                plane = std::nextafter(static_cast<float>(floor_depth), 0.0f);
            float_planes_.push_back(plane);
        }
    }
    [[nodiscard]] std::size_t size() const { return depths_.size(); }
    [[nodiscard]] const std::vector<double>& depths() const { return depths_; }
    [[nodiscard]] double grazing_cosine() const { return grazing_; }

    /// The scalar-irradiance score of a crossing with direction cosine uz, per unit weight:
    /// 1/|uz|, or 2/mu_c below the grazing cosine. For doubles, or SIMD vectors of them.
    template <class Real>
    [[nodiscard]] Real inverse_cosine(const Real& uz) const {
        using std::abs, std::max;
        using T = scalar_t<Real>;
        const Real a = abs(uz);
        return select(a >= T(grazing_), Real(T(1)) / max(a, Real(T(grazing_))), Real(T(grazing_score_)));
    }

    /// Tallies one flight into `tally` (one entry per depth). The weight decays along the
    /// flight as w exp(-int_0^t a dt') with the absorption of `absorber` (a Medium, or
    /// NoAbsorption when absorption happens at interactions).
    template <class Absorber>
    void record(const Flight& f, const Absorber& absorber, IrradianceTally* tally) const {
        if (f.uz == 0.0) return;  // a level flight crosses no plane
        const double z_min = std::min(f.z0, f.z1), z_max = std::max(f.z0, f.z1);
        for (std::size_t i = 0; i < depths_.size(); ++i) {
            const double d = planes_[i];
            if (d < z_min || d > z_max) continue;
            // Half-open crossing rule: a flight starting on the plane going down counts as Ed,
            // one ending on it going up counts as Eu (so the surface plane z = 0 works).
            const bool down = f.uz > 0.0 && f.z0 <= d && d < f.z1;
            const bool up = f.uz < 0.0 && f.z1 <= d && d < f.z0;
            if (!down && !up) continue;
            const double w = f.w * std::exp(-absorber.optical_path(Coefficient::absorption, f.z0, f.uz, (d - f.z0) / f.uz));
            tally[i][down ? Ed : Eu] += w;
            tally[i][down ? Eod : Eou] += w * inverse_cosine(f.uz);
        }
    }

    /// record() for one flight per SIMD lane (Real: a std::experimental::simd of doubles or
    /// floats; photons in lanes, transport/lane_tracer.hpp), for the lanes in `active`: the same
    /// tests lane by lane, each plane's tallies summed per lane into `tally` (the caller sums
    /// the lanes). The weight decays along the flights by `absorber`: NoAbsorption (the weight
    /// does not decay: record()'s arithmetic), or an object whose transmittance(z0, uz, s)
    /// gives exp(-int_0^s a dt') per lane for path lengths s from depths z0 along uz
    /// (LaneTracer's: LaneAbsorption in homogeneous water, LaneMediumAbsorption in depth-varying
    /// water). tests/test_lane_tracer.cpp checks it against record(). In floats the planes are
    /// rounded to float, and a plane on the bottom is the next float shallower than the floor's.
    template <class Real, class Mask, class Absorber = NoAbsorption>
    SECCHI_KERNEL void record_lanes(const Real& z0, const Real& z1, const Real& uz, const Real&, const Real& w,
                                    const Mask& active, std::array<Real, 4>* tally, const Absorber& absorber = {}) const {
        using T = scalar_t<Real>;
        const Real inverse_mu = inverse_cosine(uz);
        for (std::size_t i = 0; i < depths_.size(); ++i) {
            const T d = std::is_same_v<T, float> ? T(float_planes_[i]) : T(planes_[i]);
            const Mask down = active && uz > T(0) && z0 <= d && d < z1;
            const Mask up = active && uz < T(0) && z1 <= d && d < z0;
            if (none_of(down || up)) continue;
            Real at_plane = w;
            if constexpr (!std::same_as<Absorber, NoAbsorption>) {  // w exp(-a s), s = (d - z0) / uz to the plane
                Real s(T(0));
                where(down || up, s) = (Real(d) - z0) / uz;
                at_plane = w * absorber.transmittance(z0, uz, s);
            }
            const Real scalar = at_plane * inverse_mu;
            where(down, tally[i][Ed]) += at_plane;
            where(up, tally[i][Eu]) += at_plane;
            where(down, tally[i][Eod]) += scalar;
            where(up, tally[i][Eou]) += scalar;
        }
    }

private:
    std::vector<double> depths_, planes_;
    std::vector<float> float_planes_;  ///< the planes for float lanes (record_lanes)
    double grazing_, grazing_score_;   ///< mu_c and 2 / mu_c
};

static_assert(IrradianceDetector<IrradiancePlanes>);

}  // namespace secchi
