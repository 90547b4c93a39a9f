#pragma once
// The "volume of influence" (VOI) octree store (DIRSIG water manual, section 3.5).
//
// Each photon carries a virtual sphere of radius r_s, its volume of influence; a ray collects
// every photon whose sphere the ray segment intersects, i.e. every photon inside the cylinder
// of radius r_s around the segment. An octree of axis-aligned boxes lets whole groups be
// rejected by one failed ray-box test (manual 3.5, fig. 3.8).
//
// Build: the root is the bounding box of all positions; a node is divided into 8 equal octants
// of its cell ("divided into eight equal sized volumes by three planes", 3.5) until it holds
// <= leaf_size records (default 128, a constructor parameter), reaches depth max_depth (20), or
// all its records share one position (no division can separate them). Empty octants get no
// node. The records are reordered (a stable counting sort by octant per division) so every
// node's records are one contiguous range [begin, end) of records(). Nodes live in one flat
// vector, built breadth-first: the children of a node are contiguous (first_child,
// child_count), no pointers. Each node stores the tight bounding box of its records in float,
// rounded outward so it still contains every double position.
//
// Padding: the manual pads the boxes "to account for VOI overlap". Here the pad is the query
// radius (plus a rounding margin, search_support.hpp's detail::pruning_pad), applied at query time,
// so one tree serves any radius. (Padding at build time would fix the radius in the tree and
// save one subtraction per box test; the boxes are tight, so the padded box is as small as a
// box around the records' spheres can be.)
//
// Queries: iterative depth-first traversal with a fixed-size stack (no recursion, no
// allocation, no locking), children visited in fixed octant order (x, then y, then z bit).
// Because each node's records are the concatenation of its children's in octant order, the
// walk reports hits in increasing record index: the order is deterministic, and a subtree can
// be reported as one contiguous range without changing it.
//  - along(ray, r): skip a node whose box padded by r the segment [0, t_max] misses (slab
//    test). A node whose box lies inside the cylinder (detail::CylinderInterior: a
//    conservative test with a rounding margin) is accepted whole ("bulk accept"): its records
//    are reported without the per-record cylinder test, with t and distance2 computed by
//    in_cylinder's arithmetic, so the hits are the same values in the same order. At a leaf,
//    each record is tested with in_cylinder.
//  - within(p, r): skip a node whose box is farther than r from p; accept whole a node whose
//    farthest corner is within r (1 - 1e-9) of p.
//  - along_stats(ray, r): the counts of one along() query (nodes, records tested, records
//    accepted in bulk, hits), for tuning.
//
// Tuning (bench/search_bench --suite tune: a problem-2a map of 6.5e6 CompactRecords, 100
// vertical rays of length 8, r = 0.05 and 0.026; BENCHMARKS.md). At a leaf the
// records are filtered without a branch per record (filter()), so a leaf costs little more
// than streaming its records, while every node costs a box test and, once the map outgrows
// the cache, a likely miss. Search time per ray therefore falls with the leaf size up to 128:
// relative to 128, leaves of 4, 8, 16, 32, 64 run at about 0.4, 0.5, 0.55, 0.7, 0.9 of its
// rays/s, and memory falls too (about 42, 34, 26, 20, 19, 17 bytes per CompactRecord at 4 ...
// 128). 128 is the default. (With a branch per record, as first built, 32-128 were level.)
// Bulk accept pays when the radius is large against the leaves' boxes (at r = 0.05 about 40 %
// of the hits are accepted in bulk with leaf 128) and costs one cheap test per node otherwise.
// Software prefetching of the children and a depth-first node layout were tried and measured
// no faster. Changing the leaf size reorders the records, so sums over hits change in their
// last bits (not in value beyond rounding).
// Where the target has AVX-512 (F and VL) or AVX2 and FMA (the benchmarks' -march=native
// build), the leaf scan of CompactRecords is map/cylinder_scan.hpp's: eight (AVX-512) or four
// (AVX2) records per step, the accepted ones packed by register compresses or a table-driven
// permute, for chunks of any length (no scalar path for short ones), with the same hits and
// values. Search only, against the loops below: about 1.15 times the rays/s, with AVX-512 on
// a Zen 4 and with AVX2 on a Zen 3 alike (BENCHMARKS.md, sixth and seventh sessions). Otherwise:
// the leaf scan (filter(), measure()) computes in_cylinder's double arithmetic in loops the
// compiler vectorises (two records per SSE2 register) for chunks of 32 records or more: at
// leaf size 128 about 1.1 times the rays/s of testing one record at a time (tune suite,
// r = 0.026 and 0.05), which was bound by the floating-point ports (~25 operations per
// record, ~4 ns); shorter chunks are still tested one record at a time (filter_scalar()). Measured and not kept: a float
// pre-filter (four records per register, thresholds widened by a rounding bound, so that
// only records it cannot reject get the exact double test): 0.92-0.96 times, as 40 % of the
// tested records are accepted and need the double work anyway; the vectorised arithmetic
// for bulk ranges too: equal with the estimator, 0.95 with a counting collector
// (report_all(), inlined with the collector, skips what the collector does not use);
// prefetching further ahead (2 to 4 ranges, or a steady 2-16 KiB ahead of the scan): slower
// (none at all: 0.77 times); merging adjacent ranges of the walk (half as many ranges) and
// chunks of 128 records: no change.
//
// Threading contract: build once (the constructor); afterwards every const member may be
// called from any number of threads at once.
#include "secchi/map/cylinder_scan.hpp"
#include "secchi/map/search_support.hpp"
#include <array>
#include <bit>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace secchi {
namespace detail {

/// Squared distance from p to the box [lo, hi] (0 inside).
inline double box_distance2(const vec3& p, const vec3& lo, const vec3& hi) {
    const vec3 gap = glm::max(lo - p, vec3(0.0)) + glm::max(p - hi, vec3(0.0));
    return glm::dot(gap, gap);
}

/// Largest float <= v and smallest float >= v: float boxes rounded outward.
inline float float_below(double v) {
    const float f = static_cast<float>(v);
    return static_cast<double>(f) > v ? std::nextafter(f, -std::numeric_limits<float>::infinity()) : f;
}
inline float float_above(double v) {
    const float f = static_cast<float>(v);
    return static_cast<double>(f) < v ? std::nextafter(f, std::numeric_limits<float>::infinity()) : f;
}

/// A record whose position() is its three float members x, y, z (CompactRecord): a leaf scan
/// copies them as floats (exact in double), a plain strided load the compiler vectorises.
template <class R>
concept FloatPositionRecord = requires(const R r) {
    requires std::same_as<decltype(r.x), float>;
    requires std::same_as<decltype(r.y), float>;
    requires std::same_as<decltype(r.z), float>;
};

}  // namespace detail

