// The photon stores (k-d tree, nanoflann, VOI octree, VOI grid) against the brute-force oracle.
#include <catch2/catch.hpp>
#include "secchi/core/rng.hpp"
#include "secchi/map/brute_force.hpp"
#include "secchi/map/cell_offsets.hpp"
#include "secchi/map/kdtree.hpp"
#include "secchi/map/nanoflann_store.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/map/voi_octree.hpp"
#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

using namespace secchi;

namespace {

vec3 random_unit(PhotonRng& rng) {
    const double z = 2.0 * rng.uniform() - 1.0, phi = two_pi * rng.uniform();
    const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
    return {s * std::cos(phi), s * std::sin(phi), z};
}

enum class Layout { uniform, clustered };

/// uniform: positions uniform in the 1 x 1 x 3 box. clustered: shared coordinates on a
/// coarse grid, one position repeated many times, near-coincident points (below the octree's
/// depth limit), a plane and a line, plus some uniform points.
vec3 random_position(Layout layout, std::size_t i, PhotonRng& rng) {
    const double u = rng.uniform(), v = rng.uniform(), w = rng.uniform();
    if (layout == Layout::uniform) return {u, v, 3.0 * w};
    switch (i % 6) {
        case 0:
        case 1: return {std::floor(9 * u) * 0.125, std::floor(9 * v) * 0.125, std::floor(13 * w) * 0.25};
        case 2: return i % 4 == 0 ? vec3(0.5, 0.5, 1.5) : vec3(0.5 + 1e-7 * static_cast<double>(i % 7), 0.5, 1.5);
        case 3: return {u, v, 1.0};
        case 4: return {0.25, 0.75, std::floor(25 * w) * 0.125};
        default: return {u, v, 3.0 * w};
    }
}

template <class Record>
std::vector<Record> make_records(Layout layout, std::size_t n, std::uint64_t seed) {
    PhotonRng rng(seed, 0);
    std::vector<Record> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const vec3 p = random_position(layout, i, rng);
        out.push_back(Record::make(p, random_unit(rng), static_cast<band_index>(rng.bits() % 4),
                                   static_cast<std::uint8_t>(rng.bits() % 8)));
    }
    return out;
}

struct Query {
    vec3 point;
    Ray ray;
    double r;
};

vec3 axis_direction(std::uint32_t which) {
    const std::array<vec3, 6> axes{vec3(0, 0, 1), vec3(0, 0, -1), vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0)};
    return axes[which % 6];
}

/// ~100 queries: points and ray origins in and around the box, radii 1e-4 to 5 (larger than
/// the box), random and axis-parallel directions, zero-length segments, rays from far outside,
/// and (clustered) queries exactly on the grid with radii equal to the grid spacing.
std::vector<Query> make_queries(Layout layout, int count, std::uint64_t seed) {
    PhotonRng rng(seed, 1);
    std::vector<Query> out;
    for (int i = 0; i < count; ++i) {
        Query q{};
        q.r = std::pow(10.0, -4.0 + 4.7 * rng.uniform());
        q.point = {-0.5 + 2 * rng.uniform(), -0.5 + 2 * rng.uniform(), -1 + 5 * rng.uniform()};
        q.ray.origin = {-0.5 + 2 * rng.uniform(), -0.5 + 2 * rng.uniform(), -1 + 5 * rng.uniform()};
        q.ray.direction = i % 3 == 0 ? axis_direction(rng.bits()) : random_unit(rng);
        q.ray.t_max = 6.0 * rng.uniform();
        if (i % 20 == 7) q.ray.t_max = 0.0;
        if (i % 10 == 3) {  // from far outside, through the box
            q.ray = {vec3(-10.0, 0.3 + 0.4 * rng.uniform(), 3 * rng.uniform()), vec3(1, 0, 0), 20.0};
        }
        if (i % 25 == 11) q.ray.direction = glm::normalize(vec3(1e-20, -1e-310, 1.0));
        if (layout == Layout::clustered && i % 4 == 1) {  // exactly on the grid: ties at distance r
            const vec3 g(std::floor(9 * rng.uniform()) * 0.125, std::floor(9 * rng.uniform()) * 0.125,
                         std::floor(13 * rng.uniform()) * 0.25);
            q.point = g;
            q.ray = {vec3(g.x, g.y, -1.0), vec3(0, 0, 1), 5.0};
            q.r = (rng.bits() % 2 == 0) ? 0.125 : 0.25;
        }
        out.push_back(q);
    }
    out.push_back({vec3(0.5, 0.5, 1.5), Ray{vec3(0.5, 0.5, -1.0), vec3(0, 0, 1), 5.0}, 1e-9});
    out.push_back({vec3(0.25, 0.75, 1.0), Ray{vec3(0.25, 0.75, 5.0), vec3(0, 0, -1), 10.0}, 1e-6});
    return out;
}

/// A hit with the position of its record (stores reorder records, so positions identify them).
struct Found {
    double x, y, z, t, d2;
    std::uint32_t index;
    auto key() const { return std::tie(x, y, z, t, d2); }
};

template <class Store>
std::vector<Found> located(const Store& s, const std::vector<Hit>& hits) {
    std::vector<Found> out;
    for (const Hit& h : hits) {
        REQUIRE(h.index < s.size());
        const vec3 p = s.records()[h.index].position();
        out.push_back({p.x, p.y, p.z, h.t, h.distance2, h.index});
    }
    std::sort(out.begin(), out.end(), [](const Found& a, const Found& b) { return a.key() < b.key(); });
    return out;
}

bool close(double a, double b) { return a == b || std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b)); }

/// "" if the two hit lists hold the same multiset of positions with matching t and distance2
/// (within d2_slack where rounding dominates them) and `got` reports no record twice; else a
/// description of the first difference.
std::string compare(const std::vector<Found>& got, const std::vector<Found>& want, double d2_slack = 0.0) {
    std::ostringstream msg;
    std::vector<std::uint32_t> indices;
    for (const Found& f : got) indices.push_back(f.index);
    std::sort(indices.begin(), indices.end());
    if (std::adjacent_find(indices.begin(), indices.end()) != indices.end()) return "a record reported twice";
    if (got.size() != want.size()) {
        msg << "got " << got.size() << " hits, brute force " << want.size();
        return msg.str();
    }
    for (std::size_t i = 0; i < got.size(); ++i) {
        const Found &g = got[i], &w = want[i];
        const bool d2_matches = close(g.d2, w.d2) || std::abs(g.d2 - w.d2) <= d2_slack;
        if (g.x != w.x || g.y != w.y || g.z != w.z || !close(g.t, w.t) || !d2_matches) {
            msg.precision(17);
            msg << "hit " << i << ": (" << g.x << ", " << g.y << ", " << g.z << ") t " << g.t << " d2 " << g.d2
                << " vs (" << w.x << ", " << w.y << ", " << w.z << ") t " << w.t << " d2 " << w.d2;
            return msg.str();
        }
    }
    return {};
}

template <class Store>
std::vector<Found> run_within(const Store& s, const Query& q) {
    CollectAll all;
    const bool completed = s.within(q.point, Radius(q.r), all);
    REQUIRE(completed);
    return located(s, all.hits);
}

template <class Store>
std::vector<Found> run_along(const Store& s, const Query& q) {
    CollectAll all;
    const bool completed = s.along(q.ray, Radius(q.r), all);
    REQUIRE(completed);
    return located(s, all.hits);
}

