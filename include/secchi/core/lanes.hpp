#pragma once
// Photons in lanes: `lane_width` photons at once as SIMD vectors of doubles
// (std::experimental::simd, the Parallelism TS 2, as libstdc++ implements it: GCC >= 11, or
// clang with libstdc++, below), for LaneTracer (transport/lane_tracer.hpp). The types, and
// what only the lanes need: a logarithm for the free path -ln u (manual eq. 3.17), table
// lookups per lane and masks as bits. sin_cos and rotate_direction are math.hpp's, written once
// for doubles and vectors. Also exp, for the transmittances of many collected photons at once
// (estimate/path_radiance.hpp).
//
// The lanes are the target's native vector of doubles (2 with SSE2, 4 with AVX2, 8 with
// AVX-512), or of floats (twice as many: LaneTracer's float lanes): a portable build gains
// little from them; one for AVX2 or better does (docs/design-notes.md). A photon's history does not
// depend on the lane count (each photon draws from its own random stream); the order of the
// stored records and the rounding of the tallies' sums do.
//
// Where libstdc++'s <experimental/simd> is absent (another standard library, or GCC < 11), or
// SECCHI_DISABLE_LANES is defined (to build and test that case anywhere), SECCHI_HAS_LANES
// stays undefined and everything runs one photon at a time: LaneTracer is not declared, and the
// estimators' SIMD loops take their scalar forms. So also under clang with AVX-512: there clang
// (14) compiles libstdc++ (12)'s AVX-512 masks so that a masked assignment `where(m, v) = x`
// leaves v unchanged in every lane (sin_cos's quadrants came out wrong; the lanes' select test in
// tests/test_lane_tracer.cpp shows it); clang with SSE2 or AVX2 builds the lanes and passes their
// tests.
#include <version>  // __GLIBCXX__: which standard library
#if __has_include(<experimental/simd>) && defined(__GLIBCXX__) && !defined(SECCHI_DISABLE_LANES) && \
    !(defined(__clang__) && defined(__AVX512F__))
// GCC 12's AVX-512 intrinsics (included through <experimental/simd>) warn about their own
// deliberately undefined vectors (GCC bug 105593, fixed in GCC 13); the warnings point into
// those headers, so they are silenced where the headers are read, and where the intrinsics are
// inlined: the lanes namespace below.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include "secchi/core/config.hpp"
#include <experimental/simd>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
#define SECCHI_HAS_LANES 1
#endif

