#pragma once
// The leaf scan of the VOI stores (voi_octree.hpp, voi_grid.hpp): the records of a list of
// contiguous ranges that lie in the flat-capped cylinder of radius r around a ray segment
// (in_cylinder, store.hpp), reported in order, with in_cylinder's t and distance2 exactly.
// A store's walk queues the ranges to scan (or, when a whole range lies inside the
// cylinder, to report without testing: "bulk accept"); stream() then goes through the list,
// prefetching the records a steady prefetch_lead bytes ahead of the scan (through the ends
// of ranges into the next ones), and tests each scanned range in chunks without a branch per
// record: map/cylinder_scan.hpp's SIMD kernel where the target has AVX2 and FMA or AVX-512
// (CompactRecord, or packed records' 64-bit words read in place), else loops the compiler
// vectorises (measure()).
// The lead: the grid's column ranges (vertical rays: ~21 ranges of ~750 records per ray) are
// longer than what the processor's own prefetchers fetch ahead, so the scan is bound by
// memory latency (most of the kernel's cycles go to its loads) unless the hints run ahead of
// it. A steady lead of 4 KiB gives the grid's estimate 1.23-1.33 times the rays/s of hinting
// only the first 4 KiB of the next range (leads of 1-16 KiB alike within the noise) and leaves
// the octree's (leaves of <= 128 records) unchanged within the noise (Zen 5;
// docs/design-notes.md). The octree's tuning: voi_octree.hpp.
#include "secchi/core/config.hpp"
#include "secchi/map/cylinder_scan.hpp"
#include "secchi/map/packed_records.hpp"
#include "secchi/map/store.hpp"
#include <algorithm>
#include <array>
#include <bit>
#include <concepts>
#include <cstdint>
#include <type_traits>
#include <vector>

namespace secchi::SECCHI_ISA::detail {

/// A record whose position() is its three float members x, y, z (CompactRecord): a leaf scan
/// copies them as floats (exact in double), a plain strided load the compiler vectorises.
template <class R>
concept FloatPositionRecord = requires(const R r) {
    requires std::same_as<decltype(r.x), float>;
    requires std::same_as<decltype(r.y), float>;
    requires std::same_as<decltype(r.z), float>;
};

/// The cylinder scan over ranges of `records` (a view for one query: it keeps a reference):
/// a std::vector of records, or PackedRecords (packed_records.hpp), whose 64-bit position
/// words the scan reads in place, frame by frame (cylinder_scan.hpp's CodedPositions).
template <class Records>
class CylinderRanges {
public:
    static constexpr bool packed = std::same_as<Records, PackedRecords>;
    using Record = typename Records::value_type;

    explicit CylinderRanges(const Records& records) : records_(records) {}

    /// Record ranges queued by a store's walk: scan with the cylinder test, or report whole.
    struct WorkList {
        struct Range {
            std::uint32_t begin, end;
            bool whole;
        };
        static constexpr std::size_t capacity = 64;
        std::array<Range, capacity> items;
        std::size_t size = 0;
    };

    /// Reports the hits of the queued ranges in order, prefetching prefetch_lead bytes ahead: a bulk
    /// range all its records, a scanned range (a leaf) those filter() accepts, in chunks of at
    /// most Chunk::capacity records (to a ChunkCollector as one run of hits per chunk).
    template <Collector C>
    bool stream(const WorkList& work, const Ray& ray, double r2, C& collect) const {
        Prefetcher ahead(work, streams());
        ahead.advance(prefetch_lead / stride);
        Hit hit{};
        for (std::size_t w = 0; w < work.size; ++w) {
            const auto& range = work.items[w];
            // hinted whole (by chunks: 0.94-0.98 times the octree's rays/s); packed records go
            // through the scan instead, which accepts every one of them (the interior test's
            // margin, search_support.hpp, is far beyond rounding) and reads them in place
            if constexpr (!packed) {
                if (range.whole) {
                    ahead.advance(range.end - range.begin);
                    if (!report_all(ray, range.begin, range.end, collect)) return false;
                    continue;
                }
            }
            for (std::uint32_t begin = range.begin; begin < range.end; begin += Chunk::capacity) {
                const std::uint32_t end = std::min<std::uint32_t>(range.end, begin + Chunk::capacity);
                ahead.advance(end - begin);
                Chunk chunk;
                const std::uint32_t n = filter_chunk(begin, end, ray, r2, chunk);
                if constexpr (ChunkCollector<C>) {
                    if (!collect.hits(begin, chunk.accepted.data(), chunk.t.data(), chunk.distance2.data(), n)) return false;
                } else {
                    for (std::uint32_t k = 0; k < n; ++k) {
                        hit.index = begin + chunk.accepted[k];
                        hit.t = chunk.t[k];
                        hit.distance2 = chunk.distance2[k];
                        if (!collect(hit)) return false;
                    }
                }
            }
        }
        return true;
    }