/// Sorted positions (and directions) of the records: stores must hold a permutation of the input.
template <class Records>
std::vector<std::tuple<double, double, double, double, double, double>> contents(const Records& records) {
    std::vector<std::tuple<double, double, double, double, double, double>> out;
    for (const auto& r : records) {
        const vec3 p = r.position(), d = r.direction();
        out.emplace_back(p.x, p.y, p.z, d.x, d.y, d.z);
    }
    std::sort(out.begin(), out.end());
    return out;
}

template <class Store>
void require_agreement(const std::vector<typename Store::record_type>& records, const Store& store, Layout layout,
                       std::uint64_t seed) {
    const BruteForceStore<typename Store::record_type> brute(records);
    REQUIRE(store.size() == records.size());
    REQUIRE(contents(store.records()) == contents(records));
    for (const Query& q : make_queries(layout, 100, seed)) {
        INFO("point (" << q.point.x << ", " << q.point.y << ", " << q.point.z << ") ray origin (" << q.ray.origin.x << ", "
                       << q.ray.origin.y << ", " << q.ray.origin.z << ") direction (" << q.ray.direction.x << ", "
                       << q.ray.direction.y << ", " << q.ray.direction.z << ") t_max " << q.ray.t_max << " r " << q.r);
        REQUIRE(compare(run_within(store, q), run_within(brute, q)) == "");
        REQUIRE(compare(run_along(store, q), run_along(brute, q)) == "");
    }
}

/// Stops the search on its `limit`-th call.
struct StopAfter {
    int calls = 0;
    int limit = 5;
    bool operator()(const Hit&) { return ++calls < limit; }
};

/// Nearer first; ties broken by the smaller index.
bool nearer(const Hit& a, const Hit& b) { return std::tie(a.distance2, a.index) < std::tie(b.distance2, b.index); }

/// The k nearest by (distance2, index) over the store's own records: the exact expectation.
template <class Store>
std::vector<Hit> expected_nearest(const Store& s, const vec3& p, std::size_t k) {
    std::vector<Hit> all;
    for (std::size_t i = 0; i < s.size(); ++i) {
        const vec3 d = s.records()[i].position() - p;
        all.push_back({static_cast<std::uint32_t>(i), 0.0, glm::dot(d, d)});
    }
    std::sort(all.begin(), all.end(), nearer);
    all.resize(std::min(k, all.size()));
    return all;
}

}  // namespace

static_assert(PhotonStore<KdTreeStore<CompactRecord>> && PhotonStore<KdTreeStore<FullRecord>>);
static_assert(PhotonStore<NanoflannStore<CompactRecord>> && PhotonStore<NanoflannStore<FullRecord>>);
static_assert(PhotonStore<VoiOctreeStore<CompactRecord>> && PhotonStore<VoiOctreeStore<FullRecord>>);
/// The octree's two layouts of CompactRecords, named (the default: packed; voi_octree.hpp).
using PlainOctree = VoiOctreeStore<CompactRecord, RecordLayout::plain>;
using PackedOctree = VoiOctreeStore<CompactRecord, RecordLayout::packed>;
static_assert(PhotonStore<PlainOctree> && PhotonStore<PackedOctree>);
static_assert(std::same_as<VoiOctreeStore<CompactRecord>, PackedOctree>);
/// The grid's likewise (the default: packed; voi_grid.hpp).
using PlainGrid = VoiGridStore<CompactRecord, RecordLayout::plain>;
using PackedGrid = VoiGridStore<CompactRecord, RecordLayout::packed>;
static_assert(std::same_as<VoiGridStore<CompactRecord>, PackedGrid>);

#define SECCHI_ALL_STORES                                                                                          \
    KdTreeStore<CompactRecord>, KdTreeStore<FullRecord>, NanoflannStore<CompactRecord>, NanoflannStore<FullRecord>, \
        PlainOctree, VoiOctreeStore<FullRecord>, PackedOctree, PlainGrid, PackedGrid, VoiGridStore<FullRecord>

TEMPLATE_TEST_CASE("within and along report exactly the brute-force records", "[stores]", SECCHI_ALL_STORES) {
    using Record = typename TestType::record_type;
    SECTION("20000 uniform points in a 1 x 1 x 3 box") {
        const auto records = make_records<Record>(Layout::uniform, 20000, 11);
        require_agreement(records, TestType(records), Layout::uniform, 12);
    }
    SECTION("clustered points: shared coordinates, repeated and near-coincident positions") {
        const auto records = make_records<Record>(Layout::clustered, 6000, 13);
        require_agreement(records, TestType(records), Layout::clustered, 14);
    }
}

TEMPLATE_TEST_CASE("along matches brute force where in_cylinder's rounding dominates", "[stores]", SECCHI_ALL_STORES) {
    // Records within 0.5 r to 4 r of a ray that starts far away: in_cylinder's
    // dist^2 = |d|^2 - t^2 then loses more than r^2 to cancellation, so the oracle accepts
    // records beyond r. The stores' pruning pads must still never drop one it accepts.
    using Record = typename TestType::record_type;
    PhotonRng rng(91, 0);
    const vec3 dir = glm::normalize(vec3(0.3, -0.2, 0.9)), base(0.5, 0.5, 1.5);
    const vec3 perp = glm::normalize(glm::cross(dir, vec3(1, 0, 0))), perp2 = glm::cross(dir, perp);
    for (const double r : {1e-6, 1e-7, 1e-8}) {
        std::vector<Record> records = make_records<Record>(Layout::uniform, 2000, 92);
        for (int j = 0; j < 2000; ++j) {
            const double offset = r * (0.5 + 3.5 * rng.uniform()), phi = two_pi * rng.uniform();
            const vec3 p = base + offset * (std::cos(phi) * perp + std::sin(phi) * perp2) + (rng.uniform() - 0.5) * dir;
            records.push_back(Record::make(p, dir, 0, 0));
        }
        const TestType store(records);
        const BruteForceStore<Record> brute(records);
        for (const double far : {1.0, 10.0, 100.0, 1000.0}) {
            const Query q{base, Ray{base - far * dir, dir, 2.0 * far}, r};
            INFO("r " << r << " origin " << far << " m away");
            // Where the compiler fuses multiply-adds (-ffp-contract=fast on an FMA target) it
            // may fuse the two codes differently. Each component of perp = d - t u then differs
            // by at most a few ulp of |d| <= far + 1 (delta = 8 eps (far + 1)), so for records
            // within 4 r of the axis dist^2 = perp . perp differs by at most delta (8 r + delta).
#if defined(__FMA__)
            const double delta = 8.0 * std::numeric_limits<double>::epsilon() * (far + 1.0);
            const double d2_slack = delta * (8.0 * r + delta);
#else
            const double d2_slack = 0.0;
#endif
            REQUIRE(compare(run_along(store, q), run_along(brute, q), d2_slack) == "");
        }
    }
}

