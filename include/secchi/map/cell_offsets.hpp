#pragma once
// The VOI grid's cell index (voi_grid.hpp) in about 1.5 bytes per cell instead of 4: where each
// cell's records begin, i.e. a non-decreasing sequence of 32-bit record indices o[0..n].
//
// The entries come in blocks of 8. Block b keeps o[8b] as a 32-bit base and each of its
// entries as one byte, o[c] - o[8b] (so the block's first byte is 0). A block whose entries
// span more than 255 records is "wide": its first byte is 1, and its base is the block's
// number k in a side table of 32-bit entries, where its 8 entries are wide[8k, 8k + 8). A wide
// block spans at least 256 records, so the side table costs at most 32 / 256 = 0.125 bytes per
// record. In all: 1.5 bytes per entry (rounded up to whole blocks) plus at most 0.125 per
// record; a grid of at most 2 cells per record (VoiGridStore::max_cells_per_record) spends at
// most about 3.1 bytes per record on its index.
//
// Reading an entry is one load of its block's base and one of its byte (the same cache line as
// the block's first byte, its wide flag), or for a wide block one more from the side table.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace secchi::SECCHI_ISA {

class CellOffsets {
public:
    static constexpr std::size_t block = 8;  ///< entries per base

    CellOffsets() = default;

    /// The entries o[0..n] (non-decreasing; input_error otherwise).
    explicit CellOffsets(const std::vector<std::uint32_t>& entries) : size_(entries.size()) {
        const std::size_t blocks = (entries.size() + block - 1) / block;
        base_.resize(blocks);
        bytes_.assign(blocks * block, 0);
        for (std::size_t b = 0; b < blocks; ++b) {
            const std::size_t first = b * block, last = std::min(entries.size(), first + block);
            for (std::size_t c = std::max<std::size_t>(first, 1); c < last; ++c)
                require(entries[c] >= entries[c - 1], "cell offset", c, "must not be below the previous cell's");
            if (entries[last - 1] - entries[first] <= max_delta) {
                base_[b] = entries[first];
                for (std::size_t c = first; c < last; ++c) bytes_[c] = static_cast<std::uint8_t>(entries[c] - entries[first]);
            } else {
                base_[b] = static_cast<std::uint32_t>(wide_.size() / block);
                bytes_[first] = wide_flag;
                wide_.insert(wide_.end(), entries.begin() + static_cast<std::ptrdiff_t>(first),
                             entries.begin() + static_cast<std::ptrdiff_t>(last));
                wide_.resize(wide_.size() + block - (last - first), entries[last - 1]);
            }
        }
        wide_.shrink_to_fit();
    }

    /// Entry c (c < size()).
    [[nodiscard]] std::uint32_t operator[](std::size_t c) const {
        const std::size_t b = c / block;
        if (bytes_[b * block] == wide_flag) [[unlikely]]
            return wide_[std::size_t{base_[b]} * block + c % block];
        return base_[b] + bytes_[c];
    }

    [[nodiscard]] std::size_t size() const { return size_; }
    [[nodiscard]] std::size_t memory_bytes() const {
        return bytes_.capacity() + base_.capacity() * sizeof(std::uint32_t) + wide_.capacity() * sizeof(std::uint32_t);
    }
    /// Blocks kept in the side table (their entries span more than 255 records).
    [[nodiscard]] std::size_t wide_blocks() const { return wide_.size() / block; }

private:
    static constexpr std::uint32_t max_delta = 255;
    static constexpr std::uint8_t wide_flag = 1;  ///< a block's first byte when it is wide (else 0)

    std::size_t size_ = 0;
    std::vector<std::uint32_t> base_;   ///< per block: o[8b], or its number in wide_
    std::vector<std::uint8_t> bytes_;   ///< per entry: o[c] - o[8b] (a wide block: wide_flag, then unused)
    std::vector<std::uint32_t> wide_;   ///< the entries of the wide blocks, 8 per block
};

}  // namespace secchi
