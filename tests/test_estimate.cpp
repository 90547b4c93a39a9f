// Second pass: the collection volumes' boundary compensation, the radiance estimator's coded
// and lane paths against its per-photon formula bit for bit (homogeneous and stratified water),
// its thread independence, and what it refuses. (The solver end to end, with the exact
// single-scattering answer and the stores against each other: test_plane_parallel.cpp.)
#include <catch2/catch.hpp>
#include "../conformance/problem3.hpp"
#include "secchi/optics/iop/linear_model.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <array>
#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

using namespace secchi;

TEST_CASE("Sphere volume inside the water: caps cut by the surface and the bottom") {
    const double r = 0.1, full = 4.0 / 3.0 * pi * r * r * r;
    CHECK(sphere_volume_in_slab(1.0, r, 0.0, INFINITY) == Approx(full));
    CHECK(sphere_volume_in_slab(0.0, r, 0.0, INFINITY) == Approx(full / 2));
    CHECK(sphere_volume_in_slab(5.0, r, 0.0, 5.0) == Approx(full / 2));
    CHECK(sphere_volume_in_slab(0.05, r, 0.0, INFINITY) == Approx(full - pi * 0.05 * 0.05 * (0.3 - 0.05) / 3));
}

TEST_CASE("Disk area inside the water: circle segments cut by the surface and the bottom") {
    const double r = 0.05, full = pi * r * r;
    CHECK(disk_segment_area(0.0, r) == Approx(full / 2));
    CHECK(disk_segment_area(r, r) == 0.0);
    CHECK(disk_segment_area(-r, r) == Approx(full));
    CHECK(disk_area_in_slab(0.0, 1.0, r, 0.0, INFINITY) == full);   // vertical ray: horizontal disk
    CHECK(disk_area_in_slab(0.0, 0.0, r, 0.0, INFINITY) == Approx(full / 2));  // horizontal ray at the surface
    CHECK(disk_area_in_slab(1.0, 0.3, r, 0.0, 2.0) == full);
    // Against the disk itself: a polar grid over the disk perpendicular to the ray, counting
    // the area whose depth lies between the planes (no use of the chord argument).
    for (const auto& [zc, uz, top, bottom] : std::vector<std::array<double, 4>>{
             {0.01, 0.3, 0.0, INFINITY}, {0.03, -0.6, 0.0, 0.07}, {0.5, 0.05, 0.0, 0.52}, {-0.01, 0.2, 0.0, 1.0}}) {
        const vec3 u(std::sqrt(1.0 - uz * uz), 0.0, uz);
        const vec3 e1 = glm::normalize(glm::cross(u, vec3(0.0, 1.0, 0.0))), e2 = glm::cross(u, e1);
        const int rings = 1000, spokes = 2000;
        double inside = 0.0;
        for (int i = 0; i < rings; ++i) {
            const double rho = (i + 0.5) * r / rings;
            for (int j = 0; j < spokes; ++j) {
                const double phi = (j + 0.5) * 2.0 * pi / spokes;
                const double z = zc + rho * (std::cos(phi) * e1.z + std::sin(phi) * e2.z);
                if (z >= top && z <= bottom) inside += rho * (r / rings) * (2.0 * pi / spokes);
            }
        }
        INFO("zc " << zc << " uz " << uz << " top " << top << " bottom " << bottom);
        CHECK(disk_area_in_slab(zc, uz, r, top, bottom) == Approx(inside).epsilon(2e-3));
    }
}