TEMPLATE_TEST_CASE("empty and single-record stores", "[stores]", SECCHI_ALL_STORES) {
    using Record = typename TestType::record_type;
    const TestType empty(std::vector<Record>{});
    REQUIRE(empty.size() == 0);
    REQUIRE(std::ranges::empty(empty.records()));
    for (const Query& q : make_queries(Layout::uniform, 20, 21)) {
        CountHits count;
        REQUIRE(empty.within(q.point, Radius(q.r), count));
        REQUIRE(empty.along(q.ray, Radius(q.r), count));
        REQUIRE(count.count == 0);
    }
    const auto one = make_records<Record>(Layout::uniform, 1, 22);
    const TestType single(one);
    REQUIRE(single.size() == 1);
    require_agreement(one, single, Layout::uniform, 23);
    const vec3 p = one[0].position();
    CollectAll all;
    REQUIRE(single.within(p + vec3(0.1, 0, 0), Radius(0.2), all));
    REQUIRE(single.along(Ray{p - vec3(0, 0, 1), vec3(0, 0, 1), 2.0}, Radius(1e-6), all));
    REQUIRE(all.hits.size() == 2);
    REQUIRE(all.hits[1].t == Approx(1.0));
    // r^2 underflows to 0: the record at distance 0 is still found.
    REQUIRE(single.within(p, Radius(1e-200), all));
    REQUIRE(all.hits.size() == 3);
    REQUIRE(all.hits[2].distance2 == 0.0);
}

TEMPLATE_TEST_CASE("a collector returning false stops the search", "[stores]", SECCHI_ALL_STORES) {
    using Record = typename TestType::record_type;
    const TestType store(make_records<Record>(Layout::uniform, 20000, 31));
    StopAfter within_stop, along_stop;
    REQUIRE_FALSE(store.within(vec3(0.5, 0.5, 1.5), Radius(0.5), within_stop));
    REQUIRE(within_stop.calls == 5);
    REQUIRE_FALSE(store.along(Ray{vec3(0.5, 0.5, -1.0), vec3(0, 0, 1), 5.0}, Radius(0.2), along_stop));
    REQUIRE(along_stop.calls == 5);
    CountHits count{0, 1};
    REQUIRE_FALSE(store.along(Ray{vec3(0.3, 0.6, -1.0), glm::normalize(vec3(0.1, 0, 1)), 5.0}, Radius(0.3), count));
    REQUIRE(count.count == 1);
}

TEMPLATE_TEST_CASE("nearest matches the brute-force k nearest", "[stores]", KdTreeStore<CompactRecord>,
                   KdTreeStore<FullRecord>, NanoflannStore<CompactRecord>, NanoflannStore<FullRecord>) {
    using Record = typename TestType::record_type;
    for (const Layout layout : {Layout::uniform, Layout::clustered}) {
        const auto records = make_records<Record>(layout, 6000, 41);
        const TestType store(records);
        const BruteForceStore<Record> brute(records);
        auto points = make_queries(layout, 30, 42);
        points.push_back({vec3(0.5, 0.5, 1.5), {}, 1.0});  // 1000 records tied at distance 0
        for (const Query& q : points) {
            for (const std::size_t k : {1u, 8u, 50u}) {
                INFO("layout " << static_cast<int>(layout) << " point (" << q.point.x << ", " << q.point.y << ", "
                               << q.point.z << ") k " << k);
                std::vector<Hit> got;
                store.nearest(q.point, k, got);
                const auto want = expected_nearest(store, q.point, k);
                REQUIRE(got.size() == want.size());
                for (std::size_t i = 0; i < got.size(); ++i) {
                    REQUIRE(got[i].index == want[i].index);
                    REQUIRE(got[i].distance2 == want[i].distance2);
                }
                // The distances are those of the brute-force k nearest over the input order.
                const auto oracle = expected_nearest(brute, q.point, k);
                for (std::size_t i = 0; i < got.size(); ++i) REQUIRE(got[i].distance2 == oracle[i].distance2);
            }
        }
        std::vector<Hit> out{Hit{}};
        store.nearest(vec3(0.5), 0, out);
        REQUIRE(out.empty());
        store.nearest(vec3(0.5), 10000, out);
        REQUIRE(out.size() == records.size());
        REQUIRE(std::is_sorted(out.begin(), out.end(), nearer));
    }
    const TestType empty(std::vector<Record>{});
    std::vector<Hit> out;
    empty.nearest(vec3(0.0), 5, out);
    REQUIRE(out.empty());
}

TEMPLATE_TEST_CASE("the k-d tree is a left-balanced median tree", "[stores][kdtree]", FullRecord, CompactRecord) {
    // FullRecord keeps the split axes in a side array, CompactRecord in its spare bits.
    const auto input = make_records<TestType>(Layout::clustered, 6001, 51);
    const KdTreeStore<TestType> store(input);
    const auto& heap = store.records();
    // The records are the input's, reordered, with their batches intact.
    const auto key = [](const TestType& r) {
        const vec3 p = r.position();
        return std::tuple{p.x, p.y, p.z, int(r.batch()), int(r.band())};
    };
    std::vector<std::tuple<double, double, double, int, int>> a, b;
    for (const auto& r : input) a.push_back(key(r));
    for (const auto& r : heap) b.push_back(key(r));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    REQUIRE(a == b);
    // Every record in the left subtree of node a has coordinate <= a's along a's axis, every
    // record in the right subtree >=: walk up from each node to all its ancestors.
    for (std::size_t j = 1; j < heap.size(); ++j) {
        for (std::size_t child = j; child > 0; child = (child - 1) / 2) {
            const std::size_t a = (child - 1) / 2;
            REQUIRE(store.is_internal(a));
            const int axis = store.split_axis(a);
            const double split = heap[a].position()[axis], value = heap[j].position()[axis];
            if (child == 2 * a + 1) REQUIRE(value <= split);
            else REQUIRE(value >= split);
        }
    }
}

TEST_CASE("the VOI octree agrees with brute force for any leaf size", "[stores][octree]") {
    const auto records = make_records<FullRecord>(Layout::clustered, 6000, 61);
    for (const std::size_t leaf : {1u, 4u, 1000u}) {
        INFO("leaf size " << leaf);
        const VoiOctreeStore<FullRecord> store(records, leaf);
        REQUIRE(store.leaf_size() == leaf);
        require_agreement(records, store, Layout::clustered, 62);
    }
    REQUIRE_THROWS_AS(VoiOctreeStore<FullRecord>(records, 0), input_error);
}

TEST_CASE("memory per photon for 1e6 compact records", "[stores][memory]") {
    const std::size_t n = 1000000;
    const auto records = make_records<CompactRecord>(Layout::uniform, n, 71);
    const auto per_photon = [](std::size_t bytes) { return static_cast<double>(bytes) / static_cast<double>(n); };
    const KdTreeStore<CompactRecord> kd(records);
    const NanoflannStore<CompactRecord> nano(records);
    const PlainOctree octree(records);
    const PackedOctree packed(records);
    const PackedGrid grid(records, Radius(0.02));
    const PlainGrid plain_grid(records, Radius(0.02));
    WARN("bytes per photon: k-d tree " << per_photon(kd.memory_bytes()) << ", nanoflann " << per_photon(nano.memory_bytes())
                                       << ", VOI octree " << per_photon(octree.memory_bytes()) << " ("
                                       << octree.node_count() << " nodes), packed " << per_photon(packed.memory_bytes())
                                       << ", VOI grid for r = 0.02 " << per_photon(grid.memory_bytes())
                                       << " (plain records " << per_photon(plain_grid.memory_bytes()) << ")");
    REQUIRE(kd.memory_bytes() == n * sizeof(CompactRecord));  // the split axes live in the records
    REQUIRE(sizeof(CompactRecord) == 16);
    REQUIRE(nano.memory_bytes() > n * sizeof(CompactRecord));
    REQUIRE(octree.memory_bytes() > n * sizeof(CompactRecord));
    // Packed (packed_records.hpp): 12 bytes per record, frames and nodes within the other 4.
    REQUIRE(packed.memory_bytes() > n * 12);
    REQUIRE(packed.memory_bytes() <= n * 16);
    // The grid's index (cell_offsets.hpp): 1.5 bytes per cell offset (whole blocks of 8) and at
    // most 0.125 per record; at most max_cells_per_record cells per record (here 1.5: cells of
    // 0.01 x 0.01 x 0.02 m in the 1 x 1 x 3 m box).
    const auto cells = plain_grid.cells();
    const double offsets = static_cast<double>(cells[0] * cells[1] * cells[2] + 1);
    REQUIRE(offsets <= PlainGrid::max_cells_per_record * n + 2.0);
    REQUIRE(per_photon(plain_grid.memory_bytes()) >= sizeof(CompactRecord) + 1.5 * offsets / n);
    REQUIRE(per_photon(plain_grid.memory_bytes()) <= sizeof(CompactRecord) + 1.5 * (offsets + 7.0) / n + 0.125);
    REQUIRE(grid.memory_bytes() > n * 12);
    REQUIRE(grid.memory_bytes() <= n * 16);
}

