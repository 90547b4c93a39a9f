#pragma once
// Colour from bands: the CIE 1931 2-degree colour-matching functions and linear sRGB, for the
// RGB channels of a spectral image (estimate/render.hpp).
//
// Colour matching: the multi-lobe piecewise-Gaussian fit of Wyman, Sloan and Shirley, "Simple
// Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2), 2013, eq. 2-4:
//   x(l) = 1.056 g(l; 599.8, 37.9, 31.0) + 0.362 g(l; 442.0, 16.0, 26.7) - 0.065 g(l; 501.1, 20.4, 26.2)
//   y(l) = 0.821 g(l; 568.8, 46.9, 40.5) + 0.286 g(l; 530.9, 16.3, 31.1)
//   z(l) = 1.217 g(l; 437.0, 11.8, 36.0) + 0.681 g(l; 459.0, 26.0, 13.8)
// with g(l; mu, s1, s2) = exp(-(l - mu)^2 / (2 s^2)), s = s1 below mu and s2 above (l in nm);
// within a few per cent of the tabulated CIE functions where they matter.
//
// Tristimulus values of a spectral radiance L(l) (per nm) sampled at band wavelengths l_k:
// X = int L x dl (and Y, Z alike) by the trapezoid rule over the bands, in the radiance's own
// units (W m^-2 sr^-1: Y is the y-weighted radiance, not lumens). Linear sRGB (D65 white) from
// XYZ by the matrix of IEC 61966-2-1. An equal-energy spectrum gives X = Y = Z (x = y = 1/3)
// to the fit's accuracy.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <array>
#include <cmath>
#include <span>
#include <vector>

namespace secchi::SECCHI_ISA {

namespace detail {
/// The fit's lobe g(l; mu, s1, s2).
inline double cie_lobe(double wavelength_nm, double mu, double sigma_below, double sigma_above) {
    const double t = (wavelength_nm - mu) / (wavelength_nm < mu ? sigma_below : sigma_above);
    return std::exp(-0.5 * t * t);
}
}  // namespace detail

/// The CIE 1931 2-degree colour-matching functions (x, y, z) at a wavelength in nm (see above).
inline std::array<double, 3> cie1931_xyz(double wavelength_nm) {
    using detail::cie_lobe;
    const double l = wavelength_nm;
    return {1.056 * cie_lobe(l, 599.8, 37.9, 31.0) + 0.362 * cie_lobe(l, 442.0, 16.0, 26.7) -
                0.065 * cie_lobe(l, 501.1, 20.4, 26.2),
            0.821 * cie_lobe(l, 568.8, 46.9, 40.5) + 0.286 * cie_lobe(l, 530.9, 16.3, 31.1),
            1.217 * cie_lobe(l, 437.0, 11.8, 36.0) + 0.681 * cie_lobe(l, 459.0, 26.0, 13.8)};
}

/// Linear sRGB (D65) of tristimulus values XYZ (IEC 61966-2-1); negative outside the gamut.
inline std::array<double, 3> linear_srgb_of_xyz(const std::array<double, 3>& xyz) {
    const auto [x, y, z] = xyz;
    return {3.2406 * x - 1.5372 * y - 0.4986 * z, -0.9689 * x + 1.8758 * y + 0.0415 * z,
            0.0557 * x - 0.2040 * y + 1.0570 * z};
}

/// The weights w_k of the trapezoid rule over band wavelengths l_k (nm, strictly increasing,
/// at least 2): int f dl ~ sum_k w_k f(l_k).
inline std::vector<double> trapezoid_weights(std::span<const double> wavelengths_nm) {
    require(wavelengths_nm.size() >= 2, "band wavelengths", wavelengths_nm.size(), "needs at least 2 bands for colour");
    std::vector<double> w(wavelengths_nm.size(), 0.0);
    for (std::size_t k = 0; k + 1 < wavelengths_nm.size(); ++k) {
        const double h = wavelengths_nm[k + 1] - wavelengths_nm[k];
        require(std::isfinite(h) && h > 0.0, "band wavelength (nm)", wavelengths_nm[k + 1],
                "must be finite and above the previous band's for colour");
        w[k] += 0.5 * h;
        w[k + 1] += 0.5 * h;
    }
    return w;
}

/// For each band k, what its spectral radiance contributes to linear sRGB: the row
/// w_k M (x, y, z)(l_k), so that RGB = sum_k L_k rgb_weights[k].
inline std::vector<std::array<double, 3>> linear_srgb_weights(std::span<const double> wavelengths_nm) {
    const std::vector<double> w = trapezoid_weights(wavelengths_nm);
    std::vector<std::array<double, 3>> out(w.size());
    for (std::size_t k = 0; k < w.size(); ++k) {
        auto xyz = cie1931_xyz(wavelengths_nm[k]);
        for (double& c : xyz) c *= w[k];
        out[k] = linear_srgb_of_xyz(xyz);
    }
    return out;
}

}  // namespace secchi::SECCHI_ISA
