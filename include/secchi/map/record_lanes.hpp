#pragma once
// Records for a vector of scattering events at once (photons in lanes,
// transport/lane_tracer.hpp). LaneRecords<R>::make(p, d, band, batch, out) writes
// out[l] = R::make(p_l, d_l, band, batch[l]) for every lane l. A record type without a
// specialisation is made lane by lane; CompactRecord's direction bytes are encoded in the
// vectors by the guess-and-correct of detail::encode_theta and encode_phi (record.hpp), with
// the table lookups of the correction only where a guess is near a bin boundary; the bytes
// equal make()'s (tests/test_lane_tracer.cpp).
#include "secchi/core/config.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/map/record.hpp"
#include <bit>
#include <cstring>

#if SECCHI_HAS_LANES
namespace secchi::SECCHI_ISA {

template <class Record>
struct LaneRecords {
    /// Writes R::make(p_l, d_l, band, batch[l]) for the lanes l set in the bits of `keep`, in
    /// lane order, to out[0], out[1], ... and returns how many. Every lane's record is written
    /// at the next free place, which a kept one then takes (no branch per lane): out must have
    /// room for as many records as lanes. (Lanes of doubles or of floats.)
    template <class Real>
    static std::size_t make_kept(const Vec3Of<Real>& p, const Vec3Of<Real>& d, band_index band,
                                 const std::uint8_t* batch, unsigned keep, Record* out) {
        std::size_t n = 0;
        for (int l = 0; l < static_cast<int>(Real::size()); ++l) {
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
/// deep, not seven), beside the square root. For lanes of doubles or floats.
template <class Real>
SECCHI_KERNEL Real acos_unit(const Real& x) {
    using T = scalar_t<Real>;
    const Real x2 = x * x, x4 = x2 * x2;
    const Real p01 = T(1.5707963050) - T(0.2145988016) * x, p23 = T(0.0889789874) - T(0.0501743046) * x,
               p45 = T(0.0308918810) - T(0.0170881256) * x, p67 = T(0.0066700901) - T(0.0012624911) * x;
    return lanes::stdx::sqrt(T(1) - x) * ((p01 + x2 * p23) + x4 * (p45 + x2 * p67));
}

/// How close (in bins) to a bin boundary the lanes' guess of a direction byte may come before
/// the byte is made by the scalar encoder instead: above the guess's error, which is set by
/// the approximation for doubles (acos_unit 2.2e-8 rad = 1.8e-6 bin, atan_unit 6e-8 bin) and
/// by float rounding for floats (a few 1e-7 rad, about 4e-5 bin).
template <class T>
inline constexpr T theta_margin = std::is_same_v<T, float> ? T(1e-3) : T(1e-4);
template <class T>
inline constexpr T phi_margin = std::is_same_v<T, float> ? T(1e-3) : T(1e-6);

/// encode_theta per lane (the byte as a Real). Its guess comes from acos_unit (within
/// 1.8e-6 bin) rather than encode_theta's 4.4.45 (0.006 bin), so it is the answer unless it
/// lies within theta_margin of a boundary: such lanes (one step in 600 with 8 double lanes)
/// take encode_theta's byte.
template <class Real>
SECCHI_KERNEL Real encode_theta(const Real& dz) {
    using T = scalar_t<Real>;
    using lanes::stdx::floor;
    const Real abs_dz = lanes::stdx::abs(dz);
    const Real acos_x = acos_unit(select(abs_dz < T(1), abs_dz, Real(T(1))));
    const Real theta = select(dz < T(0), T(pi) - acos_x, acos_x);
    const Real bins = theta * T(256.0 / pi);
    Real k = lanes::stdx::min(Real(T(255)), floor(bins));
    const Real fraction = bins - floor(bins);
    // theta = 0 and pi (vertical photons, e.g. from a sun at the zenith) lie on no boundary.
    lanes::for_each((fraction < theta_margin<T> && bins >= T(1) && bins < T(256)) || fraction > T(1) - theta_margin<T>,
                    [&](int l) { k[l] = T(encode_theta(double(dz[l]))); });
    return k;
}

/// atan r for r in [0, 1], to 1.5e-9 rad (tests/test_lane_tracer.cpp): r times a polynomial
/// of degree 9 in t = r^2, a Chebyshev fit of atan(sqrt t)/sqrt t on [0, 1] (mpmath's
/// chebyfit, error 2.8e-9), by Estrin's scheme. It needs no division (the reduction of
/// atan r to pi/4 + atan((r - 1)/(r + 1)) above tan(pi/8) took one, on the way to the record).
template <class Real>
SECCHI_KERNEL Real atan_unit(const Real& r) {
    using T = scalar_t<Real>;
    const Real t = r * r, t2 = t * t, t4 = t2 * t2;
    const Real p01 = T(0.99999999716054546489) - T(0.33333276291982551432) * t,
               p23 = T(0.19998075281148713556) - T(0.14260016082820904772) * t,
               p45 = T(0.10932341501303092842) - T(0.08349724968301601747) * t,
               p67 = T(0.057089555930306190041) - T(0.030351864785781170614) * t,
               p89 = T(0.010487649254949305575) - T(0.0017011700640685972273) * t;
    return r * ((p01 + t2 * p23) + t4 * ((p45 + t2 * p67) + t4 * p89));
}

/// encode_phi per lane (the byte as a Real). Its guess of the azimuth comes from atan_unit
/// (within 6e-8 bin) instead of encode_phi's coarse one (0.07 bin): both land in the exact
/// bin away from its boundaries; lanes within phi_margin of one take encode_phi's byte.
template <class Real>
SECCHI_KERNEL Real encode_phi(const Real& dx, const Real& dy) {
    using T = scalar_t<Real>;
    using lanes::stdx::floor;
    const auto pole = dx == T(0) && dy == T(0);
    const Real ax = lanes::stdx::abs(dx), ay = lanes::stdx::abs(dy);
    Real a = atan_unit(select(pole, Real(T(0)), lanes::stdx::min(ax, ay) / lanes::stdx::max(ax, ay)));
    a = select(ay > ax, T(0.5 * pi) - a, a);
    a = select(dx < T(0), T(pi) - a, a);
    a = select(dy < T(0), T(two_pi) - a, a);
    const Real bins = a * T(256.0 / two_pi) + T(0.5);
    Real j = floor(bins);  // a >= 0: the truncation of encode_phi
    j = select(j >= T(256), j - T(256), j);
    const Real fraction = bins - floor(bins);
    lanes::for_each(fraction < phi_margin<T> || fraction > T(1) - phi_margin<T>,
                    [&](int l) { j[l] = T(encode_phi(double(dx[l]), double(dy[l]))); });
    // At the poles, atan2's choice: 0, or 128 for dx = -0.
    return select(pole, select(signbit(dx), Real(T(128)), Real(T(0))), j);
}
}  // namespace detail

template <>
struct LaneRecords<CompactRecord> {
    /// detail::grid_coordinate in lanes: the nearest multiple of position_grid for |c| <
    /// position_grid_limit (in float lanes c / position_grid, below 2^23, and its rounding are
    /// exact, as in double), else the nearest float.
    template <class Floats, class Real>
    static Floats grid_coordinates(const Real& c) {
        using T = typename Real::value_type;
        const Real on_grid = lanes::stdx::nearbyint(c * Real(T(1.0 / position_grid))) * Real(T(position_grid)) + Real(T(0));  // -0 to +0
        return lanes::stdx::static_simd_cast<Floats>(select(lanes::stdx::abs(c) < Real(T(position_grid_limit)), on_grid, c));
    }

    /// As the general make_kept. The last four bytes of a record (theta, phi, band, batch) are
    /// one 32-bit word made in the vectors; with AVX2 the four words of four lanes (x, y, z as
    /// floats, and that word) are transposed into four records in registers, instead of being
    /// put together lane by lane (about 65 instructions per four records: valgrind). Positions
    /// are rounded as CompactRecord::make rounds them (detail::grid_coordinate), lane by lane.
    template <class Real>
    SECCHI_KERNEL static std::size_t make_kept(const Vec3Of<Real>& p, const Vec3Of<Real>& d, band_index band,
                                               const std::uint8_t* batch, unsigned keep, CompactRecord* out) {
        constexpr int width = static_cast<int>(Real::size());
        static_assert(std::endian::native == std::endian::little, "the record's last word is built little-endian");
        using Words32 = lanes::stdx::rebind_simd_t<std::int32_t, Real>;
        using Floats = lanes::stdx::rebind_simd_t<float, Real>;
        // theta + 2^8 phi + 2^16 band + 2^24 batch < 2^31 (batch < 64).
        const Words32 code = lanes::stdx::static_simd_cast<Words32>(detail::encode_theta(d.z)) +
                             (lanes::stdx::static_simd_cast<Words32>(detail::encode_phi(d.x, d.y)) << 8) +
                             Words32((static_cast<std::int32_t>(band) << 16)) +
                             Words32([&](int l) { return static_cast<std::int32_t>(batch[l]) << 24; });
        alignas(64) std::int32_t word[width];
        alignas(64) float x[width], y[width], z[width];
        code.copy_to(word, lanes::stdx::vector_aligned);
        grid_coordinates<Floats>(p.x).copy_to(x, lanes::stdx::element_aligned);
        grid_coordinates<Floats>(p.y).copy_to(y, lanes::stdx::element_aligned);
        grid_coordinates<Floats>(p.z).copy_to(z, lanes::stdx::element_aligned);
        std::size_t n = 0;
#if defined(__AVX2__)  // (lanes.hpp includes the intrinsics with AVX2)
        static_assert(width % 4 == 0);
        for (int g = 0; g < width; g += 4) {
            __m128 r0 = _mm_load_ps(x + g), r1 = _mm_load_ps(y + g), r2 = _mm_load_ps(z + g),
                   r3 = _mm_castsi128_ps(_mm_load_si128(reinterpret_cast<const __m128i*>(word + g)));
            _MM_TRANSPOSE4_PS(r0, r1, r2, r3);  // now r_k is lane g + k's record
            const __m128 records[4] = {r0, r1, r2, r3};
            for (int k = 0; k < 4; ++k) {
                _mm_storeu_ps(reinterpret_cast<float*>(out + n), records[k]);
                n += (keep >> (g + k)) & 1u;
            }
        }
#else
        for (int l = 0; l < width; ++l) {
            out[n] = {x[l], y[l], z[l], 0, 0, 0, 0};
            std::memcpy(&out[n].theta, &word[l], 4);
            n += (keep >> l) & 1u;
        }
#endif
        return n;
    }
};

}  // namespace secchi
#endif
