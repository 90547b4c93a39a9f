#pragma once
// A sum of sinusoids as an air-water surface with geometry: the elevation above the mean plane
//     eta(x, y) = sum_i A_i cos(k_i . (x, y) + phi_i)
// (each term a Sinusoid, scene/wave_surface.hpp), depth z positive down, the surface at
// z_s = -eta and the water where z > z_s. Crossed or superposed swell and chop: a periodic
// section of width W holds it when every k_i W / (2 pi) is whole in x and y.
//
// Photons meet the surface where their path really crosses it. Along a ray o + t d the signed
// height over the surface is
//     g(t) = s (o_z + d_z t + sum_i A_i cos(w_i t + psi_i)),  w_i = k_i . d_h, psi_i = k_i . o_h + phi_i,
// s = +1 from the water, -1 from the air (g > 0 on the starting side). Unlike one sinusoid
// (closed-form critical points), a sum is searched with two bounds on an interval [a, b] of
// length h (M = sum_i A_i w_i^2 >= |g''|, S = sum_i A_i):
//   - no root where g stays positive: g >= min(g(a), g(b)) - M h^2 / 8 (the chord less the
//     largest sag a curvature M allows), and g >= s (o_z + d_z t) - S (the sinusoids' sum is
//     at most S in size);
//   - g monotone where |g'(a)| > M h (g' cannot change sign within h): a root there is found
//     by bisection to the last bit.
// Intervals neither pruned nor monotone are halved, left half first, so the first root is the
// first found. Only the band of depths [-S, S] the surface can reach is searched, in pieces of
// length 1 / max |w_i|. A tangential touch narrower than 1e-12 m along the ray (g reaching 0
// without a measurable crossing) is the one thing passed over. A level ray (d_z = 0) with no
// bound on its length is searched over 1000 periods of its slowest term, then taken as not
// meeting the surface (its elevation along the ray need not be periodic).
//
// At the crossing the photon is reflected or refracted at the local facet, normal grad(z + eta)
// normalised (facet_hit: Fresnel and Snell). One term is SinusoidalWave's surface, met at the
// same points (tests/test_wave_surface.cpp).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/surface.hpp"
#include "secchi/scene/wave_surface.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

class WaveSum {
public:
    /// The terms (at least one) and the refractive indices.
    explicit WaveSum(std::vector<Sinusoid> terms, double water_index = 1.34, double air_index = 1.0)
        : terms_(std::move(terms)), n_water_(water_index), n_air_(air_index) {
        require(!terms_.empty(), "wave sum terms", terms_.size(), "must be at least 1");
        check_indices(water_index, air_index);
        for (const Sinusoid& w : terms_) amplitude_sum_ += w.amplitude();
    }

    [[nodiscard]] const std::vector<Sinusoid>& terms() const { return terms_; }
    [[nodiscard]] double water_index() const { return n_water_; }
    [[nodiscard]] double air_index() const { return n_air_; }
    /// Bounds of the surface's depth (m): -S and S, S = sum_i A_i (reached where every term's
    /// crest, or trough, meets).
    [[nodiscard]] double crest_depth() const { return -amplitude_sum_; }
    [[nodiscard]] double trough_depth() const { return amplitude_sum_; }

    /// The elevation eta(x, y) (m, up) and the surface's depth -eta.
    [[nodiscard]] double elevation(double x, double y) const {
        double e = 0.0;
        for (const Sinusoid& w : terms_) e += w.elevation(x, y);
        return e;
    }
    [[nodiscard]] double surface_depth(double x, double y) const { return -elevation(x, y); }

    /// The unit normal at (x, y) pointing into the water: grad(z + eta) / |grad(z + eta)|.
    [[nodiscard]] vec3 normal_into_water(double x, double y) const {
        double sx = 0.0, sy = 0.0;
        for (const Sinusoid& w : terms_) {
            const auto [wx, wy] = w.slope(x, y);
            sx += wx;
            sy += wy;
        }
        return glm::normalize(vec3{sx, sy, 1.0});
    }

    /// Whether every term repeats over a square section of width W.
    [[nodiscard]] bool periodic_in(double width) const {
        return std::all_of(terms_.begin(), terms_.end(), [width](const Sinusoid& w) { return w.periodic_in(width); });
    }