TEST_CASE("The VOI cylinder compensates the water's top and bottom on slanted rays (manual 3.5.1)") {
    // Photons uniform in a slab of water 0.5 m deep (density rho per m^3), isotropic phase, no
    // attenuation: every in-water cylinder gathers rho * (cross-section) photons per metre, so
    // with weights 1 / (in-water cross-section) each ray's sum is rho L / (4 pi), wherever it
    // runs. Rays at 85 degrees from the vertical, 1 cm below the surface or above the bottom,
    // have a quarter or more of their cylinder out of the water; uncompensated (weights
    // 1 / (pi r^2)) they come out low by about that.
    const double depth = 0.5, length = 0.6;
    const std::size_t n = 200000;
    const unsigned batches = 10;
    PhotonRng rng(2024, 0);
    std::vector<CompactRecord> records;
    for (std::size_t i = 0; i < n; ++i)
        records.push_back(CompactRecord::make(vec3(rng.uniform(), rng.uniform(), depth * rng.uniform()), vec3(0.0, 0.0, 1.0),
                                              0, static_cast<std::uint8_t>(i % batches)));
    const double rho = static_cast<double>(n) / depth;
    const double expected = rho * length / (4.0 * pi);
    const double s = std::sin(85.0 * pi / 180.0), c = std::cos(85.0 * pi / 180.0);
    std::vector<Ray> near_top, near_bottom;
    for (const double y : {0.2, 0.35, 0.5, 0.65, 0.8}) {
        near_top.push_back({vec3(0.15, y, 0.01), vec3(s, 0.0, c), length});
        near_bottom.push_back({vec3(0.15, y, depth - 0.01), vec3(s, 0.0, -c), length});
    }
    // The photons' x and y: [0, 1), the section.
    const PhotonMap map(VoiOctreeStore<CompactRecord>(std::move(records)), RecordFlux::uniform(1.0), batches,
                        MapScene::open_water(1.0));
    const HomogeneousRayOptics optics(ConeAveragedPhase(IsotropicPhase{}, 0.005), 0.0, 0.0);
    const Radius r(0.05);
    const PathRadianceEstimator compensated(map, VoiCylinder(0.0, depth), optics, r);
    const PathRadianceEstimator uncompensated(map, VoiCylinder(-INFINITY, INFINITY), optics, r);
    for (const auto* rays : {&near_top, &near_bottom}) {
        const auto with = compensated.estimate(*rays, 2).radiance;
        const auto without = uncompensated.estimate(*rays, 2).radiance;
        INFO("expected " << expected << ", compensated " << with.value << " +- " << with.se << ", uncompensated "
                         << without.value << " +- " << without.se);
        CHECK(with.se < 0.03 * expected);
        CHECK(std::abs(with.value - expected) <= 4.0 * with.se);
        CHECK(expected - without.value > 4.0 * without.se);
    }
    // Vertical rays are never compensated: their disks are horizontal.
    const std::vector<Ray> vertical{{vec3(0.5, 0.5, 0.0), vec3(0.0, 0.0, 1.0), depth}};
    CHECK(compensated.estimate(vertical, 1).radiance.value == uncompensated.estimate(vertical, 1).radiance.value);
}

