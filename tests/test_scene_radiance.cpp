// The second pass over a 3-D scene (estimate/scene_radiance.hpp): black objects end a ray with
// the path to them only; a bottom in bins adds A Ed_bin / pi of the bin the ray meets (across the
// section's periodic copies); a grey object or the bottom with a surface map adds A E / pi of the
// map's irradiance at the point met; everything else is the wrapped RadianceEstimator's, term
// for term.
// On a map of random photons that carry flux, each against the wrapped estimator's own answer
// for the same path, exactly; and what is refused.
#include <catch2/catch.hpp>
#include "secchi/core/rng.hpp"
#include "secchi/estimate/render.hpp"
#include "secchi/estimate/scene_radiance.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/optics/phase/cone_average.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/shapes.hpp"
#include <cmath>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
constexpr double c = 0.5, bottom_depth = 4.0, albedo = 0.5, width = 1.0;
constexpr Estimate bottom_ed{0.2, 0.004};
using Map = PhotonMap<VoiGridStore<CompactRecord>>;
using Estimator = RadianceEstimator<VoiGridStore<CompactRecord>, VoiCylinder, HomogeneousRayOptics>;

/// 20,000 photons of flux 1e-3 W at random points and directions: the path terms are not 0.
Map lit_map() {
    std::vector<CompactRecord> records;
    PhotonRng rng(9, 0);
    for (int i = 0; i < 20000; ++i) {
        const double mu = 2.0 * rng.uniform() - 1.0, phi = two_pi * rng.uniform(), s = std::sqrt(1.0 - mu * mu);
        records.push_back(CompactRecord::make(vec3(width * rng.uniform(), width * rng.uniform(), bottom_depth * rng.uniform()),
                                              vec3(s * std::cos(phi), s * std::sin(phi), mu), 0, static_cast<std::uint8_t>(i % 4)));
    }
    const MapScene scene{Slab(width, Bottom::lambertian_at(bottom_depth, albedo)), FlatSurface(1.34),
                         SkyLight::of(SunAndSky(CollimatedSun(30.0, 0.0, 2.0), UniformSky(pi * 0.3)))};
    return Map(VoiGridStore<CompactRecord>(records, Radius(0.05)), RecordFlux::uniform(1e-3), 4, scene, bottom_ed);
}

Estimator estimator(const Map& map) {
    return Estimator(map, VoiCylinder(0.0, bottom_depth), HomogeneousRayOptics(ConeAveragedPhase(IsotropicPhase{}, 0.005), c, 0.4),
                     Radius(0.05));
}

/// 4 x 4 bins of distinct Ed: bin k reads 0.1 + 0.01 k, SE 0.001 (k + 1).
std::vector<Estimate> bins() {
    std::vector<Estimate> b;
    for (int k = 0; k < 16; ++k) b.push_back({0.1 + 0.01 * k, 0.001 * (k + 1)});
    return b;
}

Shapes black_box() {
    Shapes g;
    g.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::absorbing());
    return g;
}
}  // namespace

