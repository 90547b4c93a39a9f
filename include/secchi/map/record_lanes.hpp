#pragma once
// Records for a vector of scattering events at once (photons in lanes,
// transport/lane_tracer.hpp). LaneRecords<R>::make(p, d, band, batch, out) writes
// out[l] = R::make(p_l, d_l, band, batch[l]) for every lane l. A record type without a
// specialisation is made lane by lane; CompactRecord's direction bytes are encoded in the
// vectors by the guess-and-correct of detail::encode_theta and encode_phi (record.hpp), with
// the table lookups of the correction only where a guess is near a bin boundary; the bytes
// equal make()'s (tests/test_lane_tracer.cpp).
#include "secchi/core/lanes.hpp"
#include "secchi/map/record.hpp"
#include <bit>
#include <cstring>

#if SECCHI_HAS_LANES
namespace secchi {

template <class Record>
struct LaneRecords {
    /// Writes R::make(p_l, d_l, band, batch[l]) for the lanes l set in the bits of `keep`, in
    /// lane order, to out[0], out[1], ... and returns how many. Every lane's record is written
    /// at the next free place, which a kept one then takes (no branch per lane): out must have
    /// room for lane_width records.
    static std::size_t make_kept(const lanes::Vec3& p, const lanes::Vec3& d, band_index band,
                                 const std::uint8_t* batch, unsigned keep, Record* out) {
        std::size_t n = 0;
        for (int l = 0; l < lanes::lane_width; ++l) {
            out[n] = Record::make(vec3(p.x[l], p.y[l], p.z[l]), vec3(d.x[l], d.y[l], d.z[l]), band, batch[l]);
            n += (keep >> l) & 1u;
        }
        return n;
    }
};

namespace detail {
/// acos x for 0 <= x <= 1 by Abramowitz and Stegun 4.4.46: sqrt(1 - x) times a polynomial
/// of degree 7, error 2.2e-8 rad (A&S state 2e-8; measured in tests/test_lane_tracer.cpp).
/// The polynomial by Estrin's scheme (pairs of terms, then pairs of pairs: three multiply-adds
/// deep, not seven), beside the square root.
SECCHI_KERNEL lanes::Reals acos_unit(const lanes::Reals& x) {
    const lanes::Reals x2 = x * x, x4 = x2 * x2;
    const lanes::Reals p01 = 1.5707963050 - 0.2145988016 * x, p23 = 0.0889789874 - 0.0501743046 * x,
                       p45 = 0.0308918810 - 0.0170881256 * x, p67 = 0.0066700901 - 0.0012624911 * x;
    return lanes::stdx::sqrt(1.0 - x) * ((p01 + x2 * p23) + x4 * (p45 + x2 * p67));
}

/// encode_theta per lane (the byte as a double). Its guess comes from acos_unit (within
/// 1.8e-6 bin) rather than encode_theta's 4.4.45 (0.006 bin), so it is the answer unless it
/// lies within 1e-4 bin of a boundary: the two table lookups (gathers) of the correction are
/// made only when some lane is that close (one step in 600 with 8 lanes, not one in seven).
SECCHI_KERNEL lanes::Reals encode_theta(const lanes::Reals& dz) {
    using lanes::Reals, lanes::stdx::floor;
    const auto& t = direction_encode_tables();
    const Reals abs_dz = lanes::stdx::abs(dz);
    const Reals acos_x = acos_unit(select(abs_dz < 1.0, abs_dz, Reals(1.0)));
    const Reals theta = select(dz < 0.0, pi - acos_x, acos_x);
    const Reals bins = theta * (256.0 / pi);
    Reals k = lanes::stdx::min(Reals(255.0), floor(bins));
    const Reals fraction = bins - floor(bins);
    // theta = 0 and pi (vertical photons, e.g. from a sun at the zenith) lie on no boundary.
    if (none_of((fraction < 1e-4 && bins >= 1.0 && bins < 256.0) || fraction > 1.0 - 1e-4)) return k;
    lanes::stdx::where(dz <= lanes::lookup(t.theta_edge, k + 1.0), k) += 1.0;  // at or past the upper boundary
    lanes::stdx::where(dz > lanes::lookup(t.theta_edge, k), k) -= 1.0;         // before the lower boundary
    return k;
}

/// atan r for r in [0, 1], to 1.5e-9 rad (tests/test_lane_tracer.cpp): r times a polynomial
/// of degree 9 in t = r^2, a Chebyshev fit of atan(sqrt t)/sqrt t on [0, 1] (mpmath's
/// chebyfit, error 2.8e-9), by Estrin's scheme. It needs no division (the reduction of
/// atan r to pi/4 + atan((r - 1)/(r + 1)) above tan(pi/8) took one, on the way to the record).
SECCHI_KERNEL lanes::Reals atan_unit(const lanes::Reals& r) {
    using lanes::Reals;
    const Reals t = r * r, t2 = t * t, t4 = t2 * t2;
    const Reals p01 = 0.99999999716054546489 - 0.33333276291982551432 * t,
                p23 = 0.19998075281148713556 - 0.14260016082820904772 * t,
                p45 = 0.10932341501303092842 - 0.08349724968301601747 * t,
                p67 = 0.057089555930306190041 - 0.030351864785781170614 * t,
                p89 = 0.010487649254949305575 - 0.0017011700640685972273 * t;
    return r * ((p01 + t2 * p23) + t4 * ((p45 + t2 * p67) + t4 * p89));
}

/// encode_phi per lane (the byte as a double). Its guess of the azimuth comes from atan_unit
/// (within 6e-8 bin) instead of encode_phi's coarse one (0.07 bin): both land in the exact
/// bin away from its boundaries, and near one (rarely: then for all lanes) the same
/// cross-product test with the boundary decides, as in encode_phi.
SECCHI_KERNEL lanes::Reals encode_phi(const lanes::Reals& dx, const lanes::Reals& dy) {
    using lanes::Reals, lanes::stdx::floor;
    const auto& t = direction_encode_tables();
    const auto pole = dx == 0.0 && dy == 0.0;
    const Reals ax = lanes::stdx::abs(dx), ay = lanes::stdx::abs(dy);
    Reals a = atan_unit(select(pole, Reals(0.0), lanes::stdx::min(ax, ay) / lanes::stdx::max(ax, ay)));
    a = select(ay > ax, 0.5 * pi - a, a);
    a = select(dx < 0.0, pi - a, a);
    a = select(dy < 0.0, two_pi - a, a);
    const Reals bins = a * (256.0 / two_pi) + 0.5;
    Reals j = floor(bins);  // a >= 0: the truncation of encode_phi
    j = select(j >= 256.0, j - 256.0, j);
    const Reals fraction = bins - floor(bins);
    if (any_of(fraction < 1e-6 || fraction > 1.0 - 1e-6)) {
        const Reals below = select(j == 0.0, Reals(255.0), j - 1.0), above = select(j == 255.0, Reals(0.0), j + 1.0);
        const auto past_upper = lanes::lookup(t.phi_edge_cos, j) * dy - lanes::lookup(t.phi_edge_sin, j) * dx >= 0.0;
        const auto before_lower =
            lanes::lookup(t.phi_edge_cos, below) * dy - lanes::lookup(t.phi_edge_sin, below) * dx < 0.0;
        j = select(past_upper, above, select(before_lower, below, j));
    }
    // At the poles, atan2's choice: 0, or 128 for dx = -0.
    return select(pole, select(lanes::stdx::copysign(Reals(1.0), dx) < 0.0, Reals(128.0), Reals(0.0)), j);
}
}  // namespace detail

template <>
struct LaneRecords<CompactRecord> {
    /// As the general make_kept. The last four bytes of a record (theta, phi, band, batch) are
    /// one 32-bit word made in the vectors; with AVX2 the four words of four lanes (x, y, z as
    /// floats, and that word) are transposed into four records in registers (rounding to float
    /// as static_cast does), instead of being put together lane by lane (about 65 instructions
    /// per four records: valgrind).
    SECCHI_KERNEL static std::size_t make_kept(const lanes::Vec3& p, const lanes::Vec3& d, band_index band,
                                               const std::uint8_t* batch, unsigned keep, CompactRecord* out) {
        constexpr int width = lanes::lane_width;
        static_assert(std::endian::native == std::endian::little, "the record's last word is built little-endian");
        using Words32 = lanes::stdx::rebind_simd_t<std::int32_t, lanes::Reals>;
        const lanes::Reals theta = detail::encode_theta(d.z), phi = detail::encode_phi(d.x, d.y);
        // theta + 2^8 phi + 2^16 band + 2^24 batch < 2^31 (batch < 64): exact in a double and an int.
        const lanes::Reals code = theta + 256.0 * phi + 65536.0 * band +
                                  lanes::Reals([&](int l) { return 16777216.0 * batch[l]; });
        alignas(64) std::int32_t word[width];
        lanes::stdx::static_simd_cast<Words32>(code).copy_to(word, lanes::stdx::vector_aligned);
#if defined(__AVX2__)  // (lanes.hpp includes the intrinsics with AVX2)
        static_assert(width % 4 == 0);
        alignas(64) double x[width], y[width], z[width];
        p.x.copy_to(x, lanes::aligned), p.y.copy_to(y, lanes::aligned), p.z.copy_to(z, lanes::aligned);
        std::size_t n = 0;
        for (int g = 0; g < width; g += 4) {
            __m128 r0 = _mm256_cvtpd_ps(_mm256_load_pd(x + g)), r1 = _mm256_cvtpd_ps(_mm256_load_pd(y + g)),
                   r2 = _mm256_cvtpd_ps(_mm256_load_pd(z + g)),
                   r3 = _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(word + g)));
            _MM_TRANSPOSE4_PS(r0, r1, r2, r3);  // now r_k is lane g + k's record
            const __m128 records[4] = {r0, r1, r2, r3};
            for (int k = 0; k < 4; ++k) {
                _mm_storeu_ps(reinterpret_cast<float*>(out + n), records[k]);
                n += (keep >> (g + k)) & 1u;
            }
        }
        return n;
#else
        std::size_t n = 0;
        for (int l = 0; l < width; ++l) {
            out[n] = {static_cast<float>(p.x[l]), static_cast<float>(p.y[l]), static_cast<float>(p.z[l]), 0, 0, 0, 0};
            std::memcpy(&out[n].theta, &word[l], 4);
            n += (keep >> l) & 1u;
        }
        return n;
#endif
    }
};

}  // namespace secchi
#endif
