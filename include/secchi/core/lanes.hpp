#pragma once
// Photons in lanes: the per-event kernels of transport for `lane_width` photons at once, as
// SIMD vectors of doubles (std::experimental::simd, the Parallelism TS 2; GCC >= 11 and
// libstdc++). They compute what their scalar counterparts in math.hpp compute, without a
// branch per photon: the same Cody-Waite sin_cos, the same frame rotation, and a logarithm
// for the free path -ln u (manual eq. 3.17). LaneTracer (transport/lane_tracer.hpp) uses them.
//
// The lanes are the target's native vector of doubles (2 with SSE2, 4 with AVX2, 8 with
// AVX-512): a portable build gains little from them; one for AVX2 or better does
// (BENCHMARKS.md). A photon's history does not depend on the lane count (each photon draws
// from its own random stream); the order of the stored records and the rounding of the
// tallies' sums do.
#if __has_include(<experimental/simd>)
// GCC 12's AVX-512 intrinsics (included through <experimental/simd>) warn about their own
// deliberately undefined vectors (GCC bug 105593, fixed in GCC 13); the warnings point into
// those headers, so they are silenced where the headers are read.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <experimental/simd>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#define SECCHI_HAS_LANES 1
#endif

#if SECCHI_HAS_LANES
#include "secchi/core/math.hpp"
#include <cstddef>
#include <cstdint>