TEST_CASE("Scene radiance: a bottom in bins gives the bin's A Ed / pi under the ray, through the periodic copies") {
    const Map map = lit_map();
    const Estimator est = estimator(map);
    const SceneRadianceEstimator scene(est, NoGeometry{}, bins());
    PhotonRng rng(11, 0);
    for (int i = 0; i < 300; ++i) {
        const double theta = 80.0 * deg * rng.uniform(), phi = two_pi * rng.uniform();
        const vec3 d{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
        const vec3 o{6.0 * rng.uniform() - 3.0, 6.0 * rng.uniform() - 3.0, bottom_depth * rng.uniform()};
        const Ray ray{o, d, INFINITY};
        const double t_b = (bottom_depth - o.z) / d.z;
        const vec3 p = o + t_b * d;
        const auto ix = static_cast<int>(4.0 * (p.x - std::floor(p.x))), iy = static_cast<int>(4.0 * (p.y - std::floor(p.y)));
        const Estimate ed = bins()[static_cast<std::size_t>(iy * 4 + ix)];
        const double per_ed = albedo / pi * est.transmittance(Ray{o, d, t_b});  // exp(-c t_b), as the optics compute it
        const Estimate path = est.radiance(Ray{o, d, std::nextafter(t_b, 0.0)});
        const Estimate got = scene.radiance(ray);
        INFO("ray " << i << ": bin " << ix << ", " << iy);
        CHECK(got.value == Approx(path.value + per_ed * ed.value).epsilon(1e-12));
        CHECK(got.se == Approx(std::hypot(path.se, per_ed * ed.se)).epsilon(1e-12));
        // The wrapped estimator with the map's uniform bottom: the same path, the mean Ed.
        CHECK(est.radiance(ray).value == Approx(path.value + per_ed * bottom_ed.value).epsilon(1e-12));
    }
}

TEST_CASE("Scene radiance: a black object ends the ray with the path to it; other rays are the wrapped estimator's") {
    const Map map = lit_map();
    const Estimator est = estimator(map);
    const SceneRadianceEstimator scene(est, black_box());
    const Shapes box = black_box();
    PhotonRng rng(12, 0);
    int blocked = 0;
    for (int i = 0; i < 300; ++i) {
        const double mu = 2.0 * rng.uniform() - 1.0, phi = two_pi * rng.uniform(), s = std::sqrt(1.0 - mu * mu);
        const vec3 d{s * std::cos(phi), s * std::sin(phi), mu};
        vec3 o;
        do o = vec3(3.0 * rng.uniform() - 1.0, 3.0 * rng.uniform() - 1.0, bottom_depth * rng.uniform());
        while (o.z >= 2.0 && o.z <= 2.5);  // outside every copy of the box: not at its depths
        const Ray ray{o, d, INFINITY};
        const auto hit = periodic_closest_hit(box, width, o, d, INFINITY);
        const Estimate got = scene.radiance(ray);
        const double t_boundary = d.z < 0.0 ? o.z / -d.z : (bottom_depth - o.z) / d.z;
        INFO("ray " << i);
        if (hit && hit->t < t_boundary) {
            ++blocked;
            const Estimate want = est.radiance(Ray{o, d, hit->t});
            CHECK(got.value == want.value);
            CHECK(got.se == want.se);
        } else {
            const Estimate want = est.radiance(ray);
            CHECK(got.value == want.value);
            CHECK(got.se == want.se);
        }
    }
    CHECK(blocked > 30);
    CHECK(blocked < 270);
}

TEST_CASE("Scene radiance: rendered through render(); refused: grey objects met, rays from the air, bins not n x n") {
    const Map map = lit_map();
    const Estimator est = estimator(map);
    const SceneRadianceEstimator scene(est, black_box(), bins());
    const PinholeCamera camera({{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, {1.0, 0.0, 0.0}, 60.0, 8, 8});
    const Image image = render(scene, camera, {1, 2, 1});
    for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x)
            CHECK(image.channel("L")[static_cast<std::size_t>(y * 8 + x)] == static_cast<float>(scene.radiance(camera.ray(x, y)).value));

    Shapes grey;
    grey.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::lambertian(0.3));
    const SceneRadianceEstimator grey_scene(est, grey);
    CHECK_THROWS_WITH(grey_scene.radiance(Ray{vec3(0.5, 0.5, 1.0), vec3(0.0, 0.0, 1.0), INFINITY}),
                      Contains("object albedo = 0.3") && Contains("needs a surface photon map"));
    CHECK_NOTHROW(grey_scene.radiance(Ray{vec3(0.1, 0.1, 1.0), vec3(0.0, 0.0, 1.0), INFINITY}));  // beside it
    CHECK_THROWS_WITH(scene.radiance(Ray{vec3(0.5, 0.5, -1.0), vec3(0.0, 0.0, 1.0), INFINITY}), Contains("ray origin depth"));
    std::vector<Estimate> five(5, Estimate{0.1, 0.0});
    CHECK_THROWS_WITH(SceneRadianceEstimator(est, NoGeometry{}, five), Contains("bottom Ed bins = 5"));
}

