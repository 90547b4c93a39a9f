#pragma once
// The cylinder test of a run of records in SIMD, for the VOI octree's leaf scan
// (map/voi_octree.hpp): which records of a run lie in the cylinder of radius r around a ray
// segment, with in_cylinder's t and distance2 (store.hpp), packed in record order.
//
// Positions come from one of two sources: records of 16 bytes whose position is three floats
// at bytes 0, 4 and 8 (CompactRecord; FloatRecordPositions), or the packed layout's 64-bit
// words of three 21-bit integers q within one frame (packed_records.hpp; CodedPositions), each
// coordinate origin + q step, computed in double: exact, and the same double as the float the
// record holds (PackedRecords checks each record for that when it packs it). A kernel reads
// either by its loader (Load8, Load4 below); the rest of the kernel is shared.
// Two kernels, one chosen at compile time by the target (SECCHI_HAS_CYLINDER_SCAN: 1 with
// AVX-512F and VL, or with AVX2 and FMA; 0 elsewhere, where the octree keeps its portable
// loops):
//  - AVX-512: eight records at a time: two 64-byte loads, the x, y and z floats picked out by
//    three two-source permutes and widened to doubles (or one 64-byte load of eight words, each
//    integer shifted and masked out, widened to double and scaled into its frame);
//    in_cylinder's arithmetic on 8 doubles, its three comparisons as one mask, and the accepted
//    lanes packed by register compresses, each stored as a whole vector at the current fill (so
//    the output arrays need kScanSlack spare entries). The compress goes to a register, not
//    straight to memory: AMD's Zen 4 microcodes the compress-to-memory form (tens of cycles).
//  - AVX2: four records at a time: four 16-byte loads transposed into x, y and z (the classic
//    4 x 4 float transpose, w dropped), widened to doubles (or one 32-byte load of four words,
//    as above); the same arithmetic on 4 doubles. AVX2 has no compress, so the accepted lanes
//    are packed by a permute whose indices come from a 16-entry table indexed by the comparison
//    mask (kPack), stored whole as above.
//
// On vertical rays (nadir and zenith views, is_vertical) either kernel takes a vertical form
// with half the arithmetic and the same values (cylinder_lanes below).
//
// The arithmetic is in_cylinder's, in its order, written with the vector types' operators so
// that the compiler treats it as it treats in_cylinder's scalar code: where it fuses
// multiply-adds (-ffp-contract=fast, GCC's default outside ISO mode, on a target with FMA) it
// fuses both alike; tests/test_stores.cpp compares with in_cylinder bit for bit where it
// cannot fuse and to rounding where it can.
//
// Speed against the portable loops: docs/design-notes.md ("VOI leaf scan"; packed words:
// "Packed records").
#include "secchi/core/config.hpp"
#include "secchi/map/store.hpp"
#include <array>
#include <cstddef>
#include <cstdint>
#include <type_traits>

#if defined(__AVX512F__) && defined(__AVX512VL__)
#include <immintrin.h>
#define SECCHI_HAS_CYLINDER_SCAN 1
#define SECCHI_CYLINDER_SCAN_AVX512 1
#elif defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SECCHI_HAS_CYLINDER_SCAN 1
#define SECCHI_CYLINDER_SCAN_AVX512 0
#else
#define SECCHI_HAS_CYLINDER_SCAN 0
#define SECCHI_CYLINDER_SCAN_AVX512 0
#endif

