// Second pass: the map's radiance estimate against the exact single-scattering answer, and
// the collection volumes / stores against each other on identical maps.
#include <catch2/catch.hpp>
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/solver/plane_parallel.hpp"

using namespace secchi;

TEST_CASE("Sphere volume inside the water: caps cut by the surface and the bottom") {
    const double r = 0.1, full = 4.0 / 3.0 * pi * r * r * r;
    CHECK(sphere_volume_in_slab(1.0, r, 0.0, INFINITY) == Approx(full));
    CHECK(sphere_volume_in_slab(0.0, r, 0.0, INFINITY) == Approx(full / 2));
    CHECK(sphere_volume_in_slab(5.0, r, 0.0, 5.0) == Approx(full / 2));
    CHECK(sphere_volume_in_slab(0.05, r, 0.0, INFINITY) == Approx(full - pi * 0.05 * 0.05 * (0.3 - 0.05) / 3));
}

namespace {
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
    cfg.ray_length = 4.0;
    cfg.radius = 0.05;
    cfg.steps = 64;
    return cfg;
}
}  // namespace

TEST_CASE("Lu from the map equals the exact single-scattering radiance") {
    // Sun at zenith, no interface, c = 1: the direct beam E0 exp(-c s) scatters with b p(pi);
    // Lu(z) = b p(pi) E0 exp(-c z) (1 - exp(-2 c L)) / (2 c) over a ray of length L.
    for (StoreKind store : {StoreKind::voi, StoreKind::kdtree}) {
        const auto cfg = single_scattering_config(store);
        const IsotropicPhase iso;
        const auto r = solve_plane_parallel(iso, cfg);
        for (const auto& d : r.depths) {
            const double b = cfg.albedo;
            const double exact = b / (4 * pi) * std::exp(-d.depth) * (1 - std::exp(-2 * cfg.ray_length)) / 2;
            INFO(to_string(store) << " z " << d.depth << ": " << d.lu.value << " +- " << d.lu.se << " exact " << exact);
            CHECK(d.lu.se > 0);
            CHECK(d.lu.se < 0.05 * exact);
            CHECK(std::abs(d.lu.value - exact) <= 4 * d.lu.se);
        }
    }
}

TEST_CASE("Rayleigh single scattering: p(pi) = 3/(8 pi)") {
    auto cfg = single_scattering_config(StoreKind::voi);
    const auto r = solve_plane_parallel(RayleighPhase{}, cfg);
    const auto& d = r.depths[0];
    const double exact = cfg.albedo * 3 / (8 * pi) * std::exp(-d.depth) * (1 - std::exp(-2 * cfg.ray_length)) / 2;
    INFO(d.lu.value << " +- " << d.lu.se << " exact " << exact);
    CHECK(std::abs(d.lu.value - exact) <= 4 * d.lu.se);
}

TEST_CASE("k-d tree spheres, nanoflann spheres and brute force agree on identical maps") {
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
    for (std::size_t i = 0; i < c.depths.size(); ++i) {
        CHECK(c.depths[i].lu.value == Approx(d.depths[i].lu.value).epsilon(1e-9));
        CHECK(c.depths[i].photons_touched == d.depths[i].photons_touched);
    }
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