TEMPLATE_TEST_CASE("concurrent queries from 2 threads match sequential ones", "[stores][threads]",
                   KdTreeStore<CompactRecord>, NanoflannStore<CompactRecord>, PlainOctree, PackedOctree, PlainGrid,
                   PackedGrid) {
    const TestType store(make_records<CompactRecord>(Layout::clustered, 20000, 81));
    const auto queries = make_queries(Layout::clustered, 100, 82);
    // Every hit of every query, in reporting order (the order is part of the contract).
    const auto run = [&store, &queries](std::vector<std::tuple<std::uint32_t, double, double>>& out) {
        out.clear();
        for (const Query& q : queries) {
            CollectAll all;
            store.within(q.point, Radius(q.r), all);
            store.along(q.ray, Radius(q.r), all);
            if constexpr (requires(std::vector<Hit>& v) { store.nearest(q.point, 8, v); }) {
                std::vector<Hit> near;
                store.nearest(q.point, 8, near);
                all.hits.insert(all.hits.end(), near.begin(), near.end());
            }
            for (const Hit& h : all.hits) out.emplace_back(h.index, h.t, h.distance2);
        }
    };
    std::vector<std::tuple<std::uint32_t, double, double>> sequential, first, second;
    run(sequential);
    std::thread a(run, std::ref(first)), b(run, std::ref(second));
    a.join();
    b.join();
    REQUIRE(!sequential.empty());
    REQUIRE(first == sequential);
    REQUIRE(second == sequential);
}

// ---- The speed work's code paths: bulk-accepted subtrees (VOI octree) and the descending
// k-d tree walk must report exactly the oracle's records, in the structure's fixed order.

TEST_CASE("VOI octree: bulk-accepted subtrees report the oracle's records in record order", "[stores][octree][bulk]") {
    // Small leaves and radii up to the box size: whole subtrees fall inside the cylinder or sphere.
    const auto records = make_records<FullRecord>(Layout::uniform, 20000, 101);
    const BruteForceStore<FullRecord> brute(records);
    for (const std::size_t leaf : {1u, 8u, 32u, 128u}) {
        const VoiOctreeStore<FullRecord> store(records, leaf);
        PhotonRng rng(102, leaf);
        std::size_t bulk = 0;
        for (int i = 0; i < 40; ++i) {
            Query q{};
            q.r = 0.05 + 0.5 * rng.uniform();
            q.point = {rng.uniform(), rng.uniform(), 3.0 * rng.uniform()};
            q.ray.origin = {rng.uniform(), rng.uniform(), 3.0 * rng.uniform()};
            q.ray.direction = i % 2 == 0 ? axis_direction(rng.bits()) : random_unit(rng);
            if (i % 5 == 4) q.ray.direction *= 1.0 + 1e-7;  // a little off unit length
            q.ray.t_max = 3.0 * rng.uniform();
            INFO("leaf " << leaf << " query " << i << " r " << q.r);
            bulk += store.along_stats(q.ray, Radius(q.r)).bulk;
            REQUIRE(compare(run_along(store, q), run_along(brute, q)) == "");
            REQUIRE(compare(run_within(store, q), run_within(brute, q)) == "");
            // Records are laid out in depth-first leaf order and the walk visits children in
            // octant order, so hits (bulk or tested) come in increasing record index.
            for (const bool ray_query : {true, false}) {
                CollectAll all;
                if (ray_query) store.along(q.ray, Radius(q.r), all);
                else store.within(q.point, Radius(q.r), all);
                for (std::size_t k = 1; k < all.hits.size(); ++k) REQUIRE(all.hits[k - 1].index < all.hits[k].index);
            }
        }
        INFO("leaf " << leaf);
        REQUIRE(bulk > 0);  // the bulk path was exercised
    }
}

/// The oracle for a VOI store's along(): in_cylinder over records() in index order. The leaf
/// scan computes t and distance2 in SIMD or vectorised loops over chunks padded to whole
/// vectors (or one record at a time for short chunks), bulk ranges in scalar code: every hit
/// must carry in_cylinder's values bit for bit, in this order.
template <class Store>
void require_in_cylinder_values(const Store& store, const std::vector<Query>& queries, const std::string& what) {
    for (std::size_t i = 0; i < queries.size(); ++i) {
        const Query& q = queries[i];
        CollectAll want;
        for (std::uint32_t k = 0; k < store.size(); ++k) {
            Hit hit{k, 0.0, 0.0};
            if (in_cylinder(q.ray, store.records()[k].position(), q.r * q.r, hit)) want.hits.push_back(hit);
        }
        CollectAll got;
        store.along(q.ray, Radius(q.r), got);
        INFO(what << " query " << i << " r " << q.r);
        REQUIRE(got.hits.size() == want.hits.size());
        for (std::size_t k = 0; k < got.hits.size(); ++k) {
            REQUIRE(got.hits[k].index == want.hits[k].index);
#if defined(__FMA__)  // the compiler may fuse a * b + c differently in the two codes
            REQUIRE(close(got.hits[k].t, want.hits[k].t));
            REQUIRE(close(got.hits[k].distance2, want.hits[k].distance2));
#else
            REQUIRE(std::bit_cast<std::uint64_t>(got.hits[k].t) == std::bit_cast<std::uint64_t>(want.hits[k].t));
            REQUIRE(std::bit_cast<std::uint64_t>(got.hits[k].distance2) ==
                    std::bit_cast<std::uint64_t>(want.hits[k].distance2));
#endif
        }
    }
}

/// Random queries, plus two that reach whole subtrees (bulk) and long scans.
std::vector<Query> exact_value_queries() {
    auto queries = make_queries(Layout::uniform, 60, 112);
    queries.push_back({vec3(0.5), Ray{vec3(0.5, 0.5, -1.0), vec3(0, 0, 1), 5.0}, 0.3});
    queries.push_back({vec3(0.5), Ray{vec3(-1.0, -1.0, -1.0), glm::normalize(vec3(1, 1, 2)), 6.0}, 2.0});
    return queries;
}

