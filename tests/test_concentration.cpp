// Concentration models of manual 5.10: defaults of the manual's tables, eq. 5.30 and the
// linear profile at a few depths, validation, SIGMA noise, and the type-erased wrapper.
#include <catch2/catch.hpp>
#include "secchi/core/error.hpp"
#include "secchi/optics/iop/concentration.hpp"
#include <cmath>
#include <string_view>
#include <vector>

using namespace secchi;
using namespace secchi::iop;

namespace {
vec3 at_depth(double z) { return vec3(0.3, -1.2, z); }
}  // namespace

TEST_CASE("concentration defaults are the manual's tables (5.10.1-5.10.3)") {
    CHECK(std::string_view(ConstantConcentration::type_name) == "constant");
    CHECK(std::string_view(LinearConcentration::type_name) == "linear");
    CHECK(std::string_view(GaussianConcentration::type_name) == "gaussian");
    CHECK(std::string_view(NoConcentration::type_name) == "none");

    const ConstantConcentration c;
    CHECK(c.params().conc == 2.0);
    CHECK(c.noise().sigma() == 0.0);

    const LinearConcentration l;
    CHECK(l.params().atzero == 2.0);
    CHECK(l.params().zlevel == 0.0);
    CHECK(l.params().rate == -0.1);
    CHECK(l.noise().sigma() == 0.0);

    const GaussianConcentration g;
    CHECK(g.params().zlevel == 0.0);
    CHECK(g.params().dmax == 17.0);
    CHECK(g.params().bg == 0.2);
    CHECK(g.params().h == 144.0);
    CHECK(g.params().s == 9.0);
    CHECK(g.noise().sigma() == 0.0);
}

TEST_CASE("constant concentration is CONC everywhere") {
    const ConstantConcentration c({.conc = 0.5});
    for (double z : {0.0, 3.0, 100.0}) CHECK(c.concentration(at_depth(z)) == 0.5);
    CHECK(ConstantConcentration().concentration(at_depth(7.0)) == 2.0);
    CHECK(NoConcentration().concentration(at_depth(7.0)) == 1.0);
}

TEST_CASE("linear concentration: ATZERO + RATE (z - ZLEVEL), clamped at zero") {
    SECTION("defaults: 2 - 0.1 z, zero from 20 m down") {
        const LinearConcentration l;
        CHECK(l.concentration(at_depth(0.0)) == Approx(2.0).epsilon(1e-14));
        CHECK(l.concentration(at_depth(5.0)) == Approx(1.5).epsilon(1e-14));
        CHECK(l.concentration(at_depth(15.0)) == Approx(0.5).epsilon(1e-14));
        CHECK(l.concentration(at_depth(20.0)) == Approx(0.0).margin(1e-14));
        CHECK(l.concentration(at_depth(25.0)) == 0.0);   // would be -0.5: clamped
        CHECK(l.concentration(at_depth(1000.0)) == 0.0);
    }
    SECTION("shifted z-level and increasing rate") {
        const LinearConcentration l({.atzero = 1.0, .zlevel = 4.0, .rate = 0.25});
        for (double z : {4.0, 6.0, 10.0, 30.0}) CHECK(l.concentration(at_depth(z)) == Approx(1.0 + 0.25 * (z - 4.0)));
        CHECK(l.concentration(at_depth(2.0)) == Approx(0.5));  // above the z-level: extrapolated
        CHECK(l.concentration(at_depth(-10.0)) == 0.0);         // 1 + 0.25 (-14) < 0: clamped
    }
}

TEST_CASE("gaussian concentration follows eq. 5.30") {
    const auto eq530 = [](double z, double zlevel, double c0, double h, double s, double zmax) {
        const double d = z - zlevel;
        return c0 + h / (s * std::sqrt(2.0 * 3.14159265358979323846)) * std::exp(-(d - zmax) * (d - zmax) / (2.0 * s * s));
    };
    SECTION("canonical problem 3's Celtic Sea profile (the defaults)") {
        const GaussianConcentration g;  // C0 0.2, s 9, zmax 17, h 144
        CHECK(g.concentration(at_depth(17.0)) == Approx(6.583).epsilon(1e-4));
        CHECK(g.concentration(at_depth(17.0)) == Approx(0.2 + 144.0 / (9.0 * std::sqrt(2.0 * 3.14159265358979323846))));
        for (double z : {0.0, 5.0, 8.0, 26.0, 40.0, 60.0})
            CHECK(g.concentration(at_depth(z)) == Approx(eq530(z, 0.0, 0.2, 144.0, 9.0, 17.0)).epsilon(1e-13));
        // one standard deviation from the peak: background + peak * exp(-1/2)
        CHECK(g.concentration(at_depth(26.0)) - 0.2 == Approx((6.583 - 0.2) * std::exp(-0.5)).epsilon(1e-3));
        CHECK(g.concentration(at_depth(1000.0)) == Approx(0.2));  // the background far below
    }
    SECTION("other parameters, shifted z-level") {
        const GaussianConcentration g({.zlevel = -2.0, .dmax = 10.0, .bg = 1.0, .h = 20.0, .s = 3.0});
        for (double z : {-2.0, 0.0, 8.0, 11.0, 20.0})
            CHECK(g.concentration(at_depth(z)) == Approx(eq530(z, -2.0, 1.0, 20.0, 3.0, 10.0)).epsilon(1e-13));
        CHECK(g.concentration(at_depth(8.0)) > g.concentration(at_depth(7.0)));
        CHECK(g.concentration(at_depth(8.0)) > g.concentration(at_depth(9.0)));
    }
}