namespace secchi::SECCHI_ISA::detail {

/// A record the scan can read: 16 bytes, standard layout, position floats x, y, z at 0, 4, 8.
template <class R>
concept PackedFloatRecord = std::is_standard_layout_v<R> && sizeof(R) == 16 && requires(const R r) {
    requires std::is_same_v<decltype(r.x), float> && std::is_same_v<decltype(r.y), float> &&
                 std::is_same_v<decltype(r.z), float>;
    requires offsetof(R, x) == 0 && offsetof(R, y) == 4 && offsetof(R, z) == 8;
};

/// Positions of records in place: records[k]'s floats x, y, z.
template <PackedFloatRecord R>
struct FloatRecordPositions {
    const R* records;
};

/// Positions of packed records within one frame (packed_records.hpp): word k holds the
/// integers q of x (bits 0-20), y (21-41) and z (42-62), coordinate = origin + q step per axis,
/// which the packing guarantees to be exact in double and equal to the record's float.
struct CodedPositions {
    static constexpr int bits = 21;
    const std::uint64_t* codes;
    std::array<double, 3> origin, step;
};

/// Spare entries the output arrays need past the last accepted record (one vector).
inline constexpr std::uint32_t kScanSlack = 8;

/// in_cylinder's arithmetic (store.hpp) on vectors of doubles V, in its order, for both
/// kernels: d = p - o, t = d . u, perp = d - t u, distance2 = perp . perp (glm's dot sums x,
/// y, z left to right, as here). o and u: the ray's origin and direction, each component
/// broadcast to every lane. (V is deduced: GCC warns where an intrinsic vector type, with its
/// may_alias attribute, is named as a template argument.)
///
/// Vertical: the same values on a vertical ray (is_vertical: u = (0, 0, uz), uz = +-1) in 7
/// operations instead of 12. There dx ux and dy uy are zeros, so t = dz uz, exact; t ux and t uy
/// are zeros, so perp = (dx, dy, dz - dz uz uz) = (dx, dy, 0) exactly. distance2 is written
/// as the same sum of the same three squares (pz = 0), so that a compiler that fuses
/// multiply-adds fuses both forms alike: tests/test_stores.cpp compares the two kernels bit
/// for bit on vertical rays. 1.10-1.14 times the grid's search rate (docs/design-notes.md).
template <bool Vertical, class V>
inline void cylinder_lanes(const V& x, const V& y, const V& z, const V (&o)[3], const V (&u)[3], V& t, V& distance2) {
    const V dx = x - o[0], dy = y - o[1], dz = z - o[2];
    if constexpr (Vertical) {
        t = dz * u[2];
        const V pz{};  // 0
        distance2 = dx * dx + dy * dy + pz * pz;
    } else {
        t = dx * u[0] + dy * u[1] + dz * u[2];
        const V px = dx - t * u[0], py = dy - t * u[1], pz = dz - t * u[2];
        distance2 = px * px + py * py + pz * pz;
    }
}

#if SECCHI_CYLINDER_SCAN_AVX512
// GCC 12's AVX-512 intrinsics warn about their own deliberately undefined vectors where they
// are inlined (GCC bug 105593, fixed in GCC 13; as in core/lanes.hpp): silenced for this code.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
/// Loads the positions of records k to k + min(left, 8) - 1 as three vectors of 8 doubles (lanes
/// past the last record: anything finite, masked out by the kernel). Never reads past the last record.
template <class Source>
struct Load8;

template <PackedFloatRecord R>
struct Load8<FloatRecordPositions<R>> {
    explicit Load8(const FloatRecordPositions<R>& source) : floats(reinterpret_cast<const float*>(source.records)) {}
    void operator()(std::uint32_t k, std::uint32_t left, __m512d& x, __m512d& y, __m512d& z) const {
        const float* const p = floats + 4 * std::size_t{k};
        __m512 a, b;
        if (left >= 8) {
            a = _mm512_loadu_ps(p);
            b = _mm512_loadu_ps(p + 16);
        } else {  // masked loads: the floats of the records that exist
            const __mmask16 first = left >= 4 ? __mmask16(0xffff) : __mmask16((1u << (4 * left)) - 1);
            const __mmask16 second = left > 4 ? __mmask16((1u << (4 * (left - 4))) - 1) : __mmask16(0);
            a = _mm512_maskz_loadu_ps(first, p);
            b = _mm512_maskz_loadu_ps(second, p + 16);
        }
        x = _mm512_cvtps_pd(_mm512_castps512_ps256(_mm512_permutex2var_ps(a, pick_x, b)));
        y = _mm512_cvtps_pd(_mm512_castps512_ps256(_mm512_permutex2var_ps(a, pick_y, b)));
        z = _mm512_cvtps_pd(_mm512_castps512_ps256(_mm512_permutex2var_ps(a, pick_z, b)));
    }
    const float* floats;
    // permutex2var indices: element 4k (+1, +2) of the 32 floats of two vectors is record k's x (y, z).
    const __m512i pick_x = _mm512_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28, 0, 0, 0, 0, 0, 0, 0, 0);
    const __m512i pick_y = _mm512_add_epi32(pick_x, _mm512_set1_epi32(1));
    const __m512i pick_z = _mm512_add_epi32(pick_x, _mm512_set1_epi32(2));
};