    /// How far ahead of the scan the records are prefetched (bytes of what the scan reads:
    /// records, or packed records' 64-bit words; across ranges).
    static constexpr std::size_t prefetch_lead = 4096;

private:
    /// What one record occupies where the scan reads it: the record, or its 64-bit position word.
    static constexpr std::size_t stride = packed ? sizeof(std::uint64_t) : sizeof(Record);

    /// An array the prefetcher hints: record i's bytes start at base + i stride.
    struct Stream {
        const std::byte* base;
        std::size_t stride;
    };
    /// The records; packed, their position words and, for the collector, their other bytes.
    using Streams = std::array<Stream, packed ? 2 : 1>;
    [[nodiscard]] Streams streams() const {
        if constexpr (packed)
            return {Stream{reinterpret_cast<const std::byte*>(records_.codes()), stride},
                    Stream{records_.attribute_bytes(), PackedRecords::attribute_stride}};
        else
            return {Stream{reinterpret_cast<const std::byte*>(records_.data()), stride}};
    }

    /// Hints the cache to fetch the queued ranges' records in scan order (each stream's
    /// bytes of them), a given number of records at a time: the scan calls advance(n) as it
    /// starts on n records, so the hints run prefetch_lead / stride records ahead of it,
    /// through range ends into the next ranges.
    class Prefetcher {
    public:
        Prefetcher(const WorkList& work, const Streams& streams) : work_(work), streams_(streams) {}
        void advance(std::uint32_t amount) {
#if defined(__GNUC__)
            while (amount > 0 && item_ < work_.size) {
                const auto& range = work_.items[item_];
                const std::uint32_t step = std::min(amount, range.end - range.begin - done_);
                for (const Stream& s : streams_) hint(s, range.begin + done_, range.begin + done_ + step);
                done_ += step;
                amount -= step;
                if (done_ == range.end - range.begin) ++item_, done_ = 0;
            }
#else
            (void)amount;
#endif
        }

    private:
        /// One hint per 64-byte cache line that the stream's bytes of records [begin, end) touch.
        static void hint(const Stream& s, std::uint32_t begin, std::uint32_t end) {
#if defined(__GNUC__)
            if (begin == end) return;
            const auto first = reinterpret_cast<std::uintptr_t>(s.base + std::size_t{begin} * s.stride) & ~std::uintptr_t{63};
            const auto last = reinterpret_cast<std::uintptr_t>(s.base + std::size_t{end} * s.stride - 1) & ~std::uintptr_t{63};
            for (std::uintptr_t line = first; line <= last; line += 64) __builtin_prefetch(reinterpret_cast<const void*>(line));
#else
            (void)s, (void)begin, (void)end;
#endif
        }

        const WorkList& work_;
        Streams streams_;
        std::uint32_t item_ = 0, done_ = 0;  ///< the next record to hint: item_'s range, done_ records in
    };

    /// One chunk of a range [begin, end): the records in_cylinder accepts, packed in order:
    /// hit k is record begin + accepted[k] with in_cylinder's t[k] and distance2[k]. (measure()
    /// first fills slot k with record begin + k's values; filter() packs them in place.)
    struct Chunk {
        static constexpr std::uint32_t capacity = 64;
        /// Fewer records go through filter_scalar(): the vectorised loops' fixed cost per
        /// chunk (three loops, the padding) pays back only over longer chunks (leaf size 8:
        /// 0.9 times the rays/s with every chunk vectorised, and no gain at leaf size 32).
        static constexpr std::uint32_t vector_minimum = 32;
        std::array<double, capacity + detail::kScanSlack> t, distance2;
        std::array<double, capacity> inside;
        std::array<std::uint32_t, capacity + detail::kScanSlack> accepted;
    };

