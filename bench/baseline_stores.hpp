#pragma once
// The stores as they were before the speed work (git 2986986), kept verbatim in namespace
// secchi::baseline so search_bench can measure before/after ratios within one run.
// Only the namespace and the include guards differ; detail helpers come from the library.
#include "secchi/map/kdtree.hpp"
#include "secchi/map/voi_octree.hpp"

namespace secchi::baseline {
using namespace secchi;

template <PhotonRecord Record>
class VoiOctreeStore {
public:
    using record_type = Record;
    static constexpr std::size_t default_leaf_size = 32;
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
        const double r2 = r.squared();
        const detail::PaddedSegment segment(ray, r2);
        Stack stack;
        if (!nodes_.empty()) stack.push(0);
        Hit hit{};
        while (!stack.empty()) {
            const Node& node = nodes_[stack.pop()];
            if (!segment.meets(lower(node), upper(node))) continue;
            if (node.child_count > 0) {
                push_children(node, stack);
                continue;
            }
            for (std::uint32_t i = node.begin; i < node.end; ++i) {
                if (!in_cylinder(ray, records_[i].position(), r2, hit)) continue;
                hit.index = i;
                if (!collect(hit)) return false;
            }
        }
        return true;
    }

    /// Every record at distance <= r from p.
    template <Collector C>
    bool within(const vec3& p, Radius r, C& collect) const {
        const double r2 = r.squared(), prune2 = detail::pruning_radius2(r2);
        Stack stack;
        if (!nodes_.empty()) stack.push(0);
        while (!stack.empty()) {
            const Node& node = nodes_[stack.pop()];
            if (detail::box_distance2(p, lower(node), upper(node)) > prune2) continue;
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




}  // namespace secchi
namespace secchi::baseline {
using namespace secchi;

template <PhotonRecord Record>
class KdTreeStore {
public:
    using record_type = Record;

    /// Builds the left-balanced tree (Jensen 2001, ch. 6, "balance").
    explicit KdTreeStore(std::vector<Record> records) {
        detail::require_indexable(records.size());
        bounds_ = detail::bounding_box(records);
        build(records);
    }

    [[nodiscard]] std::size_t size() const { return heap_.size(); }
    /// The records in the tree's (heap) order; Hit::index refers to this order.
    [[nodiscard]] const std::vector<Record>& records() const { return heap_; }
    /// Records plus the split-axis array (the root box is a member, not allocated).
    [[nodiscard]] std::size_t memory_bytes() const {
        return heap_.capacity() * sizeof(Record) + axes_.capacity() * sizeof(std::uint8_t);
    }

    /// Split axis (0, 1, 2) of internal node i (one with a child: 2i + 1 < size()).
    [[nodiscard]] int split_axis(std::size_t i) const { return (axes_[i >> 2] >> (2 * (i & 3))) & 3; }
    [[nodiscard]] bool is_internal(std::size_t i) const { return 2 * i + 1 < heap_.size(); }

    /// Every record at distance <= r from p (Jensen 2001, "locate_photons", made iterative).
    template <Collector C>
    bool within(const vec3& p, Radius r, C& collect) const {
        const double r2 = r.squared(), prune2 = detail::pruning_radius2(r2);
        Stack<std::uint32_t> stack;
        if (!heap_.empty()) stack.push(0);
        while (!stack.empty()) {
            const std::uint32_t i = stack.pop();
            const vec3 q = heap_[i].position();
            if (is_internal(i)) {
                const int a = split_axis(i);
                const double delta = p[a] - q[a];
                const auto [near, far] = children(i, delta);
                if (far < heap_.size() && delta * delta <= prune2) stack.push(far);
                if (near < heap_.size()) stack.push(near);
            }
            const vec3 d = q - p;
            const double d2 = glm::dot(d, d);
            if (d2 <= r2 && !collect(Hit{i, 0.0, d2})) return false;
        }
        return true;
    }

    /// Every record in the flat-capped cylinder of radius r around the ray segment.
    template <Collector C>
    bool along(const Ray& ray, Radius r, C& collect) const {
        const double r2 = r.squared();
        const detail::PaddedSegment segment(ray, r2);
        Stack<BoxEntry> stack;
        if (!heap_.empty()) stack.push({0, bounds_});
        Hit hit{};
        while (!stack.empty()) {
            const BoxEntry entry = stack.pop();
            if (!segment.meets(entry.box.lo, entry.box.hi)) continue;
            const vec3 q = heap_[entry.node].position();
            if (is_internal(entry.node)) push_child_boxes(entry, q, stack);
            if (!in_cylinder(ray, q, r2, hit)) continue;
            hit.index = entry.node;
            if (!collect(hit)) return false;
        }
        return true;
    }

    /// The k nearest records to p, sorted by (distance2, index); fewer if size() < k.
    void nearest(const vec3& p, std::size_t k, std::vector<Hit>& out) const {
        detail::KBest best(k, heap_.size(), out);
        Stack<BoundEntry> stack;
        if (!heap_.empty() && k > 0) stack.push({0, 0.0});
        while (!stack.empty()) {
            const BoundEntry entry = stack.pop();
            if (!best.may_accept(entry.bound2)) continue;
            const vec3 q = heap_[entry.node].position();
            if (is_internal(entry.node)) {
                const int a = split_axis(entry.node);
                const double delta = p[a] - q[a];
                const auto [near, far] = children(entry.node, delta);
                if (far < heap_.size()) stack.push({far, std::max(entry.bound2, delta * delta)});
                if (near < heap_.size()) stack.push({near, entry.bound2});
            }
            const vec3 d = q - p;
            best.offer(Hit{entry.node, 0.0, glm::dot(d, d)});
        }
        best.finish();
    }

private:
    // Depth-first traversal pushes at most one pending sibling per level plus the current
    // node: the stack never exceeds depth + 1 <= 33 entries for 2^32 - 1 records.
    template <class T>
    using Stack = detail::FixedStack<T, 64>;

    struct BoxEntry {
        std::uint32_t node;
        detail::Box box;  ///< bounds of the node's subtree
    };
    struct BoundEntry {
        std::uint32_t node;
        double bound2;  ///< lower bound on the squared distance to the subtree's records
    };

    /// (near, far) children of internal node i, given delta = query - split coordinate.
    static std::pair<std::uint32_t, std::uint32_t> children(std::uint32_t i, double delta) {
        const std::uint32_t left = 2 * i + 1, right = 2 * i + 2;
        return delta < 0.0 ? std::pair{left, right} : std::pair{right, left};
    }

    /// Pushes the children of an internal node with their boxes (the parent's box cut at the
    /// split plane); the left child is popped first.
    void push_child_boxes(const BoxEntry& entry, const vec3& q, Stack<BoxEntry>& stack) const {
        const int a = split_axis(entry.node);
        const std::uint32_t left = 2 * entry.node + 1, right = left + 1;
        if (right < heap_.size()) {
            BoxEntry child{right, entry.box};
            child.box.lo[a] = q[a];
            stack.push(child);
        }
        BoxEntry child{left, entry.box};
        child.box.hi[a] = q[a];
        stack.push(child);
    }

    /// Size of the left subtree of a left-balanced tree of n nodes: the levels above the last
    /// are full, and the last level fills from the left (Jensen 2001, ch. 6).
    static std::size_t left_subtree_size(std::size_t n) {
        if (n <= 1) return 0;
        const std::size_t last = std::bit_width(n) - 1;               // depth of the last level
        const std::size_t above = (std::size_t{1} << last) - 1;       // nodes above it
        const std::size_t last_left = std::size_t{1} << (last - 1);   // its slots under the left child
        return (above - 1) / 2 + std::min(n - above, last_left);
    }

    /// Axis of largest extent of records [begin, end) (manual 3.4.1).
    static int widest_axis(const std::vector<Record>& records, std::size_t begin, std::size_t end) {
        detail::Box box = detail::empty_box();
        for (std::size_t i = begin; i < end; ++i) {
            box.lo = glm::min(box.lo, records[i].position());
            box.hi = glm::max(box.hi, records[i].position());
        }
        const vec3 extent = box.hi - box.lo;
        if (extent.x >= extent.y && extent.x >= extent.z) return 0;
        return extent.y >= extent.z ? 1 : 2;
    }

    void set_split_axis(std::size_t i, int axis) {
        axes_[i >> 2] = static_cast<std::uint8_t>(axes_[i >> 2] | (axis << (2 * (i & 3))));
    }

    /// Balances `records` in place (median partitions, each subtree a contiguous range), then
    /// gathers them into heap order. heap_node[i] is the position of node i's record.
    void build(std::vector<Record>& records) {
        const std::size_t n = records.size();
        axes_.assign((n / 2 + 3) / 4, 0);  // n / 2 internal nodes, 4 per byte
        std::vector<std::uint32_t> heap_node(n);
        struct Task {
            std::uint32_t node, begin, end;
        };
        std::vector<Task> tasks;
        if (n > 0) tasks.push_back({0, 0, static_cast<std::uint32_t>(n)});
        while (!tasks.empty()) {
            const Task task = tasks.back();
            tasks.pop_back();
            const std::uint32_t median = task.begin + static_cast<std::uint32_t>(left_subtree_size(task.end - task.begin));
            if (is_internal_of(task.node, n)) {
                const int axis = widest_axis(records, task.begin, task.end);
                std::nth_element(records.begin() + task.begin, records.begin() + median, records.begin() + task.end,
                                 [axis](const Record& a, const Record& b) { return a.position()[axis] < b.position()[axis]; });
                set_split_axis(task.node, axis);
                tasks.push_back({2 * task.node + 1, task.begin, median});
                if (median + 1 < task.end) tasks.push_back({2 * task.node + 2, median + 1, task.end});
            }
            heap_node[task.node] = median;
        }
        heap_.reserve(n);
        for (const std::uint32_t at : heap_node) heap_.push_back(records[at]);
    }

    static bool is_internal_of(std::size_t i, std::size_t n) { return 2 * i + 1 < n; }

    std::vector<Record> heap_;         ///< records in left-balanced heap order
    std::vector<std::uint8_t> axes_;   ///< split axis of internal node i: 2 bits at i / 4
    detail::Box bounds_{};             ///< bounding box of all positions (the root's box)
};




}  // namespace secchi
