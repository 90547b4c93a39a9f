#pragma once
// Irradiance detectors of the first pass: virtual horizontal planes at given depths that
// span the whole (periodic) section, like the manual's virtual disks (Fig. 7.27).
//  - Plane irradiances Ed, Eu: the weight of every photon crossing the plane downward /
//    upward (flux per area; no cosine weighting needed).
//  - Scalar irradiances Eod, Eou: track-length estimator in a thin layer of thickness D
//    around the depth: E_o = (sum of weight x path length in the layer) / D. Crossings
//    weighted by 1/|cos| would have unbounded variance near grazing; the track length is
//    bounded by the free path. The layer [z - D/2, z + D/2] (or [0, D] at the surface) biases
//    an exponential profile exp(-K z) by (K D)^2 / 24 (centred layer).
#include "secchi/core/math.hpp"
#include "secchi/optics/medium.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace secchi {

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

class IrradianceLayers {
public:
    IrradianceLayers(std::vector<double> depths, double layer_thickness, double floor_depth)
        : depths_(std::move(depths)), thickness_(layer_thickness) {
        for (double z : depths_) {
            double lo = std::max(0.0, z - 0.5 * thickness_);
            if (std::isfinite(floor_depth)) lo = std::min(lo, floor_depth - thickness_);
            layers_.push_back({lo, lo + thickness_});
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
            const auto [layer_lo, layer_hi] = layers_.back();
            envelopes_.push_back({std::min(layer_lo, planes_.back()), std::max(layer_hi, planes_.back()),
                                  std::abs(layer_lo) + std::abs(layer_hi)});
        }
    }
    [[nodiscard]] std::size_t size() const { return depths_.size(); }
    [[nodiscard]] const std::vector<double>& depths() const { return depths_; }
    [[nodiscard]] double thickness() const { return thickness_; }

    /// Tallies one flight into `tally` (one entry per depth). The weight decays along the
    /// flight as w exp(-int_0^t a dt') with the absorption of `absorber` (a Medium, or
    /// NoAbsorption when absorption happens at interactions). Inside a thin layer the decay
    /// uses the layer's local a (exact for homogeneous water; in stratified water the relative
    /// error is below D^2 |da/dz| / 8 per unit weight, negligible for D = 2 cm).
    template <class Absorber>
    void record(const Flight& f, const Absorber& absorber, IrradianceTally* tally) const {
        auto weight_after = [&](double t) {
            return f.w * std::exp(-absorber.optical_path(Coefficient::absorption, f.z0, f.uz, t));
        };
        // Depth range of the track, for skipping the layers it misses before any test that
        // depends on its direction (those branches are unpredictable; this one rarely fails).
        const double z_min = std::min(f.z0, f.z1), z_max = std::max(f.z0, f.z1);
        const double z_scale = std::abs(f.z0) + std::abs(f.z1);
        for (std::size_t i = 0; i < depths_.size(); ++i) {
            if (!reaches(envelopes_[i], z_min, z_max, z_scale)) continue;
            const double d = planes_[i];
            // Half-open crossing rule: a flight starting on the plane going down counts as Ed,
            // one ending on it going up counts as Eu (so the surface plane z = 0 works).
            if (f.uz > 0.0 && f.z0 <= d && d < f.z1) tally[i][Ed] += weight_after((d - f.z0) / f.uz);
            if (f.uz < 0.0 && f.z1 <= d && d < f.z0) tally[i][Eu] += weight_after((d - f.z0) / f.uz);
            const auto [lo, hi] = layers_[i];
            const auto [ta, tb] = track_in_layer(f.z0, f.uz, f.s, lo, hi);
            if (tb > ta) {
                const double a = absorber.coefficient(Coefficient::absorption, 0.5 * (lo + hi));
                tally[i][f.uz >= 0.0 ? Eod : Eou] += weight_after(ta) * weighted_length(tb - ta, a) / thickness_;
            }
        }
    }