#if SECCHI_HAS_LANES
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
namespace secchi::SECCHI_ISA::lanes {

namespace stdx = std::experimental;
/// The target's native vector of T (double or float).
template <class T>
using LanesOf = stdx::native_simd<T>;
using Reals = LanesOf<double>;
using Floats = LanesOf<float>;  ///< twice as many lanes as Reals (photons in float lanes)
inline constexpr int lane_width = static_cast<int>(Reals::size());
template <class T>
inline constexpr int width_of = static_cast<int>(LanesOf<T>::size());
using Mask = typename Reals::mask_type;
using Words = stdx::rebind_simd_t<std::uint64_t, Reals>;
using Ints = stdx::rebind_simd_t<std::int64_t, Reals>;
inline constexpr auto aligned = stdx::vector_aligned;

/// A lane's bits of a mask, as an integer (bit l set if lane l is). libstdc++'s
/// __to_bitset() is one movemask instruction on x86; reading the lanes one by one took about
/// 16 instructions per scattering event in LaneTracer, 4 % of its instructions (valgrind).
template <class T, class Abi>
SECCHI_KERNEL unsigned bits_of(const stdx::simd_mask<T, Abi>& m) {
    return static_cast<unsigned>(m.__to_bitset().to_ulong());
}

/// Calls f(l) for every lane l set in m, in lane order.
template <class T, class Abi, class F>
SECCHI_KERNEL void for_each(const stdx::simd_mask<T, Abi>& m, F&& f) {
    for (unsigned b = bits_of(m); b != 0; b &= b - 1) f(std::countr_zero(b));
}

/// A table's entries at per-lane integer indices (a vector of 64-bit integers, signed or
/// not). Written as a plain loop over arrays, which compilers turn into a gather instruction
/// where the target has one.
template <class Table, class Index>
    requires std::is_integral_v<typename Index::value_type>
SECCHI_KERNEL Reals lookup(const Table& table, const Index& index) {
    alignas(64) typename Index::value_type i[lane_width];
    alignas(64) double v[lane_width];
    index.copy_to(i, aligned);
    for (int l = 0; l < lane_width; ++l) v[l] = table[static_cast<std::size_t>(i[l])];
    return Reals(v, aligned);
}

/// The same at indices held as doubles (integers).
template <class Table>
SECCHI_KERNEL Reals lookup(const Table& table, const Reals& index) {
    return lookup(table, stdx::static_simd_cast<Ints>(index));
}

/// f (a function of Reals) for each lane of a vector of floats, lane_width lanes at a time in
/// double, the results rounded to float: a double-lane computation serving float lanes.
template <class FloatLanes, class F>
SECCHI_KERNEL FloatLanes through_doubles(const FloatLanes& x, F&& f) {
    constexpr int width = static_cast<int>(FloatLanes::size());
    alignas(64) float out[width];
    for (int g = 0; g < width; g += lane_width) {
        const Reals y = f(Reals([&](int l) { return static_cast<double>(x[g + l]); }));
        for (int l = 0; l < lane_width; ++l) out[g + l] = static_cast<float>(y[l]);
    }
    return FloatLanes(out, aligned);
}

/// Row index[l] of `rows` for every lane l, as eight vectors: column c's holds each lane's
/// element c. One load per lane and a transposition in registers (AVX-512: 8 x 8; AVX2: two
/// 4 x 4 per row half), instead of a gather per column; elsewhere a loop over the lanes.
SECCHI_KERNEL std::array<Reals, 8> lookup_rows(const std::vector<Row8>& rows, const Reals& index) {
    alignas(64) std::int64_t i[lane_width];
    stdx::static_simd_cast<Ints>(index).copy_to(i, aligned);
    const auto row = [&](int l) { return rows[static_cast<std::size_t>(i[l])].v.data(); };
#if defined(__AVX512F__)
    static_assert(lane_width == 8);
    __m512d r[8], t[8], s[8];
    for (int l = 0; l < 8; ++l) r[l] = _mm512_load_pd(row(l));
    for (int l = 0; l < 8; l += 2) {  // t[l]: rows l, l+1 at the even columns; t[l+1]: the odd
        t[l] = _mm512_unpacklo_pd(r[l], r[l + 1]);
        t[l + 1] = _mm512_unpackhi_pd(r[l], r[l + 1]);
    }
    for (int h = 0; h < 2; ++h) {  // 128-bit pairs of rows 0-3 and 4-7: columns {0, 4} and {2, 6} (+h)
        s[h] = _mm512_shuffle_f64x2(t[h], t[2 + h], 0b10001000);
        s[2 + h] = _mm512_shuffle_f64x2(t[h], t[2 + h], 0b11011101);
        s[4 + h] = _mm512_shuffle_f64x2(t[4 + h], t[6 + h], 0b10001000);
        s[6 + h] = _mm512_shuffle_f64x2(t[4 + h], t[6 + h], 0b11011101);
    }
    std::array<Reals, 8> out;
    for (int h = 0; h < 2; ++h) {
        out[0 + h] = Reals(_mm512_shuffle_f64x2(s[h], s[4 + h], 0b10001000));
        out[4 + h] = Reals(_mm512_shuffle_f64x2(s[h], s[4 + h], 0b11011101));
        out[2 + h] = Reals(_mm512_shuffle_f64x2(s[2 + h], s[6 + h], 0b10001000));
        out[6 + h] = Reals(_mm512_shuffle_f64x2(s[2 + h], s[6 + h], 0b11011101));
    }
    return out;
#elif defined(__AVX2__)
    static_assert(lane_width == 4);
    std::array<Reals, 8> out;
    for (int half = 0; half < 8; half += 4) {
        __m256d r[4];
        for (int l = 0; l < 4; ++l) r[l] = _mm256_load_pd(row(l) + half);
        const __m256d t0 = _mm256_unpacklo_pd(r[0], r[1]), t1 = _mm256_unpackhi_pd(r[0], r[1]);
        const __m256d t2 = _mm256_unpacklo_pd(r[2], r[3]), t3 = _mm256_unpackhi_pd(r[2], r[3]);
        out[half + 0] = Reals(_mm256_permute2f128_pd(t0, t2, 0x20));
        out[half + 1] = Reals(_mm256_permute2f128_pd(t1, t3, 0x20));
        out[half + 2] = Reals(_mm256_permute2f128_pd(t0, t2, 0x31));
        out[half + 3] = Reals(_mm256_permute2f128_pd(t1, t3, 0x31));
    }
    return out;
#else
    alignas(64) double v[8][lane_width];
    for (int l = 0; l < lane_width; ++l)
        for (int c = 0; c < 8; ++c) v[c][l] = row(l)[c];
    std::array<Reals, 8> out;
    for (int c = 0; c < 8; ++c) out[c] = Reals(v[c], aligned);
    return out;
#endif
}

// Philox's rounds run in vectors (philox_vector below) where the target has AVX2 or AVX-512;
// elsewhere, as loops of philox_block over the lanes.
#if defined(__AVX512F__) || defined(__AVX2__)
#define SECCHI_PHILOX_VECTOR 1
#else
#define SECCHI_PHILOX_VECTOR 0
#endif

#if SECCHI_PHILOX_VECTOR
/// Philox's rounds run on vectors of lane_width 64-bit elements, one lane each, whose low
/// halves hold the 32-bit words: every multiply of Philox has both factors below 2^32, which
/// is x86's vpmuludq (32 x 32 -> 64 bits per 64-bit element), one instruction. It reads only
/// the low half of each element, so the words are not masked to 32 bits between rounds: an
/// element's low half is the Philox word, its high half junk (mask it to use the word).
/// (AVX-512DQ's 64-bit multiply, vpmullq, is three micro-ops on Intel cores.)
namespace philox_vector {
#if defined(__AVX512F__)
using Vector = __m512i;
SECCHI_KERNEL Vector load(const std::uint64_t* p) { return _mm512_loadu_si512(p); }
SECCHI_KERNEL Vector broadcast(std::uint32_t w) { return _mm512_set1_epi64(static_cast<long long>(w)); }
SECCHI_KERNEL Vector multiply(Vector a, Vector b) { return _mm512_mul_epu32(a, b); }
SECCHI_KERNEL Vector high_half(Vector a) { return _mm512_srli_epi64(a, 32); }
SECCHI_KERNEL Vector xor3(Vector a, Vector b, Vector c) { return _mm512_ternarylogic_epi64(a, b, c, 0x96); }
/// The doubles 2^52 + word: the high halves replaced by 2^52's bits (which also drops the junk).
SECCHI_KERNEL Reals two_52_plus(Vector a) {
    return Reals(_mm512_castsi512_pd(_mm512_mask_blend_epi32(0xAAAA, a, _mm512_set1_epi64(0x4330000000000000ll))));
}
/// The words (low halves), packed as lane_width 32-bit integers.
SECCHI_KERNEL void store_words(Vector a, std::uint32_t* out) {
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm512_cvtepi64_epi32(a));
}
/// uniform_float_from_bits of each word of two groups of lanes, (w >> 8 + 1/2) 2^-24: a's
/// lanes then b's, to `out` (2 lane_width floats, vector-aligned).
SECCHI_KERNEL void store_float_uniforms(Vector a, Vector b, float* out) {
    const __m512i words = _mm512_inserti64x4(_mm512_castsi256_si512(_mm512_cvtepi64_epi32(a)), _mm512_cvtepi64_epi32(b), 1);
    const __m512 top = _mm512_cvtepi32_ps(_mm512_srli_epi32(words, 8));
    _mm512_store_ps(out, _mm512_mul_ps(_mm512_add_ps(top, _mm512_set1_ps(0.5f)), _mm512_set1_ps(0x1p-24f)));
}
#else
using Vector = __m256i;
SECCHI_KERNEL Vector load(const std::uint64_t* p) { return _mm256_loadu_si256(reinterpret_cast<const __m256i*>(p)); }
SECCHI_KERNEL Vector broadcast(std::uint32_t w) { return _mm256_set1_epi64x(static_cast<long long>(w)); }
SECCHI_KERNEL Vector multiply(Vector a, Vector b) { return _mm256_mul_epu32(a, b); }
SECCHI_KERNEL Vector high_half(Vector a) { return _mm256_srli_epi64(a, 32); }
SECCHI_KERNEL Vector xor3(Vector a, Vector b, Vector c) { return _mm256_xor_si256(_mm256_xor_si256(a, b), c); }
SECCHI_KERNEL Reals two_52_plus(Vector a) {
    return Reals(_mm256_castsi256_pd(_mm256_blend_epi32(a, _mm256_set1_epi64x(0x4330000000000000ll), 0b10101010)));
}
SECCHI_KERNEL __m128i low_words(Vector a) {
    return _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(a, _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7)));
}
SECCHI_KERNEL void store_words(Vector a, std::uint32_t* out) {
    _mm_storeu_si128(reinterpret_cast<__m128i*>(out), low_words(a));
}
SECCHI_KERNEL void store_float_uniforms(Vector a, Vector b, float* out) {
    const __m256i words = _mm256_set_m128i(low_words(b), low_words(a));
    const __m256 top = _mm256_cvtepi32_ps(_mm256_srli_epi32(words, 8));
    _mm256_store_ps(out, _mm256_mul_ps(_mm256_add_ps(top, _mm256_set1_ps(0.5f)), _mm256_set1_ps(0x1p-24f)));
}
#endif
static_assert(sizeof(Vector) == lane_width * sizeof(std::uint64_t), "one 64-bit element per lane");
}  // namespace philox_vector
#endif

