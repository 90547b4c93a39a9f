#pragma once
// A sinusoidal air-water surface with geometry (the manual's sinusoid primitive, ch. 7,
// Figure 7.10e; its caustic validation case, 7.4: amplitude 0.4 m, wavelength 5 m). The
// surface's elevation above the mean plane is
//     eta(x, y) = A cos(k . (x, y) + phi),   k = (2 pi / Lambda) (cos alpha, sin alpha),
// so with depth z positive down the surface lies at z_s(x, y) = -eta(x, y) and the water
// is where z > z_s. The crests reach depth -A (above the mean plane), the troughs +A.
//
// Photons meet the surface where their path really crosses it. Along a ray o + t d the
// signed height over the surface is g(t) = o_z + d_z t + A cos(w t + psi), w = k . d_h,
// psi = k . o_h + phi (g > 0 in the water). Its critical points solve
// sin(w t + psi) = d_z / (A w) in closed form, so between consecutive ones g is monotone:
// first_crossing walks those intervals in order and bisects the first with a sign change.
// No crossing is skipped, however grazing the ray. A sum of sinusoids has no such closed
// form; WaveSum (scene/wave_sum.hpp) finds its crossings by bounds on the derivatives.
//
// At the crossing the photon is reflected or refracted at the local facet, whose normal is
// the gradient of z + eta: Fresnel reflectance and Snell's law in vector form (fresnel.hpp;
// Mobley 1994, eq. 4.11-4.12, 4.19-4.21). Amplitude 0 is the flat surface.
//
// GeometricSurface (scene/surface.hpp) is the policy PhotonTracer reads; the second pass
// (estimate/radiance.hpp) does not model this surface: rays reaching it are refused there.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/fresnel.hpp"
#include "secchi/scene/surface.hpp"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

namespace secchi::SECCHI_ISA {

/// One sinusoid of the surface's elevation, eta(x, y) = A cos(k . (x, y) + phi),
/// k = (2 pi / Lambda) (cos alpha, sin alpha): amplitude A (m, >= 0), wavelength Lambda (m,
/// > 0), direction alpha of travel of the crests (radians from +x), phase phi (radians).
class Sinusoid {
public:
    Sinusoid(double amplitude, double wavelength, double direction = 0.0, double phase = 0.0)
        : a_(amplitude), wavelength_(wavelength), phase_(phase) {
        require(std::isfinite(amplitude) && amplitude >= 0.0, "wave amplitude (m)", amplitude, "must be >= 0");
        require(std::isfinite(wavelength) && wavelength > 0.0, "wavelength of the wave (m)", wavelength, "must be > 0");
        require(std::isfinite(direction), "wave direction (rad)", direction, "must be finite");
        require(std::isfinite(phase), "wave phase (rad)", phase, "must be finite");
        const double k = 2.0 * std::numbers::pi / wavelength;
        kx_ = k * std::cos(direction);
        ky_ = k * std::sin(direction);
    }

    [[nodiscard]] double amplitude() const { return a_; }
    [[nodiscard]] double wavelength() const { return wavelength_; }
    [[nodiscard]] double kx() const { return kx_; }
    [[nodiscard]] double ky() const { return ky_; }
    /// The argument k . (x, y) + phi.
    [[nodiscard]] double argument(double x, double y) const { return kx_ * x + ky_ * y + phase_; }
    [[nodiscard]] double elevation(double x, double y) const { return a_ * std::cos(argument(x, y)); }
    /// The elevation's slope: (d eta / dx, d eta / dy) = -A sin(k . x + phi) k.
    [[nodiscard]] std::pair<double, double> slope(double x, double y) const {
        const double s = -a_ * std::sin(argument(x, y));
        return {s * kx_, s * ky_};
    }
    /// Whether it repeats over a square section of width W: k W / (2 pi) whole numbers in x
    /// and y (to 1e-9), so that the section's periodic copies join (amplitude 0: any W).
    [[nodiscard]] bool periodic_in(double width) const {
        if (a_ == 0.0) return true;
        const auto whole = [](double v) { return std::abs(v - std::round(v)) <= 1e-9 * std::max(1.0, std::abs(v)); };
        const double cycles = width / (2.0 * std::numbers::pi);
        return whole(kx_ * cycles) && whole(ky_ * cycles);
    }

private:
    double a_, wavelength_, phase_;
    double kx_ = 0.0, ky_ = 0.0;
};

/// The refractive indices of a surface with geometry, checked by name.
inline void check_indices(double water_index, double air_index) {
    require(std::isfinite(water_index) && water_index >= 1.0, "water index", water_index, "must be >= 1");
    require(std::isfinite(air_index) && air_index >= 1.0, "air index", air_index, "must be >= 1");
}

/// The meeting of a photon moving along d, arriving from `from`, with a facet of unit normal
/// n (pointing into the water): Fresnel reflectance and the reflected and refracted directions
/// (fresnel.hpp; Mobley 1994, eq. 4.11-4.12, 4.19-4.21).
inline SurfaceHit facet_hit(const vec3& n, const vec3& d, Side from, double n_water, double n_air) {
    const vec3 m = from == Side::air ? -n : n;  // facet normal facing the incident side
    const double n1 = from == Side::air ? n_air : n_water, n2 = from == Side::air ? n_water : n_air;
    const double cos_i = -glm::dot(m, d);
    const vec3 reflected = glm::normalize(reflect_about(d, m, cos_i));
    if (cos_i <= 0.0) return {1.0, reflected, reflected};  // grazing (rounding at a tangent point)
    const double r = n1 == n2 ? 0.0 : fresnel_reflectance(cos_i, n1, n2);
    return {r, reflected, r >= 1.0 ? reflected : refract_through(d, m, cos_i, n1, n2)};
}

namespace detail {
/// The first root of g in (a, b] where g is monotone (g(a) > 0 expected): bisection to the
/// last bit; the returned t has g(t) <= 0 (on the other side, or on the surface).
template <class G>
std::optional<double> bisect_first(const G& g, double a, double b) {
    if (g(b) > 0.0) return std::nullopt;
    double lo = a, hi = b;
    for (int i = 0; i < 200 && lo < hi; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        (g(mid) > 0.0 ? lo : hi) = mid;
    }
    return hi;
}
}  // namespace detail

class SinusoidalWave {
public:
    /// amplitude A (m, >= 0), wavelength Lambda (m, > 0), direction alpha of travel of the
    /// crests (radians from +x), phase phi (radians), refractive indices.
    SinusoidalWave(double amplitude, double wavelength, double direction = 0.0, double phase = 0.0,
                   double water_index = 1.34, double air_index = 1.0)
        : wave_(amplitude, wavelength, direction, phase), n_water_(water_index), n_air_(air_index) {
        check_indices(water_index, air_index);
    }

