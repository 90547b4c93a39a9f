#include <catch2/catch.hpp>
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/core/units.hpp"
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace secchi;

TEST_CASE("Philox streams are reproducible and independent") {
    PhotonRng a(42, 7), b(42, 7), c(42, 8), d(43, 7);
    for (int i = 0; i < 10; ++i) {
        const double x = a.uniform();
        REQUIRE(x == b.uniform());
        REQUIRE(x > 0.0);
        REQUIRE(x < 1.0);
        REQUIRE(x != c.uniform());
        REQUIRE(x != d.uniform());
    }
}

TEST_CASE("A generator given its block's bits, computed elsewhere, draws what the stream draws") {
    PhotonRng stream(42, 7, 3);
    const std::array<std::uint32_t, 4> bits = philox_block(3, 7, {42, 0});
    PhotonRng given(42, 7, 3, bits);
    for (int i = 0; i < 10; ++i) REQUIRE(given.bits() == stream.bits());
    REQUIRE(given.next_block() == stream.next_block());
}

TEST_CASE("Philox4x32-10 known answer (Random123 kat_vectors: counter 0, key 0)") {
    PhotonRng rng(0, 0);
    REQUIRE(rng.bits() == 0x6627e8d5u);
    REQUIRE(rng.bits() == 0xe169c58du);
    REQUIRE(rng.bits() == 0xbc57ac4cu);
    REQUIRE(rng.bits() == 0x9b00dbd8u);
}

TEST_CASE("Philox uniforms have mean 1/2 and variance 1/12") {
    // 1e6 draws: the mean's standard error is sqrt(1/12/1e6) = 2.9e-4; 5 SE bound.
    PhotonRng rng(1, 0);
    double s = 0, s2 = 0;
    const int n = 1000000;
    for (int i = 0; i < n; ++i) {
        const double u = rng.uniform();
        s += u;
        s2 += u * u;
    }
    const double mean = s / n, var = s2 / n - mean * mean;
    REQUIRE(std::abs(mean - 0.5) < 5 * std::sqrt(1.0 / 12.0 / n));
    REQUIRE(std::abs(var - 1.0 / 12.0) < 1e-3);
}

TEST_CASE("rotate_direction keeps the scattering angle") {
    PhotonRng rng(3, 3);
    for (int i = 0; i < 1000; ++i) {
        const double mu = 2 * rng.uniform() - 1, ph = two_pi * rng.uniform();
        const vec3 d = glm::normalize(vec3(rng.uniform() - 0.5, rng.uniform() - 0.5, rng.uniform() - 0.5));
        const double cpsi = 2 * rng.uniform() - 1;
        const vec3 out = rotate_direction(d, cpsi, two_pi * rng.uniform());
        REQUIRE(glm::length(out) == Approx(1.0).margin(1e-12));
        REQUIRE(glm::dot(out, d) == Approx(cpsi).margin(1e-9));
        (void)mu;
        (void)ph;
    }
    // the poles
    REQUIRE(glm::dot(rotate_direction(vec3(0, 0, 1), 0.3, 1.0), vec3(0, 0, 1)) == Approx(0.3));
    REQUIRE(glm::dot(rotate_direction(vec3(0, 0, -1), 0.3, 1.0), vec3(0, 0, -1)) == Approx(0.3));
}

TEST_CASE("rotate_direction stays unit over a photon's whole history") {
    // Each call leaves |out| - 1 of the order of the rounding and corrects the previous error
    // to second order, so the length error does not accumulate along a chain of events.
    PhotonRng rng(5, 1);
    vec3 d(0.0, 0.0, 1.0);
    double worst = 0.0;
    for (int i = 0; i < 1'000'000; ++i) {
        d = rotate_direction(d, 2 * rng.uniform() - 1, two_pi * rng.uniform());
        worst = std::max(worst, std::abs(glm::length(d) - 1.0));
    }
    REQUIRE(worst < 1e-15);
}

