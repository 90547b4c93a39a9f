#pragma once
// A photon store over nanoflann 1.4.2 (Blanco & Rai 2014, https://github.com/jlblancoc/nanoflann):
// KDTreeSingleIndexAdaptor with the L2_Simple metric, 3 dimensions, uint32_t indices, leaf
// size 10. The records stay in input order (records()); nanoflann keeps its own permutation.
//
// Coordinates are read in double (for CompactRecord the float position converts exactly), so
// nanoflann's squared distances agree with the exact ones to a few ulps. Its L2 metric works
// in squared distances: it is given r.squared(), padded by 1e-9 relative so rounding never
// drops a candidate; every candidate is then re-tested with the exact test BruteForceStore
// uses before it reaches the Collector.
//  - within(p, r): one radius search with a result set wrapping the Collector (nanoflann's
//    RadiusResultSet idea: addPoint returns false to stop the search).
//  - along(ray, r): radius searches centred at steps of length h = 2r along the segment,
//    radius r sqrt(2) (plus the rounding pad): a record in the cylinder projects within r of
//    some centre along the ray and lies within r of the ray, so within r sqrt(2) of that
//    centre. Candidates are filtered with in_cylinder, and a hit is reported only by the step
//    whose centre is closest to its t (round(t / h)), so each record is reported exactly once.
//    Steps cover only the part of the segment inside the records' bounding box padded by r.
//  - nearest(p, k): a k-best result set; ties broken by the smaller index.
//
// Threading contract: build once (the constructor); afterwards every const member may be
// called from any number of threads at once (nanoflann's findNeighbors is const and keeps its
// state on the caller's stack).
#include "secchi/map/kdtree.hpp"
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <nanoflann.hpp>
#include <utility>
#include <vector>

namespace secchi {
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

/// Result set for within(): exact re-test, then the Collector (which may stop the search).
template <PhotonRecord Record, Collector C>
class WithinResultSet {
public:
    WithinResultSet(const std::vector<Record>& records, const vec3& p, double r2, C& collect)
        : records_(records), p_(p), r2_(r2), collect_(collect) {}

    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return pruning_radius2(r2_); }
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
    [[nodiscard]] double worstDist() const { return ball2_; }
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
/// is padded so records tied with the k-th reach addPoint (nanoflann's leaf test is strict).
template <PhotonRecord Record>
class NearestResultSet {
public:
    NearestResultSet(const std::vector<Record>& records, const vec3& p, KBest& best)
        : records_(records), p_(p), best_(best) {}

    [[nodiscard]] bool full() const { return true; }
    [[nodiscard]] double worstDist() const { return pruning_radius2(best_.worst2()); }

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
    /// The records in input order; Hit::index refers to this order.
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
        const double r2 = r.squared(), step = 2.0 * r.value();
        const detail::PaddedSegment segment(ray, r2);
        const auto [t0, t1] = segment.clip(bounds_.lo, bounds_.hi);
        if (t0 > t1) return true;
        // Ball radius: the pad (>= r plus rounding) along the ray and across it.
        const double ball2 = detail::pruning_radius2(2.0 * segment.pad() * segment.pad());
        using StepSet = detail::AlongStepResultSet<Record, C>;
        // One spare step at each end: extra steps cost time, never correctness.
        const double first = std::max(0.0, StepSet::closest_step(t0, step) - 1.0);
        const double last = StepSet::closest_step(t1, step) + 1.0;
        const auto steps = static_cast<std::uint64_t>(last - first) + 1;
        for (std::uint64_t j = 0; j < steps; ++j) {
            const double k = first + static_cast<double>(j);
            StepSet result(index_->records, ray, r2, step, k, ball2, collect);
            search(ray.origin + (k * step) * ray.direction, result);
            if (result.stopped()) return false;
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
            : records(std::move(r)), tree(3, dataset, nanoflann::KDTreeSingleIndexAdaptorParams(leaf_size)) {}
    };

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