// Vertical rays through a CompactRecord map take the coded path (PathRadianceEstimator:
// cos psi from the photon's theta byte through a per-ray table); it must give the per-photon
// formula's sums bit for bit. The reference is the same optics behind a wrapper offering only
// in_scatter(z, cos_psi, ray, t), which the estimator can only use per photon.
namespace {
template <class O>
struct PerPhotonOnly {
    O optics;
    [[nodiscard]] double in_scatter(double z, double cos_psi, const Ray& ray, double t) const {
        return optics.in_scatter(z, cos_psi, ray, t);
    }
    [[nodiscard]] double transmittance(const Ray& ray, double t) const { return optics.transmittance(ray, t); }
};

/// Counts the tables the estimator built (for_cosines calls), else the optics unchanged.
struct CountingOptics : HomogeneousRayOptics {
    using HomogeneousRayOptics::HomogeneousRayOptics;
    std::shared_ptr<std::atomic<int>> tabulated = std::make_shared<std::atomic<int>>(0);
    [[nodiscard]] Coded for_cosines(const CodedCosines& cos_psi) const {
        ++*tabulated;
        return HomogeneousRayOptics::for_cosines(cos_psi);
    }
};

static_assert(PolarCodedRecord<CompactRecord> && !PolarCodedRecord<FullRecord>);
static_assert(CodedRayOptics<HomogeneousRayOptics> && CodedRayOptics<StratifiedRayOptics<StratifiedWater<HenyeyGreensteinPhase>>>);
static_assert(RayOptics<PerPhotonOnly<HomogeneousRayOptics>> && !CodedRayOptics<PerPhotonOnly<HomogeneousRayOptics>>);

/// Rays from z0 down (+z, also written with -0 x and y), up (-z) from z0 + 4, and tilted.
std::vector<Ray> rays_every_way(double z0) {
    std::vector<Ray> rays;
    for (const Ray& r : nadir_ray_grid(z0, 4.0, 3, 1.0)) {
        rays.push_back(r);
        rays.push_back({r.origin, {-0.0, -0.0, 1.0}, r.t_max});
        rays.push_back({r.origin + vec3(0.0, 0.0, 4.0), {0.0, 0.0, -1.0}, r.t_max});
        rays.push_back({r.origin, glm::normalize(vec3(0.1, -0.05, 1.0)), r.t_max});
        rays.push_back({r.origin + vec3(0.0, 0.0, 4.0), glm::normalize(vec3(-0.02, 0.0, -1.0)), r.t_max});
    }
    return rays;
}

/// Every ray's per-batch sums from `est` equal (==) those of `reference`, and photons were collected.
template <class A, class B>
void check_bit_identical(const A& est, const B& reference, unsigned batches, const std::vector<Ray>& rays) {
    for (const Ray& ray : rays) {
        std::vector<double> a(batches, 0.0), b(batches, 0.0);
        const auto na = est.accumulate(ray, a);
        const auto nb = reference.accumulate(ray, b);
        INFO("ray from z " << ray.origin.z << " direction " << ray.direction.x << " " << ray.direction.y << " "
                           << ray.direction.z);
        CHECK(na > 100);
        CHECK(na == nb);
        CHECK(a == b);
    }
}

/// The scene compact_map traces in: a section 1 m wide, no bottom, a flat surface, the sun at 30 deg.
MapScene compact_scene() {
    return {Slab(1.0, Bottom{}, 30.0), FlatSurface(1.34), SkyLight::of(SunAndSky(CollimatedSun(30.0)))};
}

/// The first pass of `photons` photons through compact_scene() in `water`.
template <class Water>
TransportResult<CompactRecord> compact_map(const Water& water, std::uint64_t photons, DepthImportance importance = {}) {
    TransportSettings s;
    s.photons = s.map_photons = photons;
    s.importance = importance;
    s.depths = {1.0};
    s.threads = 2;
    const MapScene scene = compact_scene();
    return PhotonTracer<Water, CompactRecord>(water, scene.slab, *scene.flat_surface, CollimatedSun(30.0), s).run();
}

/// A map of the first pass's records (copied into a Store built with store_args) in
/// compact_scene(), every record of flux 1.
template <class Store, class... StoreArgs>
PhotonMap<Store> unit_flux_map(const TransportResult<CompactRecord>& first, const StoreArgs&... store_args) {
    return PhotonMap<Store>(Store(first.records, store_args...), RecordFlux::uniform(1.0), first.batches, compact_scene());
}
}  // namespace

