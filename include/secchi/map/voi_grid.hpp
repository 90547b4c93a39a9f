#pragma once
// A uniform grid for the "volume of influence" collection (DIRSIG water manual, section 3.5):
// the same query as the VOI octree (voi_octree.hpp), every record inside the flat-capped
// cylinder of radius r around a ray segment, found by walking the grid's columns instead of
// an octree's boxes.
//
// Build: the bounding box of the positions is cut into cells, `column_width` wide in x and y
// and `cell_height` tall in z. The records are sorted by cell (a stable counting sort) with
// z the fastest index, so that each column's records are one contiguous run in depth order
// and any run of its cells is one contiguous range of records(); `offsets` holds where each
// cell's records begin (CellOffsets, cell_offsets.hpp: about 1.5 bytes per cell). A point's
// cell along an axis is floor((v - lo) / width), clamped to the grid: a monotone function of
// v, so the cells of a query interval [a, b] are exactly those from a's cell to b's, with no
// rounding margin.
//
// along(ray, r): the columns the cylinder can reach are those whose square, padded by r (and
// detail::pruning_pad's rounding margin), the segment's projection meets; a column is
// skipped too when the projection passes farther than the pad from its square (its
// corners). In each column the cylinder's points lie within the pad of the segment's
// stretch over the padded square, so their depths lie in one interval, i.e. one run of
// cells, i.e. one range of records. Those ranges are scanned by the VOI stores' leaf scan
// (range_scan.hpp: in_cylinder's arithmetic, SIMD where the target has it), in column
// order: the hits come in increasing record index, deterministic for a given build.
// Columns are enumerated row by row over the segment's reach, so the walk costs one step
// per column the cylinder's shadow touches, not per cell of the grid.
//
// Against the octree (BENCHMARKS.md): the walk is a few dozen columns per ray instead of a
// tree descent with a box test per node, and each column's records are one long run that
// the processor's prefetchers stream; the records tested per hit depend on the column width
// against r (narrower: fewer wasted records, more columns). Measured (search_bench, a
// problem-2a map of 6.5e6 records, on a Zen 3), at r = 0.026 with cells r/2 by r:
//  - vertical rays (nadir views, the conformance problems' Lu) cut each column once, over
//    their length: 21 ranges and 15,900 records tested per ray for 9,200 hits (the octree:
//    601 nodes and 17,300 tested); 1.4-2.6 times the octree's search rate over
//    r = 0.013-0.052; columns of r/2 or narrower are fastest, the height matters little;
//  - slanted rays cut more columns, each over a shorter range (rays of length 1 at 30-85
//    degrees from the vertical: 160-200 ranges, 2.7-3 records tested per hit): 2.1-2.9
//    times the octree's search rate.
// Memory: the records, plus about 1.5 bytes per cell (CellOffsets); the grid is limited to
// max_cells_per_record cells per record (the widths grow by a common factor if needed), so the
// index costs at most about 3.1 bytes per record.
//
// Record layout (the Layout parameter; default_record_layout, packed_records.hpp): plain keeps a
// std::vector of the records; RecordLayout::packed (CompactRecord only, the default for it)
// keeps them in 12 bytes, 21-bit coordinates within frames that are maximal runs of the grid
// order (PackedRecords::greedy_frames: a column's records over up to 2 m of depth, or several
// neighbouring columns'). The records read back exactly, in the same order, so both layouts
// report the same hits with the same values; the leaf scan reads the packed words in place.
//
// within(p, r): the columns within r of p, the cells within r of p.z, each record's distance.
//
// Threading contract: build once (the constructor); afterwards every const member may be
// called from any number of threads at once.
#include "secchi/core/config.hpp"
#include "secchi/map/cell_offsets.hpp"
#include "secchi/map/packed_records.hpp"
#include "secchi/map/range_scan.hpp"
#include "secchi/map/search_support.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

template <PhotonRecord Record, RecordLayout Layout = default_record_layout<Record>>
class VoiGridStore {
    static constexpr bool is_packed = Layout == RecordLayout::packed;
    static_assert(!is_packed || std::same_as<Record, CompactRecord>, "only CompactRecords pack (packed_records.hpp)");

public:
    using record_type = Record;
    /// Without a column width, cells hold this many records on average over the bounding box.
    static constexpr double default_records_per_cell = 16.0;
    /// At most this many cells per record (CellOffsets: about 1.5 bytes each): wider cells beyond it.
    static constexpr double max_cells_per_record = 2.0;

