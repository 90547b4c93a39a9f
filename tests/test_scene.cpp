#include <catch2/catch.hpp>
#include "secchi/scene/flat_surface.hpp"
#include "secchi/scene/slab.hpp"
#include "secchi/scene/sun.hpp"

using namespace secchi;

TEST_CASE("Fresnel reflectance at normal incidence, n = 1.34") {
    const double expected = std::pow((1.34 - 1.0) / (1.34 + 1.0), 2);  // ((n-1)/(n+1))^2 = 0.021112
    REQUIRE(fresnel_reflectance(1.0, 1.0, 1.34) == Approx(expected).epsilon(1e-12));
    REQUIRE(fresnel_reflectance(1.0, 1.34, 1.0) == Approx(expected).epsilon(1e-12));
    REQUIRE(expected == Approx(0.021112).epsilon(1e-4));
}

TEST_CASE("Fresnel at the Brewster angle: only the s-polarised half reflects") {
    const double n = 1.34, theta_b = std::atan(n);
    const double rs = (1.0 - n * n) / (1.0 + n * n);
    REQUIRE(fresnel_reflectance(std::cos(theta_b), 1.0, n) == Approx(0.5 * rs * rs).epsilon(1e-12));
}

TEST_CASE("Total internal reflection beyond the critical angle from below") {
    const double tc = critical_angle(1.34, 1.0);
    REQUIRE(tc / deg == Approx(48.27).epsilon(1e-3));
    REQUIRE(fresnel_reflectance(std::cos(tc + 1e-6), 1.34, 1.0) == 1.0);
    REQUIRE(fresnel_reflectance(std::cos(tc - 1e-3), 1.34, 1.0) < 1.0);
    const FlatSurface s(1.34);
    const double th = 60 * deg;
    REQUIRE(s.reflectance_from_water({std::sin(th), 0, -std::cos(th)}) == 1.0);
}

TEST_CASE("Reflectance is reciprocal: R(air, theta_i) = R(water, theta_t)") {
    for (double th_deg : {10.0, 30.0, 60.0, 85.0}) {
        const double ci = std::cos(th_deg * deg);
        const double st = std::sin(th_deg * deg) / 1.34, ct = std::sqrt(1 - st * st);
        REQUIRE(fresnel_reflectance(ci, 1.0, 1.34) == Approx(fresnel_reflectance(ct, 1.34, 1.0)).epsilon(1e-12));
    }
}

TEST_CASE("The sun at 60 deg travels at 40.3 deg in water (n = 1.34)") {
    const CollimatedSun sun(60.0);
    REQUIRE(sun.plane_irradiance() == Approx(0.5));
    const vec3 d = FlatSurface(1.34).transmit_into_water(sun.direction());
    REQUIRE(std::acos(d.z) / deg == Approx(40.26).epsilon(1e-3));
    REQUIRE(glm::length(d) == Approx(1.0));
}

TEST_CASE("Water index 1.0 means no interface") {
    const FlatSurface s(1.0);
    const vec3 d = CollimatedSun(60.0).direction();
    REQUIRE(s.reflectance_from_air(d) == 0.0);
    REQUIRE(s.reflectance_from_water({d.x, d.y, -d.z}) == 0.0);
    REQUIRE(s.transmit_into_water(d).z == Approx(d.z));
}

TEST_CASE("Invalid scene input is rejected with the parameter's name") {
    REQUIRE_THROWS_WITH(FlatSurface(0.9), Catch::Contains("water index"));
    REQUIRE_THROWS_WITH(CollimatedSun(95.0), Catch::Contains("sun zenith"));
    REQUIRE_THROWS_WITH(Bottom::lambertian_at(5.0, 1.5), Catch::Contains("bottom albedo"));
    REQUIRE_THROWS_WITH(Slab(-1.0, Bottom{}, 10.0), Catch::Contains("section width"));
}

TEST_CASE("Periodic wrap lands in [0, W)") {
    const Slab slab(2.0, Bottom{}, 10.0);
    for (double x : {-5.0, -2.0, -1e-17, 0.0, 1.999, 2.0, 7.3}) {
        const double w = slab.wrap(x);
        REQUIRE(w >= 0.0);
        REQUIRE(w < 2.0);
    }
    REQUIRE(slab.wrap(7.5) == Approx(1.5));
}
