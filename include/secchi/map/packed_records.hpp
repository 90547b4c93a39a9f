#pragma once
// CompactRecords in 12 bytes: the VOI octree's packed layout (RecordLayout::packed, voi_octree.hpp).
//
// A CompactRecord (record.hpp) spends 12 of its 16 bytes on three floats. A store that keeps
// records in runs that share a small box (an octree leaf) can say the same in 8: each
// coordinate as a 21-bit integer q within its run's frame, the three in one 64-bit word
// (x in bits 0-20, y in 21-41, z in 42-62), and the four bytes of direction, band and batch in a
// parallel array: twelve bytes per record, so that the store with its index stays below 16.
//
// Frames. A frame covers the records [begin, next frame's begin) and is made from their
// box [lo, hi] (floats, the tight box). Per axis, step = 2^e is the smallest power of two with
// hi - origin <= (2^21 - 1) step, where origin = floor(lo / step) step; a coordinate c is
// stored as q = (c - origin) / step and read back as origin + q step, in float arithmetic or, by
// the leaf scan's kernels (cylinder_scan.hpp), in double (exact either way: the value is a
// float). q is an integer, and the coordinate read back bit for bit, wherever
//  - step <= position_grid (2^-20 m, record.hpp): CompactRecord::make puts every coordinate on
//    that grid (zeros as +0), so a frame up to (2^21 - 1) 2^-20 m (2 m) wide holds any
//    record; or
//  - |c| >= 2^23 step throughout the box: a float that large is a multiple of its own spacing
//    2^(exponent - 23) >= step (frames far from the origin may be wider).
// A store chooses frames for which one of the two holds on each axis (is_fine(); the octree
// splits a leaf's records into sub-octant runs until they are), and the constructor checks
// every record: one that would not be read back exactly (a CompactRecord not made by make(),
// off the grid) is refused by name. So a packed store holds exactly the records it was given,
// and its queries report the hits, with the values, that a store of plain CompactRecords
// reports (in another order within a leaf split into frames; tests/test_stores.cpp).
//
// A frame is kept in 20 bytes (three float origins, three exponents of the steps, its first
// record). Reading record i finds its frame from a table of the first frame of each block of 256
// records (frames are runs of consecutive records, so the frame is that one or a few after it);
// the leaf scan goes through a run frame by frame (for_each_frame), reading the words in place.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/map/record.hpp"
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <compare>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <ranges>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

/// How a store keeps its records: a std::vector of them, or PackedRecords (CompactRecord only).
enum class RecordLayout { plain, packed };

/// The VOI stores' default record layout: packed for CompactRecords (12 bytes per record
/// instead of 16; the estimate runs at about the plain layout's rate, faster where the target
/// has the leaf scan's SIMD kernels, cylinder_scan.hpp, a little slower with the portable
/// loops), plain for other records. Rates and bytes: BENCHMARKS.md.
template <class Record>
inline constexpr RecordLayout default_record_layout =
    std::same_as<Record, CompactRecord> ? RecordLayout::packed : RecordLayout::plain;

class PackedRecords {
public:
    using value_type = CompactRecord;  ///< what operator[] returns
    static constexpr int bits = 21;                             ///< per coordinate
    static constexpr std::uint32_t max_code = (1u << bits) - 1;  ///< largest q

    /// One axis of a frame: coordinate = origin + q step (step a power of two).
    struct Axis {
        float origin, step;
        /// (q < 2^21 converts as a signed integer: one instruction per vector where an unsigned one is several.)
        [[nodiscard]] float decode(std::uint32_t q) const { return origin + static_cast<float>(static_cast<std::int32_t>(q)) * step; }
    };

    /// A run of records [begin, the next frame's begin) and its axes.
    struct Frame {
        std::array<Axis, 3> axis;
        std::uint32_t begin;  ///< first record
    };

    /// The frame of one axis for coordinates in [lo, hi] (floats, lo <= hi), as described above.
    static Axis axis_frame(float lo, float hi) {
        const double span = static_cast<double>(hi) - static_cast<double>(lo);
        int e = -126;  // the smallest normal float: every step is a float
        if (span > 0.0) {
            int exponent = 0;
            std::frexp(span / max_code, &exponent);  // span / max_code in [2^(exponent - 1), 2^exponent)
            e = std::max(e, exponent - 1);
        }
        for (;; ++e) {  // at most two rounds: origin lies at most one step below lo
            const double step = std::ldexp(1.0, e);
            const double origin = std::floor(static_cast<double>(lo) / step) * step;
            if ((static_cast<double>(hi) - origin) / step <= max_code) return {static_cast<float>(origin), static_cast<float>(step)};
        }
    }