TEST_CASE("Vertical rays through a compact map: the theta tables are bit-identical to the per-photon formula", "[threads]") {
    const HenyeyGreensteinPhase hg(0.9);
    const auto water = HomogeneousWater<HenyeyGreensteinPhase>::from_albedo(1.0, 0.9, hg);
    const auto first = compact_map(water, 40000);
    const auto voi = unit_flux_map<VoiOctreeStore<CompactRecord>>(first);
    const auto kd = unit_flux_map<KdTreeStore<CompactRecord>>(first);
    const ConeAveragedPhase cone(hg, 0.005);
    const HomogeneousRayOptics optics(cone, water.attenuation(), water.scattering());
    const PerPhotonOnly<HomogeneousRayOptics> per_photon{optics};
    const auto rays = rays_every_way(1.0);
    const Radius r(0.1);
    SECTION("VOI cylinder") {
        check_bit_identical(PathRadianceEstimator(voi, VoiCylinder{}, optics, r),
                            PathRadianceEstimator(voi, VoiCylinder{}, per_photon, r), first.batches, rays);
    }
    SECTION("VOI cylinder in the grid (runs of photons: in_scatter_lanes with lanes::exp)") {
        const auto grid = unit_flux_map<VoiGridStore<CompactRecord>>(first, r);
        check_bit_identical(PathRadianceEstimator(grid, VoiCylinder{}, optics, r),
                            PathRadianceEstimator(grid, VoiCylinder{}, per_photon, r), first.batches, rays);
    }
    SECTION("transmittances beyond exp_table's range (c t > 708) take its special values") {
        const HomogeneousRayOptics murky(cone, 250.0, 0.0);
        const PerPhotonOnly<HomogeneousRayOptics> murky_per_photon{murky};
        const auto grid = unit_flux_map<VoiGridStore<CompactRecord>>(first, r);
        check_bit_identical(PathRadianceEstimator(grid, VoiCylinder{}, murky, r),
                            PathRadianceEstimator(grid, VoiCylinder{}, murky_per_photon, r), first.batches, rays);
    }
    SECTION("k-d tree spheres") {
        check_bit_identical(PathRadianceEstimator(kd, StepSpheres(8), optics, r),
                            PathRadianceEstimator(kd, StepSpheres(8), per_photon, r), first.batches, rays);
    }
    SECTION("the two vertical tables are built once, with the estimator; never per call, never for full records") {
        const CountingOptics counting(cone, water.attenuation(), water.scattering());
        const PathRadianceEstimator est(voi, VoiCylinder{}, counting, r);
        CHECK(*counting.tabulated == 2);  // down and up
        const auto vertical = est.estimate(nadir_ray_grid(1.0, 4.0, 3, 1.0), 2);
        const auto every_way = est.estimate(rays_every_way(1.0), 2);
        std::vector<double> sums(first.batches, 0.0);
        CHECK(est.accumulate(nadir_ray_grid(1.0, 4.0, 1, 1.0).front(), sums) > 0);
        std::vector<Ray> tilted = nadir_ray_grid(1.0, 4.0, 3, 1.0);
        for (Ray& ray : tilted) ray.direction = glm::normalize(vec3(1e-9, 0.0, 1.0));
        CHECK(est.estimate(tilted, 2).photons_touched > 0);
        CHECK(*counting.tabulated == 2);
        // A copy shares the tables (and the optics they refer to), and outlives the original.
        std::optional<PathRadianceEstimator<VoiOctreeStore<CompactRecord>, VoiCylinder, CountingOptics>> original(est);
        const auto copy = *original;
        original.reset();
        CHECK(copy.estimate(rays_every_way(1.0), 1).radiance.value == every_way.radiance.value);
        CHECK(*counting.tabulated == 2);
        std::vector<FullRecord> full;
        for (const auto& rec : first.records) full.push_back(FullRecord::make(rec.position(), rec.direction(), rec.band(), rec.batch()));
        const PhotonMap full_map(VoiOctreeStore<FullRecord>(std::move(full)), RecordFlux::uniform(1.0), first.batches,
                                 compact_scene());
        const PathRadianceEstimator full_est(full_map, VoiCylinder{}, counting, r);
        // The same photons with the same decoded directions, through the per-photon formula.
        CHECK(full_est.estimate(nadir_ray_grid(1.0, 4.0, 3, 1.0), 2).radiance.value ==
              Approx(vertical.radiance.value).epsilon(1e-12));
        CHECK(*counting.tabulated == 2);
        // The shared tables give each ray the sums accumulate() gives it alone.
        const PathRadianceEstimator plain(voi, VoiCylinder{}, optics, r);
        double total = 0.0;
        for (const Ray& ray : rays_every_way(1.0)) {
            std::vector<double> one(first.batches, 0.0);
            plain.accumulate(ray, one);
            for (double v : one) total += v;
        }
        CHECK(every_way.radiance.value * static_cast<double>(rays_every_way(1.0).size()) == Approx(total).epsilon(1e-12));
    }
}

