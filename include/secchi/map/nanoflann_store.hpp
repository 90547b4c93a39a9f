#pragma once
// A photon store over nanoflann 1.4.2 (Blanco & Rai 2014, https://github.com/jlblancoc/nanoflann):
// KDTreeSingleIndexAdaptor with the L2_Simple metric, 3 dimensions, uint32_t indices, leaf
// size 10. nanoflann builds its tree over a permutation of the records (its member vAcc) and
// reads every record through it, so in input order the records of one leaf lie anywhere in
// memory and each one read is a cache miss. After the build the records are therefore put in
// that permutation's order and the permutation made the identity: each leaf's records are
// one contiguous run, as in the other stores ("stored in build order of the tree"). The tree
// and its searches are unchanged; the hits are the same records, indexed in the new order.
// 1.3-1.75 times the search rate of input order (docs/design-notes.md).
//
// Coordinates are read in double (for CompactRecord the float position converts exactly), so
// nanoflann's squared distances agree with the exact ones to a few ulps. Its L2 metric works
// in squared distances: it is given r.squared(), padded by 1e-9 relative so rounding never
// drops a candidate; every candidate is then re-tested with the exact test BruteForceStore
// uses before it reaches the Collector.
//  - within(p, r): one radius search with a result set wrapping the Collector (nanoflann's
//    RadiusResultSet idea: addPoint returns false to stop the search).
//  - along(ray, r): radius searches centred at steps of length h = 2r along the segment,
//    radius r sqrt(2): a record in the cylinder projects within r of some centre along the ray
//    and lies within r of the ray, so within r sqrt(2) of that centre. (Exactly: r is replaced
//    by the rounding-safe pad, r plus a margin, see search_support.hpp's detail::pruning_pad.)
//    Candidates are filtered with in_cylinder, and a hit is reported only by the step whose
//    centre is closest to its t (round(t / h)), so each record is reported exactly once.
//    Steps cover only the part of the segment inside the records' bounding box padded by r,
//    and a nearest-record probe at each step skips the following steps whose balls are
//    provably empty, so empty space costs a few probes however small r is. (The pad is at
//    least ~3e-7 t_max, so a segment never needs more than ~2e6 steps.)
//  - nearest(p, k): a k-best result set; ties broken by the smaller index.
//
// Threading contract: build once (the constructor); afterwards every const member may be
// called from any number of threads at once (nanoflann's findNeighbors is const and keeps its
// state on the caller's stack).
#include "secchi/core/config.hpp"
#include "secchi/map/search_support.hpp"
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <nanoflann.hpp>
#include <numeric>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {
namespace detail {

/// nanoflann's dataset adaptor: the records' positions in double precision.
template <PhotonRecord Record>
struct NanoflannDataset {
    const std::vector<Record>* records;
    [[nodiscard]] std::size_t kdtree_get_point_count() const { return records->size(); }
    [[nodiscard]] double kdtree_get_pt(std::uint32_t i, int axis) const { return (*records)[i].position()[axis]; }
    template <class BBox>
    bool kdtree_get_bbox(BBox&) const {
        return false;  // let nanoflann compute it
    }
};

/// The bound a result set reports as worstDist(): nanoflann admits a candidate only if its
/// squared distance is strictly below it, so the rounding-safe bound is raised by one ulp
/// (records exactly at the bound, even at distance 0, still reach addPoint).
inline double admit_below(double bound2) { return std::nextafter(pruning_radius2(bound2), infinity); }

/// Result set for within(): exact re-test, then the Collector (which may stop the search).
template <PhotonRecord Record, Collector C>
class WithinResultSet {
public:
    WithinResultSet(const std::vector<Record>& records, const vec3& p, double r2, C& collect)
        : records_(records), p_(p), r2_(r2), collect_(collect) {}

    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return admit_below(r2_); }
    [[nodiscard]] bool stopped() const { return stopped_; }

    bool addPoint(double, std::uint32_t i) {
        const vec3 d = records_[i].position() - p_;
        const double d2 = glm::dot(d, d);
        if (d2 > r2_) return true;
        stopped_ = !collect_(Hit{i, 0.0, d2});
        return !stopped_;
    }

private:
    const std::vector<Record>& records_;
    vec3 p_;
    double r2_;
    C& collect_;
    bool stopped_ = false;
};