    /// Whether every float in [lo, hi] is read back exactly: |c| >= 2^23 step throughout.
    static bool lossless(const Axis& a, float lo, float hi) {
        const double smallest = (lo <= 0.0f && hi >= 0.0f) ? 0.0 : std::min(std::abs(lo), std::abs(hi));
        return smallest >= 0x1p23 * static_cast<double>(a.step);
    }

    /// Whether a frame over the box [lo, hi] reads back exactly every coordinate of a
    /// CompactRecord made by make() in that box.
    static bool is_fine(const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
        for (int k = 0; k < 3; ++k) {
            const Axis a = axis_frame(lo[k], hi[k]);
            if (a.step > position_grid && !lossless(a, lo[k], hi[k])) return false;
        }
        return true;
    }

    /// The frames of records in a store's order, where the store has no boxes of its own to
    /// frame (the VOI grid): maximal runs of consecutive records whose box is fine, each begun
    /// where the next record would make the run's box too large. Returns their begins.
    static std::vector<std::uint32_t> greedy_frames(const std::vector<CompactRecord>& records) {
        std::vector<std::uint32_t> begins;
        std::array<float, 3> lo{}, hi{};
        for (std::uint32_t i = 0; i < records.size(); ++i) {
            const std::array<float, 3> p{records[i].x, records[i].y, records[i].z};
            std::array<float, 3> l = lo, h = hi;
            for (int k = 0; k < 3; ++k) l[k] = std::min(l[k], p[k]), h[k] = std::max(h[k], p[k]);
            if (!begins.empty() && ((l == lo && h == hi) || fits(l, h))) {
                lo = l, hi = h;
                continue;
            }
            begins.push_back(i);
            lo = p, hi = p;
        }
        return begins;
    }

    PackedRecords() = default;

    /// records (in the store's order) in frames that begin at frame_begins (increasing, the
    /// first 0 when there are records; each frame runs to the next one's begin). Throws
    /// input_error, naming the record and coordinate, if one would not be read back exactly.
    PackedRecords(const std::vector<CompactRecord>& records, const std::vector<std::uint32_t>& frame_begins)
        : size_(static_cast<std::uint32_t>(records.size())) {
        require(records.empty() || (!frame_begins.empty() && frame_begins.front() == 0), "packed record frames",
                frame_begins.size(), "must start at record 0");
        codes_.resize(records.size());
        attributes_.resize(records.size());
        frames_.reserve(frame_begins.size() + 1);
        for (std::size_t f = 0; f < frame_begins.size(); ++f) {
            const std::uint32_t begin = frame_begins[f];
            const std::uint32_t end = f + 1 < frame_begins.size() ? frame_begins[f + 1] : size_;
            require(begin < end && end <= size_, "packed record frame", begin, "must be a non-empty run of the records");
            const Frame frame = make_frame(records, begin, end);
            frames_.push_back(KeptFrame::keep(frame));
            for (std::uint32_t i = begin; i < end; ++i) pack(records[i], frame, i);
        }
        frames_.push_back(KeptFrame{{}, size_, {}});  // sentinel: frame_of's search stops at it
        block_frame_.resize((std::size_t{size_} + block - 1) / block);
        std::uint32_t f = 0;
        for (std::size_t b = 0; b < block_frame_.size(); ++b) {
            while (frames_[f + 1].begin <= b * block) ++f;
            block_frame_[b] = f;
        }
    }

    [[nodiscard]] std::size_t size() const { return size_; }
    [[nodiscard]] bool empty() const { return size_ == 0; }
    [[nodiscard]] std::size_t memory_bytes() const {
        return codes_.capacity() * sizeof(std::uint64_t) + attributes_.capacity() * sizeof(Attributes) +
               frames_.capacity() * sizeof(KeptFrame) + block_frame_.capacity() * sizeof(std::uint32_t);
    }

    /// Record i as a CompactRecord: its position read back, its other bytes as stored. Read per
    /// photon in the second pass's loops: always inlined (SECCHI_KERNEL).
    [[nodiscard]] SECCHI_KERNEL CompactRecord operator[](std::uint32_t i) const {
        const Attributes a = attributes_[i];
        CompactRecord r{0.0f, 0.0f, 0.0f, a.theta, a.phi, a.band, a.batch};
        read_position(codes_[i], frames_[frame_of(i)].frame(), r);
        return r;
    }