namespace secchi::lanes {

namespace stdx = std::experimental;
using Reals = stdx::native_simd<double>;
inline constexpr int lane_width = static_cast<int>(Reals::size());
using Mask = typename Reals::mask_type;
using Words = stdx::rebind_simd_t<std::uint64_t, Reals>;
using Ints = stdx::rebind_simd_t<std::int64_t, Reals>;
inline constexpr auto aligned = stdx::vector_aligned;

// The kernels below are small bodies on 8-wide vectors called once per step: inlined, the
// vectors stay in registers instead of passing through memory at every call.
#if defined(__GNUC__)
#define SECCHI_LANE_KERNEL [[gnu::always_inline]] inline
#else
#define SECCHI_LANE_KERNEL inline
#endif

/// A lane's bits of a mask, as an integer (bit l set if lane l is).
SECCHI_LANE_KERNEL unsigned bits_of(const Mask& m) {
    unsigned b = 0;
    for (int l = 0; l < lane_width; ++l) b |= static_cast<unsigned>(m[l]) << l;
    return b;
}

/// A table's entries at per-lane indices (integers held as doubles). Written as a plain loop
/// over arrays, which compilers turn into a gather instruction where the target has one.
template <class Table>
SECCHI_LANE_KERNEL Reals lookup(const Table& table, const Reals& index) {
    alignas(64) std::int64_t i[lane_width];
    alignas(64) double v[lane_width];
    stdx::static_simd_cast<Ints>(index).copy_to(i, aligned);
    for (int l = 0; l < lane_width; ++l) v[l] = table[static_cast<std::size_t>(i[l])];
    return Reals(v, aligned);
}

/// ln x for normal x > 0 (the free path -ln u has u in (0, 1)). x = 2^e m with m in
/// [sqrt(1/2), sqrt 2); ln m = 2 atanh f with f = (m - 1)/(m + 1), |f| < 0.172, by its series
/// 2 (f + f^3/3 + ... + f^21/21) (truncation < f^23 ~ 3e-18); ln 2 split in two so that e ln2_hi
/// is exact. Within 2 ulp of std::log (tests/test_lane_tracer.cpp).
SECCHI_LANE_KERNEL Reals log(Reals x) {
    const Words bits = stdx::__proposed::simd_bit_cast<Words>(x);
    constexpr std::uint64_t sqrt_half = 0x3fe6a09e667f3bcdull, one = 0x3ff0000000000000ull;
    const Words shifted = bits + Words(one - sqrt_half);  // exponent of x / sqrt(1/2)
    const Ints e = stdx::static_simd_cast<Ints>(shifted >> 52) - Ints(1023);
    const Reals m = stdx::__proposed::simd_bit_cast<Reals>((shifted & Words(0x000fffffffffffffull)) + Words(sqrt_half));
    const Reals f = (m - 1.0) / (m + 1.0), f2 = f * f;
    const Reals series =
        2.0 / 3 + f2 * (2.0 / 5 + f2 * (2.0 / 7 + f2 * (2.0 / 9 + f2 * (2.0 / 11 + f2 * (2.0 / 13 + f2 * (2.0 / 15 +
        f2 * (2.0 / 17 + f2 * (2.0 / 19 + f2 * (2.0 / 21)))))))));
    const Reals ed = stdx::static_simd_cast<Reals>(e);
    constexpr double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
    return ed * ln2_hi + (2.0 * f + (f * f2 * series + ed * ln2_lo));
}

struct SinCos {
    Reals sin, cos;
};

struct Vec3 {
    Reals x, y, z;
};

/// secchi::sin_cos (math.hpp) per lane: the same reduction and series, the quadrant's
/// rotation by selects instead of a switch.
SECCHI_LANE_KERNEL SinCos sin_cos(Reals x) {
    constexpr double two_over_pi = 0.6366197723675814;
    constexpr double pio2_1 = 1.5707963267341256, pio2_2 = 6.077100506303966e-11, pio2_3 = 2.0222662487959506e-21;
    constexpr double shift = 0x1.8p52;  // detail::round_to_integer
    const Reals k = (x * two_over_pi + shift) - shift;
    const Reals r = ((x - k * pio2_1) - k * pio2_2) - k * pio2_3;
    const Reals r2 = r * r;
    constexpr double f3 = 0.16666666666666666, f5 = 0.008333333333333333, f7 = 0.0001984126984126984,
                     f9 = 2.7557319223985893e-06, f11 = 2.505210838544172e-08, f13 = 1.6059043836821613e-10,
                     f15 = 7.647163731819816e-13, f17 = 2.8114572543455206e-15;
    constexpr double f4 = 0.041666666666666664, f6 = 0.001388888888888889, f8 = 2.48015873015873e-05,
                     f10 = 2.755731922398589e-07, f12 = 2.08767569878681e-09, f14 = 1.1470745597729725e-11,
                     f16 = 4.779477332387385e-14, f18 = 1.5619206968586225e-16;
    const Reals ps = -f3 + r2 * (f5 + r2 * (-f7 + r2 * (f9 + r2 * (-f11 + r2 * (f13 + r2 * (-f15 + r2 * f17))))));
    const Reals pc = f4 + r2 * (-f6 + r2 * (f8 + r2 * (-f10 + r2 * (f12 + r2 * (-f14 + r2 * (f16 - r2 * f18))))));
    const Reals s = r + r * r2 * ps;
    const Reals c = (1.0 - 0.5 * r2) + r2 * r2 * pc;
    // x = k pi/2 + r: quadrant q = k mod 4 gives (sin, cos) = (s, c), (c, -s), (-s, -c), (-c, s).
    const Reals q = k - 4.0 * stdx::floor(k * 0.25);
    const Mask odd = (q == 1.0) || (q == 3.0);
    const Reals sin_abs = select(odd, c, s), cos_abs = select(odd, s, c);
    return {select(q >= 2.0, -sin_abs, sin_abs), select((q == 1.0) || (q == 2.0), -cos_abs, cos_abs)};
}

/// secchi::rotate_direction (math.hpp) per lane: Duff et al.'s frame about `d`, the
/// scattered direction at (cos_psi, phi) in it, and one Newton step back to unit length.
SECCHI_LANE_KERNEL Vec3 rotate_direction(const Vec3& d, Reals cos_psi, Reals phi) {
    const Reals sin_psi = stdx::sqrt(stdx::max(Reals(0.0), 1.0 - cos_psi * cos_psi));
    const Reals sign = stdx::copysign(Reals(1.0), d.z);
    const Reals a = -1.0 / (sign + d.z);
    const Reals b = d.x * d.y * a;
    const SinCos az = sin_cos(phi);
    const Reals u = sin_psi * az.cos, v = sin_psi * az.sin;
    // out = u t1 + v t2 + cos_psi d, t1 = (1 + sign dx^2 a, sign b, -sign dx), t2 = (b, sign + dy^2 a, -dy)
    const Reals ox = u * (1.0 + sign * d.x * d.x * a) + v * b + cos_psi * d.x;
    const Reals oy = u * (sign * b) + v * (sign + d.y * d.y * a) + cos_psi * d.y;
    const Reals oz = u * (-sign * d.x) + v * (-d.y) + cos_psi * d.z;
    const Reals n = 1.5 - 0.5 * (ox * ox + oy * oy + oz * oz);
    return {ox * n, oy * n, oz * n};
}

}  // namespace secchi::lanes

#endif
