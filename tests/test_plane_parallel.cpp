// The plane-parallel solver (solver/plane_parallel.hpp) end to end: the first pass and the
// second pass's radiance against exact answers (single scattering, a Lambertian bottom), its
// default depth importance, and its stores and process splits against each other on identical
// maps. Built once, portable: the solver's SIMD paths are those of the tracers and estimators,
// whose own tests are also built for the machine (tests/CMakeLists.txt, <name>_native).
#include <catch2/catch.hpp>
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

namespace {
constexpr double ray_length = 4.0;

PlaneParallelConfig single_scattering_config(StoreKind store) {
    PlaneParallelConfig cfg;
    cfg.albedo = 0.5;
    cfg.sun_zenith_deg = 0.0;
    cfg.water_index = 1.0;  // no interface: E0 = 1 enters unreflected
    cfg.transport.photons = 200000;
    cfg.transport.map_photons = 200000;
    cfg.transport.depths = {1.0, 3.0};
    cfg.transport.max_order = 1;  // the map holds exactly the single-scattering source
    cfg.transport.absorption = AbsorptionMode::analog;
    cfg.transport.threads = 2;
    cfg.store = store;
    cfg.ray_transmittance = std::exp(-ray_length);  // c = 1: rays of length 4
    cfg.cone_peak = ConePeak::averaged;  // single scattering: no peak travels on along the ray
    cfg.radius = 0.05;
    cfg.steps = 64;
    return cfg;
}
}  // namespace

TEST_CASE("plane-parallel runs take depth importance by default where asked: deep detectors, weighted photons") {
    // PlaneParallelConfig::auto_importance: default_depth_importance (tau_a >= ln 2 down to the
    // deepest detector) where the caller set none; what the run used and why in the result.
    PlaneParallelConfig cfg;  // c = 1, w0 = 0.9: tau_a = 0.1 z
    cfg.transport.photons = cfg.transport.map_photons = 4000;
    cfg.transport.threads = 2;
    cfg.ray_grid = 2;
    cfg.auto_importance = true;
    const IsotropicPhase iso;
    auto run = [&](std::vector<double> depths) {
        cfg.transport.depths = std::move(depths);
        return solve_plane_parallel(iso, cfg);
    };
    auto r = run({1.0, 5.0});  // tau_a 0.5
    CHECK_FALSE(r.importance.enabled());
    CHECK(r.importance_choice.rfind("auto: off", 0) == 0);
    r = run({1.0, 10.0, 5.0});  // tau_a 1 at the deepest, listed anywhere
    CHECK(r.importance.cosine == 1.0);
    CHECK(r.importance.max_depth == 10.0);
    CHECK(r.importance_choice.rfind("auto: mu_i = 1", 0) == 0);
    cfg.transport.importance = {0.5, 7.0};  // the caller's stands
    r = run({1.0, 10.0});
    CHECK(r.importance.cosine == 0.5);
    CHECK(r.importance.max_depth == 7.0);
    CHECK(r.importance_choice == "given");
    cfg.transport.importance = {};
    cfg.auto_importance = false;  // the library's default: off unless given
    r = run({1.0, 10.0});
    CHECK_FALSE(r.importance.enabled());
    CHECK(r.importance_choice == "off");
#if SECCHI_HAS_LANES
    cfg.auto_importance = true;
    for (const TracerKind lanes : {TracerKind::lanes, TracerKind::float_lanes}) {
        cfg.tracer = lanes;  // the lanes split weighted photons (the default continuous absorption)
        r = run({1.0, 10.0});
        CHECK(r.importance.cosine == 1.0);
        CHECK(r.importance_choice.rfind("auto: mu_i = 1", 0) == 0);
        cfg.transport.absorption = AbsorptionMode::analog;  // but not analog ones: off, and said
        r = run({1.0, 10.0});
        CHECK_FALSE(r.importance.enabled());
        CHECK(r.importance_choice.find("lanes") != std::string::npos);
        cfg.transport.importance = {};
        cfg.transport.absorption = AbsorptionMode::continuous;
    }
#endif
}