template <PhotonRecord Record>
class VoiOctreeStore {
public:
    using record_type = Record;
    static constexpr std::size_t default_leaf_size = 128;
    static constexpr int max_depth = 20;

    explicit VoiOctreeStore(std::vector<Record> records, std::size_t leaf_size = default_leaf_size)
        : records_(std::move(records)), leaf_size_(leaf_size) {
        detail::require_indexable(records_.size());
        require(leaf_size >= 1, "octree leaf size", leaf_size, "must be >= 1");
        build();
    }

    [[nodiscard]] std::size_t size() const { return records_.size(); }
    /// The records in octree order (each node's records contiguous); Hit::index refers to it.
    [[nodiscard]] const std::vector<Record>& records() const { return records_; }
    [[nodiscard]] std::size_t memory_bytes() const {
        return records_.capacity() * sizeof(Record) + nodes_.capacity() * sizeof(Node);
    }
    [[nodiscard]] std::size_t node_count() const { return nodes_.size(); }
    [[nodiscard]] std::size_t leaf_size() const { return leaf_size_; }

    /// Every record in the flat-capped cylinder of radius r around the ray segment: the
    /// records whose volume of influence the segment intersects (manual 3.5).
    template <Collector C>
    bool along(const Ray& ray, Radius r, C& collect) const {
        AlongStats stats;
        return along_impl<false>(ray, r, collect, stats);
    }

    /// What one along() query does: nodes whose padded box the segment meets, records tested
    /// one by one at leaves, records accepted in bulk (subtrees inside the cylinder), hits.
    struct AlongStats {
        std::size_t nodes = 0, tested = 0, bulk = 0, hits = 0;
    };
    [[nodiscard]] AlongStats along_stats(const Ray& ray, Radius r) const {
        AlongStats stats;
        CountHits count;
        along_impl<true>(ray, r, count, stats);
        stats.hits = count.count;
        return stats;
    }

