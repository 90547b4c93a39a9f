#pragma once
// Vectors through GLM, constants, and the frame rotation every scattering event needs.
#include <cmath>
#include <glm/glm.hpp>
#include <numbers>

namespace secchi {

using vec3 = glm::dvec3;   ///< positions and directions during transport (z positive down)
using vec3f = glm::vec3;   ///< compact storage

inline constexpr double pi = std::numbers::pi;
inline constexpr double two_pi = 2.0 * std::numbers::pi;
inline constexpr double four_pi = 4.0 * std::numbers::pi;
inline constexpr double deg = std::numbers::pi / 180.0;  ///< one degree in radians

/// sin x and cos x together, for the azimuth of every scattering event (|x| < 1e6; the
/// library's callers pass x in [0, 2 pi]). Cody-Waite reduction x = k pi/2 + r with pi/2 split in
/// three parts (the first two with 33 significant bits, so k times them is exact for
/// |k| < 2^20), then Taylor series on |r| <= pi/4: sin to r^17, cos to r^18 (truncation below
/// (pi/4)^19 / 19! = 8e-20). Within 2 ulp of the correctly rounded values (test_core.cpp), and
/// about three times cheaper than a libm sincos, whose range reduction serves any x.
struct SinCos {
    double sin, cos;
};
inline SinCos sin_cos(double x) {
    constexpr double two_over_pi = 0.6366197723675814;
    constexpr double pio2_1 = 1.5707963267341256, pio2_2 = 6.077100506303966e-11, pio2_3 = 2.0222662487959506e-21;
    constexpr double round_shift = 0x1.8p52;  // adding and subtracting it rounds to an integer
    const double k = (x * two_over_pi + round_shift) - round_shift;
    const double r = ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
    const double r2 = r * r;
    // 1/n! for n = 2 .. 18
    constexpr double f3 = 0.16666666666666666, f5 = 0.008333333333333333, f7 = 0.0001984126984126984,
                     f9 = 2.7557319223985893e-06, f11 = 2.505210838544172e-08, f13 = 1.6059043836821613e-10,
                     f15 = 7.647163731819816e-13, f17 = 2.8114572543455206e-15;
    constexpr double f4 = 0.041666666666666664, f6 = 0.001388888888888889, f8 = 2.48015873015873e-05,
                     f10 = 2.755731922398589e-07, f12 = 2.08767569878681e-09, f14 = 1.1470745597729725e-11,
                     f16 = 4.779477332387385e-14, f18 = 1.5619206968586225e-16;
    const double ps = -f3 + r2 * (f5 + r2 * (-f7 + r2 * (f9 + r2 * (-f11 + r2 * (f13 + r2 * (-f15 + r2 * f17))))));
    const double pc = f4 + r2 * (-f6 + r2 * (f8 + r2 * (-f10 + r2 * (f12 + r2 * (-f14 + r2 * (f16 - r2 * f18))))));
    const double s = r + r * r2 * ps;
    const double c = (1.0 - 0.5 * r2) + r2 * r2 * pc;
    switch (static_cast<long long>(k) & 3) {  // x = k pi/2 + r: rotate by quadrants
    case 0: return {s, c};
    case 1: return {c, -s};
    case 2: return {-s, -c};
    default: return {-c, s};
    }
}

/// Direction after scattering through angle psi (cos_psi) at azimuth phi about `dir`
/// (unit vector, to rounding). Builds an orthonormal frame around dir (Duff et al. 2017
/// branchless basis). The result has length 1 + e with e of the order of the rounding; one
/// Newton step for 1/sqrt(n) at n = |out|^2 ~ 1, out (3 - n) / 2, leaves an error of order e^2,
/// so the direction stays unit over any number of events without the square root and division
/// of a normalisation on the photon's critical path.
inline vec3 rotate_direction(const vec3& dir, double cos_psi, double phi) {
    const double sin_psi = std::sqrt(std::max(0.0, 1.0 - cos_psi * cos_psi));
    const double sign = std::copysign(1.0, dir.z);
    const double a = -1.0 / (sign + dir.z);
    const double b = dir.x * dir.y * a;
    const vec3 t1(1.0 + sign * dir.x * dir.x * a, sign * b, -sign * dir.x);
    const vec3 t2(b, sign + dir.y * dir.y * a, -dir.y);
    const SinCos az = sin_cos(phi);
    const vec3 out = sin_psi * az.cos * t1 + sin_psi * az.sin * t2 + cos_psi * dir;
    return out * (1.5 - 0.5 * glm::dot(out, out));
}

}  // namespace secchi
