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
#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

namespace secchi {

enum IrradianceKind : int { Ed = 0, Eu = 1, Eod = 2, Eou = 3 };
using IrradianceTally = std::array<double, 4>;  ///< indexed by IrradianceKind

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
        }
    }
    [[nodiscard]] std::size_t size() const { return depths_.size(); }
    [[nodiscard]] const std::vector<double>& depths() const { return depths_; }
    [[nodiscard]] double thickness() const { return thickness_; }

    /// Tallies one straight flight from depth z0 to z1 (direction cosine uz, path length s)
    /// into `tally` (one entry per depth). The weight is w at the start and decays as
    /// w exp(-a t) along the flight (a = 0 unless absorption is applied continuously).
    void record(double z0, double z1, double uz, double s, double w, double a, IrradianceTally* tally) const {
        for (std::size_t i = 0; i < depths_.size(); ++i) {
            const double d = planes_[i];
            // Half-open crossing rule: a flight starting on the plane going down counts as Ed,
            // one ending on it going up counts as Eu (so the surface plane z = 0 works).
            if (uz > 0.0 && z0 <= d && d < z1) tally[i][Ed] += w * std::exp(-a * (d - z0) / uz);
            if (uz < 0.0 && z1 <= d && d < z0) tally[i][Eu] += w * std::exp(-a * (d - z0) / uz);
            const auto [ta, tb] = track_in_layer(z0, uz, s, layers_[i].first, layers_[i].second);
            if (tb > ta) tally[i][uz >= 0.0 ? Eod : Eou] += w * weighted_length(ta, tb, a) / thickness_;
        }
    }

private:
    /// The part [ta, tb] of the flight's path [0, s] inside the layer [lo, hi] (ta >= tb: none).
    static std::pair<double, double> track_in_layer(double z0, double uz, double s, double lo, double hi) {
        if (uz == 0.0) return (z0 >= lo && z0 <= hi) ? std::pair{0.0, s} : std::pair{0.0, 0.0};
        double ta = (lo - z0) / uz, tb = (hi - z0) / uz;
        if (ta > tb) std::swap(ta, tb);
        return {std::max(ta, 0.0), std::min(tb, s)};
    }
    /// Integral of exp(-a t) over [ta, tb].
    static double weighted_length(double ta, double tb, double a) {
        if (a * (tb - ta) < 1e-8) return (tb - ta) * std::exp(-a * ta);
        return (std::exp(-a * ta) - std::exp(-a * tb)) / a;
    }

    std::vector<double> depths_, planes_;
    double thickness_;
    std::vector<std::pair<double, double>> layers_;
};

}  // namespace secchi