    /// Every record at distance <= r from p.
    template <Collector C>
    bool within(const vec3& p, Radius r, C& collect) const {
        const double r2 = r.squared(), prune2 = detail::pruning_radius2(r2);
        Stack stack;
        if (!nodes_.empty()) stack.push(0);
        while (!stack.empty()) {
            const Node& node = nodes_[stack.pop()];
            const vec3 lo = lower(node), hi = upper(node);
            if (detail::box_distance2(p, lo, hi) > prune2) continue;
            if (detail::box_inside_sphere(p, r2, lo, hi)) {  // bulk accept: the same hits, in the same order
                for (std::uint32_t i = node.begin; i < node.end; ++i) {
                    const vec3 d = records_[i].position() - p;
                    if (!collect(Hit{i, 0.0, glm::dot(d, d)})) return false;
                }
                continue;
            }
            if (node.child_count > 0) {
                push_children(node, stack);
                continue;
            }
            for (std::uint32_t i = node.begin; i < node.end; ++i) {
                const vec3 d = records_[i].position() - p;
                const double d2 = glm::dot(d, d);
                if (d2 <= r2 && !collect(Hit{i, 0.0, d2})) return false;
            }
        }
        return true;
    }

private:
    /// along(): depth-first over the nodes whose padded box the segment meets. A node whose
    /// box lies inside the cylinder (detail::CylinderInterior, with a rounding margin) is
    /// reported whole: its records are one contiguous range, in the same order the
    /// depth-first walk of its leaves would report them, with t and distance2 computed by
    /// in_cylinder's arithmetic, so the hits are identical, value for value and in order.
    template <bool Profile, Collector C>
    bool along_impl(const Ray& ray_in, Radius r, C& collect, AlongStats& stats) const {
        // Local copies: the collector may write doubles (the estimator's sums), which the
        // compiler would otherwise have to assume alias the ray and reload every record.
        const Ray ray = ray_in;
        const double r2 = r.squared();
        const detail::PaddedSegment segment(ray, r2);
        const detail::CylinderInterior interior(ray, r2);
        const bool bulk = interior.usable();
        const Node* const nodes = nodes_.data();
        // Two phases, so that record memory is fetched ahead of use: the walk lists the
        // record ranges to scan (leaves) or report whole (bulk), in walk order, in `work`;
        // stream() then goes through the list, prefetching each range's records one range
        // ahead. Scanning streams ~5,000 records per ray from memory and is limited by it
        // (BENCHMARKS.md); the hits and their order are those of the one-phase walk.
        WorkList work;
        Stack stack;
        if (!nodes_.empty()) stack.push(0);
        while (!stack.empty()) {
            const Node& node = nodes[stack.pop()];
            const vec3 lo = lower(node), hi = upper(node);
            if (!segment.meets(lo, hi)) continue;
            if constexpr (Profile) ++stats.nodes;
            const bool whole = bulk && interior.contains(lo, hi);
            if (!whole && node.child_count > 0) {
                push_children(node, stack);
                continue;
            }
            if constexpr (Profile) (whole ? stats.bulk : stats.tested) += node.end - node.begin;
            work.items[work.size++] = {node.begin, node.end, whole};
            if (work.size == WorkList::capacity) {
                if (!stream(work, ray, r2, collect)) return false;
                work.size = 0;
            }
        }
        return stream(work, ray, r2, collect);
    }

    /// Record ranges queued by the walk: scan with the cylinder test, or report whole.
    struct WorkList {
        struct Range {
            std::uint32_t begin, end;
            bool whole;
        };
        static constexpr std::size_t capacity = 64;
        std::array<Range, capacity> items;
        std::size_t size = 0;
    };

    /// Hints the cache to fetch records [begin, end) (at most the first 4 KiB).
    void prefetch(std::uint32_t begin, std::uint32_t end) const {
#if defined(__GNUC__)
        const char* p = reinterpret_cast<const char*>(records_.data() + begin);
        const char* const stop = reinterpret_cast<const char*>(records_.data() + end);
        for (const char* last = p + 4096; p < stop && p < last; p += 64) __builtin_prefetch(p);
#else
        (void)begin, (void)end;
#endif
    }