TEST_CASE("Vertical rays through a compact map in stratified water: per-component theta tables are bit-identical", "[threads]") {
    // Two components whose weights change with depth, so the mixture matters; depth importance
    // so photons carry different fluxes.
    const DepthProfile profile{{0.0, 3.0, 20.0}, {0.1, 0.2, 0.05}, {{0.5, 0.1, 0.3}, {0.05, 0.6, 0.2}}};
    const StratifiedWater<HenyeyGreensteinPhase> water(profile, {HenyeyGreensteinPhase(0.9), HenyeyGreensteinPhase(0.3)});
    const DepthImportance importance{0.2, 5.0};
    const auto voi = PhotonMap<VoiOctreeStore<CompactRecord>>::from_first_pass(compact_map(water, 10000, importance),
                                                                                compact_scene());
    std::vector<ConeAveragedPhase<HenyeyGreensteinPhase>> cones;
    for (const auto& p : water.phases()) cones.emplace_back(p, 0.005);
    const StratifiedRayOptics optics(water, cones);
    REQUIRE(voi.flux().importance.level(5.0) > voi.flux().importance.level(1.0));
    const PerPhotonOnly<StratifiedRayOptics<StratifiedWater<HenyeyGreensteinPhase>>> per_photon{optics};
    const Radius r(0.1);
    check_bit_identical(PathRadianceEstimator(voi, VoiCylinder{}, optics, r), PathRadianceEstimator(voi, VoiCylinder{}, per_photon, r),
                        voi.batches(), rays_every_way(1.0));
}

TEST_CASE("The second pass's estimates over many rays are bit-identical for 1 and 2 threads", "[threads]") {
    const HenyeyGreensteinPhase hg(0.9);
    const auto water = HomogeneousWater<HenyeyGreensteinPhase>::from_albedo(1.0, 0.9, hg);
    const auto first = compact_map(water, 10000);
    const auto voi = unit_flux_map<VoiOctreeStore<CompactRecord>>(first);
    const ConeAveragedPhase cone(hg, 0.005);
    const HomogeneousRayOptics optics(cone, water.attenuation(), water.scattering());
    const Radius r(0.1);
    std::vector<Ray> rays = rays_every_way(1.0);
    const PathRadianceEstimator path(voi, VoiCylinder{}, optics, r);
    const auto a = path.estimate(rays, 1), b = path.estimate(rays, 2);
    CHECK(a.photons_touched > 0);
    CHECK(a.photons_touched == b.photons_touched);
    CHECK(a.radiance.value == b.radiance.value);
    CHECK(a.radiance.se == b.radiance.se);
    // The whole radiance, also along rays from the air through the surface.
    for (const Ray& ray : nadir_ray_grid(-1.0, INFINITY, 3, 1.0)) rays.push_back(ray);
    const RadianceEstimator whole(voi, VoiCylinder{}, optics, r);
    std::uint64_t touched1 = 0, touched2 = 0;
    const Estimate c = whole.average(rays, 0, 1, &touched1), d = whole.average(rays, 0, 2, &touched2);
    CHECK(touched1 > 0);
    CHECK(touched1 == touched2);
    CHECK(c.value == d.value);
    CHECK(c.se == d.se);
}