TEST_CASE("Lu from the map equals the exact single-scattering radiance") {
    // Sun at zenith, no interface, c = 1: the direct beam E0 exp(-c s) scatters with b p(pi);
    // Lu(z) = b p(pi) E0 exp(-c z) (1 - exp(-2 c L)) / (2 c) over a ray of length L.
    for (StoreKind store : {StoreKind::voi, StoreKind::kdtree}) {
        const auto cfg = single_scattering_config(store);
        const IsotropicPhase iso;
        const auto r = solve_plane_parallel(iso, cfg);
        for (const auto& d : r.depths) {
            const double b = cfg.albedo;
            const double exact = b / (4 * pi) * std::exp(-d.depth) * (1 - std::exp(-2 * ray_length)) / 2;
            INFO(to_string(store) << " z " << d.depth << ": " << d.lu.value << " +- " << d.lu.se << " exact " << exact);
            CHECK(d.lu.se > 0);
            CHECK(d.lu.se < 0.05 * exact);
            CHECK(std::abs(d.lu.value - exact) <= 4 * d.lu.se);
        }
    }
}

TEST_CASE("On a Lambertian bottom Eou = 2 Eu, so Eou = Ed where the reflectance is 0.5 (M93's problem-6 check)") {
    PlaneParallelConfig cfg;
    cfg.albedo = 0.5;
    cfg.bottom = Bottom::lambertian_at(2.0, 0.5);
    cfg.transport.photons = cfg.transport.map_photons = 200000;
    cfg.transport.depths = {1.0, 2.0};
    cfg.transport.threads = 2;
    cfg.store = StoreKind::voi_grid;
    const auto r = solve_plane_parallel(HenyeyGreensteinPhase(0.8), cfg);
    const auto& above = r.depths[0];
    const auto& bottom = r.depths[1];
    CHECK(bottom.irradiance[Eou].value == 2.0 * bottom.irradiance[Eu].value);
    CHECK(bottom.irradiance[Eou].se == 2.0 * bottom.irradiance[Eu].se);
    const auto& ed = bottom.irradiance[Ed];
    const auto& eou = bottom.irradiance[Eou];
    INFO("Ed " << ed.value << " +- " << ed.se << ", Eou " << eou.value << " +- " << eou.se);
    CHECK(std::abs(eou.value - ed.value) <= 4.0 * std::hypot(ed.se, eou.se));
    // Above the bottom the crossing estimate stands.
    CHECK(above.irradiance[Eou].value != 2.0 * above.irradiance[Eu].value);
    // On the bottom, nadir radiance is the bottom's own: 0.5 Ed / pi.
    CHECK(bottom.lu.value == Approx(0.5 * r.bottom_ed.value / pi).epsilon(1e-12));
}

TEST_CASE("Rayleigh single scattering: p(pi) = 3/(8 pi)") {
    auto cfg = single_scattering_config(StoreKind::voi);
    const auto r = solve_plane_parallel(RayleighPhase{}, cfg);
    const auto& d = r.depths[0];
    const double exact = cfg.albedo * 3 / (8 * pi) * std::exp(-d.depth) * (1 - std::exp(-2 * ray_length)) / 2;
    INFO(d.lu.value << " +- " << d.lu.se << " exact " << exact);
    CHECK(std::abs(d.lu.value - exact) <= 4 * d.lu.se);
}

TEST_CASE("k-d tree spheres, nanoflann spheres, the VOI stores and brute force agree on identical maps", "[threads]") {
    // Same photons, same spheres: the sums differ only by the order of addition.
    auto cfg = single_scattering_config(StoreKind::kdtree);
    cfg.transport.photons = cfg.transport.map_photons = 20000;
    cfg.steps = 16;
    const auto a = solve_plane_parallel(IsotropicPhase{}, cfg);
    cfg.store = StoreKind::nanoflann;
    const auto b = solve_plane_parallel(IsotropicPhase{}, cfg);
    for (std::size_t i = 0; i < a.depths.size(); ++i) {
        CHECK(a.depths[i].lu.value == Approx(b.depths[i].lu.value).epsilon(1e-9));
        CHECK(a.depths[i].photons_touched == b.depths[i].photons_touched);
    }
    cfg.store = StoreKind::voi;
    const auto c = solve_plane_parallel(IsotropicPhase{}, cfg);
    cfg.store = StoreKind::brute_force;  // brute force uses the cylinder too
    const auto d = solve_plane_parallel(IsotropicPhase{}, cfg);
    cfg.store = StoreKind::voi_grid;
    const auto e = solve_plane_parallel(IsotropicPhase{}, cfg);
    for (std::size_t i = 0; i < c.depths.size(); ++i) {
        CHECK(c.depths[i].lu.value == Approx(d.depths[i].lu.value).epsilon(1e-9));
        CHECK(c.depths[i].photons_touched == d.depths[i].photons_touched);
        CHECK(e.depths[i].lu.value == Approx(d.depths[i].lu.value).epsilon(1e-9));
        CHECK(e.depths[i].photons_touched == d.depths[i].photons_touched);
    }
}