TEST_CASE("Scene radiance: a grey object and the bottom with a surface map add A E / pi of the map's irradiance there") {
    const Map map = lit_map();
    const Estimator est = estimator(map);
    // A surface map of random arrivals on the box's top (normal -z), on its sides and on the
    // bottom, 4 batches: the estimator's answer is checked against SurfaceIrradiance's own.
    std::vector<SurfacePhoton> arrivals;
    PhotonRng rng(13, 0);
    for (int i = 0; i < 40000; ++i) {
        const double u = rng.uniform(), v = rng.uniform();
        const auto batch = static_cast<std::uint8_t>(i % 4);
        if (i % 3 == 0) arrivals.push_back({{0.25 + 0.5 * u, 0.25 + 0.5 * v, 2.0}, {0.0, 0.0, -1.0}, 0.5 + u, 0, batch});
        else if (i % 3 == 1) arrivals.push_back({{0.25, 0.25 + 0.5 * u, 2.0 + 0.5 * v}, {-1.0, 0.0, 0.0}, 1.0, 0, batch});
        else arrivals.push_back({{u, v, bottom_depth}, {0.0, 0.0, -1.0}, 0.2 + v, SurfacePhoton::bottom, batch});
    }
    const auto surface = std::make_shared<const SurfaceIrradiance>(arrivals, 1e-4, 4, width, Radius(0.05));
    Shapes grey;
    grey.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::lambertian(0.3));
    const SceneRadianceEstimator scene(est, grey, {}, surface);
    int on_box = 0, on_bottom = 0;
    for (int i = 0; i < 300; ++i) {
        const double theta = 60.0 * deg * rng.uniform(), phi = two_pi * rng.uniform();
        const vec3 d{std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
        const vec3 o{2.0 * rng.uniform() - 0.5, 2.0 * rng.uniform() - 0.5, 1.5 * rng.uniform()};
        const Ray ray{o, d, INFINITY};
        const Estimate got = scene.radiance(ray);
        const auto hit = periodic_closest_hit(grey, width, o, d, INFINITY);
        const double t_b = (bottom_depth - o.z) / d.z;
        INFO("ray " << i);
        if (hit && hit->t < t_b) {
            ++on_box;
            const Estimate e = surface->irradiance(hit->point, hit->normal);
            const Estimate path = est.radiance(Ray{o, d, hit->t});
            const double per_e = 0.3 / pi * est.transmittance(Ray{o, d, hit->t});
            CHECK(got.value == Approx(path.value + per_e * e.value).epsilon(1e-12));
            CHECK(got.se == Approx(std::hypot(path.se, per_e * e.se)).epsilon(1e-12));
        } else {
            ++on_bottom;
            const vec3 p = o + t_b * d;
            const Estimate e = surface->irradiance(p, vec3(0.0, 0.0, -1.0));
            const Estimate path = est.radiance(Ray{o, d, std::nextafter(t_b, 0.0)});
            const double per_e = albedo / pi * est.transmittance(Ray{o, d, t_b});
            CHECK(got.value == Approx(path.value + per_e * e.value).epsilon(1e-12));
        }
    }
    CHECK(on_box > 30);
    CHECK(on_bottom > 30);
    // A glossy object is refused (its light needs the incident directions).
    Shapes shiny;
    shiny.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::ward(0.2, 0.3, 0.1));
    const SceneRadianceEstimator shiny_scene(est, shiny, {}, surface);
    CHECK_THROWS_WITH(shiny_scene.radiance(Ray{vec3(0.5, 0.5, 1.0), vec3(0.0, 0.0, 1.0), INFINITY}),
                      Contains("object glossy albedo = 0.3") && Contains("not modelled by the second pass"));
    // The map's bands must be one; a black object needs no map and adds nothing.
    const SceneRadianceEstimator black(est, black_box(), {}, surface);
    CHECK(black.radiance(Ray{vec3(0.5, 0.5, 1.0), vec3(0.0, 0.0, 1.0), INFINITY}).value ==
          est.radiance(Ray{vec3(0.5, 0.5, 1.0), vec3(0.0, 0.0, 1.0), 1.0}).value);
}