template <>
struct Load8<CodedPositions> {
    explicit Load8(const CodedPositions& source)
        : codes(source.codes),
          origin{_mm512_set1_pd(source.origin[0]), _mm512_set1_pd(source.origin[1]), _mm512_set1_pd(source.origin[2])},
          step{_mm512_set1_pd(source.step[0]), _mm512_set1_pd(source.step[1]), _mm512_set1_pd(source.step[2])} {}
    void operator()(std::uint32_t k, std::uint32_t left, __m512d& x, __m512d& y, __m512d& z) const {
        const __m512i q = left >= 8 ? _mm512_loadu_si512(codes + k) : _mm512_maskz_loadu_epi64(__mmask8((1u << left) - 1), codes + k);
        x = coordinate(q, 0);
        y = coordinate(_mm512_srli_epi64(q, CodedPositions::bits), 1);
        z = coordinate(_mm512_srli_epi64(q, 2 * CodedPositions::bits), 2);
    }
    /// origin + q step for the low 21 bits q of each word: q as a double (AVX-512DQ's
    /// conversion, else the exponent trick: the bits of 2^52 + q, minus 2^52; exact either
    /// way), then one multiply-add (q step is exact).
    [[nodiscard]] __m512d coordinate(__m512i word, int axis) const {
#if defined(__AVX512DQ__)
        const __m512d q = _mm512_cvtepi64_pd(_mm512_and_si512(word, mask));
#else
        const __m512d q = _mm512_sub_pd(_mm512_castsi512_pd(_mm512_or_si512(_mm512_and_si512(word, mask), two52_bits)), two52);
#endif
        return _mm512_fmadd_pd(q, step[axis], origin[axis]);
    }
    const std::uint64_t* codes;
    __m512d origin[3], step[3];
    const __m512i mask = _mm512_set1_epi64((1ll << CodedPositions::bits) - 1);
#if !defined(__AVX512DQ__)
    const __m512i two52_bits = _mm512_set1_epi64(0x4330000000000000ll);
    const __m512d two52 = _mm512_set1_pd(0x1p52);
#endif
};

/// The records [0, count) of `source` that in_cylinder(ray, position, r2) accepts: their t,
/// distance2 and offset (base + index into the source) written to t[n], distance2[n], offset[n]
/// for n = 0, 1, ... in record order; returns their number. The arrays need count + kScanSlack
/// entries. Never reads past record count - 1. Vertical: the ray is vertical (is_vertical;
/// scan_cylinder below chooses).
template <bool Vertical, class Source>
std::uint32_t scan_cylinder_kernel(const Source& source, std::uint32_t count, const Ray& ray, double r2, double* t,
                                   double* distance2, std::uint32_t* offset, std::uint32_t base = 0) {
    const Load8<Source> load(source);
    const __m512d o[3] = {_mm512_set1_pd(ray.origin.x), _mm512_set1_pd(ray.origin.y), _mm512_set1_pd(ray.origin.z)};
    const __m512d u[3] = {_mm512_set1_pd(ray.direction.x), _mm512_set1_pd(ray.direction.y),
                          _mm512_set1_pd(ray.direction.z)};
    const __m512d zero = _mm512_setzero_pd(), t_max = _mm512_set1_pd(ray.t_max), radius2 = _mm512_set1_pd(r2);
    const __m256i lane = _mm256_add_epi32(_mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7), _mm256_set1_epi32(static_cast<int>(base)));
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; k += 8) {
        const std::uint32_t left = count - k;
        const __mmask8 valid = left >= 8 ? __mmask8(0xff) : __mmask8((1u << left) - 1);
        __m512d x, y, z, tt, d2;
        load(k, left, x, y, z);
        cylinder_lanes<Vertical>(x, y, z, o, u, tt, d2);
        const __mmask8 inside = valid & _mm512_cmp_pd_mask(tt, zero, _CMP_GE_OQ) &
                                _mm512_cmp_pd_mask(tt, t_max, _CMP_LE_OQ) & _mm512_cmp_pd_mask(d2, radius2, _CMP_LE_OQ);
        _mm512_storeu_pd(t + n, _mm512_maskz_compress_pd(inside, tt));
        _mm512_storeu_pd(distance2 + n, _mm512_maskz_compress_pd(inside, d2));
        const __m256i index = _mm256_add_epi32(lane, _mm256_set1_epi32(static_cast<int>(k)));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(offset + n), _mm256_maskz_compress_epi32(inside, index));
        n += static_cast<std::uint32_t>(__builtin_popcount(inside));
    }
    return n;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#endif

