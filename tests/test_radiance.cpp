// The whole radiance along a ray (estimate/radiance.hpp): the boundary terms of manual eq. 3.18
// (a Lambertian bottom, the flat surface seen from below and from above, the sky) against
// their closed forms, on a map whose photons carry no flux (so that the path term is exactly
// 0); the n^2 law against the Fresnel transmittance integrated in the air; the direct sun; and
// what is refused.
#include <catch2/catch.hpp>
#include "secchi/core/rng.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/optics/phase/cone_average.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include <cmath>
#include <type_traits>
#include <vector>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
constexpr double n_water = 1.34, c = 0.5, bottom_depth = 4.0, albedo = 0.5, sky_l = 0.3;
constexpr Estimate bottom_ed{0.2, 0.004};

using Map = PhotonMap<VoiGridStore<CompactRecord>>;

/// A few photons of no flux: every path term is 0 and the radiance is the boundary terms alone.
Map dark_map(MapScene scene) {
    std::vector<CompactRecord> records;
    PhotonRng rng(3, 0);
    for (int i = 0; i < 50; ++i)
        records.push_back(CompactRecord::make(vec3(rng.uniform(), rng.uniform(), bottom_depth * rng.uniform()),
                                              vec3(0.0, 0.0, 1.0), 0, static_cast<std::uint8_t>(i % 4)));
    return Map(VoiGridStore<CompactRecord>(records, Radius(0.05)), RecordFlux::uniform(0.0), 4, std::move(scene),
               bottom_ed);
}

MapScene scene_with(Bottom bottom, std::optional<FlatSurface> surface, double sky = sky_l) {
    return {Slab(1.0, bottom), surface,
            SkyLight::of(SunAndSky(CollimatedSun(30.0, 0.0, 2.0), UniformSky(pi * sky)))};
}

HomogeneousRayOptics clear_optics() { return HomogeneousRayOptics(ConeAveragedPhase(IsotropicPhase{}, 0.005), c, 0.0); }

vec3 look(double theta_deg, double phi, bool down) {
    const double t = theta_deg * deg;
    return {std::sin(t) * std::cos(phi), std::sin(t) * std::sin(phi), down ? std::cos(t) : -std::cos(t)};
}

double bottom_radiance() { return albedo * bottom_ed.value / pi; }
}  // namespace

TEST_CASE("Boundary terms of the whole radiance: bottom, surface from below and above, sky") {
    const Map map = dark_map(scene_with(Bottom::lambertian_at(bottom_depth, albedo), FlatSurface(n_water)));
    const RadianceEstimator est(map, VoiCylinder(0.0, bottom_depth), clear_optics(), Radius(0.05));
    PhotonRng rng(5, 0);
    for (int i = 0; i < 200; ++i) {
        const double theta = 89.0 * rng.uniform(), phi = two_pi * rng.uniform(), z = bottom_depth * rng.uniform();
        const vec3 origin{3.0 * rng.uniform() - 1.0, 3.0 * rng.uniform() - 1.0, z};
        const double mu = std::cos(theta * deg);
        INFO("theta " << theta << " deg, z " << z);
        // Looking down at the bottom: A Ed / pi through exp(-c path); its SE is the bottom Ed's.
        const Estimate down = est.radiance({origin, look(theta, phi, true), INFINITY});
        const double t_down = std::exp(-c * (bottom_depth - z) / mu);
        CHECK(down.value == Approx(t_down * bottom_radiance()).epsilon(1e-12));
        CHECK(down.se == Approx(t_down * albedo * bottom_ed.se / pi).epsilon(1e-12));
        // Looking up at the surface: the sky refracted in, (1 - R) n^2 L_sky, and the bottom's
        // light reflected down there, R times the mirror ray's radiance (R = 1 beyond the
        // critical angle).
        const double r = fresnel_reflectance(mu, n_water, 1.0);
        const double mirror = std::exp(-c * bottom_depth / mu) * bottom_radiance();
        const double up = std::exp(-c * z / mu) * ((1.0 - r) * n_water * n_water * sky_l + r * mirror);
        CHECK(est.radiance({origin, look(theta, phi, false), INFINITY}).value == Approx(up).epsilon(1e-12));
        // From the air looking down: the sky reflected, plus the bottom's light leaving the water,
        // (1 - R) / n^2 of it, along the refracted ray.
        const double r_air = fresnel_reflectance(mu, 1.0, n_water);
        const double mu_w = std::sqrt(1.0 - (1.0 - mu * mu) / (n_water * n_water));
        const double above = r_air * sky_l + (1.0 - r_air) / (n_water * n_water) *
                                                 std::exp(-c * bottom_depth / mu_w) * bottom_radiance();
        const vec3 in_air{origin.x, origin.y, -1.0 - z};
        CHECK(est.radiance({in_air, look(theta, phi, true), INFINITY}).value == Approx(above).epsilon(1e-12));
        // From the air looking up, or down at something of the host's above the surface: the sky, nothing.
        CHECK(est.radiance({in_air, look(theta, phi, false), INFINITY}).value == Approx(sky_l).epsilon(1e-15));
        CHECK(est.radiance({in_air, look(theta, phi, true), 0.99 * (1.0 + z) / mu}).value == 0.0);
        // A host's object in the water halfway to the bottom: no light of ours beyond it, and its
        // own carried by T.
        const double t_object = 0.5 * (bottom_depth - z) / mu;
        const Ray to_object{origin, look(theta, phi, true), t_object};
        CHECK(est.radiance(to_object).value == 0.0);
        CHECK(est.transmittance(to_object) == Approx(std::exp(-c * t_object)).epsilon(1e-12));
        CHECK_THROWS_WITH(est.transmittance({origin, look(theta, phi, true), 3.0 * t_object}), Contains("beyond the water"));
    }
}