    /// record() for one flight per SIMD lane (Real: a std::experimental::simd of doubles or
    /// floats; photons in lanes, transport/lane_tracer.hpp) without absorption along the flights
    /// (NoAbsorption), for the lanes in `active`: the same tests and arithmetic lane by lane,
    /// each layer's tallies summed per lane into `tally` (the caller sums the lanes).
    /// tests/test_lane_tracer.cpp checks it against record(). In floats the planes and layers
    /// are rounded to float, and a plane on the bottom is the next float shallower than the floor's.
    template <class Real, class Mask>
    SECCHI_KERNEL void record_lanes(const Real& z0, const Real& z1, const Real& uz, const Real& s, const Real& w,
                                    const Mask& active, std::array<Real, 4>* tally) const {
        using std::abs, std::max, std::min;
        using T = scalar_t<Real>;
        const Real z_min = min(z0, z1), z_max = max(z0, z1), z_scale = abs(z0) + abs(z1);
        for (std::size_t i = 0; i < depths_.size(); ++i) {
            const Mask reached = active && reaches(envelopes_[i], z_min, z_max, z_scale);
            if (none_of(reached)) continue;
            const T d = std::is_same_v<T, float> ? T(float_planes_[i]) : T(planes_[i]);
            // Plane crossings (the weight is w all along the flight without absorption).
            where(reached && uz > T(0) && z0 <= d && d < z1, tally[i][Ed]) += w;
            where(reached && uz < T(0) && z1 <= d && d < z0, tally[i][Eu]) += w;
            // Track length in the layer (track_in_layer), times w / D.
            const T lo = T(layers_[i].first), hi = T(layers_[i].second);
            const Real t_lo = (lo - z0) / uz, t_hi = (hi - z0) / uz;
            const Mask level = uz == T(0);
            const Real ta = select(level, Real(T(0)), max(min(t_lo, t_hi), Real(T(0))));
            const Real tb = select(level, select(z0 >= lo && z0 <= hi, s, Real(T(0))), min(max(t_lo, t_hi), s));
            const Real track = w * (tb - ta) / T(thickness_);
            where(reached && tb > ta && uz >= T(0), tally[i][Eod]) += track;
            where(reached && tb > ta && !(uz >= T(0)), tally[i][Eou]) += track;
        }
    }

    /// Whether a flight over depths [z_min, z_max] (z_scale = |z0| + |z1|) may tally at any
    /// depth: false only if record() would skip every layer. For doubles, or for SIMD vectors
    /// of them (one flight per lane; the result is then a mask).
    template <class Real>
    [[nodiscard]] auto may_tally(Real z_min, Real z_max, Real z_scale) const {
        auto any = z_max < z_min;  // false (flights have z_min <= z_max), of the right type
        for (const Envelope& e : envelopes_) any = any || reaches(e, z_min, z_max, z_scale);
        return any;
    }

private:
    /// The depths where a layer's tallies can change: its layer and its plane.
    struct Envelope {
        double lo, hi, depth_scale;  ///< depth_scale = |layer lo| + |layer hi|, for the margin
    };

    /// A flight whose depths stay beyond the layer by more than the rounding of z0 + uz s and
    /// of the divisions in track_in_layer (< 1e-15 of the depths involved in doubles, < 1e-6
    /// in floats) has an empty track there, and one that does not reach the plane crosses
    /// nothing: skipping it changes no result.
    template <class Real>
    static auto reaches(const Envelope& e, Real z_min, Real z_max, Real z_scale) {
        using T = scalar_t<Real>;
        constexpr T relative = std::is_same_v<T, float> ? T(1e-5) : T(1e-12);
        const Real margin = relative * (z_scale + T(e.depth_scale));
        return !(z_max < T(e.lo) - margin || z_min > T(e.hi) + margin);
    }

    /// The part [ta, tb] of the flight's path [0, s] inside the layer [lo, hi] (ta >= tb: none).
    static std::pair<double, double> track_in_layer(double z0, double uz, double s, double lo, double hi) {
        if (uz == 0.0) return (z0 >= lo && z0 <= hi) ? std::pair{0.0, s} : std::pair{0.0, 0.0};
        double ta = (lo - z0) / uz, tb = (hi - z0) / uz;
        if (ta > tb) std::swap(ta, tb);
        return {std::max(ta, 0.0), std::min(tb, s)};
    }
    /// Integral of exp(-a t) over [0, l].
    static double weighted_length(double l, double a) {
        if (a * l < 1e-8) return l;
        return -std::expm1(-a * l) / a;
    }

    std::vector<double> depths_, planes_;
    std::vector<float> float_planes_;  ///< the planes for float lanes (record_lanes)
    double thickness_;
    std::vector<std::pair<double, double>> layers_;
    std::vector<Envelope> envelopes_;
};

}  // namespace secchi