#if SECCHI_HAS_CYLINDER_SCAN && !SECCHI_CYLINDER_SCAN_AVX512
/// The AVX2 packing table: for each 4-bit mask m of accepted lanes, lanes[m] lists the
/// accepted lanes in order (unused entries 0) and doubles[m] the 32-bit element pairs that a
/// permute of 4 doubles needs to move those lanes to the front.
struct PackTable {
    std::array<std::array<std::int32_t, 4>, 16> lanes{};
    std::array<std::array<std::int32_t, 8>, 16> doubles{};
};
inline constexpr PackTable kPack = [] {
    PackTable p;
    for (int m = 0; m < 16; ++m) {
        int n = 0;
        for (int lane = 0; lane < 4; ++lane) {
            if (!(m & (1 << lane))) continue;
            p.lanes[m][n] = lane;
            p.doubles[m][2 * n] = 2 * lane;
            p.doubles[m][2 * n + 1] = 2 * lane + 1;
            ++n;
        }
    }
    return p;
}();

/// As Load8 above, four records at a time.
template <class Source>
struct Load4;

template <PackedFloatRecord R>
struct Load4<FloatRecordPositions<R>> {
    explicit Load4(const FloatRecordPositions<R>& source) : floats(reinterpret_cast<const float*>(source.records)) {}
    void operator()(std::uint32_t k, std::uint32_t left, __m256d& x, __m256d& y, __m256d& z) const {
        const float* const p = floats + 4 * std::size_t{k};
        // One record per 16-byte load; past the run's end, zeros (never read).
        const __m128 rec0 = _mm_loadu_ps(p);
        const __m128 rec1 = left > 1 ? _mm_loadu_ps(p + 4) : _mm_setzero_ps();
        const __m128 rec2 = left > 2 ? _mm_loadu_ps(p + 8) : _mm_setzero_ps();
        const __m128 rec3 = left > 3 ? _mm_loadu_ps(p + 12) : _mm_setzero_ps();
        const __m128 xy01 = _mm_unpacklo_ps(rec0, rec1), xy23 = _mm_unpacklo_ps(rec2, rec3);  // x0 x1 y0 y1, x2 x3 y2 y3
        const __m128 zw01 = _mm_unpackhi_ps(rec0, rec1), zw23 = _mm_unpackhi_ps(rec2, rec3);  // z0 z1 w0 w1, z2 z3 w2 w3
        x = _mm256_cvtps_pd(_mm_movelh_ps(xy01, xy23));
        y = _mm256_cvtps_pd(_mm_movehl_ps(xy23, xy01));
        z = _mm256_cvtps_pd(_mm_movelh_ps(zw01, zw23));
    }
    const float* floats;
};

