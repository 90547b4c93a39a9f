#pragma once
// Counter-based random numbers: Philox4x32-10 (Salmon et al. 2011, "Parallel random numbers:
// as easy as 1, 2, 3", SC'11). One independent stream per photon, keyed by (seed, photon
// index), so a photon's history does not depend on which thread traced it: results are
// bit-identical for any thread count.
#include <array>
#include <cstdint>

namespace secchi {

class PhotonRng {
public:
    /// Stream `stream` (e.g. the photon index) of the generator seeded with `seed`.
    PhotonRng(std::uint64_t seed, std::uint64_t stream)
        : key_{static_cast<std::uint32_t>(seed), static_cast<std::uint32_t>(seed >> 32)},
          ctr_{0u, 0u, static_cast<std::uint32_t>(stream), static_cast<std::uint32_t>(stream >> 32)} {}

    /// Uniform double in the open interval (0, 1) (never 0, so -log(u) is finite). Inlined
    /// into the transport loop, with the block computation (once per 4 draws) out of line.
#if defined(__GNUC__)
    __attribute__((always_inline))
#endif
    double uniform() {
        if (next_ == 4) [[unlikely]] refill();
        return (static_cast<double>(buf_[next_++]) + 0.5) * 0x1p-32;
    }

    /// Raw 32 random bits.
    std::uint32_t bits() {
        if (next_ == 4) refill();
        return buf_[next_++];
    }

private:
    static constexpr std::uint32_t M0 = 0xD2511F53u, M1 = 0xCD9E8D57u;
    static constexpr std::uint32_t W0 = 0x9E3779B9u, W1 = 0xBB67AE85u;

#if defined(__GNUC__)
    __attribute__((noinline))
#endif
    void refill() {
        std::array<std::uint32_t, 4> x = ctr_;
        std::array<std::uint32_t, 2> k = key_;
        for (int round = 0; round < 10; ++round) {
            const std::uint64_t p0 = static_cast<std::uint64_t>(M0) * x[0];
            const std::uint64_t p1 = static_cast<std::uint64_t>(M1) * x[2];
            x = {static_cast<std::uint32_t>(p1 >> 32) ^ x[1] ^ k[0], static_cast<std::uint32_t>(p1),
                 static_cast<std::uint32_t>(p0 >> 32) ^ x[3] ^ k[1], static_cast<std::uint32_t>(p0)};
            k[0] += W0;
            k[1] += W1;
        }
        buf_ = x;
        next_ = 0;
        if (++ctr_[0] == 0) ++ctr_[1];  // 64-bit draw counter per stream
    }

    std::array<std::uint32_t, 2> key_;
    std::array<std::uint32_t, 4> ctr_;
    std::array<std::uint32_t, 4> buf_{};
    int next_ = 4;
};

}  // namespace secchi