    /// `column_width`: the cells' size in x and y (m); 0 for a width from the records'
    /// density (default_records_per_cell). `cell_height`: their size in z; 0 for the column
    /// width (cubic cells). Both are widened by one factor if the grid would exceed
    /// max_cells_per_record.
    explicit VoiGridStore(std::vector<Record> records, double column_width = 0.0, double cell_height = 0.0)
        : records_(std::move(records)) {
        detail::require_indexable(records_.size());
        require(std::isfinite(column_width) && column_width >= 0.0, "grid column width", column_width,
                "must be finite and >= 0 (0: from the records' density)");
        require(std::isfinite(cell_height) && cell_height >= 0.0, "grid cell height", cell_height,
                "must be finite and >= 0 (0: the column width)");
        build(column_width, cell_height);
    }

    /// Cells sized for queries of radius r: columns r / 2 wide and r tall (tuned on vertical
    /// rays through a problem-2a map and through uniform points; BENCHMARKS.md). For slanted
    /// rays, columns r wide and r tall (the width/height constructor) cut fewer, longer
    /// ranges: 1.3-2.2 times this shape's search rate at 30-85 degrees from the vertical, and
    /// 0.8 times it on vertical rays (search_bench --suite tune, on a Zen 3).
    static constexpr double column_width_per_radius = 0.5, cell_height_per_radius = 1.0;
    VoiGridStore(std::vector<Record> records, Radius collection_radius)
        : VoiGridStore(std::move(records), column_width_per_radius * collection_radius.value(),
                       cell_height_per_radius * collection_radius.value()) {}

    [[nodiscard]] std::size_t size() const { return stored().size(); }
    /// The records in grid order (by column, then depth); Hit::index refers to it. Packed: a
    /// range of CompactRecord values, their positions as read back (packed_records.hpp).
    [[nodiscard]] decltype(auto) records() const {
        if constexpr (is_packed) return packed_.view();
        else return (records_);
    }
    [[nodiscard]] std::size_t memory_bytes() const {
        return records_.capacity() * sizeof(Record) + packed_.memory_bytes() + offsets_.memory_bytes();
    }
    /// Cells per axis (x, y, z) and their size (m).
    [[nodiscard]] std::array<std::size_t, 3> cells() const { return count_; }
    [[nodiscard]] vec3 cell_size() const { return size_; }

    /// Every record in the flat-capped cylinder of radius r around the ray segment: the
    /// records whose volume of influence the segment intersects (manual 3.5).
    template <Collector C>
    bool along(const Ray& ray_in, Radius r, C& collect) const {
        const Ray ray = ray_in;  // a local copy: the collector's writes cannot alias it
        const double r2 = r.squared();
        const detail::CylinderRanges<Storage> ranges(stored());
        typename detail::CylinderRanges<Storage>::WorkList work;
        bool complete = true;
        for_each_column_range(ray, detail::pruning_pad(ray, r2), [&](std::uint32_t begin, std::uint32_t end) {
            work.items[work.size++] = {begin, end, false};
            if (work.size < work.items.size()) return true;
            complete = ranges.stream(work, ray, r2, collect);
            work.size = 0;
            return complete;
        });
        return complete && ranges.stream(work, ray, r2, collect);
    }

    /// What one along() query does: the record ranges (one per column reached), the records
    /// tested, the hits.
    struct AlongStats {
        std::size_t ranges = 0, tested = 0, hits = 0;
        AlongStats& operator+=(const AlongStats& o) {
            ranges += o.ranges, tested += o.tested, hits += o.hits;
            return *this;
        }
    };
    [[nodiscard]] AlongStats along_stats(const Ray& ray, Radius r) const {
        AlongStats stats;
        for_each_column_range(ray, detail::pruning_pad(ray, r.squared()), [&](std::uint32_t begin, std::uint32_t end) {
            ++stats.ranges;
            stats.tested += end - begin;
            return true;
        });
        CountHits count;
        along(ray, r, count);
        stats.hits = count.count;
        return stats;
    }

    /// Every record at distance <= r from p.
    template <Collector C>
    bool within(const vec3& p, Radius r, C& collect) const {
        const double r2 = r.squared(), pad = std::sqrt(detail::pruning_radius2(r2));
        // A point is a segment of length 0: its columns and depths within the pad.
        const Ray point{p, {0.0, 0.0, 0.0}, 0.0};
        return for_each_column_range(point, pad, [&](std::uint32_t begin, std::uint32_t end) {
            for (std::uint32_t i = begin; i < end; ++i) {
                const vec3 d = stored()[i].position() - p;
                const double d2 = glm::dot(d, d);
                if (d2 <= r2 && !collect(Hit{i, 0.0, d2})) return false;
            }
            return true;
        });
    }

private:
    /// Where the records live after the build: records_, or packed_ (then records_ is empty).
    using Storage = std::conditional_t<is_packed, PackedRecords, std::vector<Record>>;
    [[nodiscard]] const Storage& stored() const {
        if constexpr (is_packed) return packed_;
        else return records_;
    }

