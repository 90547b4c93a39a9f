#pragma once
// Vectors through GLM, constants, and the per-event kernels: sin_cos for the azimuth, exp_table
// for transmittances, and the frame rotation every scattering event needs.
#include "secchi/core/config.hpp"
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <glm/glm.hpp>
#include <numbers>
#include <type_traits>

// The per-event kernels are small and called once per event (or per step of photons in lanes):
// inlined, their vectors stay in registers rather than passing through memory at each call.
#if defined(__GNUC__)
#define SECCHI_KERNEL [[gnu::always_inline]] inline
#else
#define SECCHI_KERNEL inline
#endif

namespace secchi::SECCHI_ISA {

using vec3 = glm::dvec3;   ///< positions and directions during transport (z positive down)
using vec3f = glm::vec3;   ///< compact storage

inline constexpr double pi = std::numbers::pi;
inline constexpr double two_pi = 2.0 * std::numbers::pi;
inline constexpr double four_pi = 4.0 * std::numbers::pi;
inline constexpr double deg = std::numbers::pi / 180.0;  ///< one degree in radians

/// a b + c for doubles, rounded the same way wherever it is inlined: fused (one rounding) where
/// the target has fused multiply-add, else two roundings. (With FMA the compiler contracts
/// a b + c on its own, but not necessarily alike in every context a formula is inlined into;
/// two code paths that must agree bit for bit, e.g. a tabulated and a per-photon form of one
/// formula, spell their multiply-adds with this.)
SECCHI_KERNEL double mul_add(double a, double b, double c) {
#if defined(__FMA__)
    return std::fma(a, b, c);
#else
    return a * b + c;
#endif
}

/// x 2^k, exactly std::ldexp(x, k) (its one rounding of x 2^k): x times 2^k made from its bits
/// where 2^k is a normal double (-1022 <= k <= 1023), without the library call (depth
/// importance's weights and levels, per event); through ldexp beyond.
inline double times_power_of_two(double x, int k) {
    if (k < -1022 || k > 1023) return std::ldexp(x, k);
    return x * std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
}

/// a where m holds, else b: `m ? a : b`, for code written once for doubles and for SIMD
/// vectors of them (std::experimental::simd, core/lanes.hpp), where it is where(m, b) = a.
template <class Mask, class T>
SECCHI_KERNEL T select(const Mask& m, const T& a, T b) {
    if constexpr (std::is_same_v<Mask, bool>) {
        return m ? a : b;
    } else {
        where(m, b) = a;
        return b;
    }
}

/// A table row of eight doubles on one cache line (64 bytes, aligned): what one photon's
/// lookup needs at once, read by photons in lanes with one load per lane
/// (lanes::lookup_rows).
struct alignas(64) Row8 {
    std::array<double, 8> v;
};

/// The scalar type of a double or float, or of a SIMD vector of them (its value_type): code
/// written once for both writes its constants as scalar_t<Real>(c), since a vector of floats
/// takes no double (std::experimental::simd broadcasts only value-preserving conversions).
/// Its comparisons give a mask_of<Real>: bool, or the vector's mask type.
template <class Real>
struct scalar_of {
    using type = Real;
    using mask = bool;
};
template <class Real>
    requires requires { typename Real::value_type; typename Real::mask_type; }
struct scalar_of<Real> {
    using type = typename Real::value_type;
    using mask = typename Real::mask_type;
};
template <class Real>
using scalar_t = typename scalar_of<Real>::type;
template <class Real>
using mask_of = typename scalar_of<Real>::mask;

/// Whether m holds for any lane (m itself for a bool).
template <class Mask>
SECCHI_KERNEL bool any_lane(const Mask& m) {
    if constexpr (std::is_same_v<Mask, bool>) return m;
    else return any_of(m);
}

/// std::clamp(mu, -1, 1) for a double or for a SIMD vector (a cosine sampled in rounding
/// arithmetic, kept a cosine).
template <class Real>
SECCHI_KERNEL Real clamp_cosine(const Real& mu) {
    using std::max, std::min;
    using T = scalar_t<Real>;
    return min(max(mu, Real(T(-1))), Real(T(1)));
}

/// copysign(1, x): +1 or -1 with the sign bit of x (-1 for -0), for a double or a SIMD vector.
/// Under clang, vectors take signbit and a select, the same values: clang (14) cannot compile
/// libstdc++ 12's simd copysign (a bit mask it declares constexpr is not a constant expression
/// there).
template <class Real>
SECCHI_KERNEL Real unit_with_sign_of(const Real& x) {
    using T = scalar_t<Real>;
    using std::copysign;
#if defined(__clang__)
    if constexpr (!std::is_same_v<Real, T>) return select(signbit(x), Real(T(-1)), Real(T(1)));
    else return copysign(T(1), x);
#else
    return copysign(Real(T(1)), x);
#endif
}

/// x wrapped into [0, W) with period W (a section's periodic copies, scene/slab.hpp):
/// x - W floor(x / W), and 0 where rounding gives W itself (x a hair below a multiple of W).
/// For a double, or a SIMD vector of doubles or floats (photons in lanes).
template <class Real>
SECCHI_KERNEL Real periodic_wrap(Real x, scalar_t<Real> width) {
    using std::floor;
    const Real w = x - width * floor(x / width);
    return select(w < width, w, Real(scalar_t<Real>(0)));
}

namespace detail {
/// x rounded to the nearest integer (ties to even), for |x| < 2^51 (doubles; 2^22 for floats):
/// adding 1.5 2^52 (1.5 2^23) leaves no fraction bits, and subtracting it again is exact.
/// (std::nearbyint honours the rounding mode through a library call; this is two additions.)
template <class Real>
Real round_to_integer(Real x) {
    using T = scalar_t<Real>;
    constexpr T shift = std::is_same_v<T, float> ? T(0x1.8p23) : T(0x1.8p52);
    return (x + shift) - shift;
}
}  // namespace detail

/// sin x and cos x together, for the azimuth of every scattering event (|x| < 1e6; the
/// library's callers pass x in [0, 2 pi]). Cody-Waite reduction x = k pi/2 + r with pi/2 split in
/// three parts (the first two with 33 significant bits, so k times them is exact for
/// |k| < 2^20), then Taylor series on |r| <= pi/4: sin to r^17, cos to r^18 (truncation below
/// (pi/4)^19 / 19! = 8e-20). Within 2 ulp of the correctly rounded values (test_core.cpp), and
/// about three times cheaper than a libm sincos, whose range reduction serves any x.
/// For a double, or a SIMD vector of them (photons in lanes, core/lanes.hpp): the quadrant's
/// rotation is chosen by select, the same operations for both.
template <class Real>
struct SinCosOf {
    Real sin, cos;
};
using SinCos = SinCosOf<double>;

template <class Real>
SECCHI_KERNEL SinCosOf<Real> sin_cos(Real x) {
    using T = scalar_t<Real>;
    Real k, s, c;
    if constexpr (std::is_same_v<T, float>) {
        // Floats (photons in float lanes, x in [0, 2 pi]): pi/2 in three parts, the first two
        // with 8 and 11 significant bits (k times them exact for |k| < 2^13; Cody and Waite's
        // split, as in Cephes' sinf), then Taylor series to r^9 and r^10 on |r| <= pi/4
        // (truncation below (pi/4)^11 / 11! = 2e-9, under float's half ulp).
        constexpr float pio2_1 = 1.5703125f, pio2_2 = 4.837512969970703125e-4f, pio2_3 = 7.549789948768648e-8f;
        k = detail::round_to_integer(x * T(0.6366197723675814));
        const Real r = ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
        const Real r2 = r * r;
        const Real ps = T(-1.0 / 6) + r2 * (T(1.0 / 120) + r2 * (T(-1.0 / 5040) + r2 * T(1.0 / 362880)));
        const Real pc = T(1.0 / 24) + r2 * (T(-1.0 / 720) + r2 * (T(1.0 / 40320) + r2 * T(-1.0 / 3628800)));
        s = r + r * r2 * ps;
        c = (T(1) - T(0.5) * r2) + r2 * r2 * pc;
    } else {
        constexpr double two_over_pi = 0.6366197723675814;
        constexpr double pio2_1 = 1.5707963267341256, pio2_2 = 6.077100506303966e-11, pio2_3 = 2.0222662487959506e-21;
        k = detail::round_to_integer(x * two_over_pi);
        const Real r = ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
        const Real r2 = r * r;
        // 1/n! for n = 2 .. 18
        constexpr double f3 = 0.16666666666666666, f5 = 0.008333333333333333, f7 = 0.0001984126984126984,
                         f9 = 2.7557319223985893e-06, f11 = 2.505210838544172e-08, f13 = 1.6059043836821613e-10,
                         f15 = 7.647163731819816e-13, f17 = 2.8114572543455206e-15;
        constexpr double f4 = 0.041666666666666664, f6 = 0.001388888888888889, f8 = 2.48015873015873e-05,
                         f10 = 2.755731922398589e-07, f12 = 2.08767569878681e-09, f14 = 1.1470745597729725e-11,
                         f16 = 4.779477332387385e-14, f18 = 1.5619206968586225e-16;
        const Real ps = -f3 + r2 * (f5 + r2 * (-f7 + r2 * (f9 + r2 * (-f11 + r2 * (f13 + r2 * (-f15 + r2 * f17))))));
        const Real pc = f4 + r2 * (-f6 + r2 * (f8 + r2 * (-f10 + r2 * (f12 + r2 * (-f14 + r2 * (f16 - r2 * f18))))));
        s = r + r * r2 * ps;
        c = (1.0 - 0.5 * r2) + r2 * r2 * pc;
    }
    // x = k pi/2 + r: quadrant q = k mod 4 turns (s, c) into (s, c), (c, -s), (-s, -c), (-c, s);
    // a switch for one double (the selects made PhotonTracer 1.14 times slower), selects for lanes.
    if constexpr (std::is_floating_point_v<Real>) {
        switch (static_cast<long long>(k) & 3) {
        case 0: return {s, c};
        case 1: return {c, -s};
        case 2: return {-s, -c};
        default: return {-c, s};
        }
    } else {
        using std::floor;
        const Real q = k - T(4) * floor(k * T(0.25));
        const auto odd = (q == T(1)) || (q == T(3));
        const Real sin_abs = select(odd, c, s), cos_abs = select(odd, s, c);
        return {select(q >= T(2), -sin_abs, sin_abs), select((q == T(1)) || (q == T(2)), -cos_abs, cos_abs)};
    }
}

namespace detail {
/// 2^(j/64), j = 0..63, correctly rounded (computed to 60 digits).
inline constexpr double exp2_64ths[64] = {
    0x1.0000000000000p+0, 0x1.02c9a3e778061p+0, 0x1.059b0d3158574p+0, 0x1.0874518759bc8p+0,
    0x1.0b5586cf9890fp+0, 0x1.0e3ec32d3d1a2p+0, 0x1.11301d0125b51p+0, 0x1.1429aaea92de0p+0,
    0x1.172b83c7d517bp+0, 0x1.1a35beb6fcb75p+0, 0x1.1d4873168b9aap+0, 0x1.2063b88628cd6p+0,
    0x1.2387a6e756238p+0, 0x1.26b4565e27cddp+0, 0x1.29e9df51fdee1p+0, 0x1.2d285a6e4030bp+0,
    0x1.306fe0a31b715p+0, 0x1.33c08b26416ffp+0, 0x1.371a7373aa9cbp+0, 0x1.3a7db34e59ff7p+0,
    0x1.3dea64c123422p+0, 0x1.4160a21f72e2ap+0, 0x1.44e086061892dp+0, 0x1.486a2b5c13cd0p+0,
    0x1.4bfdad5362a27p+0, 0x1.4f9b2769d2ca7p+0, 0x1.5342b569d4f82p+0, 0x1.56f4736b527dap+0,
    0x1.5ab07dd485429p+0, 0x1.5e76f15ad2148p+0, 0x1.6247eb03a5585p+0, 0x1.6623882552225p+0,
    0x1.6a09e667f3bcdp+0, 0x1.6dfb23c651a2fp+0, 0x1.71f75e8ec5f74p+0, 0x1.75feb564267c9p+0,
    0x1.7a11473eb0187p+0, 0x1.7e2f336cf4e62p+0, 0x1.82589994cce13p+0, 0x1.868d99b4492edp+0,
    0x1.8ace5422aa0dbp+0, 0x1.8f1ae99157736p+0, 0x1.93737b0cdc5e5p+0, 0x1.97d829fde4e50p+0,
    0x1.9c49182a3f090p+0, 0x1.a0c667b5de565p+0, 0x1.a5503b23e255dp+0, 0x1.a9e6b5579fdbfp+0,
    0x1.ae89f995ad3adp+0, 0x1.b33a2b84f15fbp+0, 0x1.b7f76f2fb5e47p+0, 0x1.bcc1e904bc1d2p+0,
    0x1.c199bdd85529cp+0, 0x1.c67f12e57d14bp+0, 0x1.cb720dcef9069p+0, 0x1.d072d4a07897cp+0,
    0x1.d5818dcfba487p+0, 0x1.da9e603db3285p+0, 0x1.dfc97337b9b5fp+0, 0x1.e502ee78b3ff6p+0,
    0x1.ea4afa2a490dap+0, 0x1.efa1bee615a27p+0, 0x1.f50765b6e4540p+0, 0x1.fa7c1819e90d8p+0};
}  // namespace detail

namespace detail {
/// Tang's constants: 64 / ln 2, and ln2/64 in two parts (the first with 32 significant bits).
inline constexpr double exp_inv_ln2_64 = 92.33248261689366, exp_ln2_64_hi = 0.01083042469326756,
                        exp_ln2_64_lo = 2.9815858269852933e-12;

/// exp_table's arithmetic once the table entry is known, written once for doubles and SIMD
/// vectors of them (lanes::exp, core/lanes.hpp): kd = round(x 64 / ln 2) = 64 m + j,
/// t = 2^(j/64), two_m = 2^m; r = x - kd ln2/64 and e^x = 2^m 2^(j/64) (1 + (e^r - 1)).
template <class Real>
SECCHI_KERNEL Real exp_from_table(const Real& x, const Real& kd, const Real& t, const Real& two_m) {
    const Real r = (x - kd * exp_ln2_64_hi) - kd * exp_ln2_64_lo;
    const Real em1 = r * (1.0 + r * (0.5 + r * (1.0 / 6.0 + r * (1.0 / 24.0 + r * (1.0 / 120.0)))));  // e^r - 1
    return two_m * (t + t * em1);
}
}  // namespace detail

/// e^x, for the transmittance exp(-c t) of every collected photon. Tang's table method
/// (ACM TOMS 15, 1989): x = (64 m + j) ln2/64 + r with |r| <= ln2/128, ln2/64 split in two
/// (the first part with 32 significant bits, so k times it is exact for |k| < 2^21); then
/// e^x = 2^m 2^(j/64) e^r with e^r by its Taylor series to r^5 (truncation < 4e-17).
/// Within 2 ulp of the correctly rounded value (test_core.cpp). 0 below x = -708 (where e^x
/// nears the subnormal range), +inf above 709; NaN stays NaN.
inline double exp_table(double x) {
    if (!(x > -708.0 && x < 709.0)) return x != x ? x : (x > 0.0 ? INFINITY : 0.0);
    const double kd = detail::round_to_integer(x * detail::exp_inv_ln2_64);
    const auto k = static_cast<std::int64_t>(kd);
    const std::int64_t m = k >> 6;  // floor(k / 64)
    const double two_m = std::bit_cast<double>(static_cast<std::uint64_t>(m + 1023) << 52);
    return detail::exp_from_table(x, kd, detail::exp2_64ths[k & 63], two_m);
}

/// Direction after scattering through angle psi (cos_psi) at azimuth phi about `dir`
/// (unit vector, to rounding). Builds an orthonormal frame around dir (Duff et al. 2017
/// branchless basis). The result has length 1 + e with e of the order of the rounding; one
/// Newton step for 1/sqrt(n) at n = |out|^2 ~ 1, out (3 - n) / 2, leaves an error of order e^2,
/// so the direction stays unit over any number of events without the square root and division
/// of a normalisation on the photon's critical path.
template <class Real>
struct Vec3Of {
    Real x, y, z;
};

/// For directions as components (doubles, or SIMD vectors of them: photons in lanes).
template <class Real>
SECCHI_KERNEL Vec3Of<Real> rotate_direction(const Vec3Of<Real>& d, Real cos_psi, Real phi) {
    using std::max, std::sqrt;
    using T = scalar_t<Real>;
    const Real sin_psi = sqrt(max(Real(T(0)), T(1) - cos_psi * cos_psi));
    const Real sign = unit_with_sign_of(d.z);
    const Real a = T(-1) / (sign + d.z);
    const Real b = d.x * d.y * a;
    const SinCosOf<Real> az = sin_cos(phi);
    const Real u = sin_psi * az.cos, v = sin_psi * az.sin;
    // out = u t1 + v t2 + cos_psi d with t1 = (1 + sign dx^2 a, sign b, -sign dx), t2 = (b, sign + dy^2 a, -dy)
    const Real ox = u * (T(1) + sign * d.x * d.x * a) + v * b + cos_psi * d.x;
    const Real oy = u * (sign * b) + v * (sign + d.y * d.y * a) + cos_psi * d.y;
    const Real oz = u * (-sign * d.x) + v * (-d.y) + cos_psi * d.z;
    const Real n = T(1.5) - T(0.5) * (ox * ox + oy * oy + oz * oz);
    return {ox * n, oy * n, oz * n};
}

inline vec3 rotate_direction(const vec3& dir, double cos_psi, double phi) {
    const Vec3Of<double> out = rotate_direction(Vec3Of<double>{dir.x, dir.y, dir.z}, cos_psi, phi);
    return {out.x, out.y, out.z};
}

}  // namespace secchi