TEMPLATE_TEST_CASE("VOI octree along reports in_cylinder's t and distance2 exactly, in record order", "[stores][octree]",
                   FullRecord, CompactRecord) {
    // 5037 = 78 * 64 + 45 records: with leaf size 6000, one leaf whose last chunk (45
    // records, vectorised) ends at the last record, where the padding must stop short.
    const auto records = make_records<TestType>(Layout::uniform, 5037, 111);
    for (const std::size_t leaf : {1u, 5u, 43u, 128u, 6000u}) {
        require_in_cylinder_values(VoiOctreeStore<TestType>(records, leaf), exact_value_queries(),
                                   "leaf " + std::to_string(leaf));
        if constexpr (std::is_same_v<TestType, CompactRecord>)
            require_in_cylinder_values(PackedOctree(records, leaf), exact_value_queries(), "packed, leaf " + std::to_string(leaf));
    }
}

TEMPLATE_TEST_CASE("VOI grid along reports in_cylinder's t and distance2 exactly, in record order", "[stores][grid]",
                   VoiGridStore<FullRecord>, PlainGrid, PackedGrid) {
    // Columns of every length: one record per cell, a few dozen, and the whole map in one
    // cell (whose range ends at the last record, where the scan's padding must stop short).
    const auto records = make_records<typename TestType::record_type>(Layout::uniform, 5037, 111);
    for (const double width : {0.02, 0.1, 0.3, 5.0})
        require_in_cylinder_values(TestType(records, width, 2.0 * width), exact_value_queries(),
                                   "column width " + std::to_string(width));
}

/// Takes the VOI stores' runs of hits whole (ChunkCollector) and single hits (bulk ranges);
/// stops once it holds `limit` hits (0: never).
struct RunCollector {
    std::vector<Hit> got;
    std::size_t runs = 0, limit = 0;
    bool operator()(const Hit& h) {
        got.push_back(h);
        return limit == 0 || got.size() < limit;
    }
    bool hits(std::uint32_t base, const std::uint32_t* offset, const double* t, const double* distance2, std::uint32_t n) {
        ++runs;
        for (std::uint32_t k = 0; k < n; ++k) got.push_back({base + offset[k], t[k], distance2[k]});
        return limit == 0 || got.size() < limit;
    }
};
static_assert(ChunkCollector<RunCollector> && !ChunkCollector<CollectAll>);

TEMPLATE_TEST_CASE("the VOI stores pass runs of hits to a ChunkCollector: the same hits, in order", "[stores]",
                   PlainOctree, VoiOctreeStore<FullRecord>, PackedOctree, PlainGrid, PackedGrid,
                   VoiGridStore<FullRecord>) {
    const TestType store(make_records<typename TestType::record_type>(Layout::uniform, 20000, 68));
    std::size_t runs = 0, stopped = 0;
    for (const Query& q : make_queries(Layout::uniform, 60, 69)) {
        CollectAll all;
        REQUIRE(store.along(q.ray, Radius(q.r), all));
        RunCollector whole;
        REQUIRE(store.along(q.ray, Radius(q.r), whole));
        runs += whole.runs;
        REQUIRE(whole.got.size() == all.hits.size());
        for (std::size_t k = 0; k < all.hits.size(); ++k) {
            REQUIRE(whole.got[k].index == all.hits[k].index);
            REQUIRE(whole.got[k].t == all.hits[k].t);
            REQUIRE(whole.got[k].distance2 == all.hits[k].distance2);
        }
        if (all.hits.size() < 200) continue;
        RunCollector first{{}, 0, 10};  // stops within the first run of 10 or more hits
        REQUIRE_FALSE(store.along(q.ray, Radius(q.r), first));
        REQUIRE(first.got.size() < all.hits.size());
        ++stopped;
    }
    REQUIRE(runs > 0);
    REQUIRE(stopped > 0);
}

TEST_CASE("the VOI grid agrees with brute force for any cell shape", "[stores][grid]") {
    for (const Layout layout : {Layout::uniform, Layout::clustered}) {
        const auto records = make_records<FullRecord>(layout, 6000, 63);
        // Automatic, too fine for the cell limit, flat, tall, one column, and sized for r.
        const std::pair<double, double> shapes[] = {{0.0, 0.0}, {1e-4, 1e-4}, {0.05, 0.5}, {0.5, 0.02}, {5.0, 5.0}};
        for (const auto& [width, height] : shapes) {
            INFO("layout " << static_cast<int>(layout) << " column width " << width << " cell height " << height);
            const VoiGridStore<FullRecord> store(records, width, height);
            const auto cells = store.cells();
            REQUIRE(static_cast<double>(cells[0] * cells[1] * cells[2]) <=
                    VoiGridStore<FullRecord>::max_cells_per_record * static_cast<double>(records.size()) + 1.0);
            if (width == 0.5) REQUIRE(store.cell_size().z == 0.02);  // as asked: within the limit
            require_agreement(records, store, layout, 64);
        }
        const VoiGridStore<FullRecord> sized(records, Radius(0.1));
        REQUIRE(sized.cell_size().x == VoiGridStore<FullRecord>::column_width_per_radius * 0.1);
        require_agreement(records, sized, layout, 65);
    }
    const auto records = make_records<FullRecord>(Layout::uniform, 100, 66);
    for (const double bad : {-0.1, std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::infinity()}) {
        REQUIRE_THROWS_AS(VoiGridStore<FullRecord>(records, bad), input_error);
        REQUIRE_THROWS_AS(VoiGridStore<FullRecord>(records, 0.1, bad), input_error);
    }
}

TEST_CASE("VOI grid: along_stats counts the ranges and records a query scans", "[stores][grid]") {
    const auto records = make_records<CompactRecord>(Layout::uniform, 20000, 67);
    const VoiGridStore<CompactRecord> store(records, 0.05, 0.1);
    // A vertical ray through the middle (depths 1 to 2 of the 3 m box): the columns within r
    // of its axis, each cut over the cells of the ray's depths padded by r (1.2 m).
    const Ray ray{{0.512, 0.487, 1.0}, {0.0, 0.0, 1.0}, 1.0};
    const auto stats = store.along_stats(ray, Radius(0.05));
    CountHits count;
    store.along(ray, Radius(0.05), count);
    REQUIRE(stats.hits == count.count);
    REQUIRE(stats.hits > 0);
    REQUIRE(stats.tested >= stats.hits);
    // The disc of radius r = 0.05 around (0.512, 0.487) spans columns 9 to 11 in x and 8 to
    // 10 in y: at most 9 ranges, each 0.05 x 0.05 x 1.2 m with 20000 / 3 records per m^3, 20
    // records on average (180 in all; 300 is over 9 Poisson sigma above).
    REQUIRE(stats.ranges <= 9);
    REQUIRE(stats.tested < 300);
}

#if SECCHI_HAS_CYLINDER_SCAN
/// The output arrays of two runs of the scan's kernels over up to `count` records.
struct TwoScans {
    explicit TwoScans(std::uint32_t count) {
        for (int k = 0; k < 2; ++k) {
            t[k].resize(count + detail::kScanSlack);
            d2[k].resize(count + detail::kScanSlack);
            offset[k].resize(count + detail::kScanSlack);
        }
    }
    /// The runs found n and m hits: the same number, offsets, t and distance2, bit for bit.
    void require_same(std::uint32_t n, std::uint32_t m) const {
        REQUIRE(n == m);
        for (std::uint32_t k = 0; k < n; ++k) {
            REQUIRE(offset[0][k] == offset[1][k]);
            REQUIRE(std::bit_cast<std::uint64_t>(t[0][k]) == std::bit_cast<std::uint64_t>(t[1][k]));
            REQUIRE(std::bit_cast<std::uint64_t>(d2[0][k]) == std::bit_cast<std::uint64_t>(d2[1][k]));
        }
    }
    std::vector<double> t[2], d2[2];
    std::vector<std::uint32_t> offset[2];
};