    /// Calls visit(begin, end) for the record range of every column that points within `pad`
    /// of the segment [origin, origin + t_max direction] may lie in, in column order (x
    /// outer, y inner), skipping empty ranges; stops and returns false when visit does.
    template <class Visit>
    bool for_each_column_range(const Ray& ray, double pad, Visit&& visit) const {
        if (size() == 0) return true;
        const vec3 a = ray.origin, b = ray.origin + ray.t_max * ray.direction;
        // The rounding of a cell's bounds (lo + i width) against the index function: far
        // below this margin, which keeps the column tests conservative.
        const double slack = 1e-12 * (std::abs(lo_.x) + std::abs(lo_.y) + size_.x * (count_[0] + count_[1]));
        const auto [ix0, ix1] = axis_range(0, std::min(a.x, b.x) - pad, std::max(a.x, b.x) + pad);
        for (std::size_t ix = ix0; ix <= ix1; ++ix) {
            const double x0 = lo_.x + static_cast<double>(ix) * size_.x - slack, x1 = x0 + size_.x + 2.0 * slack;
            const auto [tx0, tx1] = clip(ray, 0, x0 - pad, x1 + pad, 0.0, ray.t_max);
            if (tx0 > tx1) continue;
            const double ya = ray.origin.y + tx0 * ray.direction.y, yb = ray.origin.y + tx1 * ray.direction.y;
            const auto [iy0, iy1] = axis_range(1, std::min(ya, yb) - pad, std::max(ya, yb) + pad);
            for (std::size_t iy = iy0; iy <= iy1; ++iy) {
                const double y0 = lo_.y + static_cast<double>(iy) * size_.y - slack, y1 = y0 + size_.y + 2.0 * slack;
                const auto [t0, t1] = clip(ray, 1, y0 - pad, y1 + pad, tx0, tx1);
                if (t0 > t1) continue;
                const vec3 p0 = ray.origin + t0 * ray.direction, p1 = ray.origin + t1 * ray.direction;
                if (segment_square_distance2(p0, p1, {x0, y0}, {x1, y1}) > pad * pad) continue;  // a corner
                const auto [iz0, iz1] = axis_range(2, std::min(p0.z, p1.z) - pad, std::max(p0.z, p1.z) + pad);
                if (iz0 > iz1) continue;
                const std::size_t column = (ix * count_[1] + iy) * count_[2];
                const std::uint32_t begin = offsets_[column + iz0], end = offsets_[column + iz1 + 1];
                if (begin < end && !visit(begin, end)) return false;
            }
        }
        return true;
    }

    /// The parameter interval within [t0, t1] where the segment's coordinate `axis` lies in
    /// [low, high] (detail::clip_to_slab); empty (first > second) if none.
    static std::pair<double, double> clip(const Ray& ray, int axis, double low, double high, double t0, double t1) {
        const double u = ray.direction[axis];
        const bool parallel = std::abs(u) < detail::parallel_below;
        return detail::clip_to_slab(ray.origin[axis], parallel ? 0.0 : 1.0 / u, parallel, low, high, t0, t1);
    }

    /// Squared distance in (x, y) between the segment [p0, p1] and the square [lo, hi]: 0 if
    /// they meet, else the least of the end points' distances to the square and the
    /// square's corners' distances to the segment (convex shapes that do not meet).
    static double segment_square_distance2(const vec3& p0, const vec3& p1, std::array<double, 2> lo,
                                           std::array<double, 2> hi) {
        const double dx = p1.x - p0.x, dy = p1.y - p0.y, length2 = dx * dx + dy * dy;
        auto point_square = [&](double x, double y) {
            const double gx = std::max({lo[0] - x, 0.0, x - hi[0]}), gy = std::max({lo[1] - y, 0.0, y - hi[1]});
            return gx * gx + gy * gy;
        };
        double best = std::min(point_square(p0.x, p0.y), point_square(p1.x, p1.y));
        if (best == 0.0 || length2 == 0.0) return best;
        Ray flat{{p0.x, p0.y, 0.0}, {dx, dy, 0.0}, 1.0};  // t in [0, 1] over the segment
        if (const auto [t0, t1] = clip(flat, 0, lo[0], hi[0], 0.0, 1.0); t0 <= t1) {
            if (const auto [s0, s1] = clip(flat, 1, lo[1], hi[1], t0, t1); s0 <= s1) return 0.0;
        }
        for (const double cx : {lo[0], hi[0]})
            for (const double cy : {lo[1], hi[1]}) {
                const double s = std::clamp(((cx - p0.x) * dx + (cy - p0.y) * dy) / length2, 0.0, 1.0);
                const double ex = p0.x + s * dx - cx, ey = p0.y + s * dy - cy;
                best = std::min(best, ex * ex + ey * ey);
            }
        return best;
    }