TEST_CASE("invalid concentration parameters are input errors naming the parameter") {
    CHECK_THROWS_AS(ConstantConcentration({.conc = -1.0}), input_error);
    CHECK_THROWS_WITH(ConstantConcentration({.conc = -1.0}), Catch::Contains("CONC"));
    CHECK_THROWS_AS(ConstantConcentration({.conc = std::nan("")}), input_error);
    CHECK_THROWS_WITH(LinearConcentration({.atzero = -0.5}), Catch::Contains("ATZERO"));
    CHECK_THROWS_WITH(LinearConcentration({.zlevel = INFINITY}), Catch::Contains("ZLEVEL"));
    CHECK_THROWS_WITH(LinearConcentration({.rate = std::nan("")}), Catch::Contains("RATE"));
    CHECK_THROWS_WITH(GaussianConcentration({.s = 0.0}), Catch::Contains("S = 0"));
    CHECK_THROWS_WITH(GaussianConcentration({.s = -9.0}), Catch::Contains("S = -9"));
    CHECK_THROWS_WITH(GaussianConcentration({.h = -1.0}), Catch::Contains("H = -1"));
    CHECK_THROWS_WITH(GaussianConcentration({.bg = -0.2}), Catch::Contains("BG"));
    CHECK_THROWS_WITH(GaussianConcentration({.dmax = std::nan("")}), Catch::Contains("DMAX"));
    CHECK_THROWS_WITH(GaussianConcentration({}, Noise(-0.1)), Catch::Contains("SIGMA"));
    CHECK_NOTHROW(LinearConcentration({.atzero = 0.0, .rate = 0.0}));
    CHECK_NOTHROW(GaussianConcentration({.bg = 0.0, .h = 0.0, .s = 1e-3}));
}

TEST_CASE("concentration noise is reproducible, varies with position, never negative") {
    // background 5 with sigma 0.5: clamping at zero is a 10-sigma event, deviations are N(0, 0.5)
    const GaussianConcentration::Params p{.bg = 5.0};
    const GaussianConcentration quiet(p);
    const GaussianConcentration noisy(p, Noise(0.5, /*seed=*/7, /*key=*/3));
    const GaussianConcentration other_seed(p, Noise(0.5, /*seed=*/8, /*key=*/3));
    std::vector<double> values;
    double sum_dev = 0.0, sum_dev2 = 0.0;
    const int n = 2000;
    for (int i = 0; i < n; ++i) {
        const vec3 x(0.01 * i, 0.0, 0.02 * i);
        const double v = noisy.concentration(x);
        CHECK(v == noisy.concentration(x));            // same point, same value
        CHECK(v == GaussianConcentration(p, Noise(0.5, 7, 3)).concentration(x));  // same seed and key
        values.push_back(v);
        const double dev = v - quiet.concentration(x);
        sum_dev += dev;
        sum_dev2 += dev * dev;
    }
    for (int i = 1; i < n; ++i) REQUIRE(values[i] != values[i - 1]);  // different points differ
    CHECK(noisy.concentration(vec3(1, 2, 3)) != other_seed.concentration(vec3(1, 2, 3)));
    CHECK(std::abs(sum_dev / n) < 5 * 0.5 / std::sqrt(double(n)));
    CHECK(std::sqrt(sum_dev2 / n) == Approx(0.5).epsilon(0.1));

    // sigma much larger than the value: clamped at zero, never negative
    const ConstantConcentration tiny({.conc = 0.01}, Noise(1.0, 11));
    int zeros = 0;
    for (int i = 0; i < 1000; ++i) {
        const double v = tiny.concentration(vec3(0, 0, 0.1 * i));
        REQUIRE(v >= 0.0);
        zeros += v == 0.0;
    }
    CHECK(zeros > 400);
    CHECK(zeros < 600);
}

TEST_CASE("AnyConcentration equals the wrapped models") {
    const ConstantConcentration c({.conc = 0.7}, Noise(0.1, 3));
    const LinearConcentration l({.atzero = 1.0, .rate = 0.3});
    const GaussianConcentration g({}, Noise(0.4, 5, 2));
    const std::vector<AnyConcentration> any{c, l, g, NoConcentration{}};
    CHECK(any[0].type() == "constant");
    CHECK(any[1].type() == "linear");
    CHECK(any[2].type() == "gaussian");
    CHECK(any[3].type() == "none");
    for (double z : {0.0, 1.5, 17.0, 33.0}) {
        const vec3 x = at_depth(z);
        CHECK(any[0].concentration(x) == c.concentration(x));
        CHECK(any[1].concentration(x) == l.concentration(x));
        CHECK(any[2].concentration(x) == g.concentration(x));
        CHECK(any[3].concentration(x) == 1.0);
        const AnyConcentration copy = any[2];  // copies share the model
        CHECK(copy.concentration(x) == g.concentration(x));
    }
}