TEST_CASE("the scan's vertical kernel gives the general kernel's hits and values bit for bit", "[stores][scan]") {
    // Records in the unit cube; vertical rays down and up, through the cube and from outside
    // it, with radii from a few records' spacing to most of the cube.
    const auto records = make_records<CompactRecord>(Layout::uniform, 5037, 117);
    const auto count = static_cast<std::uint32_t>(records.size());
    TwoScans scans(count);
    const Ray rays[] = {{{0.5, 0.5, -1.0}, {0.0, 0.0, 1.0}, 5.0},   {{0.3, 0.71, 0.2}, {0.0, 0.0, 1.0}, 0.5},
                        {{0.62, 0.4, 0.9}, {0.0, 0.0, -1.0}, 0.7},  {{0.05, 0.93, 3.0}, {-0.0, 0.0, -1.0}, 10.0},
                        {{1.3, 0.5, 0.5}, {0.0, -0.0, 1.0}, 0.3}};
    std::size_t hits = 0;
    for (const Ray& ray : rays) {
        REQUIRE(is_vertical(ray));
        for (const double r : {0.02, 0.1, 0.45}) {
            const detail::FloatRecordPositions<CompactRecord> positions{records.data()};
            const std::uint32_t n = detail::scan_cylinder_kernel<true>(positions, count, ray, r * r, scans.t[0].data(),
                                                                      scans.d2[0].data(), scans.offset[0].data());
            const std::uint32_t general = detail::scan_cylinder_kernel<false>(
                positions, count, ray, r * r, scans.t[1].data(), scans.d2[1].data(), scans.offset[1].data());
            INFO("ray from " << ray.origin.x << " " << ray.origin.y << " " << ray.origin.z << ", r " << r);
            scans.require_same(n, general);
            hits += n;
        }
    }
    CHECK(hits > 2000);
}
#endif

TEST_CASE("CylinderInterior accepts only boxes whose every point in_cylinder accepts", "[stores][bulk]") {
    PhotonRng rng(103, 0);
    std::size_t accepted = 0;
    for (int i = 0; i < 20000; ++i) {
        const double far = i % 4 == 0 ? 1000.0 : 0.0;
        vec3 dir = i % 3 == 0 ? axis_direction(rng.bits()) : random_unit(rng);
        if (i % 7 == 0) dir *= 1.0 + 1e-9 * (rng.uniform() - 0.5);
        const Ray ray{vec3(rng.uniform(), rng.uniform(), rng.uniform()) - far * dir, dir, far + 2.0 * rng.uniform()};
        const double r = 0.01 + 0.3 * rng.uniform();
        const vec3 centre = ray.origin + (far + rng.uniform() * 2.0) * dir + 0.2 * r * random_unit(rng);
        const vec3 half(0.3 * r * rng.uniform(), 0.3 * r * rng.uniform(), 0.3 * r * rng.uniform());
        // float corners, as the octree stores them
        const vec3 lo(static_cast<float>(centre.x - half.x), static_cast<float>(centre.y - half.y), static_cast<float>(centre.z - half.z));
        const vec3 hi(static_cast<float>(centre.x + half.x), static_cast<float>(centre.y + half.y), static_cast<float>(centre.z + half.z));
        const detail::CylinderInterior interior(ray, r * r);
        if (!interior.usable() || !interior.contains(lo, hi)) continue;
        ++accepted;
        Hit hit{};
        for (unsigned corner = 0; corner < 8; ++corner) {
            const vec3 p((corner & 1) ? hi.x : lo.x, (corner & 2) ? hi.y : lo.y, (corner & 4) ? hi.z : lo.z);
            REQUIRE(in_cylinder(ray, p, r * r, hit));
        }
        for (int k = 0; k < 4; ++k) {
            const vec3 p = lo + vec3(rng.uniform(), rng.uniform(), rng.uniform()) * (hi - lo);
            REQUIRE(in_cylinder(ray, p, r * r, hit));
        }
    }
    REQUIRE(accepted > 1000);
}

namespace {
/// Jensen's recursive locate_photons: the order the iterative k-d tree walk must reproduce.
template <class Store>
void locate_recursive(const Store& s, std::size_t i, const vec3& p, double r2, std::vector<std::uint32_t>& out) {
    if (i >= s.size()) return;
    const vec3 q = s.records()[i].position();
    const vec3 d = q - p;
    if (glm::dot(d, d) <= r2) out.push_back(static_cast<std::uint32_t>(i));
    if (!s.is_internal(i)) return;
    const int a = s.split_axis(i);
    const double delta = p[a] - q[a];
    const std::size_t near = delta < 0.0 ? 2 * i + 1 : 2 * i + 2, far = delta < 0.0 ? 2 * i + 2 : 2 * i + 1;
    locate_recursive(s, near, p, r2, out);
    if (delta * delta <= r2) locate_recursive(s, far, p, r2, out);
}
}  // namespace

TEST_CASE("k-d tree within reports in the recursive locate_photons order", "[stores][kdtree]") {
    const auto records = make_records<CompactRecord>(Layout::clustered, 20000, 104);
    const KdTreeStore<CompactRecord> store(records);
    for (const Query& q : make_queries(Layout::clustered, 100, 105)) {
        CollectAll all;
        store.within(q.point, Radius(q.r), all);
        std::vector<std::uint32_t> got, want;
        for (const Hit& h : all.hits) got.push_back(h.index);
        locate_recursive(store, 0, q.point, q.r * q.r, want);
        REQUIRE(got == want);
    }
}

// ---- The packed layout (map/packed_records.hpp): 21-bit coordinates within frames.

TEST_CASE("CompactRecord positions lie on the 2^-20 m grid, within 2^-21 m of the point", "[stores][packed]") {
    PhotonRng rng(120, 0);
    for (int i = 0; i < 200000; ++i) {
        const double c = (rng.bits() % 2 == 0 ? 1.0 : -1.0) * std::pow(10.0, -9.0 + 13.0 * rng.uniform());
        const float g = CompactRecord::make(vec3(c, -c, 0.5 * c), vec3(0, 0, 1), 0, 0).x;
        INFO("c " << c << " stored " << g);
        REQUIRE(std::fmod(static_cast<double>(g), position_grid) == 0.0);
        REQUIRE(!(g == 0.0f && std::signbit(g)));  // zeros are +0 (what the packed layout reads back)
        if (std::abs(c) < position_grid_limit) REQUIRE(std::abs(g - c) <= 0.5 * position_grid);
        else REQUIRE(g == static_cast<float>(c));
    }
}