TEST_CASE("A cone-averaged phase function's table is the same for 1 and 2 threads, its loop not reported", "[threads]") {
    // A table's values are integrals each of its own (ConeTable): the same bits on any thread
    // count. A set-up loop, it does not show as one of a program's long loops.
    struct CountingSink final : ProgressSink {
        std::atomic<int> loops{0};
        void loop_started(std::size_t) override { ++loops; }
        void advanced() override {}
        void loop_finished() override {}
    } sink;
    const ProgressScope scope(&sink);
    const HenyeyGreensteinPhase hg(0.9);
    const ConeTable small{.n_log = 64, .n_uniform = 128};
    ConeTable two = small;
    two.threads = 2;
    const ConeAveragedPhase a(hg, 0.005, ConePeak::transmitted, small), b(hg, 0.005, ConePeak::transmitted, two);
    REQUIRE(a.breakpoints() == b.breakpoints());
    CHECK(a.breakpoints().size() > 192);
    for (double psi : a.breakpoints()) REQUIRE(a.eval(std::cos(psi)) == b.eval(std::cos(psi)));
    CHECK(a.transmitted_fraction() == b.transmitted_fraction());
    CHECK(sink.loops == 0);
}

TEST_CASE("The map refuses fewer batches than its photons have, and the estimator too short a sum array") {
    const HenyeyGreensteinPhase hg(0.9);
    const auto water = HomogeneousWater<HenyeyGreensteinPhase>::from_albedo(1.0, 0.9, hg);
    const auto first = compact_map(water, 2000);
    REQUIRE(first.batches >= 2);
    const HomogeneousRayOptics optics(ConeAveragedPhase(hg, 0.005), water.attenuation(), water.scattering());
    using Catch::Matchers::Contains;
    // A photon of the last batch would be summed outside an estimator's sums.
    CHECK_THROWS_WITH(PhotonMap(VoiOctreeStore<CompactRecord>(first.records), RecordFlux::uniform(1.0), first.batches - 1, compact_scene()),
                      Contains("batches") && Contains(std::to_string(first.batches - 1)) &&
                          Contains("batch index " + std::to_string(first.batches - 1)));
    const auto voi = unit_flux_map<VoiOctreeStore<CompactRecord>>(first);
    const PathRadianceEstimator est(voi, VoiCylinder{}, optics, Radius(0.1));
    const Ray ray{{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, 4.0};
    std::vector<double> short_sums(first.batches - 1, 0.0), sums(first.batches, 0.0);
    CHECK_THROWS_WITH(est.accumulate(ray, short_sums), Contains("batch_sums size"));
    CHECK(est.accumulate(ray, sums) > 0);
}

TEST_CASE("StratifiedRayOptics needs one cone per scattering component, and says so") {
    const DepthProfile profile{{0.0, 20.0}, {0.1, 0.1}, {{0.5, 0.3}, {0.05, 0.2}}};
    const StratifiedWater<HenyeyGreensteinPhase> water(profile, {HenyeyGreensteinPhase(0.9), HenyeyGreensteinPhase(0.3)});
    const std::vector<ConeAveragedPhase<HenyeyGreensteinPhase>> one{{HenyeyGreensteinPhase(0.9), 0.005}};
    using Catch::Matchers::Contains;
    CHECK_THROWS_WITH(StratifiedRayOptics(water, one), Contains("cones") && Contains("1"));
    auto two = one;
    two.emplace_back(HenyeyGreensteinPhase(0.3), 0.005);
    CHECK_NOTHROW(StratifiedRayOptics(water, two));
}

TEST_CASE("StratifiedRayOptics of a typed water (a tuple of cones) equals that of its AnyPhaseFunction form, bit for bit") {
    const auto depths = iop::uniform_depths(100.0, 0.05);
    const auto typed = iop::stratify_typed(conformance::problem3_model(), 500.0, depths);
    const auto any = iop::stratify(conformance::problem3_model(), 500.0, depths);
    const auto cone = [](const auto& p) { return ConeAveragedPhase(p, 0.005); };
    const auto typed_cones = typed.transform_phases(cone);
    static_assert(std::tuple_size_v<std::decay_t<decltype(typed_cones)>> == 2);
    const auto any_cones = any.transform_phases(cone);
    const StratifiedRayOptics a(typed, typed_cones);
    const StratifiedRayOptics b(any, any_cones);
    CodedCosines cosines{};
    for (std::size_t k = 0; k < cosines.size(); ++k) cosines[k] = -1.0 + 2.0 * static_cast<double>(k) / 255.0;
    const auto ca = a.for_cosines(cosines);
    const auto cb = b.for_cosines(cosines);
    for (double z : {0.5, 17.0, 60.0})
        for (double uz : {1.0, -0.5, 0.3}) {
            const Ray ray{{0.0, 0.0, z}, {std::sqrt(1.0 - uz * uz), 0.0, uz}, 30.0};
            INFO("z = " << z << ", uz = " << uz);
            CHECK(a.transmittance(ray, 7.5) == b.transmittance(ray, 7.5));
            for (std::size_t k = 0; k < cosines.size(); k += 15) {
                CHECK(a.in_scatter(z, cosines[k], ray, 7.5) == b.in_scatter(z, cosines[k], ray, 7.5));
                CHECK(ca.in_scatter(z, static_cast<std::uint8_t>(k), ray, 7.5) ==
                      cb.in_scatter(z, static_cast<std::uint8_t>(k), ray, 7.5));
            }
        }
    // A tuple of one cone for two components is refused as a vector of one is.
    using Catch::Matchers::Contains;
    CHECK_THROWS_WITH(StratifiedRayOptics(typed, std::tuple{cone(RayleighPhase{})}), Contains("cones") && Contains("1"));
}

TEST_CASE("Lu's rays follow the attenuation to the stated residual transmittance, or end at the bottom") {
    PlaneParallelConfig cfg;
    cfg.ray_transmittance = 1e-4;
    // Homogeneous water, c = 1.2, b = 0.5, the peak averaged: c' = c, length ln(1e4) / 1.2.
    const ConeAveragedPhase averaged(HenyeyGreensteinPhase(0.9), 0.005, ConePeak::averaged);
    const HomogeneousRayOptics plain(averaged, 1.2, 0.5);
    CHECK(detail::nadir_ray_length(plain, 3.0, cfg) == Approx(std::log(1e4) / 1.2).epsilon(1e-8));
    // The peak transmitted: c' = c - b f, a longer ray.
    const ConeAveragedPhase transmitted(HenyeyGreensteinPhase(0.9), 0.005);
    const HomogeneousRayOptics peaked(transmitted, 1.2, 0.5);
    CHECK(detail::nadir_ray_length(peaked, 3.0, cfg) ==
          Approx(std::log(1e4) / (1.2 - 0.5 * transmitted.transmitted_fraction())).epsilon(1e-8));
    // A bottom within reach ends the ray there.
    cfg.bottom = Bottom::lambertian_at(5.0, 0.5);
    CHECK(detail::nadir_ray_length(plain, 3.0, cfg) == 2.0);
    cfg.bottom = Bottom::infinitely_deep();
    // Depth-varying water: the ray from 60 m in canonical problem 3's water, where c is about
    // 0.17 /m, reaches tens of metres (an 8 m ray kept only about three quarters of the path
    // radiance); its transmittance there is the stated residual.
    const auto water = iop::stratify(conformance::problem3_model(), 500.0, iop::uniform_depths(200.0, 0.05));
    std::vector<ConeAveragedPhase<AnyPhaseFunction>> cones;
    for (const auto& p : water.phases()) cones.emplace_back(p, 0.005);
    const StratifiedRayOptics optics(water, cones);
    const double length = detail::nadir_ray_length(optics, 60.0, cfg);
    const Ray ray{{0.0, 0.0, 60.0}, {0.0, 0.0, 1.0}, length};
    CHECK(length > 40.0);
    CHECK(optics.transmittance(ray, length) == Approx(1e-4).epsilon(1e-6));
    CHECK(optics.transmittance(ray, 8.0) > 0.2);
}