    [[nodiscard]] double amplitude() const { return wave_.amplitude(); }
    [[nodiscard]] double wavelength() const { return wave_.wavelength(); }
    [[nodiscard]] double water_index() const { return n_water_; }
    [[nodiscard]] double air_index() const { return n_air_; }
    /// Shallowest and deepest depth of the surface (m): -A and A.
    [[nodiscard]] double crest_depth() const { return -amplitude(); }
    [[nodiscard]] double trough_depth() const { return amplitude(); }

    /// The elevation eta(x, y) (m, up) and the surface's depth -eta.
    [[nodiscard]] double elevation(double x, double y) const { return wave_.elevation(x, y); }
    [[nodiscard]] double surface_depth(double x, double y) const { return -elevation(x, y); }

    /// The unit normal at (x, y) pointing into the water: grad(z + eta) / |grad(z + eta)|.
    [[nodiscard]] vec3 normal_into_water(double x, double y) const {
        const auto [sx, sy] = wave_.slope(x, y);
        return glm::normalize(vec3{sx, sy, 1.0});
    }

    /// Whether the surface repeats over a square section of width W (Sinusoid::periodic_in).
    [[nodiscard]] bool periodic_in(double width) const { return wave_.periodic_in(width); }

    /// The first t in (0, t_max] where the ray o + t d, starting on `side` (g(0) > 0 in the
    /// water, < 0 in the air), reaches the surface (g(t) = 0), or nothing. t_max may be
    /// infinite only for a ray that must meet the surface or that travels along the crests.
    [[nodiscard]] std::optional<double> first_crossing(const vec3& o, const vec3& d, Side side, double t_max) const {
        const double sign = side == Side::water ? 1.0 : -1.0;  // s g > 0 on the starting side
        const double a = amplitude(), w = wave_.kx() * d.x + wave_.ky() * d.y, psi = wave_.argument(o.x, o.y);
        const auto g = [&](double t) { return sign * (o.z + d.z * t + a * std::cos(w * t + psi)); };
        const double aw = a * std::abs(w);
        if (!std::isfinite(t_max)) {
            // Horizontal or along the crests: the ray sees every phase within one period 2 pi / |w|.
            if (w == 0.0) return std::nullopt;
            t_max = 2.0 * std::numbers::pi / std::abs(w) + (d.z != 0.0 ? 2.0 * a / std::abs(d.z) : 0.0);
        }
        if (aw <= std::abs(d.z)) return detail::bisect_first(g, 0.0, t_max);  // g monotone on the whole ray
        // Critical points: w t + psi = theta_1 = asin(r) or theta_2 = pi - asin(r) (mod 2 pi).
        const double r = d.z / (a * w), th1 = std::asin(r), th2 = std::numbers::pi - th1;
        double t0 = 0.0;
        while (t0 < t_max) {
            const double t1 = std::min(t_max, next_critical(w, psi, t0, th1, th2));
            if (auto t = detail::bisect_first(g, t0, t1)) return t;
            t0 = t1;
        }
        return std::nullopt;
    }

    /// The meeting of a photon at surface point p moving along d, arriving from `side`:
    /// Fresnel reflectance at the local facet and the two directions it may go on in.
    [[nodiscard]] SurfaceHit hit_at(const vec3& p, const vec3& d, Side from) const {
        return facet_hit(normal_into_water(p.x, p.y), d, from, n_water_, n_air_);
    }

private:
    /// The first critical point of g after t0: the next t > t0 with w t + psi = theta (mod 2 pi)
    /// for theta in {th1, th2}.
    static double next_critical(double w, double psi, double t0, double th1, double th2) {
        const double two_pi = 2.0 * std::numbers::pi;
        const double phase0 = w * t0 + psi;
        // Smallest phase increment reaching th, past the one at t0 itself (t0 is the last
        // critical point, reached up to rounding: increments below 1e-9 rad are that one).
        const auto next = [&](double th) {
            double dphi = std::fmod(w > 0 ? th - phase0 : phase0 - th, two_pi);
            if (dphi <= 1e-9) dphi += two_pi;
            return t0 + dphi / std::abs(w);
        };
        return std::max(std::nextafter(t0, INFINITY), std::min(next(th1), next(th2)));
    }

    Sinusoid wave_;
    double n_water_, n_air_;
};

static_assert(GeometricSurface<SinusoidalWave>);

}  // namespace secchi