TEST_CASE("packed records hold CompactRecords exactly, in frames of the smallest step", "[stores][packed]") {
    // Random frames of 1-600 records made by CompactRecord::make: a random corner (magnitude
    // 10^[-6, 4] m, either sign, or 0) and extent (10^-9 to 10^1.5 m) per axis. Frames that
    // is_fine() accepts pack and read back bit for bit; a coarse frame is refused by name.
    PhotonRng rng(121, 0);
    std::vector<CompactRecord> records;
    std::vector<std::uint32_t> begins;
    std::size_t refused = 0;
    for (int f = 0; f < 600; ++f) {
        std::vector<CompactRecord> frame;
        const std::uint32_t n = 1 + static_cast<std::uint32_t>(rng.bits() % 600);
        std::array<double, 3> lo{}, extent{};
        for (int k = 0; k < 3; ++k) {
            lo[k] = rng.bits() % 16 == 0 ? 0.0 : (rng.bits() % 2 == 0 ? 1.0 : -1.0) * std::pow(10.0, -6.0 + 10.0 * rng.uniform());
            extent[k] = std::pow(10.0, -9.0 + 10.5 * rng.uniform());
        }
        for (std::uint32_t i = 0; i < n; ++i) {
            vec3 p;
            for (int k = 0; k < 3; ++k) p[k] = lo[k] + extent[k] * (rng.bits() % 8 == 0 ? 0.0 : rng.uniform());
            frame.push_back(CompactRecord::make(p, random_unit(rng), static_cast<band_index>(rng.bits() % 7),
                                                static_cast<std::uint8_t>(rng.bits() % 64)));
        }
        std::array<float, 3> flo{INFINITY, INFINITY, INFINITY}, fhi{-INFINITY, -INFINITY, -INFINITY};
        for (const CompactRecord& r : frame) {
            const std::array<float, 3> c{r.x, r.y, r.z};
            for (int k = 0; k < 3; ++k) flo[k] = std::min(flo[k], c[k]), fhi[k] = std::max(fhi[k], c[k]);
        }
        if (!PackedRecords::is_fine(flo, fhi)) {
            ++refused;
            CHECK_THROWS_WITH(PackedRecords(frame, {0}), Catch::Contains("cannot be packed exactly"));
            continue;
        }
        // The step: a power of two, the smallest that spans the box from a multiple of itself.
        for (int k = 0; k < 3; ++k) {
            const PackedRecords::Axis a = PackedRecords::axis_frame(flo[k], fhi[k]);
            const double step = a.step, half = 0.5 * step;
            REQUIRE(std::exp2(std::round(std::log2(step))) == step);
            REQUIRE(std::floor(static_cast<double>(a.origin) / step) * step == a.origin);
            if (half >= 0x1p-126) REQUIRE((static_cast<double>(fhi[k]) - std::floor(flo[k] / half) * half) / half > PackedRecords::max_code);
        }
        begins.push_back(static_cast<std::uint32_t>(records.size()));
        records.insert(records.end(), frame.begin(), frame.end());
    }
    REQUIRE(refused > 20);
    REQUIRE(begins.size() > 300);
    const PackedRecords packed(records, begins);
    REQUIRE(packed.size() == records.size());
    REQUIRE(packed.memory_bytes() >= 12 * records.size());
    std::size_t f = 0;
    for (std::uint32_t i = 0; i < records.size(); ++i) {
        while (f + 1 < begins.size() && begins[f + 1] <= i) ++f;
        REQUIRE(packed.frame_of(i) == f);
        REQUIRE(std::bit_cast<std::array<std::uint8_t, 16>>(packed[i]) == std::bit_cast<std::array<std::uint8_t, 16>>(records[i]));
    }
    // for_each_frame() cuts runs across frames at the frames' begins, in order.
    for (int trial = 0; trial < 200; ++trial) {
        const auto begin = static_cast<std::uint32_t>(rng.bits() % (records.size() - 700));
        const auto end = begin + 1 + static_cast<std::uint32_t>(rng.bits() % 700);
        std::uint32_t next = begin;
        packed.for_each_frame(begin, end, [&](std::uint32_t first, std::uint32_t last, const PackedRecords::Frame& frame) {
            REQUIRE(first == next);
            REQUIRE(first < last);
            REQUIRE(frame.begin == begins[packed.frame_of(first)]);
            REQUIRE(packed.frame_of(last - 1) == packed.frame_of(first));
            REQUIRE((last == end || std::ranges::binary_search(begins, last)));
            next = last;
        });
        REQUIRE(next == end);
    }
    const auto view = packed.view();
    REQUIRE(std::ranges::size(view) == records.size());
    for (std::uint32_t i = 0; i < records.size(); i += 97)
        REQUIRE(std::bit_cast<std::array<std::uint8_t, 16>>(view[i]) == std::bit_cast<std::array<std::uint8_t, 16>>(records[i]));
#if SECCHI_HAS_CYLINDER_SCAN
    // The leaf scan's kernel on the 64-bit words of one frame (CodedPositions) gives the hits,
    // offsets and values of the kernel on the records' floats, bit for bit: rays through each
    // frame's box in random directions (a third vertical), radii from a hundredth to the box.
    std::size_t hits = 0;
    for (std::size_t g = 0; g < begins.size(); ++g) {
        const std::uint32_t first = begins[g], last = g + 1 < begins.size() ? begins[g + 1] : packed.size();
        const std::uint32_t count = last - first, base = static_cast<std::uint32_t>(rng.bits() % 100);
        TwoScans scans(count);
        vec3 lo = records[first].position(), hi = lo;
        for (std::uint32_t i = first; i < last; ++i) lo = glm::min(lo, records[i].position()), hi = glm::max(hi, records[i].position());
        const PackedRecords::Frame frame = [&] {
            PackedRecords::Frame found{};
            packed.for_each_frame(first, last, [&](std::uint32_t, std::uint32_t, const PackedRecords::Frame& f) { found = f; });
            return found;
        }();
        const auto& a = frame.axis;
        const detail::CodedPositions coded{packed.codes() + first, {a[0].origin, a[1].origin, a[2].origin}, {a[0].step, a[1].step, a[2].step}};
        const double size = std::max(glm::length(hi - lo), 1e-12);
        for (int trial = 0; trial < 3; ++trial) {
            const vec3 dir = trial == 0 ? vec3(0.0, 0.0, rng.bits() % 2 ? 1.0 : -1.0) : random_unit(rng);
            const vec3 through = lo + vec3(rng.uniform(), rng.uniform(), rng.uniform()) * (hi - lo);
            const Ray ray{through - size * dir, dir, 2.0 * size};
            const double r = size * std::pow(10.0, -2.0 + 2.0 * rng.uniform());
            const std::uint32_t n = detail::scan_cylinder(coded, count, ray, r * r, scans.t[0].data(), scans.d2[0].data(),
                                                          scans.offset[0].data(), base);
            const std::uint32_t m = detail::scan_cylinder(detail::FloatRecordPositions<CompactRecord>{records.data() + first}, count,
                                                          ray, r * r, scans.t[1].data(), scans.d2[1].data(), scans.offset[1].data(), base);
            INFO("frame " << g << " of " << count << " records, ray " << trial);
            scans.require_same(n, m);
            hits += n;
        }
    }
    CHECK(hits > 10000);
#endif
    // A record off the grid (not made by make()) is refused by name, not rounded.
    std::vector<CompactRecord> off{CompactRecord::make(vec3(0.25, 0.25, 0.25), vec3(0, 0, 1), 0, 0),
                                   CompactRecord::make(vec3(0.75, 0.75, 0.75), vec3(0, 0, 1), 0, 0)};
    off[1].x = std::nextafter(0.75f, 1.0f);  // 0.75 + 2^-24: finer than the grid
    CHECK_THROWS_WITH(PackedRecords(off, {0}), Catch::Contains("photon record 1 coordinate x"));
    off[1] = off[0];
    off[1].z = -0.0f;  // would read back as +0
    CHECK_THROWS_WITH(PackedRecords(off, {0}), Catch::Contains("photon record 1 coordinate z"));
}