/// Philox's 64-bit key (two words) and, for the vector rounds, its ten round keys broadcast
/// once (per tracer) rather than in every block's rounds (two instructions each, 40 per block).
struct PhiloxKey {
    explicit PhiloxKey(std::array<std::uint32_t, 2> key) : words(key) {
#if SECCHI_PHILOX_VECTOR
        for (std::uint32_t r = 0; r < 10; ++r) {
            round[r][0] = philox_vector::broadcast(key[0] + r * 0x9E3779B9u);
            round[r][1] = philox_vector::broadcast(key[1] + r * 0xBB67AE85u);
        }
#endif
    }
    std::array<std::uint32_t, 2> words;
#if SECCHI_PHILOX_VECTOR
    philox_vector::Vector round[10][2];
#endif
};

#if SECCHI_PHILOX_VECTOR
/// Philox4x32-10 (philox_block, core/rng.hpp) for lane_width lanes from their 64-bit block
/// and stream numbers: x[k]'s element l holds word k of lane l's block in its low half.
struct PhiloxWords {
    philox_vector::Vector x[4];
};
SECCHI_KERNEL PhiloxWords philox_rounds(const std::uint64_t* block, const std::uint64_t* stream, const PhiloxKey& key) {
    using namespace philox_vector;
    const Vector m0 = broadcast(0xD2511F53u), m1 = broadcast(0xCD9E8D57u);
    const Vector b = load(block), i = load(stream);
    PhiloxWords r{{b, high_half(b), i, high_half(i)}};
    Vector(&x)[4] = r.x;
    for (int round = 0; round < 10; ++round) {
        const Vector p0 = multiply(x[0], m0), p1 = multiply(x[2], m1);
        x[0] = xor3(high_half(p1), x[1], key.round[round][0]);
        x[1] = p1;
        x[2] = xor3(high_half(p0), x[3], key.round[round][1]);
        x[3] = p0;
    }
    return r;
}
#endif

