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
// <= leaf_size records (default 512, a constructor parameter), reaches depth max_depth (20), or
// all its records share one position (no division can separate them). Empty octants get no
// node. The records are reordered (a stable counting sort by octant per division) so every
// node's records are one contiguous range [begin, end) of records(). Nodes live in one flat
// vector, built breadth-first: the children of a node are contiguous (first_child,
// child_count), no pointers. Each node stores the tight bounding box of its records in float,
// rounded outward so it still contains every double position.
//
// Record layout (the Layout parameter; default_record_layout, packed_records.hpp): plain keeps a
// std::vector of the records. RecordLayout::packed (CompactRecord only, packed_records.hpp)
// keeps them in 12 bytes, 21-bit coordinates within frames: a leaf's records, or where the
// leaf's box is too large for one frame, its records sorted by sub-octant within the leaf's
// range (no further nodes), one frame each. The records read back exactly; records() is then a
// range of CompactRecord values, and the leaf scan reads the packed words in place
// (range_scan.hpp). Packed is the default for CompactRecords. Bytes per photon and speed of
// the two: BENCHMARKS.md.
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
// Leaf size (bench/search_bench --suite tune; BENCHMARKS.md, "Tuning tables"). At a leaf the
// records are filtered without a branch per record (range_scan.hpp's filter()), so a leaf
// costs little more than streaming its records, while every node costs a box test and, once
// the map outgrows the cache, a likely miss. On the tune suite's problem-2a map (6.5e6
// CompactRecords, vertical rays, r = 0.026 and 0.05) the search rate rises with the leaf size
// up to 256-1024 and falls beyond; the memory falls throughout (the nodes' share: 1.4 bytes
// per record at 128, 0.33 at 512). 512 is the default. Bulk accept pays when the radius is
// large against the leaves' boxes and costs one cheap test per node otherwise.
// Changing the leaf size reorders the records, so sums over hits change in their
// last bits (not in value beyond rounding).
// Where the target has AVX-512 (F and VL) or AVX2 and FMA (the benchmarks' -march=native
// build), the leaf scan of CompactRecords is map/cylinder_scan.hpp's: eight (AVX-512) or four
// (AVX2) records per step, the accepted ones packed by register compresses or a table-driven
// permute, for chunks of any length (no scalar path for short ones), with the same hits and
// values (docs/design-notes.md). Otherwise the leaf scan (range_scan.hpp: filter(), measure())
// computes in_cylinder's double arithmetic in loops the compiler vectorises (two records per
// SSE2 register) for chunks of 32 records or more; shorter chunks are tested one record at a
// time (filter_scalar()).
// Records are prefetched a steady 4 KiB ahead of the scan (range_scan.hpp).
//
// Threading contract: build once (the constructor); afterwards every const member may be
// called from any number of threads at once.
#include "secchi/core/config.hpp"
#include "secchi/map/cylinder_scan.hpp"
#include "secchi/map/packed_records.hpp"
#include "secchi/map/range_scan.hpp"
#include "secchi/map/search_support.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {
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

}  // namespace detail

template <PhotonRecord Record, RecordLayout Layout = default_record_layout<Record>>
class VoiOctreeStore {
    static constexpr bool is_packed = Layout == RecordLayout::packed;
    static_assert(!is_packed || std::same_as<Record, CompactRecord>, "only CompactRecords pack (packed_records.hpp)");

public:
    using record_type = Record;
    static constexpr std::size_t default_leaf_size = 512;
    static constexpr int max_depth = 20;

    explicit VoiOctreeStore(std::vector<Record> records, std::size_t leaf_size = default_leaf_size)
        : records_(std::move(records)), leaf_size_(leaf_size) {
        detail::require_indexable(records_.size());
        require(leaf_size >= 1, "octree leaf size", leaf_size, "must be >= 1");
        build();
    }

