// Radiance queries per second for a camera: the whole radiance (estimate/radiance.hpp) of the
// rays of a 512 x 512 pinhole camera 4 m under the water looking up (the scene of
// examples/underwater_camera, coastal_scene.hpp; rays to the surface, Snell's window, the
// water's light reflected beyond it down to the bottom), through one photon map held by each store with its collection volume: the
// VOI grid and the VOI octree with the cylinder, the k-d tree with n spheres per ray segment.
// Every rows_step-th row of the image is timed (the rows spread over the whole field of view),
// each store on the same rays, in paired rounds: the ratios of one round see the same load of
// the shared machine. Also printed: the mean radiance of the timed pixels by each store (the
// same quantity, within its SE) and the photons each ray collects.
#include "coastal_scene.hpp"
#include "bench_timing.hpp"
#include <secchi/estimate/render.hpp>
#include <secchi/io/cli.hpp>
#include <secchi/map/kdtree.hpp>
#include <secchi/map/voi_grid.hpp>
#include <secchi/map/voi_octree.hpp>
#include <secchi/solver/plane_parallel.hpp>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace {
constexpr const char* usage = R"(usage: camera_bench [options]
  --map-photons N   photons whose events are stored (default 1e6)
  --size N          the camera's N x N pixels (default 512)
  --rows-step K     time every K-th row (default 16)
  --rounds R        paired rounds (default 3)
  --steps N         k-d tree spheres per ray segment (default 64)
  --threads T       (default 2)
)";

using namespace secchi;

struct Result {
    double seconds = 0, mean = 0, mean_se = 0;
    std::uint64_t photons = 0;
};

/// The timed rays' whole radiance through one estimator, rays in parallel.
template <class Estimator>
Result run(const Estimator& est, const std::vector<Ray>& rays, unsigned threads) {
    Result r;
    RadianceSum sum(est.map().batches());
    r.seconds = bench::seconds([&] { sum = est.sum_over(rays, 0, threads); });
    const Estimate e = sum.estimate(static_cast<double>(rays.size()));
    r.mean = e.value;
    r.mean_se = e.se;
    r.photons = sum.photons_touched();
    return r;
}
}  // namespace

int main(int argc, char** argv) {
    return run_program(argc, argv, "camera_bench", usage, [&] {
        const CommandLine cl(argc, argv, {"map-photons", "size", "rows-step", "rounds", "steps", "threads"});
        const unsigned threads = cl.threads(2);
        constexpr std::uint64_t max_side = 1u << 15;  // a camera side up to 32768 pixels
        const int size = static_cast<int>(cl.count("size", 512, 1, max_side));
        const int step = static_cast<int>(cl.count("rows-step", 16, 1, max_side));
        const int rounds = static_cast<int>(cl.count("rounds", 3, 1, 1000));

        const auto water = examples::coastal_water();
        const PlaneParallelConfig cfg = examples::coastal_config(cl.count("map-photons", 1'000'000), threads);
        const Radius radius(0.05);
        auto first = trace_photon_map<VoiGridStore<CompactRecord>>(water, cfg, radius);
        const auto& grid = first.map;
        const auto grid_records = grid.store().records();  // (packed: a range of values)
        const std::vector<CompactRecord> records(grid_records.begin(), grid_records.end());
        const PhotonMap octree(VoiOctreeStore<CompactRecord>(records), grid.flux(), grid.batches(), grid.scene(), grid.bottom_ed());
        const PhotonMap kd(KdTreeStore<CompactRecord>(records), grid.flux(), grid.batches(), grid.scene(), grid.bottom_ed());

        const HomogeneousRayOptics optics(ConeAveragedPhase(water.phase(), 0.005), water.attenuation(), water.scattering());
        const VoiCylinder cylinder(0.0, cfg.bottom.depth());
        const RadianceEstimator by_grid(grid, cylinder, optics, radius);
        const RadianceEstimator by_octree(octree, cylinder, optics, radius);
        const RadianceEstimator by_kd(kd, StepSpheres(cl.unsigned_count("steps", 64), 0.0, cfg.bottom.depth()),
                                      optics, radius);

        const PinholeCamera camera({{0.5, 0.5, 4.0}, {0.0, 0.0, -1.0}, {1.0, 0.0, 0.0}, 120.0, size, size});
        std::vector<Ray> rays;
        for (int y = step / 2; y < size; y += step)
            for (int x = 0; x < size; ++x) rays.push_back(camera.ray(x, y));
        std::printf("map: %zu photons stored; %zu rays timed (every %d-th row of %d x %d), %u threads\n",
                    records.size(), rays.size(), step, size, size, threads);

        std::vector<double> grid_s, octree_s, kd_s, octree_ratio, kd_ratio;
        Result g, o, k;
        for (int round = 0; round < rounds; ++round) {
            g = run(by_grid, rays, threads);
            o = run(by_octree, rays, threads);
            k = run(by_kd, rays, threads);
            grid_s.push_back(g.seconds);
            octree_s.push_back(o.seconds);
            kd_s.push_back(k.seconds);
            octree_ratio.push_back(o.seconds / g.seconds);
            kd_ratio.push_back(k.seconds / g.seconds);
        }
        const double n = static_cast<double>(rays.size());
        // Work to a given SE: time x SE^2 (the SE of the pixels' mean falls as 1 / sqrt(rays)).
        const auto row = [&](const char* name, const std::vector<double>& s, const Result& r, double ratio) {
            std::printf("| %-22s | %9.0f | %9.3g | %.5f +- %.3g | %6.2f | %6.2f |\n", name, n / bench::median(s),
                        static_cast<double>(r.photons) / n, r.mean, r.mean_se, ratio,
                        ratio * (r.mean_se * r.mean_se) / (g.mean_se * g.mean_se));
        };
        std::printf("| store, volume | rays/s | photons per ray | mean L of the timed pixels | time / VOI grid's | "
                    "time x SE^2 / VOI grid's |\n");
        std::printf("|---|---|---|---|---|---|\n");
        row("VOI grid, cylinder", grid_s, g, 1.0);
        row("VOI octree, cylinder", octree_s, o, bench::median(octree_ratio));
        row("k-d tree, spheres", kd_s, k, bench::median(kd_ratio));
        std::printf("rounds: %d; time ratios are the median of the rounds' paired ratios\n", rounds);
        return 0;
    });
}