/// One Philox4x32-10 block per lane (philox_block, core/rng.hpp) from 64-bit block and
/// stream numbers, as four uniforms per lane: u[k] in lane l is
/// uniform_from_bits(philox_block(block_l, stream_l, key)[k]) exactly (tests/test_lane_tracer.cpp).
/// With AVX2 or AVX-512 the rounds run in vectors (philox_rounds; LaneTracer 1.18x on a Zen 3
/// with AVX2, docs/design-notes.md), and a word w becomes a double as (2^52 + w) - (2^52 - 1/2)
/// = w + 1/2 exactly (Sterbenz), times 2^-32. Elsewhere a loop of philox_block over the lanes,
/// which GCC vectorises with its 32 x 32 -> 64-bit multiplies (vector rounds are 1.06x slower
/// with SSE2). The lanes' block and stream numbers are read from `block` and `stream`, the
/// uniforms written to u[0..3] (arrays of lane_width doubles, vector-aligned).
inline void philox_uniforms(const std::uint64_t* block, const std::uint64_t* stream, const PhiloxKey& key,
                            double* const (&u)[4]) {
#if SECCHI_PHILOX_VECTOR
    const auto [x] = philox_rounds(block, stream, key);
    for (int w = 0; w < 4; ++w) ((philox_vector::two_52_plus(x[w]) - (0x1p52 - 0.5)) * 0x1p-32).copy_to(u[w], aligned);
#else
    for (int l = 0; l < lane_width; ++l) {
        const auto r = philox_block(block[l], stream[l], key.words);
        for (int k = 0; k < 4; ++k) u[k][l] = uniform_from_bits(r[k]);
    }
#endif
}