    [[nodiscard]] std::size_t size() const { return stored().size(); }
    /// The records in octree order (each node's records contiguous); Hit::index refers to it.
    /// Packed: a range of CompactRecord values, their positions as read back (packed_records.hpp).
    [[nodiscard]] decltype(auto) records() const {
        if constexpr (is_packed) return packed_.view();
        else return (records_);
    }
    [[nodiscard]] std::size_t memory_bytes() const {
        return records_.capacity() * sizeof(Record) + packed_.memory_bytes() + nodes_.capacity() * sizeof(Node);
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
        AlongStats& operator+=(const AlongStats& o) {
            nodes += o.nodes, tested += o.tested, bulk += o.bulk, hits += o.hits;
            return *this;
        }
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
                    const vec3 d = position(i) - p;
                    if (!collect(Hit{i, 0.0, glm::dot(d, d)})) return false;
                }
                continue;
            }
            if (node.child_count > 0) {
                push_children(node, stack);
                continue;
            }
            for (std::uint32_t i = node.begin; i < node.end; ++i) {
                const vec3 d = position(i) - p;
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
        // stream() then goes through the list, prefetching the records a few KiB ahead of
        // the scan. Scanning streams ~5,000 records per ray from memory and is limited by it
        // (docs/design-notes.md); the hits and their order are those of the one-phase walk.
        const detail::CylinderRanges<Storage> ranges(stored());
        typename detail::CylinderRanges<Storage>::WorkList work;
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
            if (work.size == work.items.size()) {
                if (!ranges.stream(work, ray, r2, collect)) return false;
                work.size = 0;
            }
        }
        return ranges.stream(work, ray, r2, collect);
    }

    /// Where the records live after the build: records_, or packed_ (then records_ is empty).
    using Storage = std::conditional_t<is_packed, PackedRecords, std::vector<Record>>;
    [[nodiscard]] const Storage& stored() const {
        if constexpr (is_packed) return packed_;
        else return records_;
    }
    [[nodiscard]] vec3 position(std::uint32_t i) const { return stored()[i].position(); }

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
        if constexpr (is_packed) pack(cells, scratch);
    }

    bool should_divide(const Node& node, const Cell& cell) const {
        // lo == hi only if every position is the same float value (the box is rounded outward).
        const bool single_position = node.lo == node.hi;
        return node.end - node.begin > leaf_size_ && cell.depth < max_depth && !single_position;
    }

    /// Packs the records in frames: each leaf's records, or where their box is too large for
    /// one frame (PackedRecords::is_fine), the runs of its sub-octants (frames_of).
    void pack(const std::vector<Cell>& cells, std::vector<Record>& scratch) {
        std::vector<std::uint32_t> leaves, begins;
        for (std::uint32_t i = 0; i < nodes_.size(); ++i)
            if (nodes_[i].child_count == 0) leaves.push_back(i);
        std::sort(leaves.begin(), leaves.end(), [&](std::uint32_t a, std::uint32_t b) { return nodes_[a].begin < nodes_[b].begin; });
        for (const std::uint32_t i : leaves) frames_of(nodes_[i], cells[i], begins, scratch);
        packed_ = PackedRecords(records_, begins);
        records_ = std::vector<Record>();  // (not `= {}`: that keeps the capacity)
    }

    /// The frames of the records of `run` (a leaf, or part of one, with its box), appended to
    /// `begins`: one if their box is fine, else their records sorted by octant of `cell` (as
    /// divide() sorts them, but without nodes: the leaf keeps its range and its records stay
    /// in it) and each octant's frames in turn. Halving the cell ends in fine boxes: at the
    /// latest where a cell is narrower than the records' position grid, its records share
    /// their coordinates.
    void frames_of(const Node& run, const Cell& cell, std::vector<std::uint32_t>& begins, std::vector<Record>& scratch) {
        if (PackedRecords::is_fine(run.lo, run.hi)) {  // (also where the records share one position)
            begins.push_back(run.begin);
            return;
        }
        const auto start = sort_by_octant(run.begin, run.end, cell.centre, scratch);
        for (unsigned o = 0; o < 8; ++o)
            if (start[o] != start[o + 1])
                frames_of(make_node(run.begin + start[o], run.begin + start[o + 1]), cell.child(o), begins, scratch);
    }

    /// Divides node i into its non-empty octants: a stable counting sort of its records by
    /// octant, then one child node per non-empty octant.
    void divide(std::size_t i, std::vector<Cell>& cells, std::vector<Record>& scratch) {
        const Node node = nodes_[i];
        const Cell cell = cells[i];
        const auto start = sort_by_octant(node.begin, node.end, cell.centre, scratch);
        nodes_[i].first_child = static_cast<std::uint32_t>(nodes_.size());
        for (unsigned o = 0; o < 8; ++o) {
            if (start[o] == start[o + 1]) continue;
            nodes_.push_back(make_node(node.begin + start[o], node.begin + start[o + 1]));
            cells.push_back(cell.child(o));
            ++nodes_[i].child_count;
        }
    }

    /// A stable counting sort of records_[begin, end) by octant of `centre`: octant o's records
    /// are then [begin + start[o], begin + start[o + 1]).
    std::array<std::uint32_t, 9> sort_by_octant(std::uint32_t begin, std::uint32_t end, const vec3& centre,
                                                std::vector<Record>& scratch) {
        std::array<std::uint32_t, 9> start{};
        for (std::uint32_t k = begin; k < end; ++k) ++start[octant(records_[k].position(), centre) + 1];
        for (unsigned o = 0; o < 8; ++o) start[o + 1] += start[o];
        std::array<std::uint32_t, 8> cursor{};
        std::copy(start.begin(), start.end() - 1, cursor.begin());
        scratch.assign(end - begin, records_[begin]);
        for (std::uint32_t k = begin; k < end; ++k) scratch[cursor[octant(records_[k].position(), centre)]++] = records_[k];
        std::copy(scratch.begin(), scratch.end(), records_.begin() + begin);
        return start;
    }

    std::vector<Record> records_;  ///< in octree order (packed: only while building)
    PackedRecords packed_;         ///< packed: the records in octree order
    std::vector<Node> nodes_;      ///< nodes_[0] is the root; children contiguous
    std::size_t leaf_size_;
};

static_assert(PhotonStore<VoiOctreeStore<CompactRecord>>);
static_assert(PhotonStore<VoiOctreeStore<FullRecord>>);

}  // namespace secchi
