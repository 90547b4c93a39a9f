// Images of the radiance: the pinhole camera's rays, the rendered image against the whole
// radiance of the same rays (estimate/render.hpp), the latitude-longitude distribution's
// directions (estimate/radiance_distribution.hpp), the photon map's projection on a vertical
// plane (map/projection.hpp), the OpenEXR round trip (io/exr.hpp) and the PNG preview's bytes
// (io/png_preview.hpp).
#include <catch2/catch.hpp>
#include "secchi/core/rng.hpp"
#include "secchi/estimate/radiance_distribution.hpp"
#include "secchi/estimate/render.hpp"
#include "secchi/io/exr.hpp"
#include "secchi/io/png_preview.hpp"
#include "secchi/map/projection.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/optics/phase/cone_average.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <numeric>
#include <vector>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
using Map = PhotonMap<VoiGridStore<CompactRecord>>;

/// Uniform photons of flux `phi` in [0, 1)^2 x [0, 6), isotropic directions, 8 batches, under a
/// flat surface with a uniform sky of radiance 0.3 and a Lambertian bottom at 6 m.
Map test_map(double phi) {
    std::vector<CompactRecord> records;
    PhotonRng rng(9, 0);
    for (int i = 0; i < 40000; ++i) {
        const double mu = 2.0 * rng.uniform() - 1.0, az = two_pi * rng.uniform(), s = std::sqrt(1.0 - mu * mu);
        records.push_back(CompactRecord::make(vec3(rng.uniform(), rng.uniform(), 6.0 * rng.uniform()),
                                              vec3(s * std::cos(az), s * std::sin(az), mu), 0,
                                              static_cast<std::uint8_t>(i % 8)));
    }
    const MapScene scene{Slab(1.0, Bottom::lambertian_at(6.0, 0.4)), FlatSurface(1.34),
                         SkyLight::of(SunAndSky(CollimatedSun(30.0), UniformSky(pi * 0.3)))};
    return Map(VoiGridStore<CompactRecord>(records, Radius(0.1)), RecordFlux::uniform(phi), 8, scene, {0.25, 0.002});
}
HomogeneousRayOptics optics() { return HomogeneousRayOptics(ConeAveragedPhase(IsotropicPhase{}, 0.005), 0.3, 0.2); }
}  // namespace

