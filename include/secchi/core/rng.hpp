#pragma once
// Counter-based random numbers: Philox4x32-10 (Salmon et al. 2011, "Parallel random numbers:
// as easy as 1, 2, 3", SC'11). One independent stream per photon, keyed by (seed, photon
// index), so a photon's history does not depend on which thread traced it: results are
// bit-identical for any thread count.
#include "secchi/core/config.hpp"
#include <array>
#include <cstdint>

namespace secchi::SECCHI_ISA {

/// One Philox4x32-10 block: ten rounds of the bijection on the 128-bit counter `x` under the
/// 64-bit key `k` (Salmon et al. 2011, section 3.3). Branch-free, so a loop over photons in
/// lanes (transport/lane_tracer.hpp) vectorises.
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline std::array<std::uint32_t, 4> philox4x32_10(std::array<std::uint32_t, 4> x, std::array<std::uint32_t, 2> k) {
    constexpr std::uint32_t M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
    constexpr std::uint32_t W0 = 0x9E3779B9u, W1 = 0xBB67AE85u;
    for (int round = 0; round < 10; ++round) {
        const std::uint64_t p0 = static_cast<std::uint64_t>(M0) * x[0];
        const std::uint64_t p1 = static_cast<std::uint64_t>(M1) * x[2];
        x = {static_cast<std::uint32_t>(p1 >> 32) ^ x[1] ^ k[0], static_cast<std::uint32_t>(p1),
             static_cast<std::uint32_t>(p0 >> 32) ^ x[3] ^ k[1], static_cast<std::uint32_t>(p0)};
        k[0] += W0;
        k[1] += W1;
    }
    return x;
}

/// Block `block` of stream `stream` under `key`: Philox on the counter (block lo, block hi,
/// stream lo, stream hi), as PhotonRng lays it out.
#if defined(__GNUC__)
__attribute__((always_inline))
#endif
inline std::array<std::uint32_t, 4> philox_block(std::uint64_t block, std::uint64_t stream,
                                                 std::array<std::uint32_t, 2> key) {
    return philox4x32_10({static_cast<std::uint32_t>(block), static_cast<std::uint32_t>(block >> 32),
                          static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)},
                         key);
}

/// A 32-bit random word as a uniform double in the open interval (0, 1).
inline double uniform_from_bits(std::uint32_t bits) { return (static_cast<double>(bits) + 0.5) * 0x1p-32; }

/// A 32-bit random word as a uniform float in (0, 1], from its top 24 bits (a float's
/// precision): (w / 2^8 + 1/2) 2^-24, exact below 1/2; above, the half rounds to an even
/// integer of the top bits, and the top word gives 1 exactly (once in 2^24 draws: a free path
/// -ln u of 0, an angle at the end of its range, never a division by zero). For photons in
/// float lanes.
inline float uniform_float_from_bits(std::uint32_t bits) {
    return (static_cast<float>(bits >> 8) + 0.5f) * 0x1p-24f;
}

class PhotonRng {
public:
    /// Stream `stream` (e.g. the photon index) of the generator seeded with `seed`, from its
    /// block `block` on (the first block by default). A stream is the sequence of Philox
    /// blocks with counter (block, stream); a draw never reuses a block.
    PhotonRng(std::uint64_t seed, std::uint64_t stream, std::uint64_t block = 0)
        : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
          ctr_{static_cast<std::uint32_t>(block), static_cast<std::uint32_t>(block >> 32),
               static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)} {}

    /// The same generator when its block `block` has already been computed elsewhere
    /// (`bits` = that block's Philox output, e.g. for many streams at once in SIMD lanes): the
    /// next draws take `bits` first, then block + 1 on.
    PhotonRng(std::uint64_t seed, std::uint64_t stream, std::uint64_t block, const std::array<std::uint32_t, 4>& bits)
        : PhotonRng(seed, stream, block + 1) {
        buf_ = bits;
        next_ = 0;
    }

    /// The first block not yet drawn from: where another generator on this stream may go on
    /// (the unused draws of the current block are skipped).
    [[nodiscard]] std::uint64_t next_block() const { return ctr_[0] | (static_cast<std::uint64_t>(ctr_[1]) << 32); }

    /// Uniform double in the open interval (0, 1) (never 0, so -log(u) is finite). Inlined
    /// into the transport loop, with the block computation (once per 4 draws) out of line.
#if defined(__GNUC__)
    __attribute__((always_inline))
#endif
    double uniform() {
        if (next_ == 4) [[unlikely]] refill();
        return uniform_from_bits(buf_[next_++]);
    }

    /// Raw 32 random bits.
    std::uint32_t bits() {
        if (next_ == 4) refill();
        return buf_[next_++];
    }

private:
#if defined(__GNUC__)
    __attribute__((noinline))
#endif
    void refill() {
        buf_ = philox4x32_10(ctr_, key_);
        next_ = 0;
        if (++ctr_[0] == 0) ++ctr_[1];  // 64-bit draw counter per stream
    }

    std::array<std::uint32_t, 2> key_;
    std::array<std::uint32_t, 4> ctr_;
    std::array<std::uint32_t, 4> buf_{};
    int next_ = 4;
};

}  // namespace secchi
