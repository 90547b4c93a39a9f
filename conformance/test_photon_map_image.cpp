// The problem-2a photon-map image: projection of records on the x-z plane, written as
// OpenEXR and read back with OpenEXR.
#include <catch2/catch.hpp>
#include "photon_map_image.hpp"
#include <cstdio>
#include <numeric>

using namespace secchi;

TEST_CASE("Photon map image: density per voxel, written and read back with OpenEXR") {
    std::vector<CompactRecord> map;
    for (int i = 0; i < 1000; ++i)  // all in one column (x in the first pixel), spread in depth
        map.push_back(CompactRecord::make({0.001, 0.5, 12.0 * (i + 0.5) / 1000}, {0, 0, 1}, 0, 0));
    const double flux = 2e-3;
    const auto img = conformance::project_photon_map(map, 1.0, 12.0, flux, 64, 128);
    const double voxel = (1.0 / 64) * (12.0 / 128) * 1.0;
    const double total = std::accumulate(img.pixels.begin(), img.pixels.end(), 0.0) * voxel;
    CHECK(total == Approx(1000 * flux).epsilon(1e-5));  // flux is conserved
    CHECK(img.pixels[1] == 0.0f);                        // nothing outside the first column

    const std::string path = "test_photon_map_image.exr";
    conformance::write_exr(img, path);
    const auto back = conformance::read_exr(path);
    REQUIRE(back.width == 64);
    REQUIRE(back.height == 128);
    CHECK(back.pixels == img.pixels);
    std::remove(path.c_str());
}