/// Result set for one step of along(): candidates in the step's ball that are in the cylinder
/// and whose closest step is this one.
template <PhotonRecord Record, Collector C>
class AlongStepResultSet {
public:
    AlongStepResultSet(const std::vector<Record>& records, const Ray& ray, double r2, double step, double k,
                       double ball2, C& collect)
        : records_(records), ray_(ray), r2_(r2), step_(step), k_(k), ball2_(ball2), collect_(collect) {}

    /// The step whose centre k h is closest to t.
    static double closest_step(double t, double step) { return std::floor(t / step + 0.5); }

    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return admit_below(ball2_); }
    [[nodiscard]] bool stopped() const { return stopped_; }

    bool addPoint(double, std::uint32_t i) {
        Hit hit{};
        if (!in_cylinder(ray_, records_[i].position(), r2_, hit) || closest_step(hit.t, step_) != k_) return true;
        hit.index = i;
        stopped_ = !collect_(hit);
        return !stopped_;
    }

private:
    const std::vector<Record>& records_;
    const Ray& ray_;
    double r2_, step_, k_, ball2_;
    C& collect_;
    bool stopped_ = false;
};

/// Result set for nearest(): exact distances into a k-best list. The reported worst distance
/// is padded so records tied with the k-th reach addPoint (ties are broken by index).
template <PhotonRecord Record>
class NearestResultSet {
public:
    NearestResultSet(const std::vector<Record>& records, const vec3& p, KBest& best)
        : records_(records), p_(p), best_(best) {}

    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return admit_below(best_.worst2()); }

    bool addPoint(double, std::uint32_t i) {
        const vec3 d = records_[i].position() - p_;
        best_.offer(Hit{i, 0.0, glm::dot(d, d)});
        return true;
    }

private:
    const std::vector<Record>& records_;
    vec3 p_;
    KBest& best_;
};

/// Result set for the distance to the nearest record (exact squared distance).
template <PhotonRecord Record>
class NearestDistanceResultSet {
public:
    NearestDistanceResultSet(const std::vector<Record>& records, const vec3& p) : records_(records), p_(p) {}

    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return admit_below(best2_); }
    [[nodiscard]] double distance2() const { return best2_; }

    bool addPoint(double, std::uint32_t i) {
        const vec3 d = records_[i].position() - p_;
        best2_ = std::min(best2_, glm::dot(d, d));
        return true;
    }

private:
    const std::vector<Record>& records_;
    vec3 p_;
    double best2_ = infinity;
};

}  // namespace detail

template <PhotonRecord Record>
class NanoflannStore {
public:
    using record_type = Record;
    static constexpr std::size_t leaf_size = 10;

    explicit NanoflannStore(std::vector<Record> records) {
        detail::require_indexable(records.size());
        bounds_ = detail::bounding_box(records);
        index_ = std::make_unique<Index>(std::move(records));
        index_bytes_ = index_->tree.usedMemory(index_->tree);
    }

    [[nodiscard]] std::size_t size() const { return index_->records.size(); }
    /// The records in the tree's leaf order (each leaf's records contiguous); Hit::index refers to this order.
    [[nodiscard]] const std::vector<Record>& records() const { return index_->records; }
    /// Records, nanoflann's nodes and index permutation (its usedMemory), and the holder.
    [[nodiscard]] std::size_t memory_bytes() const {
        return index_->records.capacity() * sizeof(Record) + index_bytes_ + sizeof(Index);
    }

    /// Every record at distance <= r from p.
    template <Collector C>
    bool within(const vec3& p, Radius r, C& collect) const {
        detail::WithinResultSet<Record, C> result(index_->records, p, r.squared(), collect);
        search(p, result);
        return !result.stopped();
    }