TEST_CASE("Radiance crossing the surface keeps L / n^2 times the Fresnel transmittance (a uniform sky's Ed just below)") {
    // Black water under a uniform sky: Ed(0-) is the sky's light transmitted, 2 pi L integral of
    // (1 - R(mu_a)) mu_a d mu_a over the air's hemisphere. The same from the water's side: the
    // radiance the estimator returns for rays looking up from just below, integrated over the
    // water's hemisphere with mu_w d mu_w. The two agree only with Snell's law, the n^2 law and
    // total internal reflection (R = 1) beyond the critical angle. Midpoint rule, 20000 nodes.
    const Map map = dark_map(scene_with(Bottom::infinitely_deep(), FlatSurface(n_water)));
    const RadianceEstimator est(map, VoiCylinder(0.0, INFINITY), clear_optics(), Radius(0.05));
    const int nodes = 20000;
    double from_air = 0.0, from_water = 0.0;
    for (int i = 0; i < nodes; ++i) {
        const double mu = (i + 0.5) / nodes;
        from_air += (1.0 - fresnel_reflectance(mu, 1.0, n_water)) * mu;
        const vec3 up{std::sqrt(1.0 - mu * mu), 0.0, -mu};
        from_water += est.radiance({{0.3, 0.7, 0.0}, up, INFINITY}).value * mu;
    }
    from_air *= two_pi * sky_l / nodes;
    from_water *= two_pi / nodes;
    INFO("Ed(0-) from the air's side " << from_air << ", from the water's " << from_water);
    CHECK(from_water == Approx(from_air).epsilon(2e-4));  // the midpoint rule at the critical angle's kink
    CHECK(from_air == Approx(pi * sky_l * 0.934).epsilon(0.01));  // Mobley 1994 table 4.3: t of a uniform sky ~0.934
}

TEST_CASE("The direct sun: E_perp through the surface, narrowed by the refraction and attenuated along the beam") {
    const Map map = dark_map(scene_with(Bottom::infinitely_deep(), FlatSurface(n_water)));
    const RadianceEstimator est(map, VoiCylinder(0.0, INFINITY), clear_optics(), Radius(0.05));
    const double mu_a = std::cos(30.0 * deg), mu_w = std::sqrt(1.0 - (1.0 - mu_a * mu_a) / (n_water * n_water));
    const DirectBeam air = est.direct_sun({0.2, 0.2, -1.0});
    CHECK(air.e_perp == Approx(2.0));
    CHECK(air.direction.z == Approx(mu_a));
    const DirectBeam at2 = est.direct_sun({0.2, 0.2, 2.0});
    CHECK(at2.direction.z == Approx(mu_w).epsilon(1e-12));
    // Ed of the direct beam: E_perp mu_a (1 - R) just below, exp(-c z / mu_w) at depth z.
    CHECK(at2.e_perp * at2.direction.z ==
          Approx(2.0 * mu_a * (1.0 - fresnel_reflectance(mu_a, 1.0, n_water)) * std::exp(-c * 2.0 / mu_w)).epsilon(1e-12));
}