    /// A coordinate's cell along an axis: floor((v - lo) / size), clamped to the grid.
    /// Monotone in v, so a point in [a, b] has its cell in [cell(a), cell(b)].
    [[nodiscard]] std::size_t cell(int axis, double v) const {
        const double f = (v - lo_[axis]) / size_[axis];
        if (!(f > 0.0)) return 0;
        const double last = static_cast<double>(count_[axis] - 1);
        return static_cast<std::size_t>(std::min(std::floor(f), last));
    }

    /// The cells along an axis that points with coordinate in [a, b] occupy; empty (first >
    /// second) if [a, b] misses the records' bounding box.
    [[nodiscard]] std::pair<std::size_t, std::size_t> axis_range(int axis, double a, double b) const {
        if (b < lo_[axis] || a > hi_[axis]) return {1, 0};
        return {cell(axis, a), cell(axis, b)};
    }

    [[nodiscard]] std::size_t cell_index(const vec3& p) const {
        return (cell(0, p.x) * count_[1] + cell(1, p.y)) * count_[2] + cell(2, p.z);
    }

    void build(double column_width, double cell_height) {
        if (records_.empty()) return;
        const detail::Box box = detail::bounding_box(records_);
        lo_ = box.lo;
        hi_ = box.hi;
        const vec3 extent = hi_ - lo_;
        if (column_width == 0.0) column_width = density_width(extent);
        vec3 size(column_width, column_width, cell_height > 0.0 ? cell_height : column_width);
        // Cell indices are 32-bit (sort_by_cell), as record indices are.
        const double max_cells =
            std::min(max_cells_per_record * static_cast<double>(records_.size()) + 1.0, 4294967294.0);
        for (;;) {  // widen every size by one factor until the grid is small enough
            double cells = 1.0;
            for (int a = 0; a < 3; ++a) cells *= std::max(1.0, std::ceil(extent[a] / size[a]));
            if (cells <= max_cells) break;
            size *= std::max(1.01, std::cbrt(cells / max_cells));
        }
        size_ = size;
        for (int a = 0; a < 3; ++a)
            count_[a] = static_cast<std::size_t>(std::max(1.0, std::ceil(extent[a] / size[a])));
        sort_by_cell();
        if constexpr (is_packed) {
            packed_ = PackedRecords(records_, PackedRecords::greedy_frames(records_));
            records_ = std::vector<Record>();  // (not `= {}`: that keeps the capacity)
        }
    }

    /// The width that puts default_records_per_cell records in a cell on average over the
    /// bounding box (its flat axes ignored); 1 m if the records share one position.
    [[nodiscard]] double density_width(const vec3& extent) const {
        double volume = 1.0;
        int dimensions = 0;
        for (int a = 0; a < 3; ++a)
            if (extent[a] > 0.0) volume *= extent[a], ++dimensions;
        if (dimensions == 0) return 1.0;
        return std::pow(volume * default_records_per_cell / static_cast<double>(records_.size()), 1.0 / dimensions);
    }

    /// A stable counting sort of the records by cell; offsets_[c] is cell c's first record.
    void sort_by_cell() {
        const std::size_t cells = count_[0] * count_[1] * count_[2];
        std::vector<std::uint32_t> offsets(cells + 1, 0);
        std::vector<std::uint32_t> cell_of(records_.size());
        for (std::size_t i = 0; i < records_.size(); ++i) {
            cell_of[i] = static_cast<std::uint32_t>(cell_index(records_[i].position()));
            ++offsets[cell_of[i] + 1];
        }
        for (std::size_t c = 0; c < cells; ++c) offsets[c + 1] += offsets[c];
        std::vector<std::uint32_t> cursor(offsets.begin(), offsets.end() - 1);
        std::vector<Record> sorted(records_.size());
        for (std::size_t i = 0; i < records_.size(); ++i) sorted[cursor[cell_of[i]]++] = records_[i];
        records_.swap(sorted);
        offsets_ = CellOffsets(offsets);
    }

    std::vector<Record> records_;  ///< in grid order (packed: only while building)
    PackedRecords packed_;         ///< packed: the records in grid order
    CellOffsets offsets_;          ///< cells + 1 entries: cell c's records are [offsets_[c], offsets_[c + 1])
    vec3 lo_{0.0}, hi_{0.0};              ///< the records' bounding box
    vec3 size_{1.0};                      ///< a cell's size per axis (m)
    std::array<std::size_t, 3> count_{1, 1, 1};  ///< cells per axis
};

static_assert(PhotonStore<VoiGridStore<CompactRecord>> && PhotonStore<VoiGridStore<CompactRecord, RecordLayout::plain>>);
static_assert(PhotonStore<VoiGridStore<FullRecord>>);

}  // namespace secchi
