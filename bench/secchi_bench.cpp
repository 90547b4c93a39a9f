// secchi_bench: headline performance figures (a benchmark, never part of the tests).
//   secchi_bench [--quick] [--json FILE]
// Each figure is the median of repeated timed runs. Propagation: scattering events per second
// per core (analog transport, w0 = 0.9, every scattering stored), for the Henyey-Greenstein
// (g = 0.9) and Petzold samplers, and for HG with LaneTracer (photons in SIMD lanes of doubles,
// and of floats); photons per second for problems 1a, 2a and 2b on 1 and 2
// threads (thread_speedup_propagation is problem 2a's), and for 1a and 2a in double and float
// lanes on one. Collection: rays per
// second through a problem-2a map, k-d tree spheres at n = 32 against the VOI cylinder at the
// same radius and at equal photons per ray (the speed-ups paired: the two timed in turn, round
// by round), the cylinder in the VOI octree (voi_*) and in the grid of columns (voi_grid_*). Thread speed-ups: 2 threads against 1 on the same work, alternated run by run
// (collection also on a cache-resident map, thread_speedup_collection_cached_map, to separate
// memory traffic), and thread_speedup_compute_loop(_throughput_bound): pure compute loops,
// latency-bound and throughput-bound, timed in the same rounds: the speed-up the shared
// machine allowed at that moment; thread_speedup_memory_loop: the same for a loop bound by
// memory latency (a pointer chase through 64 MB per thread), where the two cores share the
// memory system as the collection's stores do.
#include "bench_problems.hpp"
#include "bench_timing.hpp"
#include "problem3.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/io/json_writer.hpp"
#include "secchi/optics/phase/fournier_forand.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <algorithm>
#include <array>
#include <stdexcept>
#include <cmath>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <numeric>
#include <random>

namespace {

using namespace secchi;
using namespace secchi::bench;

/// Scattering events per second on one core: analog transport, all events stored, into fresh
/// memory every run, or (`reuse_map`) into the memory of the previous run's map.
template <class Phase, template <class...> class Tracer = PhotonTracer>
double events_per_second(const Phase& phase, std::uint64_t photons, int repeats, bool reuse_map = false) {
    std::vector<CompactRecord> map;
    auto run = [&] {
        map = trace_slab<CompactRecord, Tracer>(phase, 0.9, 0.0, 1.0, photons, 1, AbsorptionMode::analog,
                                                reuse_map ? std::move(map) : std::vector<CompactRecord>{})
                  .records;
    };
    if (reuse_map) run();  // untimed: the memory every timed run reuses
    const double t = time_runs(repeats, run).median;
    return static_cast<double>(map.size()) / t;
}

/// Photons per second of a canonical problem's first pass on one core (sun at 60 deg, n = 1.34,
/// continuous absorption as in the conformance runs) by Tracer.
template <template <class...> class Tracer, class Phase>
double photons_per_second(const Phase& phase, double w0, std::uint64_t photons, int repeats) {
    const double t = time_runs(repeats, [&] {
                         trace_slab<CompactRecord, Tracer>(phase, w0, 60, 1.34, photons, 1, AbsorptionMode::continuous);
                     }).median;
    return static_cast<double>(photons) / t;
}

/// Photons per second of canonical problem 3's first pass on one core (its stratified water at
/// 500 nm with nodes every 5 cm to 100 m, as canonical's; sun at 60 deg, n = 1.34, continuous
/// absorption, detectors at 5, 25 and 60 m, no depth importance) by Tracer.
template <template <class...> class Tracer>
double problem3_photons_per_second(std::uint64_t photons, int repeats) {
    const auto water = iop::stratify_typed(conformance::problem3_model(), conformance::problem3_wavelength_nm,
                                           iop::uniform_depths(100.0, 0.05));
    using Water = std::decay_t<decltype(water)>;
    TransportSettings s;
    s.photons = s.map_photons = photons;
    s.threads = 1;
    s.absorption = AbsorptionMode::continuous;
    s.depths = {5.0, 25.0, 60.0};
    const Tracer<Water, CompactRecord> tracer(water, Slab(section_width, Bottom{}, 100.0), FlatSurface(1.34),
                                              CollimatedSun(60.0), s);
    return static_cast<double>(photons) / time_runs(repeats, [&] { tracer.run(); }).median;
}

struct CollectionFigures {
    double rays_per_s;
    double photons_per_ray;
    Estimate lu;
};

template <class Store, class Volume, class Cone>
CollectionFigures collect(const PhotonMap<Store>& map, const Volume& volume, const Cone& cone, const std::vector<Ray>& rays,
                          unsigned threads, int repeats, double radius = 0.05) {
    const auto est = radiance_estimator(map, volume, cone, radius);
    RadianceEstimate r;
    const double t = time_runs(repeats, [&] { r = est.estimate(rays, threads); }).median;
    return {static_cast<double>(rays.size()) / t, static_cast<double>(r.photons_touched) / rays.size(), r.radiance};
}

/// Seconds for two equal items of a pure compute loop (no memory traffic) on `threads`
/// threads: what the machine's cores give at that moment. Chains = 1: one dependent
/// multiply-add chain, latency-bound (the "pure compute loop"); Chains = 12:
/// independent chains that keep the floating-point units busy, throughput-bound, so two
/// threads sharing one physical core's units show it.
template <int Chains>
double compute_loop_seconds(unsigned threads) {
    std::array<double, 2> sink{};
    const auto t0 = std::chrono::steady_clock::now();
    parallel_for(2, threads, [&](std::size_t i) {
        std::array<double, Chains> x;
        for (int c = 0; c < Chains; ++c) x[c] = 1.0 + static_cast<double>(i + c);
        for (int k = 0; k < 4'000'000; ++k)
            for (auto& v : x) v = v * 0.9999999 + 1e-7;
        for (double v : x) sink[i] += v;
    });
    const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!(sink[0] > 0 && sink[1] > 0)) throw std::logic_error("compute loop");  // keeps the loop
    return t;
}