    /// Reports the hits of the queued ranges in order, prefetching one range ahead: a bulk
    /// range all its records, a scanned range (a leaf) those filter() accepts, in chunks of at
    /// most Chunk::capacity records.
    template <Collector C>
    bool stream(const WorkList& work, const Ray& ray, double r2, C& collect) const {
        if (work.size > 0) prefetch(work.items[0].begin, work.items[0].end);
        Hit hit{};
        for (std::size_t w = 0; w < work.size; ++w) {
            if (w + 1 < work.size) prefetch(work.items[w + 1].begin, work.items[w + 1].end);
            const auto& range = work.items[w];
            if (range.whole) {
                if (!report_all(ray, range.begin, range.end, collect)) return false;
                continue;
            }
            for (std::uint32_t begin = range.begin; begin < range.end; begin += Chunk::capacity) {
                const std::uint32_t end = std::min<std::uint32_t>(range.end, begin + Chunk::capacity);
                Chunk chunk;
                const std::uint32_t n = filter(begin, end, ray, r2, chunk);
                for (std::uint32_t k = 0; k < n; ++k) {
                    hit.index = begin + chunk.accepted[k];
                    hit.t = chunk.t[k];
                    hit.distance2 = chunk.distance2[k];
                    if (!collect(hit)) return false;
                }
            }
        }
        return true;
    }

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
    /// bit. (Testing the records one by one in scalar double, as before, was bound by the
    /// floating-point ports: ~25 operations per record.) The loops run to a whole number of
    /// 4-record vectors where the records exist, so that no scalar remainder loop runs
    /// (leaves are 43 records on average); the extra slots are computed and ignored.
    void measure(std::uint32_t begin, std::uint32_t end, const Ray& ray, double r2, Chunk& chunk) const {
        using Coordinate = std::conditional_t<detail::FloatPositionRecord<Record>, float, double>;
        const Record* const records = records_.data() + begin;
        const auto available = static_cast<std::uint32_t>(records_.size()) - begin;
        const std::uint32_t lanes = std::min(((end - begin) + 3) & ~3u, available);
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
    std::uint32_t filter(std::uint32_t begin, std::uint32_t end, const Ray& ray, double r2, Chunk& chunk) const {
#if SECCHI_HAS_CYLINDER_SCAN
        if constexpr (detail::PackedFloatRecord<Record>)
            return detail::scan_cylinder(records_.data() + begin, end - begin, ray, r2, chunk.t.data(),
                                         chunk.distance2.data(), chunk.accepted.data());
#endif
        if (end - begin < Chunk::vector_minimum) return filter_scalar(begin, end, ray, r2, chunk);
        measure(begin, end, ray, r2, chunk);
        std::uint32_t n = 0;
        for (std::uint32_t k = 0; k < end - begin; ++k) {  // packed in place: n <= k
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
    std::uint32_t filter_scalar(std::uint32_t begin, std::uint32_t end, const Ray& ray, double r2, Chunk& chunk) const {
        const Record* const records = records_.data() + begin;
        const vec3 o = ray.origin, u = ray.direction;
        const double t_max = ray.t_max;
        std::uint32_t n = 0;
        for (std::uint32_t k = 0; k < end - begin; ++k) {
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

    struct Node {
        std::array<float, 3> lo, hi;    ///< tight box of the node's records, rounded outward
        std::uint32_t begin, end;       ///< records_[begin, end)
        std::uint32_t first_child;      ///< index in nodes_ of the first (contiguous) child
        std::uint32_t child_count;      ///< 0 for a leaf
    };

    /// Build-time geometry of a node: its octree cell (centre, half extent) and depth.
    struct Cell {
        vec3 centre, half;
        int depth;
        [[nodiscard]] Cell child(unsigned octant) const {
            const vec3 h = 0.5 * half;
            const vec3 sign((octant & 1) ? 1.0 : -1.0, (octant & 2) ? 1.0 : -1.0, (octant & 4) ? 1.0 : -1.0);
            return {centre + sign * h, h, depth + 1};
        }
    };

    // Depth-first: each popped node pushes <= 8 children, so at most 7 pending siblings per
    // level on the current path plus 8: 7 * max_depth + 8 <= 8 * (max_depth + 1) entries.
    using Stack = detail::FixedStack<std::uint32_t, 8 * (max_depth + 1)>;

    static vec3 lower(const Node& n) { return {n.lo[0], n.lo[1], n.lo[2]}; }
    static vec3 upper(const Node& n) { return {n.hi[0], n.hi[1], n.hi[2]}; }

    /// Pushes the children in reverse, so they are popped in octant order.
    static void push_children(const Node& node, Stack& stack) {
        for (std::uint32_t c = node.child_count; c-- > 0;) stack.push(node.first_child + c);
    }

    /// Octant of p in a cell: bit 0 for x >= centre.x, bit 1 for y, bit 2 for z.
    static unsigned octant(const vec3& p, const vec3& centre) {
        return (p.x >= centre.x ? 1u : 0u) | (p.y >= centre.y ? 2u : 0u) | (p.z >= centre.z ? 4u : 0u);
    }

    /// A leaf node over records_[begin, end) with its tight box.
    Node make_node(std::uint32_t begin, std::uint32_t end) const {
        detail::Box box = detail::empty_box();
        for (std::uint32_t i = begin; i < end; ++i) {
            box.lo = glm::min(box.lo, records_[i].position());
            box.hi = glm::max(box.hi, records_[i].position());
        }
        Node node{};
        for (int a = 0; a < 3; ++a) {
            node.lo[a] = detail::float_below(box.lo[a]);
            node.hi[a] = detail::float_above(box.hi[a]);
        }
        node.begin = begin;
        node.end = end;
        return node;
    }

    /// Breadth-first build: nodes are divided in index order, so children are appended
    /// contiguously after all existing nodes.
    void build() {
        if (records_.empty()) return;
        const detail::Box box = detail::bounding_box(records_);
        std::vector<Cell> cells{{0.5 * (box.lo + box.hi), 0.5 * (box.hi - box.lo), 0}};
        nodes_.push_back(make_node(0, static_cast<std::uint32_t>(records_.size())));
        std::vector<Record> scratch;
        for (std::size_t i = 0; i < nodes_.size(); ++i) {
            if (should_divide(nodes_[i], cells[i])) divide(i, cells, scratch);
        }
        nodes_.shrink_to_fit();
    }

    bool should_divide(const Node& node, const Cell& cell) const {
        // lo == hi only if every position is the same float value (the box is rounded outward).
        const bool single_position = node.lo == node.hi;
        return node.end - node.begin > leaf_size_ && cell.depth < max_depth && !single_position;
    }

    /// Divides node i into its non-empty octants: a stable counting sort of its records by
    /// octant, then one child node per non-empty octant.
    void divide(std::size_t i, std::vector<Cell>& cells, std::vector<Record>& scratch) {
        const Node node = nodes_[i];
        const Cell cell = cells[i];
        std::array<std::uint32_t, 9> start{};
        for (std::uint32_t k = node.begin; k < node.end; ++k) ++start[octant(records_[k].position(), cell.centre) + 1];
        for (unsigned o = 0; o < 8; ++o) start[o + 1] += start[o];
        std::array<std::uint32_t, 8> cursor{};
        std::copy(start.begin(), start.end() - 1, cursor.begin());
        scratch.assign(node.end - node.begin, records_[node.begin]);
        for (std::uint32_t k = node.begin; k < node.end; ++k)
            scratch[cursor[octant(records_[k].position(), cell.centre)]++] = records_[k];
        std::copy(scratch.begin(), scratch.end(), records_.begin() + node.begin);

        nodes_[i].first_child = static_cast<std::uint32_t>(nodes_.size());
        for (unsigned o = 0; o < 8; ++o) {
            if (start[o] == start[o + 1]) continue;
            nodes_.push_back(make_node(node.begin + start[o], node.begin + start[o + 1]));
            cells.push_back(cell.child(o));
            ++nodes_[i].child_count;
        }
    }

    std::vector<Record> records_;  ///< in octree order
    std::vector<Node> nodes_;      ///< nodes_[0] is the root; children contiguous
    std::size_t leaf_size_;
};

static_assert(PhotonStore<VoiOctreeStore<CompactRecord>>);
static_assert(PhotonStore<VoiOctreeStore<FullRecord>>);

}  // namespace secchi