/// The same blocks as 32-bit words: bits[k][l] = philox_block(block_l, stream_l, key)[k]
/// (arrays of Width words, Width a multiple of lane_width), for PhotonRng's first block of
/// photons launched in lanes.
template <int Width = lane_width>
inline void philox_words(const std::uint64_t* block, const std::uint64_t* stream, const PhiloxKey& key,
                         std::uint32_t* const (&bits)[4]) {
    static_assert(Width % lane_width == 0);
#if SECCHI_PHILOX_VECTOR
    for (int g = 0; g < Width; g += lane_width) {
        const auto [x] = philox_rounds(block + g, stream + g, key);
        for (int k = 0; k < 4; ++k) philox_vector::store_words(x[k], bits[k] + g);
    }
#else
    for (int l = 0; l < Width; ++l) {
        const auto r = philox_block(block[l], stream[l], key.words);
        for (int k = 0; k < 4; ++k) bits[k][l] = r[k];
    }
#endif
}

/// philox_uniforms for float lanes (width_of<float> of them): u[k] in lane l is
/// uniform_float_from_bits(philox_block(block_l, stream_l, key)[k]) exactly
/// (tests/test_lane_tracer.cpp). With AVX2 or AVX-512, the rounds of two groups of
/// lane_width lanes, their words' top 24 bits made floats in one vector.
inline void philox_uniforms(const std::uint64_t* block, const std::uint64_t* stream, const PhiloxKey& key,
                            float* const (&u)[4]) {
    constexpr int width = width_of<float>;
#if SECCHI_PHILOX_VECTOR
    static_assert(width == 2 * lane_width);
    // Both groups' rounds first (independent chains, side by side), then their words together.
    const auto [a] = philox_rounds(block, stream, key);
    const auto [b] = philox_rounds(block + lane_width, stream + lane_width, key);
    for (int k = 0; k < 4; ++k) philox_vector::store_float_uniforms(a[k], b[k], u[k]);
#else
    for (int l = 0; l < width; ++l) {
        const auto r = philox_block(block[l], stream[l], key.words);
        for (int k = 0; k < 4; ++k) u[k][l] = uniform_float_from_bits(r[k]);
    }
#endif
}