/// Two random cycles through 64 MB each (8-byte links, one pass of a shuffle): the machine's
/// memory-latency-bound reference (every step a cache and TLB miss; no bandwidth to speak of).
struct PointerChase {
    static constexpr std::size_t links = std::size_t{1} << 23;
    std::array<std::vector<std::uint64_t>, 2> next;
    PointerChase() {
        for (std::size_t c = 0; c < next.size(); ++c) {
            std::vector<std::uint64_t> order(links);
            std::iota(order.begin(), order.end(), 0);
            std::shuffle(order.begin() + 1, order.end(), std::mt19937_64(c + 1));
            next[c].resize(links);
            for (std::size_t i = 0; i < links; ++i) next[c][order[i]] = order[(i + 1) % links];
        }
    }
    /// Seconds for 500,000 steps along each cycle on `threads` threads (a cycle per thread with 2).
    [[nodiscard]] double seconds(unsigned threads) const {
        std::array<std::uint64_t, 2> end{};
        const auto t0 = std::chrono::steady_clock::now();
        parallel_for(2, threads, [&](std::size_t c) {
            std::uint64_t i = 0;
            for (int step = 0; step < 500'000; ++step) i = next[c][i];
            end[c] = i;
        });
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        if (end[0] == links) throw std::logic_error("pointer chase");  // keeps the loop
        return t;
    }
};

}  // namespace