TEST_CASE("sin_cos is within 2 ulp of the correctly rounded sine and cosine") {
    // Reference: long double (64-bit mantissa) sinl and cosl, 11 bits beyond double.
    auto ulps = [](double value, long double exact) {
        const double e = static_cast<double>(exact);
        const double ulp = std::nextafter(std::abs(e), INFINITY) - std::abs(e);
        return static_cast<double>(std::abs(static_cast<long double>(value) - exact) / ulp);
    };
    PhotonRng rng(9, 2);
    double worst_sin = 0.0, worst_cos = 0.0;
    for (int i = 0; i < 400'000; ++i) {
        // The azimuth range the library uses, then beyond it in both directions.
        const double x = i < 200'000 ? two_pi * rng.uniform() : 40.0 * (rng.uniform() - 0.5);
        const SinCos sc = sin_cos(x);
        worst_sin = std::max(worst_sin, ulps(sc.sin, std::sin(static_cast<long double>(x))));
        worst_cos = std::max(worst_cos, ulps(sc.cos, std::cos(static_cast<long double>(x))));
    }
    REQUIRE(worst_sin < 2.0);
    REQUIRE(worst_cos < 2.0);
    // Quadrant boundaries and the exact values there.
    for (int k = -8; k <= 8; ++k) {
        const double x = k * (pi / 2);
        REQUIRE(std::abs(sin_cos(x).sin - std::sin(x)) < 1e-15);
        REQUIRE(std::abs(sin_cos(x).cos - std::cos(x)) < 1e-15);
    }
    REQUIRE(sin_cos(0.0).sin == 0.0);
    REQUIRE(sin_cos(0.0).cos == 1.0);
}

TEST_CASE("exp_table is within 2 ulp of the correctly rounded exponential") {
    PhotonRng rng(11, 4);
    double worst = 0.0;
    for (int i = 0; i < 400'000; ++i) {
        // Transmittances (x in [-50, 0], and small |x|), then the whole finite range.
        const double x = i < 200'000 ? -50.0 * rng.uniform() * (i % 2 ? 1.0 : 1e-6) : 1416.0 * rng.uniform() - 707.0;
        const long double exact = std::exp(static_cast<long double>(x));
        const double e = static_cast<double>(exact);
        const double ulp = std::nextafter(e, INFINITY) - e;
        worst = std::max(worst, static_cast<double>(std::abs(static_cast<long double>(exp_table(x)) - exact) / ulp));
    }
    REQUIRE(worst < 2.0);
    REQUIRE(exp_table(0.0) == 1.0);
    REQUIRE(exp_table(-800.0) == 0.0);
    REQUIRE(exp_table(800.0) == INFINITY);
    REQUIRE(std::isnan(exp_table(NAN)));
}

TEST_CASE("times_power_of_two(x, k) is ldexp(x, k) bit for bit") {
    for (int k = -1100; k <= 1100; ++k) REQUIRE(times_power_of_two(1.0, k) == std::ldexp(1.0, k));
    PhotonRng rng(11, 5);
    for (int i = 0; i < 100'000; ++i) {
        // Weights over many decades (down to subnormal products) and the levels' range and beyond.
        const double x = rng.uniform() * std::ldexp(1.0, static_cast<int>(-1000 * rng.uniform()));
        const int k = static_cast<int>(2200 * rng.uniform()) - 1100;
        const double a = times_power_of_two(x, k), b = std::ldexp(x, k);
        REQUIRE(std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b));
    }
}

TEST_CASE("batch estimate") {
    std::vector<double> v{1, 2, 3, 4};
    const auto e = batch_estimate(v);
    REQUIRE(e.value == Approx(2.5));
    REQUIRE(e.se == Approx(std::sqrt((2.25 + 0.25 + 0.25 + 2.25) / 3.0 / 4.0)));
}

TEST_CASE("Radius rejects non-positive values with a message naming it") {
    REQUIRE_THROWS_AS(Radius(-1.0), input_error);
    REQUIRE_THROWS_WITH(Radius(0.0), Catch::Contains("radius") && Catch::Contains("0"));
    REQUIRE(Radius(2.0).squared() == 4.0);
}