    /// in_cylinder's arithmetic over records [begin, end) (at most Chunk::capacity) into
    /// chunk's slots, as plain loops over arrays that the compiler vectorises (SSE2: two
    /// records per register): first the positions are copied into one array per axis, then
    /// t, distance2 and the acceptance are computed for every slot without a branch. Each
    /// lane does in_cylinder's operations in its order, so the values are its values, bit for
    /// bit. (Testing the records one by one in scalar double is bound by the
    /// floating-point ports: ~25 operations per record.) The loops run to a whole number of
    /// 4-record vectors where the records exist, so that no scalar remainder loop runs
    /// (leaves are 43 records on average); the extra slots are computed and ignored.
    static void measure(const Record* records, std::uint32_t count, std::uint32_t available, const Ray& ray, double r2,
                        Chunk& chunk) {
        using Coordinate = std::conditional_t<detail::FloatPositionRecord<Record>, float, double>;
        const std::uint32_t lanes = std::min((count + 3) & ~3u, available);
        std::array<Coordinate, Chunk::capacity> xs, ys, zs;
        for (std::uint32_t k = 0; k < lanes; ++k) {
            if constexpr (detail::FloatPositionRecord<Record>) {
                xs[k] = records[k].x;
                ys[k] = records[k].y;
                zs[k] = records[k].z;
            } else {
                const vec3 p = records[k].position();
                xs[k] = p.x;
                ys[k] = p.y;
                zs[k] = p.z;
            }
        }
        measure(xs, ys, zs, lanes, ray, r2, chunk);
    }

    /// measure()'s arithmetic on positions xs, ys, zs [0, lanes).
    template <class Coordinate>
    static void measure(const std::array<Coordinate, Chunk::capacity>& xs, const std::array<Coordinate, Chunk::capacity>& ys,
                        const std::array<Coordinate, Chunk::capacity>& zs, std::uint32_t lanes, const Ray& ray, double r2,
                        Chunk& chunk) {
        const double ox = ray.origin.x, oy = ray.origin.y, oz = ray.origin.z;
        const double ux = ray.direction.x, uy = ray.direction.y, uz = ray.direction.z;
        const double t_max = ray.t_max;
        for (std::uint32_t k = 0; k < lanes; ++k) {
            // in_cylinder: d = p - o, t = d . u, perp = d - t u, distance2 = perp . perp
            // (glm's dot sums x, y, z left to right, as here).
            const double dx = static_cast<double>(xs[k]) - ox, dy = static_cast<double>(ys[k]) - oy,
                         dz = static_cast<double>(zs[k]) - oz;
            const double t = dx * ux + dy * uy + dz * uz;
            const double px = dx - t * ux, py = dy - t * uy, pz = dz - t * uz;
            const double dist2 = px * px + py * py + pz * pz;
            chunk.t[k] = t;
            chunk.distance2[k] = dist2;
            // A double flag (not bool or int) keeps the loop in one element width: it vectorises.
            chunk.inside[k] = ((t >= 0.0) & (t <= t_max) & (dist2 <= r2)) ? 1.0 : 0.0;
        }
    }

    /// The positions of packed records from `first` on, within one frame, as the kernels read them.
    [[nodiscard]] CodedPositions coded(std::uint32_t first, const PackedRecords::Frame& frame) const {
        static_assert(CodedPositions::bits == PackedRecords::bits);
        const auto& a = frame.axis;
        return {records_.codes() + first, {a[0].origin, a[1].origin, a[2].origin}, {a[0].step, a[1].step, a[2].step}};
    }

    /// The records [begin, end) (at most one chunk) in the cylinder, into chunk (filter()'s
    /// contract). Packed records go frame by frame, their 64-bit words read in place: to the
    /// SIMD kernel where the target has it, else decoded into measure()'s arrays as floats
    /// (PackedRecords::read_positions; every chunk: reading a short one back for
    /// filter_scalar() costs as much).
    std::uint32_t filter_chunk(std::uint32_t begin, std::uint32_t end, const Ray& ray, double r2, Chunk& chunk) const {
        if constexpr (packed) {
#if SECCHI_HAS_CYLINDER_SCAN
            std::uint32_t n = 0;
            records_.for_each_frame(begin, end, [&](std::uint32_t first, std::uint32_t last, const PackedRecords::Frame& frame) {
                n += scan_cylinder(coded(first, frame), last - first, ray, r2, chunk.t.data() + n, chunk.distance2.data() + n,
                                   chunk.accepted.data() + n, first - begin);
            });
            return n;
#else
            std::array<float, Chunk::capacity> xs, ys, zs;
            records_.for_each_frame(begin, end, [&](std::uint32_t first, std::uint32_t last, const PackedRecords::Frame& frame) {
                records_.read_positions(first, last, frame, xs.data() + (first - begin), ys.data() + (first - begin),
                                        zs.data() + (first - begin));
            });
            const std::uint32_t lanes = (end - begin + 3) & ~3u;  // <= capacity; the extra slots: zeros, ignored
            for (std::uint32_t k = end - begin; k < lanes; ++k) xs[k] = ys[k] = zs[k] = 0.0f;
            measure(xs, ys, zs, lanes, ray, r2, chunk);
            return compact(end - begin, chunk);
#endif
        } else {
            return filter(records_.data() + begin, end - begin, static_cast<std::uint32_t>(records_.size()) - begin, ray, r2, chunk);
        }
    }

