// Kirk's relations and the reductions `canonical --problem kirk` scores with (kirk.hpp).
#include <catch2/catch.hpp>
#include "kirk.hpp"
#include <cmath>
#include <vector>

using namespace secchi;
namespace kk = secchi::conformance::kirk;

TEST_CASE("Kirk's relations give the manual's numbers") {
    CHECK(kk::reflectance_c(1.0) == Approx(0.346).margin(1e-12));  // manual eq. 7.4, C(0 deg)
    // The manual's HG case (7.5.4): a = 0.1, b = 0.9, mean cosine 0.8, sun at nadir: 19.9 m
    // from the 1994 relation (canonical_problems.md section 7: 19.94 m).
    const double z94 = kk::euphotic_depth(kk::kd_bar_relation(0.1, 0.9, 1.0, kk::g_1994(1.0, 0.8)));
    CHECK(z94 == Approx(19.94).margin(0.01));
    // The 1991 form at the same point: G' = 2.236/0.8 - 2.447 - 0.849/0.8 + 0.739 = 0.02575.
    CHECK(kk::g_1991(1.0, 0.8) == Approx(0.02575).margin(1e-12));
    CHECK(kk::kd_bar_relation(1.0, 0.0, 0.5, 0.3) == Approx(2.0));  // b = 0: Kd_bar = a / mu0
    CHECK_THROWS_AS(kk::kd_bar_relation(0.0, 1.0, 1.0, 0.2), input_error);
    CHECK_THROWS_AS(kk::kd_bar_relation(1.0, 1.0, 1.5, 0.2), input_error);
    CHECK_THROWS_AS(kk::kd_bar_relation(1.0, 10.0, 1.0, -0.2), input_error);  // 1 + G b/a < 0
}

TEST_CASE("b for a given k gives that k back") {
    for (double k : kk::domain_k()) {
        const double b = kk::scattering_for_k(k, 1.0, 0.0184);
        const double bb = 0.0184 * b;
        CHECK(bb / (1.0 + bb) == Approx(k).epsilon(1e-12));
    }
    CHECK_THROWS_AS(kk::scattering_for_k(1.0, 1.0, 0.0184), input_error);
    CHECK_THROWS_AS(kk::scattering_for_k(0.1, 1.0, 0.0), input_error);
}

TEST_CASE("z1% from an Ed profile: exact for an exponential, SE from the bracketing detectors") {
    const double kd = 0.7, z_true = std::log(100.0) / kd;
    const auto depths = kk::euphotic_grid(z_true * 1.07);  // the guess need not be right
    REQUIRE(depths.front() == 0.0);
    REQUIRE(depths.size() == 82);
    CHECK(depths[1] == Approx(0.6 * z_true * 1.07));
    CHECK(depths.back() == Approx(1.4 * z_true * 1.07));
    std::vector<Estimate> ed;
    const double r = 0.003;  // the same relative SE everywhere below the surface
    for (double z : depths) ed.push_back({2.0 * std::exp(-kd * z), z == 0.0 ? 0.0 : r * 2.0 * std::exp(-kd * z)});
    const Estimate z1 = kk::depth_of_fraction(depths, ed, 0.01);
    CHECK(z1.value == Approx(z_true).epsilon(1e-12));  // ln Ed is linear: interpolation is exact
    CHECK(z1.se == Approx(r / kd).epsilon(1e-9));       // ((1 - u) r + u r + 0) / Kd
    ed[0].se = 0.001 * ed[0].value;                     // the surface's own error adds (upper bound)
    CHECK(kk::depth_of_fraction(depths, ed, 0.01).se == Approx((r + 0.001) / kd).epsilon(1e-9));
}

TEST_CASE("z1% refuses profiles that do not bracket it") {
    const std::vector<double> depths = {0.0, 1.0, 2.0, 3.0};
    const std::vector<Estimate> slow = {{1.0, 0.0}, {0.5, 0.0}, {0.3, 0.0}, {0.2, 0.0}};  // never below 1 %
    CHECK_THROWS_AS(kk::depth_of_fraction(depths, slow, 0.01), input_error);
    const std::vector<Estimate> fast = {{1.0, 0.0}, {0.005, 0.0}, {0.001, 0.0}, {1e-4, 0.0}};  // below at 1 m already
    CHECK_THROWS_AS(kk::depth_of_fraction(depths, fast, 0.01), input_error);
    const std::vector<double> no_surface = {0.5, 1.0, 2.0, 3.0};
    CHECK_THROWS_AS(kk::depth_of_fraction(no_surface, slow, 0.5), input_error);
    CHECK_THROWS_AS(kk::depth_of_fraction(depths, slow, 0.0), input_error);
}

TEST_CASE("Slope through the origin and its SE; ratio SE bound") {
    const std::vector<double> x = {1.0, 2.0, 3.0};
    const std::vector<Estimate> y = {{2.1, 0.1}, {3.9, 0.2}, {6.0, 0.3}};
    const Estimate s = kk::slope_through_origin(x, y);
    CHECK(s.value == Approx((2.1 + 7.8 + 18.0) / 14.0));
    CHECK(s.se == Approx(std::sqrt(0.01 + 4 * 0.04 + 9 * 0.09) / 14.0));
    CHECK_THROWS_AS(kk::slope_through_origin(std::vector<double>{}, std::vector<Estimate>{}), input_error);
    const Estimate q = kk::ratio({2.0, 0.02}, {4.0, 0.08});
    CHECK(q.value == Approx(0.5));
    CHECK(q.se == Approx(0.5 * (0.01 + 0.02)));
    CHECK_THROWS_AS(kk::ratio({1.0, 0.0}, {0.0, 0.0}), input_error);
}