TEST_CASE("the packed octree splits leaves too large for one frame, and agrees with brute force",
          "[stores][packed][octree]") {
    // 3000 records spread over 100 m on each axis, from 0: leaves of 512 records span tens of
    // metres, where 21 bits give steps of ~2^-15 m, coarser than the records' grid near the
    // origin, so the packed octree splits their records into sub-octant frames (same nodes).
    PhotonRng rng(131, 0);
    std::vector<CompactRecord> records;
    for (int i = 0; i < 3000; ++i)
        records.push_back(CompactRecord::make(vec3(100.0 * rng.uniform(), 100.0 * rng.uniform(), 100.0 * rng.uniform()),
                                              random_unit(rng), 0, static_cast<std::uint8_t>(i % 8)));
    const PackedOctree packed(records);
    const PlainOctree plain(records);
    REQUIRE(packed.node_count() == plain.node_count());
    // (One frame per leaf would be refused: its records could not be read back exactly.)
    REQUIRE(contents(packed.records()) == contents(records));  // exactly the records given
    const BruteForceStore<CompactRecord> brute(records);
    for (int i = 0; i < 50; ++i) {
        const vec3 p(100.0 * rng.uniform(), 100.0 * rng.uniform(), 100.0 * rng.uniform());
        const Query q{p, Ray{p, random_unit(rng), 100.0 * rng.uniform()}, 20.0 * rng.uniform()};
        REQUIRE(compare(run_within(packed, q), run_within(brute, q)) == "");
        REQUIRE(compare(run_along(packed, q), run_along(brute, q)) == "");
    }
}

TEST_CASE("the packed grid frames runs of its order, and agrees with brute force over tens of metres",
          "[stores][packed][grid]") {
    // 3000 records spread over 60 m on each axis around (100, -50, -30), columns of 0.5 m: the
    // grid's order puts records metres apart next to each other, so its frames are short runs
    // (some far from the origin, where floats are coarser than the records' grid near it).
    PhotonRng rng(141, 0);
    std::vector<CompactRecord> records;
    for (int i = 0; i < 3000; ++i)
        records.push_back(CompactRecord::make(vec3(100.0, -50.0, -30.0) + 60.0 * vec3(rng.uniform(), rng.uniform(), rng.uniform()),
                                              random_unit(rng), 0, static_cast<std::uint8_t>(i % 8)));
    const PackedGrid packed(records, 0.5, 0.5);
    const PlainGrid plain(records, 0.5, 0.5);
    REQUIRE(contents(packed.records()) == contents(plain.records()));  // the same records, in the same order
    for (std::size_t i = 0; i < records.size(); ++i) REQUIRE(std::bit_cast<std::array<std::uint32_t, 4>>(packed.records()[i]) ==
                                                               std::bit_cast<std::array<std::uint32_t, 4>>(plain.records()[i]));
    const BruteForceStore<CompactRecord> brute(records);
    for (int i = 0; i < 50; ++i) {
        const vec3 p = vec3(100.0, -50.0, -30.0) + 60.0 * vec3(rng.uniform(), rng.uniform(), rng.uniform());
        const Query q{p, Ray{p, random_unit(rng), 60.0 * rng.uniform()}, 10.0 * rng.uniform()};
        REQUIRE(compare(run_within(packed, q), run_within(brute, q)) == "");
        REQUIRE(compare(run_along(packed, q), run_along(brute, q)) == "");
    }
    // greedy_frames: every frame's box is fine, and the record after a frame would not fit in it.
    std::vector<CompactRecord> ordered(plain.records().begin(), plain.records().end());
    const auto begins = PackedRecords::greedy_frames(ordered);
    REQUIRE(begins.size() > 10);
    REQUIRE(begins.front() == 0);
    for (std::size_t f = 0; f < begins.size(); ++f) {
        const std::uint32_t end = f + 1 < begins.size() ? begins[f + 1] : static_cast<std::uint32_t>(ordered.size());
        std::array<float, 3> lo{INFINITY, INFINITY, INFINITY}, hi{-INFINITY, -INFINITY, -INFINITY};
        const auto extend = [&](const CompactRecord& r) {
            const std::array<float, 3> c{r.x, r.y, r.z};
            for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
        };
        for (std::uint32_t i = begins[f]; i < end; ++i) extend(ordered[i]);
        REQUIRE(PackedRecords::is_fine(lo, hi));
        if (end == ordered.size()) continue;
        extend(ordered[end]);
        REQUIRE_FALSE(PackedRecords::is_fine(lo, hi));
    }
}

TEST_CASE("CellOffsets reads back every entry, in its byte blocks and its wide ones", "[stores][grid]") {
    // Random non-decreasing sequences: runs of empty cells, cells of a few records, and cells
    // of hundreds to millions (wide blocks), of every length modulo the block.
    PhotonRng rng(151, 0);
    for (int trial = 0; trial < 200; ++trial) {
        const std::size_t n = 1 + rng.bits() % 3000;
        const int kind = static_cast<int>(rng.bits() % 3);
        std::vector<std::uint32_t> entries(n);
        std::uint64_t total = 0, wide_records = 0;
        for (std::size_t c = 0; c < n; ++c) {
            entries[c] = static_cast<std::uint32_t>(total);
            const std::uint64_t draw = rng.bits();
            const std::uint64_t count = draw % 4 == 0 ? 0 : kind == 0 ? draw % 40 : kind == 1 ? draw % 300 : draw % 2000000;
            total += count;
        }
        if (total > 0xffffffffu) continue;
        const CellOffsets offsets(entries);
        REQUIRE(offsets.size() == n);
        for (std::size_t c = 0; c < n; ++c) REQUIRE(offsets[c] == entries[c]);
        // The bound: 1.5 bytes per entry of whole blocks, 32 bytes per wide block, each of
        // which spans at least 256 records.
        for (std::size_t b = 0; b * CellOffsets::block < n; ++b) {
            const std::size_t last = std::min(n, (b + 1) * CellOffsets::block) - 1;
            if (entries[last] - entries[b * CellOffsets::block] > 255) wide_records += entries[last] - entries[b * CellOffsets::block];
        }
        const std::size_t blocks = (n + CellOffsets::block - 1) / CellOffsets::block;
        REQUIRE(offsets.memory_bytes() == blocks * (CellOffsets::block + 4) + offsets.wide_blocks() * 4 * CellOffsets::block);
        REQUIRE(static_cast<double>(offsets.wide_blocks()) * 256.0 <= static_cast<double>(wide_records));
        if (kind == 0) REQUIRE(offsets.wide_blocks() == 0);  // 7 cells of < 40 records: bytes
    }
    const std::vector<std::uint32_t> decreasing{0, 5, 4};
    REQUIRE_THROWS_WITH(CellOffsets(decreasing), Catch::Contains("cell offset") && Catch::Contains("2"));
    const std::vector<std::uint32_t> across_blocks{0, 1, 2, 3, 4, 5, 6, 7, 6};  // the fall at a block's first entry
    REQUIRE_THROWS_WITH(CellOffsets(across_blocks), Catch::Contains("cell offset") && Catch::Contains("8"));
}
