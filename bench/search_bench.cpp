// search_bench: the search-structure benchmarks (a benchmark, never part of the tests).
//   search_bench --suite build|collect|uniform|scaling|tune|spectral|all [--quick] [--md FILE] [--csv FILE]
//                [--repeats R] [--max-records N] [--map-photons N]
// Every figure is the median of R timed runs (spread: min-max), 1 thread.
//  - build:   map build time and bytes per photon for the k-d tree, the nanoflann adaptor, the
//             VOI octree and the VOI grid (cells for r = 0.05) at 1e5, 1e6, 1e7 records,
//             CompactRecord and FullRecord. Records:
//             the problem-2a light field (traced, FullRecord, converted to CompactRecord), the
//             first N records in photon order.
//  - collect: rays per second for vertical rays of length 8 from tau 1 through a problem-2a map,
//             k-d tree spheres at n = 8..128 and the VOI cylinder (octree and grid) at equal
//             radius, with photons per ray and Lu +- SE; then at equal photons per ray
//             (cylinder radius scaled), the octree and then the grid against the k-d tree.
//  - uniform: search only, 1e6 uniform points in the unit cube, ~50 per sphere (the scale
//             figures): k-d tree and nanoflann stepping at n = 32 against the VOI cylinder
//             (octree and grid); and Embree 3 collecting every sphere the ray hits, where CMake
//             found Embree (the optional comparator, embree_spheres.hpp).
//  - scaling: build and query cost against record count 1e4..1e7 (2a light field prefixes);
//             --csv writes the rows for plot_scaling.py.
//  - tune:    on the collect map, the VOI octree's leaf size and the VOI grid's cell shape;
//             on slanted rays, the grid against the octree and the grid's cell shape.
//  - spectral: spectral compensation (manual 3.5.2) on an 8-band map: the VOI cylinder's one
//             search per ray segment for every band and both radii, and the k-d tree step
//             spheres' one search per band for both radii, against the per-band searches of
//             its definition (paired).
#include "bench_problems.hpp"
#include "bench_timing.hpp"
#include "secchi/estimate/spectral_compensation.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/map/brute_force.hpp"
#include "secchi/map/kdtree.hpp"
#include "secchi/map/nanoflann_store.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/map/voi_octree.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include "secchi/solver/spectral.hpp"
#if SECCHI_BENCH_EMBREE
#include "embree_spheres.hpp"
#endif
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <random>
#include <sstream>
#include <string>

