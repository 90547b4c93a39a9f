#pragma once
// The first pass's work units and where their records go. Photons are traced in fixed
// blocks (any thread may take any block); each block writes its records into chunks of fixed
// size, and the blocks' records are appended to the photon map in block order as soon as
// every earlier block is done. The map is therefore the same for any thread count, and a
// block's chunks go back to a pool for the next blocks as soon as its records are copied:
// the records are written into warm memory, and the map is built while tracing instead of
// after it (peak memory about one map, not two).
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/spectral.hpp"
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <utility>
#include <vector>
#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace secchi::SECCHI_ISA::detail {

/// Asks the kernel to back the whole 2 MiB pages inside [p, p + bytes) with transparent huge
/// pages where it does so on request (Linux's "madvise" mode): the first touch of fresh map
/// memory then faults once per 2 MiB instead of once per 4 KiB. A hint: the memory and its
/// contents are unchanged, and elsewhere, or if the kernel declines, nothing happens.
inline void advise_huge_pages([[maybe_unused]] void* p, [[maybe_unused]] std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    constexpr std::uintptr_t huge = std::uintptr_t{1} << 21;
    const auto first = reinterpret_cast<std::uintptr_t>(p);
    const std::uintptr_t begin = (first + huge - 1) & ~(huge - 1), end = (first + bytes) & ~(huge - 1);
    if (end > begin) madvise(reinterpret_cast<void*>(begin), end - begin, MADV_HUGEPAGE);
#endif
}

/// One work unit: photons [begin, end) all of one batch.
struct Block {
    std::uint64_t begin, end;
    unsigned batch;
};

inline std::vector<Block> make_blocks(std::uint64_t photons, unsigned batches, std::uint64_t block_size) {
    std::vector<Block> blocks;
    for (unsigned b = 0; b < batches; ++b) {
        // photons * b / batches without overflow: photons = q batches + r.
        const std::uint64_t q = photons / batches, r = photons % batches;
        const std::uint64_t lo = q * b + r * b / batches, hi = q * (b + 1) + r * (b + 1) / batches;
        for (std::uint64_t s = lo; s < hi; s += block_size) blocks.push_back({s, std::min(hi, s + block_size), b});
    }
    return blocks;
}

/// Record chunks (64 kB each) handed back once their records are in the map, for the
/// blocks traced next. Shared by the workers of one run: one lock per chunk taken or given.
/// A chunk is a vector of per_chunk records (its slots, written over from the start each time
/// it is used), so that a block can write a lane group's records into it before knowing how
/// many it keeps (RecordChunks::room).
template <class Record>
class ChunkPool {
public:
    static constexpr std::size_t per_chunk = std::max<std::size_t>(1, 65536 / sizeof(Record));

    /// A new chunk of per_chunk slots, filled with a record made by the record's own make()
    /// (a PhotonRecord need not be default-constructible).
    static std::vector<Record> fresh() {
        return std::vector<Record>(per_chunk, Record::make(vec3(0.0), vec3(0.0, 0.0, 1.0), band_index{0}, 0));
    }
    /// A chunk of per_chunk slots: one given back, else a fresh one.
    std::vector<Record> take() {
        {
            std::lock_guard lock(mutex_);
            if (!free_.empty()) {
                std::vector<Record> chunk = std::move(free_.back());
                free_.pop_back();
                return chunk;
            }
        }
        return fresh();
    }
    void give(std::vector<Record>&& chunk) {
        std::lock_guard lock(mutex_);
        free_.push_back(std::move(chunk));
    }
    /// Chunks waiting to be taken again.
    [[nodiscard]] std::size_t idle() {
        std::lock_guard lock(mutex_);
        return free_.size();
    }

private:
    std::mutex mutex_;
    std::vector<std::vector<Record>> free_;
};

/// A block's records in chunks of fixed capacity: appending never moves stored records, as
/// one growing vector would (copying each about once more, into fresh pages). Chunks come
/// from the pool if there is one, else from the heap. The last chunk is written through a
/// cursor; the chunks before it are full up to their counts in used_.
template <class Record>
class RecordChunks {
public:
    RecordChunks() = default;
    explicit RecordChunks(ChunkPool<Record>* pool) : pool_(pool) {}
    // Moved, the chunks keep their memory, so the cursor stays valid; the source is left empty.
    RecordChunks(RecordChunks&& o) noexcept
        : pool_(o.pool_), chunks_(std::move(o.chunks_)), used_(std::move(o.used_)),
          cursor_(std::exchange(o.cursor_, nullptr)), end_(std::exchange(o.end_, nullptr)) {}
    RecordChunks& operator=(RecordChunks&& o) noexcept {
        pool_ = o.pool_;
        chunks_ = std::move(o.chunks_);
        used_ = std::move(o.used_);
        cursor_ = std::exchange(o.cursor_, nullptr);
        end_ = std::exchange(o.end_, nullptr);
        return *this;
    }
    RecordChunks(const RecordChunks&) = delete;
    RecordChunks& operator=(const RecordChunks&) = delete;

