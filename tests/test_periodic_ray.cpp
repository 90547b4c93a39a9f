// A ray's pieces in a periodic section and their images (estimate/periodic_ray.hpp), and the
// estimator on any ray in the section, seams crossed or followed, against a uniform map's
// exact radiance.
#include <catch2/catch.hpp>
#include "secchi/core/rng.hpp"
#include "secchi/estimate/path_radiance.hpp"
#include "secchi/map/kdtree.hpp"
#include "secchi/map/photon_map.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/map/voi_octree.hpp"
#include "secchi/optics/phase/cone_average.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include <cmath>
#include <string>
#include <vector>

using namespace secchi;

namespace {
struct Piece {
    Ray ray;
    double t0;
    vec3 offset;
};

std::vector<Piece> pieces_of(const PeriodicSection& section, const Ray& ray) {
    std::vector<Piece> pieces;
    section.for_each_piece(ray, [&](const Ray& piece, double t0, const vec3& offset) { pieces.push_back({piece, t0, offset}); });
    return pieces;
}

/// The unit vector at theta_deg from +z (down), azimuth phi (radians).
vec3 direction_at(double theta_deg, double phi) {
    const double theta = theta_deg * pi / 180.0;
    return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

/// The pieces tile the ray: the first starts at its start, each where the last ended (t0
/// cumulative), their lengths sum to the ray's, each lies in the section [0, W]^2, and each is
/// the unwrapped ray's segment moved by its cell's offset.
void check_tiles(const PeriodicSection& section, const Ray& ray) {
    const double w = section.width(), eps = 1e-12 * (1.0 + ray.t_max + glm::length(ray.origin));
    const auto pieces = pieces_of(section, ray);
    INFO("ray from " << ray.origin.x << " " << ray.origin.y << " " << ray.origin.z << " along " << ray.direction.x << " "
                     << ray.direction.y << " " << ray.direction.z << ", length " << ray.t_max);
    REQUIRE(!pieces.empty());
    CHECK(pieces.front().t0 == 0.0);
    double sum = 0.0;
    for (std::size_t k = 0; k < pieces.size(); ++k) {
        const Piece& p = pieces[k];
        INFO("piece " << k << " t0 " << p.t0 << " length " << p.ray.t_max);
        CHECK(p.ray.t_max > 0.0);
        CHECK(p.t0 == Approx(sum).margin(eps));
        sum += p.ray.t_max;
        for (const vec3& end : {p.ray.origin, p.ray.origin + p.ray.t_max * p.ray.direction}) {
            CHECK(end.x >= -eps);
            CHECK(end.x <= w + eps);
            CHECK(end.y >= -eps);
            CHECK(end.y <= w + eps);
        }
        const vec3 unwrapped = p.ray.origin + p.offset, expected = ray.origin + p.t0 * ray.direction;
        CHECK(glm::length(unwrapped - expected) <= eps);
        CHECK(p.ray.direction == ray.direction);
    }
    CHECK(sum == Approx(ray.t_max).margin(eps));
}
}  // namespace

TEST_CASE("A ray's pieces in a periodic section: cut at the seams, moved into the section, t0 cumulative") {
    const PeriodicSection section(0.5);
    SECTION("a ray that crosses no seam is one piece, itself") {
        const Ray ray{{0.1, 0.4, 2.0}, {0.0, 0.0, 1.0}, 7.0};
        const auto pieces = pieces_of(section, ray);
        REQUIRE(pieces.size() == 1);
        CHECK(pieces[0].ray.origin == ray.origin);
        CHECK(pieces[0].ray.t_max == ray.t_max);
        CHECK(pieces[0].offset == vec3(0.0));
    }
    SECTION("a horizontal ray along x: a piece per section crossed") {
        const Ray ray{{0.25, 0.3, 1.0}, {1.0, 0.0, 0.0}, 2.0};
        const auto pieces = pieces_of(section, ray);
        REQUIRE(pieces.size() == 5);
        const double lengths[] = {0.25, 0.5, 0.5, 0.5, 0.25};
        for (std::size_t k = 0; k < pieces.size(); ++k) {
            CHECK(pieces[k].ray.t_max == Approx(lengths[k]));
            CHECK(pieces[k].offset.x == Approx(0.5 * static_cast<double>(k)));
        }
        check_tiles(section, ray);
        check_tiles(section, {ray.origin, -ray.direction, ray.t_max});
    }
    SECTION("through the corners: one cut where x and y seams are crossed together") {
        const Ray ray{{0.25, 0.25, 1.0}, glm::normalize(vec3(1.0, 1.0, 0.0)), 1.5 * std::sqrt(2.0)};
        CHECK(pieces_of(section, ray).size() == 4);
        check_tiles(section, ray);
    }
    SECTION("along a seam, from outside the section, and at random") {
        check_tiles(section, {{0.0, 0.2, 1.0}, direction_at(60.0, 0.5 * pi), 4.0});  // x = 0 throughout
        check_tiles(section, {{0.5, 0.2, 1.0}, direction_at(85.0, 1.5 * pi), 4.0});  // x = W throughout
        check_tiles(section, {{0.3, 0.0, 1.0}, direction_at(30.0, pi), 4.0});        // y = 0 throughout
        check_tiles(section, {{-3.2, 7.9, 1.0}, direction_at(70.0, 2.0), 3.0});      // starts eight cells away
        PhotonRng rng(11, 0);
        for (int i = 0; i < 500; ++i) {
            const Ray ray{{0.5 * rng.uniform(), 0.5 * rng.uniform(), 1.0}, direction_at(180.0 * rng.uniform(), 2.0 * pi * rng.uniform()),
                          5.0 * rng.uniform()};
            check_tiles(section, ray);
        }
    }
}

TEST_CASE("A region reaching across a section edge is also searched moved by a width, to the opposite side") {
    const PeriodicSection section(0.5);
    auto images = [&](double lo_x, double hi_x, double lo_y, double hi_y) {
        std::vector<vec3> shifts;
        section.for_each_image(lo_x, hi_x, lo_y, hi_y, [&](const vec3& s) { shifts.push_back(s); });
        return shifts;
    };
    CHECK(images(0.1, 0.2, 0.1, 0.2) == std::vector<vec3>{vec3(0.0)});
    CHECK(images(0.0, 0.2, 0.1, 0.5) == std::vector<vec3>{vec3(0.0)});  // touching an edge: nothing beyond it
    CHECK(images(-0.05, 0.05, 0.1, 0.2) == std::vector<vec3>{vec3(0.0), vec3(0.5, 0.0, 0.0)});
    CHECK(images(0.1, 0.2, 0.45, 0.55) == std::vector<vec3>{vec3(0.0), vec3(0.0, -0.5, 0.0)});
    CHECK(images(0.45, 0.55, -0.05, 0.05) ==
          std::vector<vec3>{vec3(0.0), vec3(0.0, 0.5, 0.0), vec3(-0.5, 0.0, 0.0), vec3(-0.5, 0.5, 0.0)});
    CHECK(images(-0.05, 0.55, 0.1, 0.2).size() == 3);  // a piece across the whole section
}

TEST_CASE("The estimator refuses a radius of half the section width or more, and rays of no finite length") {
    const std::vector<CompactRecord> records{CompactRecord::make(vec3(0.1, 0.1, 1.0), vec3(0.0, 0.0, 1.0), 0, 0)};
    const PhotonMap map(VoiOctreeStore<CompactRecord>(records), RecordFlux::uniform(1.0), 1, MapScene::open_water(0.5));
    const HomogeneousRayOptics optics(ConeAveragedPhase(IsotropicPhase{}, 0.005), 0.5, 0.0);
    using Catch::Matchers::Contains;
    CHECK_THROWS_WITH(PathRadianceEstimator(map, VoiCylinder{}, optics, Radius(0.25)),
                      Contains("radius") && Contains("0.25") && Contains("half the section width"));
    CHECK_THROWS_WITH(PeriodicSection(0.0), Contains("section width"));
    const PathRadianceEstimator est(map, VoiCylinder{}, optics, Radius(0.2));
    std::vector<double> sums(1, 0.0);
    CHECK_THROWS_WITH(est.accumulate({{0.1, 0.1, 0.5}, direction_at(60.0, 1.0), INFINITY}, sums), Contains("ray length"));
}

namespace {
/// Photons uniform over the section [0, W)^2 and depths [0, depth], isotropic directions, a
/// flux of 1 each, in `batches` batches: rho = n / (W^2 depth) per m^3 everywhere.
std::vector<CompactRecord> uniform_map(double width, double depth, std::size_t n, unsigned batches) {
    PhotonRng rng(2025, 0);
    std::vector<CompactRecord> records;
    records.reserve(n);
    for (std::size_t i = 0; i < n; ++i) {
        const vec3 p(width * rng.uniform(), width * rng.uniform(), depth * rng.uniform());
        const double mu = 2.0 * rng.uniform() - 1.0, phi = 2.0 * pi * rng.uniform();
        const double s = std::sqrt(1.0 - mu * mu);
        records.push_back(CompactRecord::make(p, vec3(s * std::cos(phi), s * std::sin(phi), mu), 0,
                                              static_cast<std::uint8_t>(i % batches)));
    }
    return records;
}

/// A ray at theta_deg from the vertical (down or up), random azimuth, origin anywhere within
/// five section widths of the section, length up to `longest`, centred on depth `middle`.
Ray random_ray(PhotonRng& rng, double theta_deg, double width, double longest, double middle) {
    vec3 u = direction_at(theta_deg, 2.0 * pi * rng.uniform());
    if (rng.uniform() < 0.5) u.z = -u.z;
    const double length = longest * (0.05 + 0.95 * rng.uniform());
    return {{width * (10.0 * rng.uniform() - 4.5), width * (10.0 * rng.uniform() - 4.5), middle - 0.5 * length * u.z}, u,
            length};
}
}  // namespace

TEST_CASE("Any ray in a periodic section collects a uniform map's exact radiance (VOI octree, VOI grid, k-d tree spheres)") {
    // Photons of flux 1 at density rho, isotropic phase (1 / 4 pi), attenuation c' = 0.5 /m:
    // a ray of length L gathers rho / (4 pi) (1 - exp(-c' L)) / c', wherever it runs and however
    // often it crosses the seams; only with every photon image counted once, at its distance
    // along the unwrapped ray.
    const double width = 0.5, depth = 12.0, attenuation = 0.5;
    const std::size_t n = 400000;
    const unsigned batches = 32;
    const auto records = uniform_map(width, depth, n, batches);
    const double rho = static_cast<double>(n) / (width * width * depth);
    const Radius r(0.05);
    const MapScene scene = MapScene::open_water(width);
    const HomogeneousRayOptics optics(ConeAveragedPhase(IsotropicPhase{}, 0.005), attenuation, 0.0);
    const RecordFlux flux = RecordFlux::uniform(1.0);
    const PhotonMap octree(VoiOctreeStore<CompactRecord>(records), flux, batches, scene);
    const PhotonMap grid(VoiGridStore<CompactRecord>(records, r), flux, batches, scene);
    const PhotonMap kd(KdTreeStore<CompactRecord>(records), flux, batches, scene);
    const VoiCylinder cylinder(0.0, depth);
    const PathRadianceEstimator by_octree(octree, cylinder, optics, r);
    const PathRadianceEstimator by_grid(grid, cylinder, optics, r);
    const PathRadianceEstimator by_spheres(kd, StepSpheres(64, 0.0, depth), optics, r);

    // Groups of rays: at 0, 30, 60, 85 and 90 degrees from the vertical and in directions
    // uniform on the sphere, up to 10 widths long, from origins within five widths of the
    // section; and rays along the seams (x = 0, x = W, y = 0), through the corners, and vertical
    // rays whose cylinders cross a seam or a corner.
    PhotonRng rng(7, 0);
    std::vector<std::pair<std::string, std::vector<Ray>>> groups;
    for (const double theta : {0.0, 30.0, 60.0, 85.0, 90.0}) {
        std::vector<Ray> rays;
        for (int i = 0; i < 12; ++i) rays.push_back(random_ray(rng, theta, width, 10.0 * width, 0.5 * depth));
        groups.emplace_back(std::to_string(static_cast<int>(theta)) + " deg", rays);
    }
    std::vector<Ray> any_direction;  // directions uniform on the sphere
    for (int i = 0; i < 24; ++i)
        any_direction.push_back(random_ray(rng, std::acos(rng.uniform()) / deg, width, 10.0 * width, 0.5 * depth));
    groups.emplace_back("any direction", any_direction);
    const double z = 0.5 * depth;
    groups.emplace_back("seams and corners",
                        std::vector<Ray>{{{0.0, 0.2, z}, direction_at(60.0, 0.5 * pi), 4.0},
                                         {{width, 0.1, z}, direction_at(85.0, 1.5 * pi), 5.0},
                                         {{0.3, 0.0, z}, direction_at(30.0, pi), 3.0},
                                         {{0.0, 0.0, z}, direction_at(85.0, 0.25 * pi), 5.0},
                                         {{0.0, 0.0, z}, direction_at(90.0, 0.25 * pi), 5.0},
                                         {{width, width, z}, direction_at(90.0, 1.25 * pi), 2.0},
                                         {{0.01, 0.3, 2.0}, {0.0, 0.0, 1.0}, 5.0},
                                         {{0.3, width - 0.02, 8.0}, {0.0, 0.0, -1.0}, 5.0},
                                         {{0.0, 0.0, 2.0}, {0.0, 0.0, 1.0}, 5.0}});
    for (const auto& [name, rays] : groups) {
        double exact = 0.0;
        for (const Ray& ray : rays) exact += rho / (4.0 * pi) * (1.0 - std::exp(-attenuation * ray.t_max)) / attenuation;
        exact /= static_cast<double>(rays.size());
        const auto check = [&, &name = name, &rays = rays](const auto& est, const char* store) {
            const Estimate e = est.estimate(rays, 2).radiance;
            INFO(name << ", " << store << ": estimate / exact " << e.value / exact << " +- " << e.se / exact);
            CHECK(e.se < 0.03 * exact);
            CHECK(std::abs(e.value / exact - 1.0) <= 3.0 * e.se / exact);
        };
        check(by_octree, "VOI octree");
        check(by_grid, "VOI grid");
        check(by_spheres, "k-d tree spheres");
    }
}