TEST_CASE("The whole radiance refuses what it cannot answer, naming why") {
    const HomogeneousRayOptics optics = clear_optics();
    SECTION("a wind-blown surface (not modelled by the second pass)") {
        const Map map = dark_map(scene_with(Bottom::infinitely_deep(), std::nullopt));
        const RadianceEstimator est(map, VoiCylinder(0.0, INFINITY), optics, Radius(0.05));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 1.0}, {0.0, 0.0, -1.0}, INFINITY}), Contains("wind-blown"));
        CHECK_THROWS_WITH(est.direct_sun({0.5, 0.5, 1.0}), Contains("wind-blown"));
        CHECK_NOTHROW(est.radiance({{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, INFINITY}));  // never meets the surface
    }
    SECTION("a traced atmosphere's sky, wherever a ray sees it") {
        const MapScene scene{Slab(1.0, Bottom::infinitely_deep()), FlatSurface(n_water),
                             SkyLight::of(TracedAtmosphere(AtmosphereSpec{}))};
        const Map map = dark_map(scene);
        const RadianceEstimator est(map, VoiCylinder(0.0, INFINITY), optics, Radius(0.05));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, -1.0}, {0.0, 0.0, -1.0}, INFINITY}), Contains("traced atmosphere"));
        // Beyond the critical angle a ray from below sees no sky: only the water, reflected.
        CHECK_NOTHROW(est.radiance({{0.5, 0.5, 1.0}, look(60.0, 0.0, false), INFINITY}));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 1.0}, look(10.0, 0.0, false), INFINITY}), Contains("sky"));
    }
    SECTION("rays below the bottom, of no unit direction, in a band the map lacks") {
        const Map map = dark_map(scene_with(Bottom::lambertian_at(bottom_depth, albedo), FlatSurface(n_water)));
        const RadianceEstimator est(map, VoiCylinder(0.0, bottom_depth), optics, Radius(0.05));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 4.5}, {0.0, 0.0, -1.0}, INFINITY}),
                          Contains("ray origin depth") && Contains("4.5") && Contains("below the bottom"));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 1.0}, {0.0, 0.0, 2.0}, INFINITY}), Contains("ray direction length"));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, INFINITY}, 1), Contains("band") && Contains("1"));
        CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, -1.0}), Contains("ray length"));
    }
    SECTION("a map whose photons lie in more batches or bands than it says") {
        const std::vector<CompactRecord> records{CompactRecord::make(vec3(0.5), vec3(0.0, 0.0, 1.0), 2, 5)};
        CHECK_THROWS_WITH(Map(VoiGridStore<CompactRecord>(records, Radius(0.05)), RecordFlux::uniform(1.0), 4,
                              MapScene::open_water(1.0)),
                          Contains("batches") && Contains("batch index 5"));
        CHECK_THROWS_WITH(Map(VoiGridStore<CompactRecord>(records, Radius(0.05)), RecordFlux::uniform(1.0), 6,
                              MapScene::open_water(1.0), {}, {450.0, 550.0}),
                          Contains("bands") && Contains("band index 2"));
    }
    // An estimator never refers to a map that is gone by the end of the expression that made it.
    static_assert(!std::is_constructible_v<RadianceEstimator<VoiGridStore<CompactRecord>, VoiCylinder, HomogeneousRayOptics>,
                                           Map&&, VoiCylinder, HomogeneousRayOptics, Radius>);
    static_assert(std::is_constructible_v<RadianceEstimator<VoiGridStore<CompactRecord>, VoiCylinder, HomogeneousRayOptics>,
                                          const Map&, VoiCylinder, HomogeneousRayOptics, Radius>);
    static_assert(!std::is_constructible_v<PathRadianceEstimator<VoiGridStore<CompactRecord>, VoiCylinder, HomogeneousRayOptics>,
                                           Map&&, VoiCylinder, HomogeneousRayOptics, Radius>);
}