TEST_CASE("shards: the same first pass, and Lu from S maps equal to one map's up to the order of addition") {
    // Each batch's sum comes from the shard holding its records: the same terms as one map's,
    // added in another order; the irradiances are untouched by the second pass.
    auto cfg = single_scattering_config(StoreKind::voi);
    cfg.transport.photons = cfg.transport.map_photons = 16000;
    cfg.transport.batches = 16;
    cfg.steps = 16;
    for (StoreKind store : {StoreKind::voi, StoreKind::kdtree}) {
        cfg.store = store;
        cfg.shards = 1;
        const auto one = solve_plane_parallel(IsotropicPhase{}, cfg);
        cfg.shards = 4;
        const auto four = solve_plane_parallel(IsotropicPhase{}, cfg);
        REQUIRE(one.depths.size() == four.depths.size());
        CHECK(one.photons_stored == four.photons_stored);
        for (std::size_t i = 0; i < one.depths.size(); ++i) {
            for (int k = 0; k < 4; ++k) CHECK(one.depths[i].irradiance[k].value == four.depths[i].irradiance[k].value);
            CHECK(one.depths[i].lu.value > 0.0);
            CHECK(four.depths[i].lu.value == Approx(one.depths[i].lu.value).epsilon(1e-9));
            CHECK(four.depths[i].lu.se == Approx(one.depths[i].lu.se).epsilon(1e-6));
            CHECK(four.depths[i].photons_touched == one.depths[i].photons_touched);
        }
    }
    cfg.shards = 3;  // does not divide 16 batches
    CHECK_THROWS_AS(solve_plane_parallel(IsotropicPhase{}, cfg), input_error);
    cfg.shards = 0;
    CHECK_THROWS_AS(solve_plane_parallel(IsotropicPhase{}, cfg), input_error);
}

TEST_CASE("AnyPassSplit hands each exchange to the split it holds; by default one process") {
    // A split that answers with its own numbers and logs what it was handed.
    struct Logging {
        unsigned r, n;
        std::vector<std::string>* log;
        unsigned rank() const { return r; }
        unsigned ranks() const { return n; }
        void gather_tallies(FirstPassPart<CompactRecord>& part) const {
            log->push_back("tallies " + std::to_string(part.traced.first) + " " + std::to_string(part.traced.last));
        }
        std::uint64_t total(std::uint64_t x) const { return 10 * x + r; }
        void gather_lu(std::vector<RadianceSum>& sums, unsigned first, unsigned last) const {
            log->push_back("lu " + std::to_string(sums.size()) + " " + std::to_string(first) + " " + std::to_string(last));
        }
    };
    std::vector<std::string> log;
    const AnyPassSplit split(Logging{3, 4, &log});
    const AnyPassSplit copy = split;
    CHECK(copy.rank() == 3);
    CHECK(copy.ranks() == 4);
    CHECK(copy.total(5) == 53);
    FirstPassPart<CompactRecord> part;
    part.traced = {2, 7};
    copy.gather_tallies(part);
    std::vector<RadianceSum> sums(2, RadianceSum(4));
    copy.gather_lu(sums, 1, 3);
    CHECK(log == std::vector<std::string>{"tallies 2 7", "lu 2 1 3"});

    const AnyPassSplit one;
    CHECK(one.rank() == 0);
    CHECK(one.ranks() == 1);
    CHECK(one.total(5) == 5);
}

TEST_CASE("k-d tree spheres and the VOI cylinder give the same Lu within their combined SE on identical maps") {
    // Multiple scattering with a peaked phase function; the same seed gives the same map.
    PlaneParallelConfig cfg;
    cfg.albedo = 0.9;
    cfg.transport.photons = cfg.transport.map_photons = 400000;
    cfg.transport.depths = {1.0, 3.0};
    cfg.transport.threads = 2;
    cfg.steps = 64;
    const HenyeyGreensteinPhase hg(0.9);
    cfg.store = StoreKind::kdtree;
    const auto kd = solve_plane_parallel(hg, cfg);
    cfg.store = StoreKind::voi;
    const auto voi = solve_plane_parallel(hg, cfg);
    REQUIRE(kd.photons_stored == voi.photons_stored);
    for (std::size_t i = 0; i < kd.depths.size(); ++i) {
        const auto& a = kd.depths[i].lu;
        const auto& b = voi.depths[i].lu;
        INFO("z " << kd.depths[i].depth << ": kd " << a.value << " +- " << a.se << ", voi " << b.value << " +- " << b.se);
        CHECK(a.se < 0.05 * a.value);
        CHECK(std::abs(a.value - b.value) <= std::hypot(a.se, b.se));
    }
}