    /// The records of [begin, end) (at most Chunk::capacity) that in_cylinder accepts: their
    /// slots in chunk.accepted, in order, without a branch per record (near the cylinder's
    /// surface acceptance is a coin toss, which a branch would mispredict half the time): each
    /// slot is written and the write position advances only if it is accepted. Returns the
    /// count. Chunks of at least Chunk::vector_minimum records go through measure(), shorter
    /// ones through filter_scalar(). Out of line, so its code does not depend on the
    /// collector inlined around it.
#if defined(__GNUC__)
    __attribute__((noinline))
#endif
    static std::uint32_t filter(const Record* records, std::uint32_t count, std::uint32_t available, const Ray& ray,
                                double r2, Chunk& chunk) {
#if SECCHI_HAS_CYLINDER_SCAN
        if constexpr (detail::PackedFloatRecord<Record>)
            return detail::scan_cylinder(FloatRecordPositions<Record>{records}, count, ray, r2, chunk.t.data(),
                                         chunk.distance2.data(), chunk.accepted.data());
#endif
        if (count < Chunk::vector_minimum) return filter_scalar(records, count, ray, r2, chunk);
        measure(records, count, available, ray, r2, chunk);
        return compact(count, chunk);
    }

    /// Packs measure()'s slots [0, count) in place to the accepted ones (n <= k), in order.
    static std::uint32_t compact(std::uint32_t count, Chunk& chunk) {
        std::uint32_t n = 0;
        for (std::uint32_t k = 0; k < count; ++k) {
            chunk.accepted[n] = k;
            chunk.t[n] = chunk.t[k];
            chunk.distance2[n] = chunk.distance2[k];
            // 1.0 is 0x3FF0... and 0.0 is 0: the top three bits are 001 or 000 (integer work only).
            n += static_cast<std::uint32_t>(std::bit_cast<std::uint64_t>(chunk.inside[k]) >> 61);
        }
        return n;
    }

    /// filter() for a short chunk: in_cylinder's arithmetic one record at a time (glm, scalar
    /// double), with the same branch-free compaction.
    static std::uint32_t filter_scalar(const Record* records, std::uint32_t count, const Ray& ray, double r2, Chunk& chunk) {
        const vec3 o = ray.origin, u = ray.direction;
        const double t_max = ray.t_max;
        std::uint32_t n = 0;
        for (std::uint32_t k = 0; k < count; ++k) {
            const vec3 d = records[k].position() - o;
            const double t = glm::dot(d, u);
            const vec3 perp = d - t * u;
            const double dist2 = glm::dot(perp, perp);
            chunk.t[n] = t;
            chunk.distance2[n] = dist2;
            chunk.accepted[n] = k;
            n += static_cast<std::uint32_t>((t >= 0.0) & (t <= t_max) & (dist2 <= r2));
        }
        return n;
    }

    /// Reports records [begin, end), all inside the cylinder, with in_cylinder's t and
    /// distance2 (kept out of line: the walk's hot loop stays small). Inlined with the
    /// collector, the compiler drops what the collector does not use (the estimator uses t
    /// only, a counter neither), which the vectorised measure() cannot: it is slower here.
    template <Collector C>
#if defined(__GNUC__)
    __attribute__((noinline))
#endif
    bool report_all(const Ray& ray, std::uint32_t begin, std::uint32_t end, C& collect) const {
        const Record* const records = records_.data();
        Hit hit{};
        for (std::uint32_t i = begin; i < end; ++i) {
            const vec3 d = records[i].position() - ray.origin;
            hit.t = glm::dot(d, ray.direction);
            const vec3 perp = d - hit.t * ray.direction;
            hit.distance2 = glm::dot(perp, perp);
            hit.index = i;
            if (!collect(hit)) return false;
        }
        return true;
    }

    const Records& records_;
};

}  // namespace secchi::detail