template <>
struct Load4<CodedPositions> {
    explicit Load4(const CodedPositions& source)
        : codes(source.codes),
          origin{_mm256_set1_pd(source.origin[0]), _mm256_set1_pd(source.origin[1]), _mm256_set1_pd(source.origin[2])},
          step{_mm256_set1_pd(source.step[0]), _mm256_set1_pd(source.step[1]), _mm256_set1_pd(source.step[2])} {}
    void operator()(std::uint32_t k, std::uint32_t left, __m256d& x, __m256d& y, __m256d& z) const {
        const auto* const p = reinterpret_cast<const long long*>(codes + k);
        const __m256i q = left >= 4 ? _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p))
                                    : _mm256_maskload_epi64(p, _mm256_cmpgt_epi64(_mm256_set1_epi64x(left), lanes));
        x = coordinate(q, 0);
        y = coordinate(_mm256_srli_epi64(q, CodedPositions::bits), 1);
        z = coordinate(_mm256_srli_epi64(q, 2 * CodedPositions::bits), 2);
    }
    /// As Load8's, by the exponent trick.
    [[nodiscard]] __m256d coordinate(__m256i word, int axis) const {
        const __m256d q = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(_mm256_and_si256(word, mask), two52_bits)), two52);
        return _mm256_fmadd_pd(q, step[axis], origin[axis]);
    }
    const std::uint64_t* codes;
    __m256d origin[3], step[3];
    const __m256i lanes = _mm256_setr_epi64x(0, 1, 2, 3);
    const __m256i mask = _mm256_set1_epi64x((1ll << CodedPositions::bits) - 1);
    const __m256i two52_bits = _mm256_set1_epi64x(0x4330000000000000ll);
    const __m256d two52 = _mm256_set1_pd(0x1p52);
};

/// As the AVX-512 kernel above (same contract), four records at a time.
template <bool Vertical, class Source>
std::uint32_t scan_cylinder_kernel(const Source& source, std::uint32_t count, const Ray& ray, double r2, double* t,
                                   double* distance2, std::uint32_t* offset, std::uint32_t base = 0) {
    const Load4<Source> load(source);
    const __m256d o[3] = {_mm256_set1_pd(ray.origin.x), _mm256_set1_pd(ray.origin.y), _mm256_set1_pd(ray.origin.z)};
    const __m256d u[3] = {_mm256_set1_pd(ray.direction.x), _mm256_set1_pd(ray.direction.y),
                          _mm256_set1_pd(ray.direction.z)};
    const __m256d zero = _mm256_setzero_pd(), t_max = _mm256_set1_pd(ray.t_max), radius2 = _mm256_set1_pd(r2);
    std::uint32_t n = 0;
    for (std::uint32_t k = 0; k < count; k += 4) {
        const std::uint32_t left = count - k;
        const int valid = left >= 4 ? 0xf : (1 << left) - 1;
        __m256d x, y, z, tt, d2;
        load(k, left, x, y, z);
        cylinder_lanes<Vertical>(x, y, z, o, u, tt, d2);
        const __m256d inside = _mm256_and_pd(_mm256_and_pd(_mm256_cmp_pd(tt, zero, _CMP_GE_OQ), _mm256_cmp_pd(tt, t_max, _CMP_LE_OQ)),
                                             _mm256_cmp_pd(d2, radius2, _CMP_LE_OQ));
        const int m = _mm256_movemask_pd(inside) & valid;
        const __m256i pack = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(kPack.doubles[m].data()));
        _mm256_storeu_pd(t + n, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(tt), pack)));
        _mm256_storeu_pd(distance2 + n, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(d2), pack)));
        const __m128i lanes = _mm_loadu_si128(reinterpret_cast<const __m128i*>(kPack.lanes[m].data()));
        _mm_storeu_si128(reinterpret_cast<__m128i*>(offset + n),
                         _mm_add_epi32(lanes, _mm_set1_epi32(static_cast<int>(base + k))));
        n += static_cast<std::uint32_t>(__builtin_popcount(static_cast<unsigned>(m)));
    }
    return n;
}
#endif

#if SECCHI_HAS_CYLINDER_SCAN
/// The records [0, count) of `source` (FloatRecordPositions or CodedPositions) that
/// in_cylinder(ray, position, r2) accepts, by the target's kernel (contract above), in its
/// vertical form on vertical rays.
template <class Source>
std::uint32_t scan_cylinder(const Source& source, std::uint32_t count, const Ray& ray, double r2, double* t,
                            double* distance2, std::uint32_t* offset, std::uint32_t base = 0) {
    if (is_vertical(ray)) return scan_cylinder_kernel<true>(source, count, ray, r2, t, distance2, offset, base);
    return scan_cylinder_kernel<false>(source, count, ray, r2, t, distance2, offset, base);
}
#endif

}  // namespace secchi::detail