    void push_back(const Record& r) {
        *room(1) = r;
        commit(1);
    }
    /// Room for n <= per_chunk records after the last: write them there, then commit() those
    /// kept (photons in lanes write every lane's record and keep some; transport/lane_tracer.hpp).
    [[nodiscard]] Record* room(std::size_t n) {
        if (static_cast<std::size_t>(end_ - cursor_) < n) [[unlikely]] next_chunk();
        return cursor_;
    }
    /// Keeps the first n records written at room().
    void commit(std::size_t n) { cursor_ += n; }

    [[nodiscard]] std::size_t size() const {
        std::size_t n = chunks_.empty() ? 0 : last_used();
        for (std::size_t used : used_) n += used;
        return n;
    }
    /// Appends the records to `out` in order and gives the chunks back (to the pool, or frees them).
    void move_to(std::vector<Record>& out) {
        if (!chunks_.empty()) used_.push_back(last_used());
        for (std::size_t i = 0; i < chunks_.size(); ++i) {
            const auto first = chunks_[i].begin();
            out.insert(out.end(), first, first + static_cast<std::ptrdiff_t>(used_[i]));
            if (pool_) pool_->give(std::move(chunks_[i]));
        }
        std::vector<std::vector<Record>>().swap(chunks_);
        std::vector<std::size_t>().swap(used_);
        cursor_ = end_ = nullptr;
    }

private:
    [[nodiscard]] std::size_t last_used() const { return static_cast<std::size_t>(cursor_ - chunks_.back().data()); }
    void next_chunk() {
        if (!chunks_.empty()) used_.push_back(last_used());
        chunks_.push_back(pool_ ? pool_->take() : ChunkPool<Record>::fresh());
        cursor_ = chunks_.back().data();
        end_ = cursor_ + chunks_.back().size();
    }

    ChunkPool<Record>* pool_ = nullptr;
    std::vector<std::vector<Record>> chunks_;
    std::vector<std::size_t> used_;  ///< records kept in each chunk before the last
    Record* cursor_ = nullptr;       ///< the last chunk's next free slot
    Record* end_ = nullptr;          ///< and its end
};

/// The photon map, built in block order while blocks finish in any order: `finished(i)`
/// (any thread) appends block i's records and every later finished block's that now follows
/// a complete prefix. The map's capacity is set from the records per map photon of the
/// blocks appended so far, with 1/8 to spare (untouched, so not resident), so it is rarely
/// copied to grow.
template <class Record>
class OrderedRecords {
public:
    /// `storage`: where the records go (cleared; its capacity is kept).
    /// `blocks`: every block of the run, or a contiguous part of them (a process's share of a
    /// first pass split among processes); the capacity heuristic counts only their map photons.
    OrderedRecords(const std::vector<Block>& blocks, std::uint64_t map_photons, std::vector<Record> storage = {})
        : blocks_(blocks), map_photons_(map_photons), done_(blocks.size(), false), records_(std::move(storage)) {
        records_.clear();
        for (const Block& b : blocks_) map_photons_here_ += std::min(b.end, map_photons_) - std::min(b.begin, map_photons_);
    }

    template <class Results>
    void finished(std::size_t i, Results& results) {
        std::lock_guard lock(mutex_);
        done_[i] = true;
        for (; next_ < done_.size() && done_[next_]; ++next_) append(blocks_[next_], results[next_].records);
    }

    /// The map, once every block has finished.
    std::vector<Record> take() { return std::move(records_); }

private:
    void append(const Block& b, RecordChunks<Record>& chunks) {
        const std::size_t needed = records_.size() + chunks.size();
        map_photons_done_ += std::min(b.end, map_photons_) - std::min(b.begin, map_photons_);
        if (needed > records_.capacity()) {
            const double done = static_cast<double>(std::max<std::uint64_t>(map_photons_done_, 1));
            const double per_photon = static_cast<double>(needed) / done;
            const auto expected = static_cast<std::size_t>(1.125 * per_photon * static_cast<double>(map_photons_here_));
            records_.reserve(std::max(needed, expected));
            advise_huge_pages(records_.data() + records_.size(), (records_.capacity() - records_.size()) * sizeof(Record));
        }
        chunks.move_to(records_);
    }

    const std::vector<Block>& blocks_;
    std::uint64_t map_photons_, map_photons_here_ = 0, map_photons_done_ = 0;
    std::vector<bool> done_;
    std::size_t next_ = 0;
    std::vector<Record> records_;
    std::mutex mutex_;
};

}  // namespace secchi::detail
