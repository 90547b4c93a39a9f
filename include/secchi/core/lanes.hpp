#pragma once
// Photons in lanes: `lane_width` photons at once as SIMD vectors of doubles
// (std::experimental::simd, the Parallelism TS 2; GCC >= 11 and libstdc++), for LaneTracer
// (transport/lane_tracer.hpp). The types, and what only the lanes need: a logarithm for the
// free path -ln u (manual eq. 3.17), table lookups per lane and masks as bits. sin_cos and
// rotate_direction are math.hpp's, written once for doubles and vectors. Also exp, for the
// transmittances of many collected photons at once (estimate/path_radiance.hpp).
//
// The lanes are the target's native vector of doubles (2 with SSE2, 4 with AVX2, 8 with
// AVX-512), or of floats (twice as many: LaneTracer's float lanes): a portable build gains
// little from them; one for AVX2 or better does (docs/design-notes.md). A photon's history does not
// depend on the lane count (each photon draws from its own random stream); the order of the
// stored records and the rounding of the tallies' sums do.
//
// Where <experimental/simd> is absent (or SECCHI_DISABLE_LANES is defined, to build and test
// that case anywhere), SECCHI_HAS_LANES stays undefined and everything runs one photon at a
// time: LaneTracer is not declared, and the estimators' SIMD loops take their scalar forms.
#if __has_include(<experimental/simd>) && !defined(SECCHI_DISABLE_LANES)
// GCC 12's AVX-512 intrinsics (included through <experimental/simd>) warn about their own
// deliberately undefined vectors (GCC bug 105593, fixed in GCC 13); the warnings point into
// those headers, so they are silenced where the headers are read.
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

/// Philox's 64-bit key (two words) and, for the AVX2 rounds, its ten round keys broadcast
/// once (per tracer) rather than in every block's rounds (two instructions each, 40 per block).
struct PhiloxKey {
    explicit PhiloxKey(std::array<std::uint32_t, 2> key) : words(key) {
#if defined(__AVX2__) && !defined(__AVX512DQ__)
        for (int r = 0; r < 10; ++r) {
            round[r][0] = _mm256_set1_epi64x(static_cast<std::uint32_t>(key[0] + r * 0x9E3779B9u));
            round[r][1] = _mm256_set1_epi64x(static_cast<std::uint32_t>(key[1] + r * 0xBB67AE85u));
        }
#endif
    }
    std::array<std::uint32_t, 2> words;
#if defined(__AVX2__) && !defined(__AVX512DQ__)
    __m256i round[10][2];
#endif
};

#if defined(__AVX512DQ__)
/// Philox4x32-10 (philox_block, core/rng.hpp) for every lane, on vectors of 64-bit words each
/// holding a 32-bit word: AVX-512DQ has the 64-bit multiply per lane.
struct PhiloxWords {
    Words x[4];
};
SECCHI_KERNEL PhiloxWords philox_rounds(const std::uint64_t* block, const std::uint64_t* stream,
                                        const PhiloxKey& philox_key) {
    std::array<std::uint32_t, 2> key = philox_key.words;
    const Words lo32(0xffffffffull), b(block, stdx::element_aligned), i(stream, stdx::element_aligned);
    PhiloxWords r{{b & lo32, b >> 32, i & lo32, i >> 32}};
    Words(&x)[4] = r.x;
    for (int round = 0; round < 10; ++round) {
        const Words p0 = x[0] * Words(0xD2511F53ull), p1 = x[2] * Words(0xCD9E8D57ull);
        x[0] = (p1 >> 32) ^ x[1] ^ Words(key[0]);
        x[1] = p1 & lo32;
        x[2] = (p0 >> 32) ^ x[3] ^ Words(key[1]);
        x[3] = p0 & lo32;
        key[0] += 0x9E3779B9u;
        key[1] += 0xBB67AE85u;
    }
    return r;
}
#elif defined(__AVX2__)
/// The same rounds for four lanes per 256-bit vector: every multiply has both factors below
/// 2^32, which is AVX2's vpmuludq (32 x 32 -> 64 bits per 64-bit lane), one instruction. It
/// reads only the low half of each 64-bit lane, so the words are not masked to 32 bits between
/// rounds: a lane's low half is the Philox word, its high half junk (mask it to use the word).
struct PhiloxWords4 {
    __m256i x[4];
};
SECCHI_KERNEL PhiloxWords4 philox_rounds4(const std::uint64_t* block, const std::uint64_t* stream,
                                          const PhiloxKey& key) {
    const __m256i m0 = _mm256_set1_epi64x(0xD2511F53ll), m1 = _mm256_set1_epi64x(0xCD9E8D57ll);
    const __m256i b = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(block));
    const __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(stream));
    PhiloxWords4 r{{b, _mm256_srli_epi64(b, 32), i, _mm256_srli_epi64(i, 32)}};
    __m256i(&x)[4] = r.x;
    for (int round = 0; round < 10; ++round) {
        const __m256i p0 = _mm256_mul_epu32(x[0], m0), p1 = _mm256_mul_epu32(x[2], m1);
        x[0] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p1, 32), x[1]), key.round[round][0]);
        x[1] = p1;
        x[2] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p0, 32), x[3]), key.round[round][1]);
        x[3] = p0;
    }
    return r;
}
#endif

