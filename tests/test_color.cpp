// Colour from bands (core/color.hpp) and the RGB channels of spectral images
// (estimate/render.hpp): the CIE fit's known integrals and chromaticities, the hue of
// monochromatic light, and the image's R, G, B as the bands' weighted sums.
#include <catch2/catch.hpp>
#include "secchi/core/color.hpp"
#include "secchi/estimate/render.hpp"
#include <algorithm>
#include <cmath>
#include <vector>

using namespace secchi;

TEST_CASE("the CIE 1931 fit: peak of y, its integral, and the white point of an equal-energy spectrum") {
    double sx = 0, sy = 0, sz = 0, y_peak = 0, l_peak = 0;
    for (double l = 360.0; l <= 830.0; l += 1.0) {
        const auto xyz = cie1931_xyz(l);
        sx += xyz[0], sy += xyz[1], sz += xyz[2];
        if (xyz[1] > y_peak) y_peak = xyz[1], l_peak = l;
    }
    CHECK(y_peak == Approx(1.0).margin(0.01));   // CIE: y(555) = 1.000
    CHECK(std::abs(l_peak - 556.0) <= 3.0);
    CHECK(sy == Approx(106.857).epsilon(0.02));    // CIE 1931 table: sum of y at 1 nm, 360-830 nm
    const double total = sx + sy + sz;              // illuminant E: x = y = 1/3
    CHECK(sx / total == Approx(1.0 / 3.0).margin(0.01));
    CHECK(sy / total == Approx(1.0 / 3.0).margin(0.01));
}

TEST_CASE("monochromatic light has the hue of its wavelength in linear sRGB") {
    const auto largest = [](double l) {
        const auto rgb = linear_srgb_of_xyz(cie1931_xyz(l));
        return static_cast<int>(std::max_element(rgb.begin(), rgb.end()) - rgb.begin());
    };
    CHECK(largest(450.0) == 2);
    CHECK(largest(530.0) == 1);
    CHECK(largest(630.0) == 0);
}

TEST_CASE("band weights integrate by the trapezoid rule and refuse bands that make no spectrum") {
    const std::vector<double> l{400.0, 450.0, 550.0};
    CHECK(trapezoid_weights(l) == std::vector<double>{25.0, 75.0, 50.0});
    CHECK_THROWS_AS(trapezoid_weights(std::vector<double>{500.0}), input_error);
    CHECK_THROWS_AS(trapezoid_weights(std::vector<double>{500.0, 500.0}), input_error);
    CHECK_THROWS_AS(trapezoid_weights(std::vector<double>{500.0, NAN}), input_error);
}

TEST_CASE("a spectral image's R, G, B are the bands' colour-weighted sums; no colour without wavelengths") {
    const std::vector<double> l{420.0, 480.0, 540.0, 600.0, 660.0};
    // Blue water's radiance: falling with wavelength; pixel i scales it by (1 + i).
    const auto f = [&](std::size_t i, unsigned band) {
        return Estimate{(1.0 + static_cast<double>(i)) * std::exp(-0.01 * (l[band] - 420.0)), 0.0};
    };
    const Image image = detail::radiance_image(3, 2, l, 1, f);
    const auto weights = linear_srgb_weights(l);
    for (std::size_t i = 0; i < 6; ++i) {
        std::array<double, 3> rgb{0, 0, 0};
        for (unsigned k = 0; k < l.size(); ++k)
            for (int c = 0; c < 3; ++c) rgb[c] += weights[k][c] * f(i, k).value;
        CHECK(image.channel("R")[i] == Approx(rgb[0]).epsilon(1e-6));
        CHECK(image.channel("G")[i] == Approx(rgb[1]).epsilon(1e-6));
        CHECK(image.channel("B")[i] == Approx(rgb[2]).epsilon(1e-6));
        CHECK(image.channel("B")[i] > image.channel("R")[i]);  // blue water looks blue
    }
    const Image unstated = detail::radiance_image(3, 2, std::vector<double>{NAN, NAN}, 1, f);
    CHECK_THROWS_AS(unstated.channel("R"), input_error);
    const Image grey = detail::radiance_image(3, 2, std::vector<double>{NAN}, 1, f);
    CHECK(grey.channel("R") == grey.channel("L"));
}