    /// Every record in the flat-capped cylinder of radius r around the ray segment.
    template <Collector C>
    bool along(const Ray& ray, Radius r, C& collect) const {
        if (size() == 0) return true;
        const double r2 = r.squared();
        const detail::PaddedSegment segment(ray, r2);
        const auto [t0, t1] = segment.clip(bounds_.lo, bounds_.hi);
        if (t0 > t1) return true;
        // Steps of 2 pad (pad = r plus the rounding margin, detail::pruning_pad); a record the
        // oracle accepts lies within pad of the ray and within pad of its closest centre along
        // it, so within pad sqrt(2) of that centre.
        const double step = 2.0 * segment.pad(), ball = std::sqrt(2.0) * segment.pad();
        const double ball2 = ball * ball;
        const double stride = step * glm::length(ray.direction);  // distance between centres
        using StepSet = detail::AlongStepResultSet<Record, C>;
        // One spare step at each end: extra steps cost time, never correctness.
        const double first = std::max(0.0, StepSet::closest_step(t0, step) - 1.0);
        const double last = StepSet::closest_step(t1, step) + 1.0;
        for (double k = first; k <= last;) {
            const vec3 centre = ray.origin + (k * step) * ray.direction;
            if (const double empty = empty_steps(centre, ball, stride); empty > 0.0) {
                k += empty;
                continue;
            }
            StepSet result(index_->records, ray, r2, step, k, ball2, collect);
            search(centre, result);
            if (result.stopped()) return false;
            k += 1.0;
        }
        return true;
    }

    /// The k nearest records to p, sorted by (distance2, index); fewer if size() < k.
    void nearest(const vec3& p, std::size_t k, std::vector<Hit>& out) const {
        detail::KBest best(k, size(), out);
        if (k > 0) {
            detail::NearestResultSet<Record> result(index_->records, p, best);
            search(p, result);
        }
        best.finish();
    }

private:
    using Dataset = detail::NanoflannDataset<Record>;
    using Metric = nanoflann::L2_Simple_Adaptor<double, Dataset, double, std::uint32_t>;
    using Tree = nanoflann::KDTreeSingleIndexAdaptor<Metric, Dataset, 3, std::uint32_t>;

    /// Heap-held, so the tree's reference to the dataset survives moves of the store.
    struct Index {
        std::vector<Record> records;
        Dataset dataset{&records};
        Tree tree;
        explicit Index(std::vector<Record> r)
            : records(std::move(r)), tree(3, dataset, nanoflann::KDTreeSingleIndexAdaptorParams(leaf_size)) {
            into_leaf_order();
        }
        /// Puts the records in the order of nanoflann's permutation (vAcc, public in 1.4) and
        /// makes the permutation the identity: record i is then where the tree looks for it.
        void into_leaf_order() {
            std::vector<Record> ordered;
            ordered.reserve(records.size());
            for (const std::uint32_t i : tree.vAcc) ordered.push_back(records[i]);
            records.swap(ordered);  // the dataset points at `records`, which now holds them
            std::iota(tree.vAcc.begin(), tree.vAcc.end(), std::uint32_t{0});
        }
    };

    /// How many steps, from the one centred at `centre`, have provably empty balls: the ball
    /// j strides further lies inside the sphere of radius j stride + ball about `centre`,
    /// which holds no record while that radius is below the nearest record's distance
    /// (shrunk by 1e-9 for rounding). This lets along() cross empty space in a few steps
    /// however small the radius.
    double empty_steps(const vec3& centre, double ball, double stride) const {
        detail::NearestDistanceResultSet<Record> nearest(index_->records, centre);
        search(centre, nearest);
        const double clearance = std::sqrt(nearest.distance2()) * (1.0 - 1e-9) - ball;
        if (clearance <= 0.0) return 0.0;
        return stride > 0.0 ? std::floor(clearance / stride) + 1.0 : detail::infinity;
    }

    template <class ResultSet>
    void search(const vec3& centre, ResultSet& result) const {
        if (size() == 0) return;
        const std::array<double, 3> query{centre.x, centre.y, centre.z};
        index_->tree.findNeighbors(result, query.data(), nanoflann::SearchParams());
    }

    std::unique_ptr<Index> index_;
    std::size_t index_bytes_ = 0;
    detail::Box bounds_{};
};

static_assert(PhotonStore<NanoflannStore<CompactRecord>>);
static_assert(PhotonStore<NanoflannStore<FullRecord>>);

}  // namespace secchi