/// One Philox4x32-10 block per lane (philox_block, core/rng.hpp) from 64-bit block and
/// stream numbers, as four uniforms per lane: u[k] in lane l is
/// uniform_from_bits(philox_block(block_l, stream_l, key)[k]) exactly (tests/test_lane_tracer.cpp).
/// With AVX-512DQ (a 64-bit multiply per lane) the rounds run on vectors of 64-bit words,
/// each holding a 32-bit word, and a word becomes a double as (2^52 + word) - 2^52 (1.10x
/// LaneTracer's speed). With AVX2 the same rounds run on 256-bit vectors with vpmuludq, the
/// 32 x 32 -> 64-bit multiply, as the one multiply each needs: LaneTracer 1.18x on a Zen 3
/// (docs/design-notes.md); written through std::experimental::simd, GCC makes each a 64-bit
/// multiply of three instructions, and such rounds are 1.08x slower than the loop below.
/// Elsewhere a loop of philox_block over the lanes, which GCC vectorises with its
/// 32 x 32 -> 64-bit multiplies (vector rounds are 1.06x slower with SSE2).
/// The lanes' block and stream numbers are read from `block` and `stream`, the uniforms
/// written to u[0..3] (arrays of lane_width doubles, vector-aligned).
inline void philox_uniforms(const std::uint64_t* block, const std::uint64_t* stream, const PhiloxKey& key,
                            double* const (&u)[4]) {
#if defined(__AVX512DQ__)
    const auto [x] = philox_rounds(block, stream, key);
    for (int k = 0; k < 4; ++k) {
        const Reals word = stdx::__proposed::simd_bit_cast<Reals>(x[k] | Words(0x4330000000000000ull)) - 0x1p52;
        ((word + 0.5) * 0x1p-32).copy_to(u[k], aligned);
    }
#elif defined(__AVX2__)
    static_assert(lane_width % 4 == 0, "with AVX2 the lanes are 4 doubles (or 8, AVX-512F without DQ)");
    // A word w becomes 2^52 + w by taking the high half from 2^52's bits (a blend, which also
    // drops the junk), then (2^52 + w) - (2^52 - 1/2) = w + 1/2 exactly (Sterbenz), times 2^-32.
    const __m256i exponent = _mm256_set1_epi64x(0x4330000000000000ll);
    for (int g = 0; g < lane_width; g += 4) {
        const auto [x] = philox_rounds4(block + g, stream + g, key);
        for (int w = 0; w < 4; ++w) {
            const __m256d shifted = _mm256_castsi256_pd(_mm256_blend_epi32(x[w], exponent, 0b10101010));
            _mm256_store_pd(u[w] + g, _mm256_mul_pd(_mm256_sub_pd(shifted, _mm256_set1_pd(0x1p52 - 0.5)),
                                                    _mm256_set1_pd(0x1p-32)));
        }
    }
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
#if defined(__AVX512DQ__)
    using Words32 = stdx::rebind_simd_t<std::uint32_t, Reals>;
    for (int g = 0; g < Width; g += lane_width) {
        const auto [x] = philox_rounds(block + g, stream + g, key);
        for (int k = 0; k < 4; ++k) stdx::static_simd_cast<Words32>(x[k]).copy_to(bits[k] + g, stdx::element_aligned);
    }
#elif defined(__AVX2__)
    const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    for (int g = 0; g < Width; g += 4) {
        const auto [x] = philox_rounds4(block + g, stream + g, key);
        for (int k = 0; k < 4; ++k)
            _mm_storeu_si128(reinterpret_cast<__m128i*>(bits[k] + g),
                             _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(x[k], low_halves)));
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
/// (tests/test_lane_tracer.cpp). With AVX2, the rounds of two groups of four lanes (as for
/// doubles), their words packed into one vector of eight and made floats there.
inline void philox_uniforms(const std::uint64_t* block, const std::uint64_t* stream, const PhiloxKey& key,
                            float* const (&u)[4]) {
    constexpr int width = width_of<float>;
#if defined(__AVX512DQ__)
    // The 64-bit rounds of lane_width lanes at a time, their words' top 24 bits made floats.
    using Words32 = stdx::rebind_simd_t<std::uint32_t, Reals>;
    using Floats32 = stdx::rebind_simd_t<float, Reals>;
    for (int g = 0; g < width; g += lane_width) {
        const auto [x] = philox_rounds(block + g, stream + g, key);
        for (int k = 0; k < 4; ++k) {
            const Floats32 top = stdx::static_simd_cast<Floats32>(stdx::static_simd_cast<Words32>(x[k]) >> 8);
            ((top + 0.5f) * 0x1p-24f).copy_to(u[k] + g, stdx::element_aligned);
        }
    }
#elif defined(__AVX2__)
    static_assert(width % 8 == 0);
    const __m256i low_halves = _mm256_setr_epi32(0, 2, 4, 6, 1, 3, 5, 7);
    for (int g = 0; g < width; g += 8) {
        const auto [a] = philox_rounds4(block + g, stream + g, key);
        const auto [b] = philox_rounds4(block + g + 4, stream + g + 4, key);
        for (int w = 0; w < 4; ++w) {
            // Lanes g..g+3 from a's low halves, g+4..g+7 from b's; (w >> 8) + 1/2, times 2^-24.
            const __m256i words = _mm256_permute2x128_si256(_mm256_permutevar8x32_epi32(a[w], low_halves),
                                                            _mm256_permutevar8x32_epi32(b[w], low_halves), 0x20);
            const __m256 top = _mm256_cvtepi32_ps(_mm256_srli_epi32(words, 8));
            _mm256_store_ps(u[w] + g, _mm256_mul_ps(_mm256_add_ps(top, _mm256_set1_ps(0.5f)), _mm256_set1_ps(0x1p-24f)));
        }
    }
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

/// Positions and directions per lane.
using Vec3 = Vec3Of<Reals>;
using Vec3F = Vec3Of<Floats>;

}  // namespace secchi::lanes

#endif