    /// The records as a random-access range of CompactRecord values (what the store's
    /// records() gives). Written out rather than std::views::iota | transform: clang 14 cannot
    /// compile libstdc++ 12's iota_view.
    class View {
    public:
        class iterator {
        public:
            using iterator_concept = std::random_access_iterator_tag;
            using iterator_category = std::input_iterator_tag;  // its reference is a value
            using value_type = CompactRecord;
            using difference_type = std::ptrdiff_t;
            iterator() = default;
            iterator(const PackedRecords* records, difference_type i) : records_(records), i_(i) {}
            CompactRecord operator*() const { return (*records_)[static_cast<std::uint32_t>(i_)]; }
            CompactRecord operator[](difference_type n) const { return *(*this + n); }
            iterator& operator++() { return ++i_, *this; }
            iterator operator++(int) { return {records_, i_++}; }
            iterator& operator--() { return --i_, *this; }
            iterator operator--(int) { return {records_, i_--}; }
            iterator& operator+=(difference_type n) { return i_ += n, *this; }
            iterator& operator-=(difference_type n) { return i_ -= n, *this; }
            friend iterator operator+(iterator it, difference_type n) { return it += n; }
            friend iterator operator+(difference_type n, iterator it) { return it += n; }
            friend iterator operator-(iterator it, difference_type n) { return it -= n; }
            friend difference_type operator-(const iterator& a, const iterator& b) { return a.i_ - b.i_; }
            friend bool operator==(const iterator& a, const iterator& b) { return a.i_ == b.i_; }
            friend auto operator<=>(const iterator& a, const iterator& b) { return a.i_ <=> b.i_; }

        private:
            const PackedRecords* records_ = nullptr;
            difference_type i_ = 0;
        };

        explicit View(const PackedRecords& records) : records_(&records) {}
        [[nodiscard]] iterator begin() const { return {records_, 0}; }
        [[nodiscard]] iterator end() const { return {records_, static_cast<std::ptrdiff_t>(records_->size())}; }
        [[nodiscard]] std::size_t size() const { return records_->size(); }
        [[nodiscard]] bool empty() const { return records_->empty(); }
        CompactRecord operator[](std::size_t i) const { return (*records_)[static_cast<std::uint32_t>(i)]; }

    private:
        const PackedRecords* records_;
    };
    [[nodiscard]] View view() const { return View(*this); }

    /// The index of the frame holding record i (i < size()).
    [[nodiscard]] std::uint32_t frame_of(std::uint32_t i) const {
        std::uint32_t f = block_frame_[i / block];
        while (frames_[f + 1].begin <= i) ++f;
        return f;
    }

    /// Calls visit(first, last, frame) for each run [first, last) of records [begin, end)
    /// (begin < end <= size()) that one frame holds, in order.
    template <class Visit>
    void for_each_frame(std::uint32_t begin, std::uint32_t end, Visit&& visit) const {
        for (std::uint32_t f = frame_of(begin); begin < end; ++f) {
            const std::uint32_t stop = std::min(end, frames_[f + 1].begin);
            visit(begin, stop, frames_[f].frame());
            begin = stop;
        }
    }

    /// Integer q of coordinate `axis` (0: x, 1: y, 2: z) in a position word.
    [[nodiscard]] static std::uint32_t field(std::uint64_t code, int axis) {
        return static_cast<std::uint32_t>(code >> (bits * axis)) & max_code;
    }

    /// The positions of records [first, last) of one frame (a run for_each_frame gives) as
    /// floats, exact, into x, y and z [0, last - first): a loop the compiler vectorises (the
    /// leaf scan's portable form; its SIMD kernels read the words themselves).
    void read_positions(std::uint32_t first, std::uint32_t last, const Frame& frame, float* x,
                        float* y, float* z) const {
        const std::uint64_t* const codes = codes_.data() + first;
        const Axis ax = frame.axis[0], ay = frame.axis[1], az = frame.axis[2];
        for (std::uint32_t k = 0; k < last - first; ++k) {
            x[k] = ax.decode(field(codes[k], 0));
            y[k] = ay.decode(field(codes[k], 1));
            z[k] = az.decode(field(codes[k], 2));
        }
    }

    /// The 64-bit position words, in record order (the leaf scan prefetches them).
    [[nodiscard]] const std::uint64_t* codes() const { return codes_.data(); }
    /// The other bytes of the records (direction, band, batch), attribute_stride per record in
    /// record order (the leaf scan prefetches them for the collector).
    [[nodiscard]] const std::byte* attribute_bytes() const { return reinterpret_cast<const std::byte*>(attributes_.data()); }
    static constexpr std::size_t attribute_stride = 4;

private:
    static constexpr std::uint32_t block = 256;  ///< records per entry of block_frame_

    /// is_fine(lo, hi), with a shortcut: on an axis where hi - lo <= (2^21 - 2) position_grid,
    /// axis_frame's step is at most position_grid (its origin lies less than one step below lo,
    /// so hi - origin < (2^21 - 1) step at step = position_grid). The bound below keeps one more
    /// step, for the rounding of the difference.
    static bool fits(const std::array<float, 3>& lo, const std::array<float, 3>& hi) {
        constexpr double narrow = (max_code - 2) * position_grid;
        bool narrow_box = true;
        for (int k = 0; k < 3; ++k) narrow_box = narrow_box && static_cast<double>(hi[k]) - lo[k] <= narrow;
        return narrow_box || is_fine(lo, hi);
    }