int main(int argc, char** argv) {
    if (CommandLine::wants_help(argc, argv)) {
        std::cout << "usage: secchi_bench [--quick] [--json FILE]\n";
        return 0;
    }
    try {
        const CommandLine cl(argc, argv, {"json"}, {"quick"});
        const bool quick = cl.has("quick");
        const int repeats = quick ? 3 : 5;
        const std::uint64_t scale = quick ? 1 : 4;
        std::map<std::string, double> fig;

        const HenyeyGreensteinPhase hg(0.9);
        const TabulatedPhase petzold = petzold_m93();
        fig["events_per_s_per_core_hg"] = events_per_second(hg, 100'000 * scale, repeats);
        fig["events_per_s_per_core_petzold"] = events_per_second(petzold, 100'000 * scale, repeats);
        fig["events_per_s_per_core_hg_map_reused"] = events_per_second(hg, 100'000 * scale, repeats, true);
#if SECCHI_HAS_LANES
        // LaneTracer at this build's vector width (lane_width: 8 doubles with AVX-512, in the
        // benchmarks' default -march=native build; 2 in a portable x86-64 build).
        fig["events_per_s_per_core_hg_lanes"] = events_per_second<HenyeyGreensteinPhase, LaneTracer>(hg, 100'000 * scale, repeats);
        fig["events_per_s_per_core_hg_lanes_map_reused"] =
            events_per_second<HenyeyGreensteinPhase, LaneTracer>(hg, 100'000 * scale, repeats, true);
        fig["lane_width"] = lanes::lane_width;
        // The same in float lanes (twice as many per vector: FloatLaneTracer).
        fig["events_per_s_per_core_hg_float_lanes"] =
            events_per_second<HenyeyGreensteinPhase, FloatLaneTracer>(hg, 100'000 * scale, repeats);
        fig["events_per_s_per_core_hg_float_lanes_map_reused"] =
            events_per_second<HenyeyGreensteinPhase, FloatLaneTracer>(hg, 100'000 * scale, repeats, true);
        fig["float_lane_width"] = lanes::width_of<float>;
        // Petzold in the lanes (the table's sampler in double lanes; in float lanes its inverse
        // CDF's float table, float_inverse_table.hpp).
        fig["events_per_s_per_core_petzold_lanes"] =
            events_per_second<TabulatedPhase, LaneTracer>(petzold, 100'000 * scale, repeats);
        fig["events_per_s_per_core_petzold_float_lanes"] =
            events_per_second<TabulatedPhase, FloatLaneTracer>(petzold, 100'000 * scale, repeats);
#endif
        // Fournier-Forand (b_b/b = 0.0183, Petzold's; sampled from its table), each tracer.
        const auto ff = FournierForandPhase::from_backscatter_fraction(0.0183);
        fig["events_per_s_per_core_ff"] = events_per_second(ff, 100'000 * scale, repeats);
#if SECCHI_HAS_LANES
        fig["events_per_s_per_core_ff_lanes"] = events_per_second<FournierForandPhase, LaneTracer>(ff, 100'000 * scale, repeats);
        fig["events_per_s_per_core_ff_float_lanes"] =
            events_per_second<FournierForandPhase, FloatLaneTracer>(ff, 100'000 * scale, repeats);
#endif

        // Building a cone-averaged phase table as every radiance estimator does once (omega =
        // 0.005 sr, the peak transmitted, one thread; optics/phase/cone_average.hpp): seconds,
        // median of the repeats.
        const auto cone_table_seconds = [&](const auto& phase) {
            std::vector<double> t;
            double sink = 0.0;
            for (int r = 0; r < repeats; ++r)
                t.push_back(seconds([&] { sink += ConeAveragedPhase(phase, 0.005).eval(0.5); }));
            if (!(sink > 0.0)) throw std::logic_error("cone table");
            return median(t);
        };
        fig["cone_table_seconds_petzold"] = cone_table_seconds(petzold);
        fig["cone_table_seconds_rayleigh"] = cone_table_seconds(RayleighPhase{});

        // Photons per second for problems 1a, 2a and 2b (sun at 60 deg, n = 1.34, continuous
        // absorption as in the conformance runs), on 1 and 2 threads.
        const std::uint64_t n2a = 200'000 * scale;
        auto photons_per_s = [&](const std::string& name, const auto& phase, double w0) {
            // 1 and 2 threads alternated, run by run: the speed-up is the median of the rounds' ratios
            std::vector<double> t1, t2, ratios;
            for (int round = 0; round < repeats; ++round) {
                t1.push_back(seconds([&] { trace_slab<CompactRecord>(phase, w0, 60, 1.34, n2a, 1, AbsorptionMode::continuous); }));
                t2.push_back(seconds([&] { trace_slab<CompactRecord>(phase, w0, 60, 1.34, n2a, 2, AbsorptionMode::continuous); }));
                ratios.push_back(t1.back() / t2.back());
            }
            fig["photons_per_s_problem_" + name] = static_cast<double>(n2a) / median(t1);
            fig["photons_per_s_problem_" + name + "_2_threads"] = static_cast<double>(n2a) / median(t2);
            return median(ratios);
        };
        fig["thread_speedup_propagation"] = photons_per_s("2a", petzold, 0.9);
        photons_per_s("1a", RayleighPhase{}, 0.9);
        photons_per_s("2b", petzold, 0.2);
#if SECCHI_HAS_LANES
        // Problems 1a and 2a in double and float lanes, one core (--tracer lanes, lanes-float).
        fig["photons_per_s_problem_1a_lanes"] = photons_per_second<LaneTracer>(RayleighPhase{}, 0.9, n2a, repeats);
        fig["photons_per_s_problem_1a_float_lanes"] = photons_per_second<FloatLaneTracer>(RayleighPhase{}, 0.9, n2a, repeats);
        fig["photons_per_s_problem_2a_lanes"] = photons_per_second<LaneTracer>(petzold, 0.9, n2a, repeats);
        fig["photons_per_s_problem_2a_float_lanes"] = photons_per_second<FloatLaneTracer>(petzold, 0.9, n2a, repeats);
#endif
        // Problem 3 (stratified water), one core, one photon at a time and in double and float lanes.
        const std::uint64_t n3 = 50'000 * scale;
        fig["photons_per_s_problem_3"] = problem3_photons_per_second<PhotonTracer>(n3, repeats);
#if SECCHI_HAS_LANES
        fig["photons_per_s_problem_3_lanes"] = problem3_photons_per_second<LaneTracer>(n3, repeats);
        fig["photons_per_s_problem_3_float_lanes"] = problem3_photons_per_second<FloatLaneTracer>(n3, repeats);
#endif

        // Collection through a problem-2a map: vertical rays of length 8 from tau 1.
        const auto first = trace_slab<CompactRecord>(petzold, 0.9, 60, 1.34, n2a, 2, AbsorptionMode::continuous);
        const MapScene scene = slab_scene(60, 1.34);
        fig["bytes_per_photon_compact"] =
            static_cast<double>(KdTreeStore<CompactRecord>(first.records).memory_bytes()) / first.records.size();
        const auto kd = photon_map<KdTreeStore<CompactRecord>>(first, scene);
        const auto voi = photon_map<VoiOctreeStore<CompactRecord>>(first, scene);
        const ConeAveragedPhase cone(petzold, 0.005);
        const auto rays = nadir_ray_grid(1.0, 8.0, quick ? 6 : 10, 1.0);
        const auto k1 = collect(kd, StepSpheres(32), cone, rays, 1, repeats);
        const auto v1 = collect(voi, VoiCylinder{}, cone, rays, 1, repeats);
        // Thread speed-up of collection: 1 and 2 threads alternated over 7 rounds (median), so
        // short runs and the machine's noise weigh less. Each round also times the pure compute
        // loop on 1 and 2 threads (thread_speedup_compute_loop, the median over all rounds): the
        // speed-up the shared machine allowed while the collection figures were taken.
        std::vector<double> loop_speedups, busy_loop_speedups, memory_loop_speedups;
        const PointerChase chase;
        auto median_thread_speedup = [&](const auto& map, const std::vector<Ray>& grid) {
            std::vector<double> speedups;
            for (int round = 0; round < 7; ++round) {
                const auto one = collect(map, VoiCylinder{}, cone, grid, 1, 1);
                const auto two = collect(map, VoiCylinder{}, cone, grid, 2, 1);
                speedups.push_back(two.rays_per_s / one.rays_per_s);
                loop_speedups.push_back(compute_loop_seconds<1>(1) / compute_loop_seconds<1>(2));
                busy_loop_speedups.push_back(compute_loop_seconds<12>(1) / compute_loop_seconds<12>(2));
                memory_loop_speedups.push_back(chase.seconds(1) / chase.seconds(2));
            }
            return median(speedups);
        };
        // The full 10 x 10 grid even with --quick; then the same estimate on a map that stays in
        // cache (every 32nd record, about 5e4: 0.8 MB) over a 60 x 60 grid, which separates the
        // two cores' shared memory traffic from the estimate itself.
        const double collection_speedup = median_thread_speedup(voi, nadir_ray_grid(1.0, 8.0, 10, 1.0));
        std::vector<CompactRecord> sparse;
        for (std::size_t i = 0; i < first.records.size(); i += 32) sparse.push_back(first.records[i]);
        const PhotonMap sparse_map(VoiOctreeStore<CompactRecord>(std::move(sparse)), first.map_flux, first.batches, scene,
                                   first.bottom_ed);
        const double cached_speedup = median_thread_speedup(sparse_map, nadir_ray_grid(1.0, 8.0, 60, 1.0));
        // At equal photons per ray: the cylinder radius scaled so it touches as many photons
        // per ray as the 32 spheres (photons per ray scale with the cross-section).
        const double r_equal = 0.05 * std::sqrt(k1.photons_per_ray / v1.photons_per_ray);
        const auto ve = collect(voi, VoiCylinder{}, cone, rays, 1, repeats, r_equal);
        fig["voi_rays_per_s_equal_photons"] = ve.rays_per_s;
        fig["kd_rays_per_s"] = k1.rays_per_s;
        fig["voi_rays_per_s"] = v1.rays_per_s;
        // The speed-ups are paired (bench_timing.hpp's paired_ratio): 7 rounds, each timing the
        // k-d tree's estimate and then the cylinder's; the median of the rounds' ratios.
        auto speedup_vs_kd32 = [&](const auto& map, double voi_radius) {
            const auto kd_est = radiance_estimator(kd, StepSpheres(32), cone, 0.05);
            const auto voi_est = radiance_estimator(map, VoiCylinder{}, cone, voi_radius);
            return paired_ratio(7, [&] { kd_est.estimate(rays, 1); }, [&] { voi_est.estimate(rays, 1); }).median;
        };
        fig["voi_speedup_vs_kd32"] = speedup_vs_kd32(voi, 0.05);
        fig["voi_speedup_vs_kd32_equal_photons"] = speedup_vs_kd32(voi, r_equal);
        // The same cylinder on the uniform grid of columns (VoiGridStore), its cells sized for
        // the radius it serves.
        const auto grid = photon_map<VoiGridStore<CompactRecord>>(first, scene, Radius(0.05));
        const auto grid_equal = photon_map<VoiGridStore<CompactRecord>>(first, scene, Radius(r_equal));
        const auto g1 = collect(grid, VoiCylinder{}, cone, rays, 1, repeats);
        const auto ge = collect(grid_equal, VoiCylinder{}, cone, rays, 1, repeats, r_equal);
        fig["voi_grid_rays_per_s"] = g1.rays_per_s;
        fig["voi_grid_rays_per_s_equal_photons"] = ge.rays_per_s;
        fig["voi_grid_speedup_vs_kd32"] = speedup_vs_kd32(grid, 0.05);
        fig["voi_grid_speedup_vs_kd32_equal_photons"] = speedup_vs_kd32(grid_equal, r_equal);
        fig["thread_speedup_collection_grid"] = median_thread_speedup(grid, nadir_ray_grid(1.0, 8.0, 10, 1.0));
        fig["thread_speedup_collection"] = collection_speedup;
        fig["thread_speedup_collection_cached_map"] = cached_speedup;
        fig["thread_speedup_compute_loop"] = median(loop_speedups);
        fig["thread_speedup_compute_loop_throughput_bound"] = median(busy_loop_speedups);
        fig["thread_speedup_memory_loop"] = median(memory_loop_speedups);

        std::printf("map: %zu photons stored; rays of length 8 from tau 1, radius 0.05\n", first.records.size());
        std::printf("  k-d n=32: %.3g photons/ray, Lu %.4e +- %.1e\n", k1.photons_per_ray, k1.lu.value, k1.lu.se);
        std::printf("  VOI     : %.3g photons/ray, Lu %.4e +- %.1e\n", v1.photons_per_ray, v1.lu.value, v1.lu.se);
        std::printf("  VOI r=%.4f (equal photons): %.3g photons/ray, Lu %.4e +- %.1e\n", r_equal, ve.photons_per_ray,
                    ve.lu.value, ve.lu.se);
        std::printf("  VOI grid: %.3g photons/ray, Lu %.4e +- %.1e; r=%.4f: %.3g photons/ray, Lu %.4e +- %.1e\n",
                    g1.photons_per_ray, g1.lu.value, g1.lu.se, r_equal, ge.photons_per_ray, ge.lu.value, ge.lu.se);
        for (const auto& [k, v] : fig) std::printf("%-32s %.4g\n", k.c_str(), v);
        if (cl.has("json")) {
            std::ofstream os(cl.text("json"));
            JsonWriter j(os);
            j.begin_object();
            for (const auto& [k, v] : fig) j.value(k.c_str(), v);
            j.end_object();
        }
        return 0;
    } catch (const input_error& e) {
        std::cerr << "secchi_bench: " << e.what() << "\n";
        return 2;
    }
}