namespace {

using namespace secchi;
using namespace secchi::bench;
using Cone = ConeAveragedPhase<TabulatedPhase>;

/// The problem-2a light field (Petzold, w0 = 0.9, sun at 60 deg, n = 1.34, no bottom), as
/// secchi_bench traces it.
template <class Record>
TransportResult<Record> trace_2a(std::uint64_t photons, unsigned threads) {
    return trace_slab<Record>(petzold_m93(), 0.9, 60.0, 1.34, photons, threads, AbsorptionMode::continuous);
}

/// The scene trace_2a traces in.
MapScene scene_2a() { return slab_scene(60.0, 1.34); }

/// At least n records of the 2a light field (FullRecord), in photon order, cut to n.
std::vector<FullRecord> records_2a(std::size_t n) {
    std::uint64_t photons = n / 7 + 1000;  // about 8.2 records per photon
    for (;;) {
        auto r = trace_2a<FullRecord>(photons, 2);
        if (r.records.size() >= n) {
            r.records.resize(n);
            r.records.shrink_to_fit();
            return std::move(r.records);
        }
        photons = photons * 3 / 2;
    }
}

std::vector<CompactRecord> to_compact(const std::vector<FullRecord>& full, std::size_t n) {
    std::vector<CompactRecord> out;
    out.reserve(n);
    for (std::size_t i = 0; i < n; ++i) out.push_back(CompactRecord::make(full[i].pos, full[i].dir, full[i].band_, full[i].batch_));
    return out;
}
std::vector<FullRecord> prefix(const std::vector<FullRecord>& full, std::size_t n) {
    return {full.begin(), full.begin() + static_cast<std::ptrdiff_t>(n)};
}

struct Options {
    bool quick = false;
    int repeats = 5;
    std::size_t max_records = 10'000'000;
    std::uint64_t map_photons = 800'000;
    std::ostream* md = nullptr;
    std::ostream* csv = nullptr;
};

void out(const Options& o, const std::string& line) {
    std::cout << line << "\n";
    if (o.md) *o.md << line << "\n";
}

// ---------------------------------------------------------------------------------- build

template <class Store, class Record, class... Args>
void build_row(const Options& o, const char* store_name, const char* policy, const std::vector<Record>& records,
               int repeats, const Args&... args) {
    std::vector<Record> copy;
    std::size_t bytes = 0;
    const Timing t = time_runs(
        repeats, [&] { copy = records; },
        [&] {
            const Store s(std::move(copy), args...);
            bytes = s.memory_bytes();
        });
    out(o, "| " + std::string(store_name) + " | " + policy + " | " + fmt("%.0e", static_cast<double>(records.size())) +
               " | " + time_cell(t, 1.0) + " | " + fmt("%.3g", records.size() / t.median / 1e6) + " | " +
               fmt("%.2f", static_cast<double>(bytes) / records.size()) + " |");
}

void suite_build(const Options& o) {
    std::vector<std::size_t> sizes;
    for (std::size_t n : {100'000ul, 1'000'000ul, 10'000'000ul})
        if (n <= o.max_records) sizes.push_back(n);
    const auto full = records_2a(sizes.back());
    out(o, "### Map build: time and bytes per photon\n");
    out(o, "Records: the problem-2a light field (traced once in FullRecord, converted with CompactRecord::make), "
           "the first N in photon order. Time: the store's constructor from a moved vector (copy outside the timer), "
           "median [min-max] of " + std::to_string(o.repeats) + " runs (3 at 1e7), 1 thread. Bytes: memory_bytes() / N "
           "(records, nodes and index arrays).\n");
    out(o, "| store | record | N | build s, median [min-max] | M records/s | bytes/photon |");
    out(o, "|---|---|---|---|---|---|");
    for (std::size_t n : sizes) {
        const int reps = n >= 10'000'000 ? 3 : o.repeats;
        const auto compact = to_compact(full, n);
        build_row<KdTreeStore<CompactRecord>>(o, "k-d tree", "compact", compact, reps);
        build_row<NanoflannStore<CompactRecord>>(o, "nanoflann", "compact", compact, reps);
        build_row<VoiOctreeStore<CompactRecord, RecordLayout::packed>>(o, "VOI octree (packed records, the default)", "compact", compact, reps);
        build_row<VoiOctreeStore<CompactRecord, RecordLayout::plain>>(o, "VOI octree (plain records)", "compact", compact, reps);
        build_row<VoiGridStore<CompactRecord, RecordLayout::packed>>(o, "VOI grid (cells for r = 0.05, packed records, the default)", "compact", compact, reps, Radius(0.05));
        build_row<VoiGridStore<CompactRecord, RecordLayout::plain>>(o, "VOI grid (cells for r = 0.05, plain records)", "compact", compact, reps, Radius(0.05));
        const auto fullp = prefix(full, n);
        build_row<KdTreeStore<FullRecord>>(o, "k-d tree", "full", fullp, reps);
        build_row<NanoflannStore<FullRecord>>(o, "nanoflann", "full", fullp, reps);
        build_row<VoiOctreeStore<FullRecord>>(o, "VOI octree", "full", fullp, reps);
        build_row<VoiGridStore<FullRecord>>(o, "VOI grid (cells for r = 0.05)", "full", fullp, reps, Radius(0.05));
    }
    out(o, "");
}

// -------------------------------------------------------------------------------- collect

struct Collected {
    Timing t;
    double rays_per_s;
    double photons_per_ray;
    Estimate lu;
};

template <class Store, class Volume>
Collected collect(const Options& o, const PhotonMap<Store>& map, const Volume& volume, const Cone& cone,
                  const std::vector<Ray>& rays, double radius) {
    const auto est = radiance_estimator(map, volume, cone, radius);
    RadianceEstimate r;
    const Timing t = time_runs(o.repeats, [&] { r = est.estimate(rays, 1); });
    return {t, rays.size() / t.median, static_cast<double>(r.photons_touched) / rays.size(), r.radiance};
}

/// Search only: the collection volume's gather with a counting visitor (no radiance work).
template <class Store, class Volume>
std::pair<Timing, double> search_only(int repeats, const Store& store, const Volume& volume,
                                      const std::vector<Ray>& rays, double radius) {
    std::uint64_t count = 0;
    const Timing t = time_runs(repeats, [&] {
        count = 0;
        for (const Ray& ray : rays) volume.gather(store, ray, Radius(radius), [&](std::uint32_t, double, double) { ++count; });
    });
    return {t, static_cast<double>(count) / rays.size()};
}

#if SECCHI_BENCH_EMBREE
/// search_only for the Embree comparator: time for the rays and spheres hit per ray.
std::pair<Timing, double> embree_search(int repeats, const EmbreeSpheres& embree, const std::vector<Ray>& rays) {
    std::uint64_t count = 0;
    const Timing t = time_runs(repeats, [&] {
        count = 0;
        for (const Ray& ray : rays) count += embree.count_along(ray);
    });
    return {t, static_cast<double>(count) / rays.size()};
}
#endif

std::string lu_cell(const Estimate& e) { return fmt("%.4e", e.value) + " +- " + fmt("%.1e", e.se); }

/// The rays from the same origins, tilted by the zenith angle theta (degrees) in the x-z plane,
/// each of length 1 (the tune suite's slanted rays).
std::vector<Ray> tilted(const std::vector<Ray>& rays, double theta) {
    std::vector<Ray> out;
    for (Ray ray : rays) {
        ray.direction = {std::sin(theta * deg), 0.0, std::cos(theta * deg)};
        ray.t_max = 1.0;
        out.push_back(ray);
    }
    return out;
}

void suite_collect(const Options& o) {
    const auto first = trace_2a<CompactRecord>(o.map_photons, 2);
    const MapScene scene = scene_2a();
    const auto kd = photon_map<KdTreeStore<CompactRecord>>(first, scene);
    const auto voi = photon_map<VoiOctreeStore<CompactRecord>>(first, scene);
    const Cone cone(petzold_m93(), 0.005);
    const auto rays = nadir_ray_grid(1.0, 8.0, 10, 1.0);
    const double r = 0.05;
    const double nr = static_cast<double>(rays.size());

    out(o, "### Radiance collection through a problem-2a map\n");
    out(o, "Map: " + fmt("%.3g", static_cast<double>(o.map_photons)) + " photons traced for problem 2a, " +
               fmt("%.3g", static_cast<double>(first.records.size())) +
               " CompactRecords stored. Rays: the 10 x 10 grid of vertical rays of length L = 8 m from tau = 1 "
               "(nadir_ray_grid), radiance estimator (cone-averaged Petzold, omega = 0.005 sr), 1 thread; "
               "rays/s = 100 / (median time of " + std::to_string(o.repeats) + " runs), [min-max]. "
               "\"search only\" runs the same gather with a counting visitor (no radiance arithmetic).\n");
    out(o, "#### At equal collection radius r = 0.05 m\n");
    out(o, "| collection | rays/s [min-max] | search-only rays/s | photons/ray | ns per photon | of which radiance arithmetic | Lu +- SE |");
    out(o, "|---|---|---|---|---|---|---|");
    const auto v = collect(o, voi, VoiCylinder{}, cone, rays, r);
    const auto vs = search_only(o.repeats, voi.store(), VoiCylinder{}, rays, r);
    std::vector<Collected> k;
    std::vector<double> k_search;  // search-only median seconds per n
    for (unsigned n : {8u, 16u, 32u, 64u, 128u}) {
        const auto c = collect(o, kd, StepSpheres(n), cone, rays, r);
        const auto s = search_only(o.repeats, kd.store(), StepSpheres(n), rays, r);
        k.push_back(c);
        k_search.push_back(s.first.median);
        out(o, "| k-d tree, n = " + std::to_string(n) + " | " + rate_cell(c.t, nr) + " | " + fmt("%.4g", nr / s.first.median) +
                   " | " + fmt("%.4g", c.photons_per_ray) + " | " + fmt("%.3g", c.t.median / nr / c.photons_per_ray * 1e9) +
                   " | " + fmt("%.3g", (c.t.median - s.first.median) / nr / c.photons_per_ray * 1e9) + " | " + lu_cell(c.lu) + " |");
    }
    {
        const auto nf = photon_map<NanoflannStore<CompactRecord>>(first, scene);
        const auto c = collect(o, nf, StepSpheres(32), cone, rays, r);
        const auto s = search_only(o.repeats, nf.store(), StepSpheres(32), rays, r);
        out(o, "| nanoflann, n = 32 | " + rate_cell(c.t, nr) + " | " + fmt("%.4g", nr / s.first.median) + " | " +
                   fmt("%.4g", c.photons_per_ray) + " | " + fmt("%.3g", c.t.median / nr / c.photons_per_ray * 1e9) +
                   " | " + fmt("%.3g", (c.t.median - s.first.median) / nr / c.photons_per_ray * 1e9) + " | " + lu_cell(c.lu) + " |");
    }
    auto cylinder_row = [&](const std::string& name, const Collected& c, const std::pair<Timing, double>& search) {
        out(o, "| " + name + " | " + rate_cell(c.t, nr) + " | " + fmt("%.4g", nr / search.first.median) + " | " +
                   fmt("%.4g", c.photons_per_ray) + " | " + fmt("%.3g", c.t.median / nr / c.photons_per_ray * 1e9) + " | " +
                   fmt("%.3g", (c.t.median - search.first.median) / nr / c.photons_per_ray * 1e9) + " | " + lu_cell(c.lu) + " |");
    };
    cylinder_row("VOI cylinder (octree)", v, vs);
    {
        const auto grid = photon_map<VoiGridStore<CompactRecord>>(first, scene, Radius(r));
        cylinder_row("VOI cylinder (grid, cells for r)", collect(o, grid, VoiCylinder{}, cone, rays, r),
                     search_only(o.repeats, grid.store(), VoiCylinder{}, rays, r));
    }
    out(o, "");
    out(o, "VOI / k-d rays/s at equal radius: " + [&] {
        std::string s;
        const unsigned ns[] = {8, 16, 32, 64, 128};
        for (std::size_t i = 0; i < k.size(); ++i)
            s += (i ? ", " : "") + std::string("n = ") + std::to_string(ns[i]) + ": " + fmt("%.3g", v.rays_per_s / k[i].rays_per_s);
        return s;
    }() + ".\n");

    out(o, "#### At equal photons per ray\n");
    out(o, "For each n the VOI cylinder radius is r_c = 0.05 sqrt(P_kd(n) / P_voi(0.05)) (photons per ray scale with "
           "the cylinder's cross-section), so the cylinder touches as many photons per ray as the n spheres of radius "
           "0.05; the measured counts are shown. \"search only\" compares the two gathers with a counting visitor (the "
           "search structures alone, without the radiance arithmetic both share per photon). The last ratio instead widens the k-d spheres to "
           "R_n = 0.05 (P_voi(0.05) / P_kd(n))^(1/3) so they touch as many as the cylinder at r = 0.05.\n");
    out(o, "**VOI / k-d** is paired: " + std::to_string(o.repeats) + " rounds, each timing the k-d tree's estimate "
           "and then the cylinder's, the median [min-max] of the rounds' ratios (the two in one round see about the "
           "same load on the shared machine). The other ratios divide medians timed at different moments.\n");
    out(o, "| n | k-d photons/ray | k-d rays/s | r_c (m) | VOI photons/ray | VOI rays/s [min-max] | VOI Lu +- SE | k-d Lu +- SE | **VOI / k-d**, paired | search only: VOI / k-d | R_n (m) | k-d(R_n) photons/ray | k-d(R_n) rays/s | VOI(0.05) / k-d(R_n) |");
    out(o, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    const unsigned ns[] = {8, 16, 32, 64, 128};
    for (std::size_t i = 0; i < k.size(); ++i) {
        const double rc = r * std::sqrt(k[i].photons_per_ray / v.photons_per_ray);
        const auto c = collect(o, voi, VoiCylinder{}, cone, rays, rc);
        const auto cs = search_only(o.repeats, voi.store(), VoiCylinder{}, rays, rc);
        const auto kd_est = radiance_estimator(kd, StepSpheres(ns[i]), cone, r);
        const auto voi_est = radiance_estimator(voi, VoiCylinder{}, cone, rc);
        const Timing paired = paired_ratio(o.repeats, [&] { kd_est.estimate(rays, 1); }, [&] { voi_est.estimate(rays, 1); });
        const double rn = r * std::cbrt(v.photons_per_ray / k[i].photons_per_ray);
        const auto kw = collect(o, kd, StepSpheres(ns[i]), cone, rays, rn);
        out(o, "| " + std::to_string(ns[i]) + " | " + fmt("%.4g", k[i].photons_per_ray) + " | " + fmt("%.4g", k[i].rays_per_s) +
                   " | " + fmt("%.4f", rc) + " | " + fmt("%.4g", c.photons_per_ray) + " | " + rate_cell(c.t, nr) + " | " +
                   lu_cell(c.lu) + " | " + lu_cell(k[i].lu) + " | **" + fmt("%.3g", paired.median) + "** [" +
                   fmt("%.3g", paired.lo) + "-" + fmt("%.3g", paired.hi) + "] | " + fmt("%.3g", k_search[i] / cs.first.median) + " | " + fmt("%.4f", rn) + " | " + fmt("%.4g", kw.photons_per_ray) + " | " + fmt("%.4g", kw.rays_per_s) +
                   " | " + fmt("%.3g", v.rays_per_s / kw.rays_per_s) + " |");
    }
    out(o, "");

    // The VOI stores' two record layouts (map/packed_records.hpp), the same map, paired: make(rc,
    // layout tag) gives a store's photon map for the cylinder radius rc.
    const auto layout_table = [&](const std::string& store, auto make_plain, auto make_packed) {
        const std::string by_default = default_record_layout<CompactRecord> == RecordLayout::packed ? "packed" : "plain";
        const auto per_photon = [&](std::size_t bytes) { return static_cast<double>(bytes) / static_cast<double>(first.records.size()); };
        out(o, "The " + store + "'s record layouts on this map: packed (12 bytes per record) against plain (16-byte "
               "CompactRecords); the default in this build: " + by_default + ". Bytes per photon, index included. "
               "**packed / plain** rays/s, paired as above, for the estimate and for the search only (counting visitor).\n");
        out(o, "| r_c (m) | photons/ray | packed rays/s | bytes/photon, packed / plain | **packed / plain**, estimate | **packed / plain**, search only |");
        out(o, "|---|---|---|---|---|---|");
        for (const double rc : {r, r * std::sqrt(k[2].photons_per_ray / v.photons_per_ray)}) {
            const auto plain = make_plain(rc);
            const auto packed = make_packed(rc);
            const auto packed_est = radiance_estimator(packed, VoiCylinder{}, cone, rc);
            const auto plain_est = radiance_estimator(plain, VoiCylinder{}, cone, rc);
            const auto c = collect(o, packed, VoiCylinder{}, cone, rays, rc);
            const Timing estimate = paired_ratio(o.repeats, [&] { plain_est.estimate(rays, 1); }, [&] { packed_est.estimate(rays, 1); });
            const Timing search = paired_ratio(
                o.repeats, [&] { search_only(1, plain.store(), VoiCylinder{}, rays, rc); },
                [&] { search_only(1, packed.store(), VoiCylinder{}, rays, rc); });
            out(o, "| " + fmt("%.4f", rc) + " | " + fmt("%.4g", c.photons_per_ray) + " | " + rate_cell(c.t, nr) + " | " +
                       fmt("%.2f", per_photon(packed.store().memory_bytes())) + " / " +
                       fmt("%.2f", per_photon(plain.store().memory_bytes())) + " | **" + fmt("%.3g", estimate.median) +
                       "** [" + fmt("%.3g", estimate.lo) + "-" + fmt("%.3g", estimate.hi) + "] | **" +
                       fmt("%.3g", search.median) + "** [" + fmt("%.3g", search.lo) + "-" + fmt("%.3g", search.hi) + "] |");
        }
        out(o, "");
    };
    layout_table(
        "VOI octree", [&](double) { return photon_map<VoiOctreeStore<CompactRecord, RecordLayout::plain>>(first, scene); },
        [&](double) { return photon_map<VoiOctreeStore<CompactRecord, RecordLayout::packed>>(first, scene); });
    layout_table(
        "VOI grid (cells for each r_c)",
        [&](double rc) { return photon_map<VoiGridStore<CompactRecord, RecordLayout::plain>>(first, scene, Radius(rc)); },
        [&](double rc) { return photon_map<VoiGridStore<CompactRecord, RecordLayout::packed>>(first, scene, Radius(rc)); });

    out(o, "The same cylinder radii r_c in the VOI grid (VoiGridStore, its cells sized for each r_c: columns r_c / 2 "
           "wide, r_c tall; built per row), against the same k-d tree estimates; **grid / k-d** paired as above.\n");
    out(o, "| n | r_c (m) | grid photons/ray | grid rays/s [min-max] | grid Lu +- SE | k-d Lu +- SE | **grid / k-d**, paired | search only: grid / k-d | grid / octree at r_c, search only |");
    out(o, "|---|---|---|---|---|---|---|---|---|");
    for (std::size_t i = 0; i < k.size(); ++i) {
        const double rc = r * std::sqrt(k[i].photons_per_ray / v.photons_per_ray);
        const auto grid = photon_map<VoiGridStore<CompactRecord>>(first, scene, Radius(rc));
        const auto c = collect(o, grid, VoiCylinder{}, cone, rays, rc);
        const auto cs = search_only(o.repeats, grid.store(), VoiCylinder{}, rays, rc);
        const auto os = search_only(o.repeats, voi.store(), VoiCylinder{}, rays, rc);
        const auto kd_est = radiance_estimator(kd, StepSpheres(ns[i]), cone, r);
        const auto grid_est = radiance_estimator(grid, VoiCylinder{}, cone, rc);
        const Timing paired = paired_ratio(o.repeats, [&] { kd_est.estimate(rays, 1); }, [&] { grid_est.estimate(rays, 1); });
        out(o, "| " + std::to_string(ns[i]) + " | " + fmt("%.4f", rc) + " | " + fmt("%.4g", c.photons_per_ray) + " | " +
                   rate_cell(c.t, nr) + " | " + lu_cell(c.lu) + " | " + lu_cell(k[i].lu) + " | **" + fmt("%.3g", paired.median) +
                   "** [" + fmt("%.3g", paired.lo) + "-" + fmt("%.3g", paired.hi) + "] | " +
                   fmt("%.3g", k_search[i] / cs.first.median) + " | " + fmt("%.3g", os.first.median / cs.first.median) + " |");
    }
#if SECCHI_BENCH_EMBREE
    {  // the optional comparator at the n = 32 cylinder's radius (embree_spheres.hpp), search only
        const double rc = r * std::sqrt(k[2].photons_per_ray / v.photons_per_ray);
        const VoiGridStore<CompactRecord> grid(first.records, Radius(rc));
        const EmbreeSpheres embree(grid.records(), rc);
        const auto es = embree_search(o.repeats, embree, rays);
        const auto gs = search_only(o.repeats, grid, VoiCylinder{}, rays, rc);
        out(o, "");
        out(o, "Search only at r_c = " + fmt("%.4f", rc) + " (equal photons to k-d n = 32): " + EmbreeSpheres::version() +
                   " collecting every sphere of radius r_c that the ray hits "
                   "(the records in the grid's order) counts " + fmt("%.4g", es.second) + " photons per ray at " +
                   rate_cell(es.first, nr) + " rays/s: " + fmt("%.3g", k_search[2] / es.first.median) +
                   " times the k-d tree's search at n = 32, and the grid's search " + fmt("%.3g", es.first.median / gs.first.median) +
                   " times Embree's.");
    }
#endif
    out(o, "");
}

// -------------------------------------------------------------------------------- uniform

void suite_uniform(const Options& o) {
    const std::size_t n = 1'000'000;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<CompactRecord> recs;
    recs.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
        recs.push_back(CompactRecord::make({u(rng), u(rng), u(rng)}, {0, 0, 1}, 0, static_cast<std::uint8_t>(i % 32)));
    const KdTreeStore<CompactRecord> kd(recs);
    const NanoflannStore<CompactRecord> nf(recs);
    const VoiOctreeStore<CompactRecord> voi(recs);
    // ~50 points per sphere: 1e6 * 4/3 pi r^3 = 50.
    const double r = std::cbrt(50.0 / (n * 4.0 / 3.0 * pi));
    std::vector<Ray> rays;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) rays.push_back({{0.1 + 0.08 * i + 0.004, 0.1 + 0.08 * j + 0.002, 0.0}, {0, 0, 1}, 1.0});
    const double nr = static_cast<double>(rays.size());
    const auto ks = search_only(o.repeats, kd, StepSpheres(32), rays, r);
    const auto ns = search_only(o.repeats, nf, StepSpheres(32), rays, r);
    const double rc = r * std::sqrt(ks.second / (n * pi * r * r));
    const auto vs = search_only(o.repeats, voi, VoiCylinder{}, rays, rc);
    const auto ve = search_only(o.repeats, voi, VoiCylinder{}, rays, r);
    const VoiGridStore<CompactRecord> grid_c(recs, Radius(rc)), grid_r(recs, Radius(r));
    const auto gs = search_only(o.repeats, grid_c, VoiCylinder{}, rays, rc);
    const auto ge = search_only(o.repeats, grid_r, VoiCylinder{}, rays, r);
    out(o, "### Search only, 1e6 uniform points (the issue's scale figures)\n");
    out(o, "1e6 uniform CompactRecords in the unit cube; 100 vertical rays of length 1; sphere radius " + fmt("%.4f", r) +
               " (50 points expected per sphere); the cylinder radius r_c = r sqrt(P_kd / (N pi r^2)) gives equal photons "
               "per ray. Counting visitor, 1 thread, median [min-max] of " + std::to_string(o.repeats) + " runs.\n");
    out(o, "| search | rays/s [min-max] | photons/ray | ratio to k-d n = 32 |");
    out(o, "|---|---|---|---|");
    out(o, "| k-d tree, n = 32 | " + rate_cell(ks.first, nr) + " | " + fmt("%.4g", ks.second) + " | 1 |");
    out(o, "| nanoflann, n = 32 | " + rate_cell(ns.first, nr) + " | " + fmt("%.4g", ns.second) + " | " +
               fmt("%.3g", ks.first.median / ns.first.median) + " |");
    out(o, "| VOI cylinder, r_c = " + fmt("%.4f", rc) + " (equal photons) | " + rate_cell(vs.first, nr) + " | " +
               fmt("%.4g", vs.second) + " | " + fmt("%.3g", ks.first.median / vs.first.median) + " |");
    out(o, "| VOI cylinder, r = " + fmt("%.4f", r) + " (equal radius) | " + rate_cell(ve.first, nr) + " | " +
               fmt("%.4g", ve.second) + " | " + fmt("%.3g", ks.first.median / ve.first.median) + " |");
    out(o, "| VOI grid (cells for r_c), r_c = " + fmt("%.4f", rc) + " (equal photons) | " + rate_cell(gs.first, nr) + " | " +
               fmt("%.4g", gs.second) + " | " + fmt("%.3g", ks.first.median / gs.first.median) + " |");
    out(o, "| VOI grid (cells for r), r = " + fmt("%.4f", r) + " (equal radius) | " + rate_cell(ge.first, nr) + " | " +
               fmt("%.4g", ge.second) + " | " + fmt("%.3g", ks.first.median / ge.first.median) + " |");
#if SECCHI_BENCH_EMBREE
    // The optional comparator: spheres of radius r_c and r around the records, in the grid's
    // cell order (embree_spheres.hpp), every sphere the ray hits counted.
    for (const auto& [radius, label] : {std::pair{rc, "r_c"}, std::pair{r, "r"}}) {
        const EmbreeSpheres embree(grid_c.records(), radius);
        const auto es = embree_search(o.repeats, embree, rays);
        out(o, "| " + EmbreeSpheres::version() + ", every sphere of radius " + label + " = " + fmt("%.4f", radius) +
                   " the ray hits | " + rate_cell(es.first, nr) + " | " + fmt("%.4g", es.second) + " | " +
                   fmt("%.3g", ks.first.median / es.first.median) + " |");
    }
#else
    out(o, "| Embree 3 (optional comparator) | not built: CMake did not find Embree 3 (Debian: libembree-dev) | | |");
#endif
    out(o, "");
}

// -------------------------------------------------------------------------------- scaling

void suite_scaling(const Options& o) {
    std::vector<std::size_t> sizes;
    for (double e = 4.0; e <= 7.01; e += 0.5) {
        const auto n = static_cast<std::size_t>(std::llround(std::pow(10.0, e)));
        if (n <= o.max_records) sizes.push_back(n);
    }
    const auto full = records_2a(sizes.back());
    // Query points: the 100 ray origins at depths 1..9 (the populated, horizontally uniform field).
    const auto rays = nadir_ray_grid(1.0, 8.0, 10, 1.0);
    std::vector<vec3> points;
    for (const Ray& ray : rays)
        for (int s = 0; s < 8; ++s) points.push_back(ray.origin + (s + 0.5) * ray.direction);
    out(o, "### Scaling: build and query cost against record count\n");
    out(o, "Records: prefixes of one problem-2a light field (CompactRecord). Build: median of runs (5 below 1e6, 3 "
           "above), 1 thread. Queries, 1 thread, per query: k-d tree `within` at 800 points (depths 1-9) and VOI "
           "`along` for 100 vertical rays of length 8 (counting collector). \"fixed r\": r = 0.05 m, so k grows with N "
           "(O(log N + k)); \"fixed k\": the radius shrinks with N (sphere r = 0.015 (N/1e7)^(-1/3), cylinder r = 0.005 "
           "(N/1e7)^(-1/2)) so k stays about constant and the log N term shows (at the smallest N the sphere or cylinder "
           "reaches past the 1 m section's edge for the outer points, so k there is a little lower).\n");
    out(o, "| N | k-d build s | k-d build ns/(N log2 N) | VOI build s | VOI build ns/(N log2 N) | within us (fixed r) | k | within us (fixed k) | k | along us (fixed r) | k | along us (fixed k) | k |");
    out(o, "|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    if (o.csv) *o.csv << "n,kd_build_s,voi_build_s,within_fixed_r_us,within_fixed_r_k,within_fixed_k_us,within_fixed_k_k,along_fixed_r_us,along_fixed_r_k,along_fixed_k_us,along_fixed_k_k\n";
    for (std::size_t n : sizes) {
        const auto recs = to_compact(full, n);
        const int reps = n >= 1'000'000 ? 3 : 5;
        std::vector<CompactRecord> copy;
        const Timing kb = time_runs(reps, [&] { copy = recs; }, [&] { const KdTreeStore<CompactRecord> s(std::move(copy)); });
        const Timing vb = time_runs(reps, [&] { copy = recs; }, [&] { const VoiOctreeStore<CompactRecord> s(std::move(copy)); });
        const KdTreeStore<CompactRecord> kd(recs);
        const VoiOctreeStore<CompactRecord> voi(recs);
        // Median time per query (us) of query(q, Radius(r), collector) over `queries`; k: hits per query.
        auto per_query = [&](const auto& queries, auto&& query, double r, double& k) {
            std::size_t total = 0;
            const Timing t = time_runs(o.repeats, [&] {
                CountHits c;
                for (const auto& q : queries) query(q, Radius(r), c);
                total = c.count;
            });
            k = static_cast<double>(total) / queries.size();
            return t.median / queries.size() * 1e6;
        };
        auto within = [&](double r, double& k) {
            return per_query(points, [&](const vec3& p, Radius rr, CountHits& c) { kd.within(p, rr, c); }, r, k);
        };
        auto along = [&](double r, double& k) {
            return per_query(rays, [&](const Ray& ray, Radius rr, CountHits& c) { voi.along(ray, rr, c); }, r, k);
        };
        const double scale = static_cast<double>(n) / 1e7;
        double k1, k2, k3, k4;
        const double w1 = within(0.05, k1), w2 = within(0.015 * std::cbrt(1.0 / scale), k2);
        const double a1 = along(0.05, k3), a2 = along(0.005 * std::sqrt(1.0 / scale), k4);
        const double nlogn = n * std::log2(static_cast<double>(n));
        out(o, "| " + fmt("%.3g", static_cast<double>(n)) + " | " + fmt("%.3g", kb.median) + " | " +
                   fmt("%.3g", kb.median / nlogn * 1e9) + " | " + fmt("%.3g", vb.median) + " | " +
                   fmt("%.3g", vb.median / nlogn * 1e9) + " | " + fmt("%.3g", w1) + " | " + fmt("%.3g", k1) + " | " +
                   fmt("%.3g", w2) + " | " + fmt("%.3g", k2) + " | " + fmt("%.3g", a1) + " | " + fmt("%.3g", k3) + " | " +
                   fmt("%.3g", a2) + " | " + fmt("%.3g", k4) + " |");
        if (o.csv)
            *o.csv << n << "," << kb.median << "," << vb.median << "," << w1 << "," << k1 << "," << w2 << "," << k2 << ","
                   << a1 << "," << k3 << "," << a2 << "," << k4 << "\n";
    }
    out(o, "");
}

// ----------------------------------------------------------------------------------- tune

void suite_tune(const Options& o) {
    const auto map = trace_2a<CompactRecord>(o.map_photons, 2);
    const auto rays = nadir_ray_grid(1.0, 8.0, 10, 1.0);
    const double nr = static_cast<double>(rays.size());
    const Cone cone(petzold_m93(), 0.005);
    out(o, "### VOI octree: leaf size\n");
    out(o, "Same problem-2a map and 100 rays as the collection table (" + fmt("%.3g", static_cast<double>(map.records.size())) +
               " CompactRecords). Per ray (counting collector, 1 thread): nodes whose padded box the ray meets, records "
               "tested one by one, records accepted in bulk (subtrees inside the cylinder), hits; search-only rays/s, "
               "median of " + std::to_string(o.repeats) + " runs. r = 0.05 (equal radius) and r = 0.026 (equal photons "
               "to k-d n = 32).\n");
    out(o, "| leaf size | nodes | bytes/photon | build s | r | nodes/ray | tested/ray | bulk/ray | hits/ray | rays/s [min-max] |");
    out(o, "|---|---|---|---|---|---|---|---|---|---|");
    for (std::size_t leaf : {4ul, 8ul, 16ul, 32ul, 64ul, 128ul, 256ul, 512ul, 1024ul, 2048ul}) {
        std::vector<CompactRecord> copy;
        const Timing b = time_runs(3, [&] { copy = map.records; }, [&] { const VoiOctreeStore<CompactRecord> s(std::move(copy), leaf); });
        const VoiOctreeStore<CompactRecord> voi(map.records, leaf);
        for (double r : {0.05, 0.026}) {
            typename VoiOctreeStore<CompactRecord>::AlongStats sum;
            for (const Ray& ray : rays) sum += voi.along_stats(ray, Radius(r));
            const auto so = search_only(o.repeats, voi, VoiCylinder{}, rays, r);
            out(o, "| " + std::to_string(leaf) + " | " + std::to_string(voi.node_count()) + " | " +
                       fmt("%.2f", static_cast<double>(voi.memory_bytes()) / voi.size()) + " | " + fmt("%.3g", b.median) +
                       " | " + fmt("%.3f", r) + " | " + fmt("%.4g", sum.nodes / nr) + " | " + fmt("%.4g", sum.tested / nr) +
                       " | " + fmt("%.4g", sum.bulk / nr) + " | " + fmt("%.4g", sum.hits / nr) + " | " + rate_cell(so.first, nr) + " |");
        }
    }
    out(o, "");

    out(o, "### VOI octree: leaf size with the radiance estimator\n");
    out(o, "The same map and rays through PhotonMap<VoiOctreeStore> (the collection table's estimator: cone-averaged "
           "Petzold, omega = 0.005 sr), 1 thread. Each leaf size's estimate is paired with leaf 128's: " +
               std::to_string(o.repeats) + " rounds, each timing leaf 128 and then the other, the median [min-max] of "
               "the rounds' rate ratios.\n");
    out(o, "| leaf size | r | rays/s [min-max] | / leaf 128, paired |");
    out(o, "|---|---|---|---|");
    {
        const MapScene scene = scene_2a();
        const auto base = photon_map<VoiOctreeStore<CompactRecord>>(map, scene, std::size_t{128});
        for (std::size_t leaf : {128ul, 256ul, 512ul, 1024ul}) {
            const auto voi = photon_map<VoiOctreeStore<CompactRecord>>(map, scene, leaf);
            for (double r : {0.05, 0.0258}) {
                const auto c = collect(o, voi, VoiCylinder{}, cone, rays, r);
                const auto base_est = radiance_estimator(base, VoiCylinder{}, cone, r);
                const auto est = radiance_estimator(voi, VoiCylinder{}, cone, r);
                const Timing paired = paired_ratio(o.repeats, [&] { base_est.estimate(rays, 1); }, [&] { est.estimate(rays, 1); });
                out(o, "| " + std::to_string(leaf) + " | " + fmt("%.4f", r) + " | " + rate_cell(c.t, nr) + " | " +
                           fmt("%.3g", paired.median) + " [" + fmt("%.3g", paired.lo) + "-" + fmt("%.3g", paired.hi) + "] |");
            }
        }
    }
    out(o, "");

    out(o, "### VOI grid: cell shape\n");
    out(o, "The same map and rays. VoiGridStore with columns w wide and cells h tall, in units of the query radius r "
           "(at most 2 cells per record: finer shapes are widened, as the cell sizes shown say). Per ray (counting "
           "collector): record ranges scanned (one per column), records tested, hits; search-only rays/s, median of " +
           std::to_string(o.repeats) + " runs.\n");
    out(o, "| r | w / r | h / r | cell w x h (m) | bytes/photon | ranges/ray | tested/ray | hits/ray | rays/s [min-max] |");
    out(o, "|---|---|---|---|---|---|---|---|---|");
    for (double r : {0.05, 0.026})
        for (double w : {1.0, 0.5, 0.33})
            for (double h : {0.5, 1.0, 2.0, 4.0}) {
                const VoiGridStore<CompactRecord> grid(map.records, w * r, h * r);
                typename VoiGridStore<CompactRecord>::AlongStats sum;
                for (const Ray& ray : rays) sum += grid.along_stats(ray, Radius(r));
                const auto so = search_only(o.repeats, grid, VoiCylinder{}, rays, r);
                out(o, "| " + fmt("%.3f", r) + " | " + fmt("%.2g", w) + " | " + fmt("%.2g", h) + " | " +
                           fmt("%.4f", grid.cell_size().x) + " x " + fmt("%.4f", grid.cell_size().z) + " | " +
                           fmt("%.2f", static_cast<double>(grid.memory_bytes()) / grid.size()) + " | " +
                           fmt("%.3g", sum.ranges / nr) + " | " + fmt("%.4g", sum.tested / nr) + " | " +
                           fmt("%.4g", sum.hits / nr) + " | " + rate_cell(so.first, nr) + " |");
            }
    out(o, "");

    out(o, "### VOI grid against the octree: slanted rays\n");
    out(o, "The same map; the 100 ray origins of the collection table, rays of length 1 tilted by the zenith angle "
           "theta in the x-z plane; r = 0.026, the grid built for it (columns r/2 wide, r tall), the octree with leaf "
           "size " + std::to_string(VoiOctreeStore<CompactRecord>::default_leaf_size) + " (the default). Search only, counting collector, median of " + std::to_string(o.repeats) + " runs.\n");
    out(o, "| theta (deg) | hits/ray | grid ranges/ray | grid tested/ray | grid rays/s [min-max] | octree tested/ray | octree rays/s [min-max] | grid / octree |");
    out(o, "|---|---|---|---|---|---|---|---|");
    {
        const double r = 0.026;
        const VoiGridStore<CompactRecord> grid(map.records, Radius(r));
        const VoiOctreeStore<CompactRecord> voi(map.records);
        for (double theta : {0.0, 30.0, 60.0, 85.0}) {
            const std::vector<Ray> slanted = tilted(rays, theta);
            typename VoiGridStore<CompactRecord>::AlongStats g;
            typename VoiOctreeStore<CompactRecord>::AlongStats v;
            for (const Ray& ray : slanted) {
                g += grid.along_stats(ray, Radius(r));
                v += voi.along_stats(ray, Radius(r));
            }
            const auto gs = search_only(o.repeats, grid, VoiCylinder{}, slanted, r);
            const auto vs = search_only(o.repeats, voi, VoiCylinder{}, slanted, r);
            out(o, "| " + fmt("%.0f", theta) + " | " + fmt("%.4g", g.hits / nr) + " | " + fmt("%.3g", g.ranges / nr) + " | " +
                       fmt("%.4g", g.tested / nr) + " | " + rate_cell(gs.first, nr) + " | " +
                       fmt("%.4g", (v.tested + v.bulk) / nr) + " | " + rate_cell(vs.first, nr) + " | " +
                       fmt("%.3g", vs.first.median / gs.first.median) + " |");
        }
    }
    out(o, "");

    out(o, "### VOI grid: cell shape on slanted rays\n");
    out(o, "The slanted rays above (r = 0.026), through grids of other cell shapes (columns w wide, cells h tall, "
           "in units of r; at most 2 cells per record). Search only, counting collector, median of " +
               std::to_string(o.repeats) + " runs; the last column divides by the default shape's rate (w = r/2, "
               "h = r), timed in the same loop.\n");
    out(o, "| theta (deg) | w / r | h / r | ranges/ray | tested/ray | hits/ray | rays/s [min-max] | / default |");
    out(o, "|---|---|---|---|---|---|---|---|");
    {
        const double r = 0.026;
        const std::pair<double, double> shapes[] = {{0.5, 1.0}, {0.25, 1.0}, {0.5, 0.5}, {0.5, 2.0}, {1.0, 1.0}, {1.0, 2.0}};
        std::vector<VoiGridStore<CompactRecord>> grids;
        for (const auto& [w, h] : shapes) grids.emplace_back(map.records, w * r, h * r);
        for (double theta : {30.0, 60.0, 85.0}) {
            const std::vector<Ray> slanted = tilted(rays, theta);
            double default_median = 0.0;
            for (std::size_t i = 0; i < grids.size(); ++i) {
                typename VoiGridStore<CompactRecord>::AlongStats g;
                for (const Ray& ray : slanted) g += grids[i].along_stats(ray, Radius(r));
                const auto gs = search_only(o.repeats, grids[i], VoiCylinder{}, slanted, r);
                if (i == 0) default_median = gs.first.median;
                out(o, "| " + fmt("%.0f", theta) + " | " + fmt("%.2g", shapes[i].first) + " | " + fmt("%.2g", shapes[i].second) +
                           " | " + fmt("%.3g", g.ranges / nr) + " | " + fmt("%.4g", g.tested / nr) + " | " +
                           fmt("%.4g", g.hits / nr) + " | " + rate_cell(gs.first, nr) + " | " +
                           fmt("%.3g", default_median / gs.first.median) + " |");
            }
        }
    }
    out(o, "");
}

// ------------------------------------------------------------------------------- spectral

/// One row per r_spectral of the spectral suite: `volume`'s shared searches (one per ray
/// segment for every band, or one per band's segment for a volume that follows the segment's
/// length) against the per-band estimators at each radius, paired.
template <class Store, class Volume>
void spectral_rows(const Options& o, const std::string& label, const PhotonMap<Store>& map, const Volume& volume,
                   const std::vector<HomogeneousRayOptics>& optics, const std::vector<Ray>& rays, double r_core) {
    const double nr = static_cast<double>(rays.size());
    const unsigned bands = map.bands();
    for (const double r_spectral : {0.1, 0.2}) {
        const SpectralCompensationEstimator est(map, volume, optics, SpectralCompensation{r_core, r_spectral});
        const auto per_band = [&] {
            CompensatedSum total = est.empty_sum();
            for (const Ray& ray : rays) {
                std::vector<RadianceSum> at_core(bands, RadianceSum(map.batches())), at_spectral(bands, RadianceSum(map.batches()));
                for (unsigned k = 0; k < bands; ++k) {
                    est.core().add(ray, k, 1.0, at_core[k]);
                    est.spectral().add(ray, k, 1.0, at_spectral[k]);
                }
                total.add_ray(at_core, at_spectral, 1.0);
            }
            return total;
        };
        CompensatedSum one = est.empty_sum(), definition = est.empty_sum();
        const Timing t_one = time_runs(o.repeats, [&] { one = est.sum_over(rays, 1); });
        const Timing t_def = time_runs(o.repeats, [&] { definition = per_band(); });
        const Timing ratio = paired_ratio(o.repeats, [&] { definition = per_band(); }, [&] { one = est.sum_over(rays, 1); });
        double worst = 0.0;
        for (unsigned k = 0; k < bands; ++k) {
            const double a = one.estimate(k).value, b = definition.estimate(k).value;
            worst = std::max(worst, std::abs(a - b) / std::abs(b));
        }
        out(o, "| " + label + " | " + fmt("%.2f", r_spectral) + " | " +
                   fmt("%.4g", static_cast<double>(one.photons_touched()) / nr) + " | " + rate_cell(t_one, nr) + " | " +
                   rate_cell(t_def, nr) + " | **" + fmt("%.3g", ratio.median) + "** [" + fmt("%.3g", ratio.lo) + "-" +
                   fmt("%.3g", ratio.hi) + "] | " + fmt("%.1e", worst) + " |");
    }
}

/// Spectral compensation (estimate/spectral_compensation.hpp): the shared searches (manual
/// 3.5.2.3) against the definition, the per-band estimators at each radius (2 x bands searches
/// per segment), paired: the VOI cylinder in the VOI grid (one search per ray segment for every
/// band and both radii), and k-d tree step spheres (one search per band's segment for both radii).
void suite_spectral(const Options& o) {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    constexpr unsigned bands = 8;
    const double r_core = 0.05;
    std::vector<Water> waters;
    std::vector<double> wavelengths;
    std::vector<HomogeneousRayOptics> optics;
    for (unsigned k = 0; k < bands; ++k) {  // c from 0.4 to 1.5 /m, albedo 0.9 to 0.5: as 400-700 nm might
        const double c = 0.4 + 1.1 * k / (bands - 1), w0 = 0.9 - 0.4 * k / (bands - 1);
        waters.push_back(Water::from_albedo(c, w0, HenyeyGreensteinPhase(0.85)));
        wavelengths.push_back(400.0 + 300.0 * k / (bands - 1));
        optics.emplace_back(ConeAveragedPhase(waters.back().phase(), 0.005), waters.back().attenuation(), waters.back().scattering());
    }
    PlaneParallelConfig cfg;
    cfg.sun_zenith_deg = 30.0;
    cfg.transport.photons = cfg.transport.map_photons = o.quick ? 20'000 : 100'000;
    cfg.transport.threads = 2;
    cfg.transport.depths = {1.0};
    cfg.transport.map_depth = 60.0;
    const auto grid = trace_spectral_map<VoiGridStore<CompactRecord>>(waters, wavelengths, cfg, Radius(r_core));
    std::vector<Ray> rays = nadir_ray_grid(1.0, INFINITY, 10, grid.map.section_width());
    for (unsigned i = 0; i < 20; ++i)  // slanted rays, 45 degrees from the vertical, 2 m long
        rays.push_back({{0.05 * i, 0.5, 1.0}, {std::sqrt(0.5), 0.0, std::sqrt(0.5)}, 2.0});

    out(o, "### Spectral compensation: shared searches for every band and both radii\n");
    out(o, "Map: " + std::to_string(bands) + " bands (HG g = 0.85 waters, c 0.4-1.5 /m, albedo 0.9-0.5), " +
               fmt("%.3g", static_cast<double>(cfg.transport.photons)) + " photons per band, " +
               fmt("%.3g", static_cast<double>(grid.map.store().size())) +
               " CompactRecords (VOI grid: cells for r_core = 0.05; the same records in a k-d tree). Rays: 100 nadir "
               "rays from 1 m (ending where the transmittance falls to 1e-4) and 20 rays at 45 deg, 2 m long; 1 thread. "
               "**shared / per band**: the rays' compensated radiances (SpectralCompensationEstimator::sum_over: the "
               "cylinder's one gather_nested per ray segment, the step spheres' one per band's segment) against the "
               "same from the per-band estimators at each radius (2 x bands searches per segment), paired, " +
               std::to_string(o.repeats) + " rounds, rate ratio median [min-max]; the largest relative difference of "
               "the bands' values.\n");
    out(o, "| volume, store | r_spectral (m) | photons per ray, shared | rays/s, shared | rays/s, per band | **shared / per band** | largest relative difference |");
    out(o, "|---|---|---|---|---|---|---|");
    spectral_rows(o, "VOI cylinder, VOI grid", grid.map, VoiCylinder(0.0, INFINITY), optics, rays, r_core);
    const auto kdtree = trace_spectral_map<KdTreeStore<CompactRecord>>(waters, wavelengths, cfg);
    spectral_rows(o, "step spheres (n = 32), k-d tree", kdtree.map, StepSpheres(32), optics, rays, r_core);
    out(o, "");
}

}  // namespace

int main(int argc, char** argv) {
    if (CommandLine::wants_help(argc, argv)) {
        std::cout << "usage: search_bench --suite build|collect|uniform|scaling|tune|spectral|all [--quick] [--md FILE] [--csv FILE]\n"
                     "                    [--repeats R] [--max-records N] [--map-photons N]\n";
        return 0;
    }
    try {
        const CommandLine cl(argc, argv, {"suite", "md", "csv", "repeats", "max-records", "map-photons"}, {"quick"});
        Options o;
        o.quick = cl.has("quick");
        if (o.quick) {
            o.repeats = 3;
            o.max_records = 1'000'000;
            o.map_photons = 200'000;
        }
        if (cl.has("repeats")) o.repeats = std::stoi(cl.text("repeats"));
        if (cl.has("max-records")) o.max_records = static_cast<std::size_t>(std::stod(cl.text("max-records")));
        if (cl.has("map-photons")) o.map_photons = static_cast<std::uint64_t>(std::stod(cl.text("map-photons")));
        std::ofstream md, csv;
        if (cl.has("md")) {
            md.open(cl.text("md"));
            o.md = &md;
        }
        if (cl.has("csv")) {
            csv.open(cl.text("csv"));
            o.csv = &csv;
        }
        const std::string suite = cl.text("suite", "all");
        if (suite != "all" && suite != "build" && suite != "collect" && suite != "uniform" && suite != "scaling" && suite != "tune" &&
            suite != "spectral")
            throw input_error("search_bench: --suite must be build, collect, uniform, scaling, tune, spectral or all");
        if (suite == "all" || suite == "collect") suite_collect(o);
        if (suite == "all" || suite == "uniform") suite_uniform(o);
        if (suite == "all" || suite == "build") suite_build(o);
        if (suite == "all" || suite == "scaling") suite_scaling(o);
        if (suite == "all" || suite == "tune") suite_tune(o);
        if (suite == "all" || suite == "spectral") suite_spectral(o);
        return 0;
    } catch (const input_error& e) {
        std::cerr << "search_bench: " << e.what() << "\n";
        return 2;
    } catch (const std::exception& e) {
        std::cerr << "search_bench: " << e.what() << "\n";
        return 2;
    }
}