    /// A frame as kept: its steps (powers of two) as exponents, 20 bytes instead of Frame's 28.
    struct KeptFrame {
        std::array<float, 3> origin;
        std::uint32_t begin;
        std::array<std::int8_t, 3> exponent;  ///< step = 2^exponent, exponent in [-126, 127]

        static KeptFrame keep(const Frame& f) {
            KeptFrame k{{f.axis[0].origin, f.axis[1].origin, f.axis[2].origin}, f.begin, {}};
            for (int a = 0; a < 3; ++a) k.exponent[a] = static_cast<std::int8_t>(std::ilogb(f.axis[a].step));
            return k;
        }
        [[nodiscard]] Frame frame() const {
            // 2^e as a normal float: its biased exponent e + 127 in bits 23-30
            const auto step = [](int e) { return std::bit_cast<float>(static_cast<std::uint32_t>(e + 127) << 23); };
            return {{Axis{origin[0], step(exponent[0])}, Axis{origin[1], step(exponent[1])}, Axis{origin[2], step(exponent[2])}}, begin};
        }
    };
    static_assert(sizeof(KeptFrame) == 20);

    struct Attributes {
        std::uint8_t theta, phi, band, batch;
    };
    static_assert(sizeof(Attributes) == attribute_stride);

    static Frame make_frame(const std::vector<CompactRecord>& records, std::uint32_t begin, std::uint32_t end) {
        std::array<float, 3> lo{records[begin].x, records[begin].y, records[begin].z}, hi = lo;
        for (std::uint32_t i = begin; i < end; ++i) {
            const std::array<float, 3> p{records[i].x, records[i].y, records[i].z};
            for (int k = 0; k < 3; ++k) {
                require(std::isfinite(p[k]), "photon record coordinate", p[k], "must be finite");
                lo[k] = std::min(lo[k], p[k]);
                hi[k] = std::max(hi[k], p[k]);
            }
        }
        return Frame{{axis_frame(lo[0], hi[0]), axis_frame(lo[1], hi[1]), axis_frame(lo[2], hi[2])}, begin};
    }

    /// q = (c - origin) / step, in [0, max_code] for c in the frame's box; input_error unless
    /// it is an integer that reads c back exactly, both in float (decode) and in double
    /// (origin + q step, as the leaf scan's kernels compute it: cylinder_scan.hpp).
    static std::uint64_t code(float c, const Axis& a, std::uint32_t record, const char* axis) {
        // times 1 / step, a power of two (exact), and rounded by two additions: no library call
        // (std::nearbyint is one without SSE4.1); a q that is not exact fails the test below.
        const double q = detail::round_to_integer((static_cast<double>(c) - a.origin) * (1.0 / static_cast<double>(a.step)));
        const bool exact = q >= 0.0 && q <= max_code &&
                           std::bit_cast<std::uint32_t>(a.decode(static_cast<std::uint32_t>(q))) == std::bit_cast<std::uint32_t>(c) &&
                           static_cast<double>(a.origin) + q * static_cast<double>(a.step) == static_cast<double>(c);
        if (!exact)
            reject(std::string("photon record ") + std::to_string(record) + " coordinate " + axis, c,
                   "cannot be packed exactly with its neighbours (step " + std::to_string(a.step) +
                       " m): make CompactRecords with CompactRecord::make, whose coordinates lie on its 2^-20 m grid");
        return static_cast<std::uint64_t>(q);
    }

    void pack(const CompactRecord& r, const Frame& frame, std::uint32_t i) {
        codes_[i] = code(r.x, frame.axis[0], i, "x") | code(r.y, frame.axis[1], i, "y") << bits |
                    code(r.z, frame.axis[2], i, "z") << (2 * bits);
        attributes_[i] = {r.theta, r.phi, r.band_, r.batch_};
    }

    static void read_position(std::uint64_t code, const Frame& frame, CompactRecord& r) {
        r.x = frame.axis[0].decode(field(code, 0));
        r.y = frame.axis[1].decode(field(code, 1));
        r.z = frame.axis[2].decode(field(code, 2));
    }

    std::uint32_t size_ = 0;
    std::vector<std::uint64_t> codes_;       ///< positions, 21 bits per axis
    std::vector<Attributes> attributes_;     ///< theta, phi, band, batch (with the store's tag bits)
    std::vector<KeptFrame> frames_;          ///< in record order, then a sentinel at size_
    std::vector<std::uint32_t> block_frame_; ///< the frame holding record b * block
};

static_assert(std::random_access_iterator<PackedRecords::View::iterator>);
static_assert(std::ranges::random_access_range<PackedRecords::View> && std::ranges::sized_range<PackedRecords::View>);

}  // namespace secchi