TEST_CASE("The pinhole camera's rays: the centre along forward, the edges at half the field of view") {
    const PinholeCamera cam({{0.0, 0.0, 2.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 60.0, 300, 200});
    // Pixel centres straddle the image centre: the centre point (x, y) = (150, 100) at u = v = 0.
    const Ray centre = cam.ray(150, 100, 0.0, 0.0);
    CHECK(centre.direction.x == Approx(1.0));
    CHECK(centre.t_max == INFINITY);
    const Ray top = cam.ray(150, 0, 0.0, 0.0);  // the top edge: up (-z) by half the vertical field
    CHECK(std::acos(top.direction.x) == Approx(30.0 * deg));
    CHECK(top.direction.z < 0.0);
    const Ray right = cam.ray(300, 100, 0.0, 0.0);  // the right edge: tan(half) scaled by the aspect
    CHECK(std::atan2(std::abs(right.direction.y), right.direction.x) == Approx(std::atan(1.5 * std::tan(30.0 * deg))));
    CHECK_THROWS_WITH(PinholeCamera({{0.0, 0.0, 2.0}, {0.0, 0.0, -1.0}, {0.0, 0.0, 1.0}, 60.0, 8, 8}),
                      Contains("camera up"));
    CHECK_THROWS_WITH(PinholeCamera({{0.0, 0.0, 2.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 180.0, 8, 8}),
                      Contains("field of view"));
}

TEST_CASE("A rendered pixel is the whole radiance of its ray, with its SE, for any thread count", "[threads]") {
    const Map map = test_map(1e-4);
    const RadianceEstimator est(map, VoiCylinder(0.0, 6.0), optics(), Radius(0.1));
    for (const PinholeCameraSpec& spec :
         {PinholeCameraSpec{{0.5, 0.5, 3.0}, {0.0, 0.0, -1.0}, {1.0, 0.0, 0.0}, 120.0, 12, 10},
          PinholeCameraSpec{{0.5, 0.5, -2.0}, {1.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, 70.0, 12, 10}}) {
        const PinholeCamera cam(spec);
        const Image one = render(est, cam, {1, 1, 1}), two = render(est, cam, {1, 2, 1});
        CHECK(one.channel("L") == two.channel("L"));
        CHECK(one.channel("R") == one.channel("L"));
        for (int y = 0; y < cam.height(); ++y)
            for (int x = 0; x < cam.width(); ++x) {
                const Estimate e = est.radiance(cam.ray(x, y));
                const std::size_t i = static_cast<std::size_t>(y) * cam.width() + x;
                CHECK(one.channel("L")[i] == static_cast<float>(e.value));
                CHECK(one.channel("L.se")[i] == static_cast<float>(e.se));
            }
        // Jittered samples: the same image for any thread count too.
        CHECK(render(est, cam, {3, 1, 5}).channel("L") == render(est, cam, {3, 2, 5}).channel("L"));
    }
}

TEST_CASE("The latitude-longitude distribution: row 0 looks straight up, the last row straight down") {
    // Photons of no flux: the radiance is the boundaries' alone. Looking up from 3 m inside
    // Snell's window sees the sky; looking down sees the bottom.
    const Map map = test_map(0.0);
    const RadianceEstimator est(map, VoiCylinder(0.0, 6.0), optics(), Radius(0.1));
    const Image d = radiance_distribution(est, 3.0, {8, 90, 1, 2, 1});
    const double n = 1.34, r0 = fresnel_reflectance(1.0, n, 1.0);
    const double up = std::exp(-0.3 * 3.0) * ((1.0 - r0) * n * n * 0.3 + r0 * std::exp(-0.3 * 6.0) * 0.4 * 0.25 / pi);
    const double down = std::exp(-0.3 * 3.0) * 0.4 * 0.25 / pi;
    CHECK(d.channel("L")[0] == Approx(up).epsilon(2e-3));                        // within 1 deg of the zenith
    CHECK(d.channel("L")[89 * 8] == Approx(down).epsilon(2e-3));                 // within 1 deg of the nadir
    CHECK(d.channel("L")[45 * 8] < d.channel("L")[89 * 8]);                      // beyond the window: darker
}

TEST_CASE("An image survives the OpenEXR round trip; the PNG preview is a valid greyscale PNG") {
    Image image(5, 3);
    std::vector<float>& l = image.add_channel("L");
    std::vector<float>& se = image.add_channel("L.se");
    for (std::size_t i = 0; i < l.size(); ++i) {
        l[i] = 0.1f * static_cast<float>(i);
        se[i] = 1e-3f * static_cast<float>(i);
    }
    CHECK_THROWS_WITH(image.add_channel("L"), Contains("exists already"));
    write_exr(image, "test_images_roundtrip.exr");
    const Image back = read_exr("test_images_roundtrip.exr");
    CHECK(back.width() == 5);
    CHECK(back.height() == 3);
    CHECK(back.channel("L") == l);
    CHECK(back.channel("L.se") == se);
    CHECK_THROWS_WITH(read_exr("no_such_file.exr"), Contains("no_such_file.exr") && Contains("cannot be read"));
    CHECK_THROWS_WITH(write_exr(image, "/no/such/dir/x.exr"), Contains("cannot be written"));

    CHECK(write_png_preview(image, "L", "test_images_preview.png", {1.0, 0.0}) == Approx(1.4));  // the maximum
    std::ifstream png("test_images_preview.png", std::ios::binary);
    const std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(png)), {});
    REQUIRE(bytes.size() > 33);
    CHECK(std::vector<unsigned char>(bytes.begin(), bytes.begin() + 8) ==
          std::vector<unsigned char>{137, 80, 78, 71, 13, 10, 26, 10});
    CHECK(std::string(bytes.begin() + 12, bytes.begin() + 16) == "IHDR");
    CHECK(bytes[19] == 5);  // width, big-endian
    CHECK(bytes[23] == 3);  // height
    CHECK(std::string(bytes.end() - 8, bytes.end() - 4) == "IEND");
    std::remove("test_images_roundtrip.exr");
    std::remove("test_images_preview.png");
}

TEST_CASE("The photon map projected on a vertical plane: flux density per voxel, the flux conserved") {
    std::vector<CompactRecord> records;
    for (int i = 0; i < 1000; ++i)  // all in one column (x in the first pixel), spread in depth
        records.push_back(CompactRecord::make({0.001, 0.5, 12.0 * (i + 0.5) / 1000}, {0, 0, 1}, 0, 0));
    const double flux = 2e-3;
    const Image img = project_photon_map(records, RecordFlux::uniform(flux), 1.0, 12.0, 64, 128);
    const std::vector<float>& y = img.channel("Y");
    const double voxel = (1.0 / 64) * (12.0 / 128) * 1.0;
    CHECK(std::accumulate(y.begin(), y.end(), 0.0) * voxel == Approx(1000 * flux).epsilon(1e-5));
    CHECK(y[1] == 0.0f);  // nothing outside the first column
    // A map's own projection: its records, flux and section.
    const PhotonMap map(VoiGridStore<CompactRecord>(records, Radius(0.1)), RecordFlux::uniform(flux), 1,
                        MapScene::open_water(1.0));
    CHECK(project_photon_map(map, 12.0, 64, 128).channel("Y") == y);
}

TEST_CASE("The projection from above the mean surface shows a wave's crests") {
    std::vector<CompactRecord> records;  // 400 photons from 0.4 m above the mean surface to 0.4 m below it
    for (int i = 0; i < 400; ++i) records.push_back(CompactRecord::make({0.5, 0.5, -0.4 + 0.8 * (i + 0.5) / 400}, {0, 0, 1}, 0, 0));
    const double flux = 1e-3;
    const Image crests = project_photon_map(records, RecordFlux::uniform(flux), 1.0, 2.0, 8, 24, -0.4);
    const std::vector<float>& y = crests.channel("Y");
    CHECK(std::accumulate(y.begin(), y.end(), 0.0) * (1.0 / 8) * (2.4 / 24) * 1.0 == Approx(400 * flux).epsilon(1e-5));
    CHECK(y[4] > 0.0f);  // row 0 (z in [-0.4, -0.3)), the column x = 0.5
    const Image below = project_photon_map(records, RecordFlux::uniform(flux), 1.0, 2.0, 8, 24);  // from z = 0: half of them
    const std::vector<float>& yb = below.channel("Y");
    CHECK(std::accumulate(yb.begin(), yb.end(), 0.0) * (1.0 / 8) * (2.0 / 24) * 1.0 == Approx(200 * flux).epsilon(1e-5));
    CHECK_THROWS_WITH(project_photon_map(records, RecordFlux::uniform(flux), 1.0, 2.0, 8, 24, 0.5),
                      Catch::Contains("projection top depth"));
}