    /// The first t in (0, t_max] where the ray o + t d, starting on `side`, reaches the surface
    /// (g(t) <= 0), or nothing (header comment: the bounds that make the search exhaustive).
    [[nodiscard]] std::optional<double> first_crossing(const vec3& o, const vec3& d, Side side, double t_max) const {
        const Along along(*this, o, d, side);
        double lo = 0.0, hi = t_max;
        if (d.z != 0.0) {  // the part of the ray in the band of depths [-S, S], and 1 nm either side
            const double ta = (-amplitude_sum_ - o.z) / d.z, tb = (amplitude_sum_ - o.z) / d.z;
            lo = std::max(lo, std::min(ta, tb) - band_margin);
            hi = std::min(hi, std::max(ta, tb) + band_margin);
        } else if (std::abs(o.z) > amplitude_sum_) {
            return std::nullopt;
        } else if (!std::isfinite(hi)) {
            if (along.w_min == 0.0) return std::nullopt;  // g constant along the ray
            hi = level_periods * 2.0 * std::numbers::pi / along.w_min;
        }
        if (!(lo <= hi)) return std::nullopt;
        const double piece = along.w_max > 0.0 ? 1.0 / along.w_max : hi - lo;
        for (double a = lo;;) {
            const double b = std::min(hi, a + piece);
            if (auto t = along.first_root(a, b)) return t;
            if (!(b < hi)) return std::nullopt;
            a = b;
        }
    }

    /// The meeting of a photon at surface point p moving along d, arriving from `side`.
    [[nodiscard]] SurfaceHit hit_at(const vec3& p, const vec3& d, Side from) const {
        return facet_hit(normal_into_water(p.x, p.y), d, from, n_water_, n_air_);
    }

private:
    static constexpr double level_periods = 1000.0;
    /// The band of depths is searched this far (m) beyond its ends: an amplitude-0 sum's band
    /// is the plane z = 0 itself.
    static constexpr double band_margin = 1e-9;
    /// Intervals shorter than this (m) are decided by their end's sign (a tangential touch).
    static constexpr double shortest = 1e-12;

    /// g and g' along one ray, M = sum A_i w_i^2, and the largest and the smallest nonzero
    /// |w_i| of the terms of nonzero amplitude.
    struct Along {
        const WaveSum& wave;
        vec3 o, d;
        double s;
        double m = 0.0, w_max = 0.0, w_min = INFINITY;

        Along(const WaveSum& wv, const vec3& origin, const vec3& dir, Side side)
            : wave(wv), o(origin), d(dir), s(side == Side::water ? 1.0 : -1.0) {
            for (const Sinusoid& w : wave.terms_) {
                const double wi = std::abs(w.kx() * d.x + w.ky() * d.y);
                if (w.amplitude() == 0.0 || wi == 0.0) continue;
                m += w.amplitude() * wi * wi;
                w_max = std::max(w_max, wi);
                w_min = std::min(w_min, wi);
            }
            if (!std::isfinite(w_min)) w_min = 0.0;
        }
        [[nodiscard]] double g(double t) const {
            const vec3 p = o + t * d;
            return s * (p.z + wave.elevation(p.x, p.y));
        }
        /// g'(t) = s (d_z + d_h . grad eta).
        [[nodiscard]] double slope(double t) const {
            const vec3 p = o + t * d;
            double e = 0.0;
            for (const Sinusoid& w : wave.terms_) {
                const auto [sx, sy] = w.slope(p.x, p.y);
                e += sx * d.x + sy * d.y;
            }
            return s * (d.z + e);
        }
        /// The lower bound of g on [a, b] that does not need g inside it.
        [[nodiscard]] double lower_bound(double a, double ga, double b, double gb) const {
            const double h = b - a;
            const double sag = std::min(ga, gb) - m * h * h / 8.0;
            const double line = std::min(s * (o.z + d.z * a), s * (o.z + d.z * b)) - wave.amplitude_sum_;
            return std::max(sag, line);
        }

        /// The first root of g in (a, b] (g(a) > 0 expected), or nothing.
        [[nodiscard]] std::optional<double> first_root(double a, double b) const {
            struct Interval {
                double a, ga, b, gb;
            };
            std::array<Interval, 128> stack;  // halving from at most 1 / w_max to 1e-12 m: depth < 64
            std::size_t top = 0;
            stack[top++] = {a, g(a), b, g(b)};
            while (top > 0) {
                const Interval iv = stack[--top];
                const double h = iv.b - iv.a;
                const bool monotone = std::abs(slope(iv.a)) > m * h;
                if (iv.gb <= 0.0 && monotone) return detail::bisect_first([this](double t) { return g(t); }, iv.a, iv.b);
                if (iv.gb > 0.0 && (monotone || lower_bound(iv.a, iv.ga, iv.b, iv.gb) > 0.0)) continue;
                if (h <= shortest || top + 2 > stack.size()) {
                    if (iv.gb <= 0.0) return iv.b;
                    continue;
                }
                const double mid = 0.5 * (iv.a + iv.b), gm = g(mid);
                stack[top++] = {mid, gm, iv.b, iv.gb};  // the right half waits
                stack[top++] = {iv.a, iv.ga, mid, gm};  // the left half first
            }
            return std::nullopt;
        }
    };

    std::vector<Sinusoid> terms_;
    double n_water_, n_air_;
    double amplitude_sum_ = 0.0;
};

static_assert(GeometricSurface<WaveSum>);

}  // namespace secchi