/// ln x for normal x > 0 (the free path -ln u has u in (0, 1)). x = 2^e m with m in
/// [sqrt(1/2), sqrt 2); ln m = 2 atanh f with f = (m - 1)/(m + 1), |f| < 0.172, by its series
/// 2 (f + f^3/3 + ... + f^21/21) (truncation < f^23 ~ 3e-18); ln 2 split in two so that e ln2_hi
/// is exact. Within 2 ulp of std::log (tests/test_lane_tracer.cpp).
SECCHI_KERNEL Reals log(Reals x) {
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

/// ln x for float lanes, normal x > 0: the same reduction as for doubles, with the series to
/// f^9/9 (truncation below 2 f^11/11 < 8e-10, under float's precision).
SECCHI_KERNEL Floats log(Floats x) {
    using Words32 = stdx::rebind_simd_t<std::uint32_t, Floats>;
    using Ints32 = stdx::rebind_simd_t<std::int32_t, Floats>;
    const Words32 bits = stdx::__proposed::simd_bit_cast<Words32>(x);
    constexpr std::uint32_t sqrt_half = 0x3f3504f3u, one = 0x3f800000u;  // float(sqrt(1/2)), 1
    const Words32 shifted = bits + Words32(one - sqrt_half);
    const Ints32 e = stdx::static_simd_cast<Ints32>(shifted >> 23) - Ints32(127);
    const Floats m = stdx::__proposed::simd_bit_cast<Floats>((shifted & Words32(0x007fffffu)) + Words32(sqrt_half));
    const Floats f = (m - 1.0f) / (m + 1.0f), f2 = f * f;
    const Floats series = 2.0f / 3 + f2 * (2.0f / 5 + f2 * (2.0f / 7 + f2 * (2.0f / 9)));
    const Floats ef = stdx::static_simd_cast<Floats>(e);
    constexpr float ln2_hi = 0.693145751953125f, ln2_lo = 1.428606765330187e-06f;  // ln2_hi: 16 bits
    return ef * ln2_hi + (2.0f * f + (f * f2 * series + ef * ln2_lo));
}

/// exp_table (core/math.hpp) per lane, by the same operations: equal to it lane by lane for
/// x in (-708, 709) (tests/test_lane_tracer.cpp); lanes outside that range are the caller's
/// (exp_table's special values). For the transmittances exp(-c t) of many collected photons
/// at once (estimate/path_radiance.hpp).
SECCHI_KERNEL Reals exp(const Reals& x) {
    const Reals kd = detail::round_to_integer(x * detail::exp_inv_ln2_64);
    // kd = k is an integer of magnitude below 2^51, so kd + 1.5 * 2^52 is exact and its bits
    // are those of 1.5 * 2^52 plus k (two's complement): j = k mod 64 and 64 m = k - j there.
    const Words k = stdx::__proposed::simd_bit_cast<Words>(kd + 0x1.8p52) - Words(0x4338000000000000ull);
    const Words two_m = ((k & Words(~63ull)) << 46) + Words(1023ull << 52);  // (m + 1023) << 52: 2^m
    return detail::exp_from_table(x, kd, lookup(detail::exp2_64ths, k & Words(63)),
                                  stdx::__proposed::simd_bit_cast<Reals>(two_m));
}

/// e^x for float lanes (the weights' decay exp(-a s) in LaneTracer's continuous absorption):
/// x = n ln 2 + r with n = round(x / ln 2) and |r| <= ln2/2 (ln 2 split in two as in log, so
/// that n ln2_hi is exact for |n| < 2^8), e^r by its Taylor series to r^7 (truncation below
/// (ln2/2)^8 / 8! < 6e-9, relative), times 2^n made in the exponent bits. 0 below x = -87
/// (where 2^n would leave the normal floats); x above 88 is taken as 88 (e^88 = 1.7e38, the
/// largest power of e below the largest float). Within 4 float ulp of exp in [-87, 88]
/// (tests/test_lane_tracer.cpp). (x is clamped to [-88, 88] before n is made an integer, which
/// must fit in an int.)
SECCHI_KERNEL Floats exp(const Floats& x_in) {
    using Ints32 = stdx::rebind_simd_t<std::int32_t, Floats>;
    const Floats x = stdx::min(stdx::max(x_in, Floats(-88.0f)), Floats(88.0f));
    const Floats n = detail::round_to_integer(x * 1.44269504088896341f);
    constexpr float ln2_hi = 0.693145751953125f, ln2_lo = 1.428606765330187e-06f;
    const Floats r = (x - n * ln2_hi) - n * ln2_lo;
    const Floats series =
        1.0f + r * (1.0f + r * (1.0f / 2 + r * (1.0f / 6 + r * (1.0f / 24 + r * (1.0f / 120 + r * (1.0f / 720 + r * (1.0f / 5040)))))));
    const Ints32 exponent = (stdx::static_simd_cast<Ints32>(n) + Ints32(127)) << 23;
    Floats out = series * stdx::__proposed::simd_bit_cast<Floats>(exponent);
    stdx::where(x_in < -87.0f, out) = 0.0f;
    return out;
}

/// Positions and directions per lane.
using Vec3 = Vec3Of<Reals>;
using Vec3F = Vec3Of<Floats>;

}  // namespace secchi::lanes
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

#endif
