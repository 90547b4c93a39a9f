#pragma once
// Images of the whole radiance (estimate/radiance.hpp) through a pinhole camera
// (estimate/camera.hpp), in and above the water: per pixel the mean radiance of
// samples_per_pixel rays jittered over the pixel, with its SE. Channels, per band k of the map:
// "L" and "L.se" for one band, "L<k>" and "L<k>.se" for several; and R, G, B: for a map of one
// band equal to L, so that any EXR viewer shows it as grey; for several bands of stated, increasing
// wavelengths, linear sRGB of the spectrum (CIE 1931 colour matching over the bands,
// core/color.hpp; in the radiance's units, Y = int L y dl). The direct sun (a delta) is not
// in the image. Pixels are independent: rows run in parallel, each pixel's jitter from its own
// random stream, so the image is the same for any thread count.
#include "secchi/core/config.hpp"
#include "secchi/core/color.hpp"
#include "secchi/core/image.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/estimate/camera.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/core/parallel.hpp"
#include <cstdint>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

struct RenderSettings {
    unsigned samples_per_pixel = 1;  ///< 1: the pixel's centre; more: jittered over the pixel
    unsigned threads = 1;
    std::uint64_t seed = 1;
};

namespace detail {
/// The channel names of band k of a map of `bands` bands.
inline std::string radiance_channel(std::size_t k, std::size_t bands) {
    std::string name(1, 'L');  // appended, not "L" + string: g++ 12 -O3 warns falsely (-Wrestrict) on the latter
    if (bands > 1) name += std::to_string(k);
    return name;
}

/// Whether bands of these wavelengths make a colour: at least 2, finite and increasing.
inline bool colour_bands(const std::vector<double>& wavelengths_nm) {
    if (wavelengths_nm.size() < 2) return false;
    for (std::size_t k = 0; k < wavelengths_nm.size(); ++k)
        if (!std::isfinite(wavelengths_nm[k]) || (k > 0 && !(wavelengths_nm[k] > wavelengths_nm[k - 1]))) return false;
    return true;
}

/// The channels R, G, B of an image whose bands' radiances are "L<k>": linear sRGB of the
/// spectrum, RGB = sum_k L_k rgb_k (core/color.hpp).
inline void add_colour(Image& image, const std::vector<double>& wavelengths_nm) {
    const auto weights = linear_srgb_weights(wavelengths_nm);
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c) {
        std::vector<double> sum(image.channel(radiance_channel(0, weights.size())).size(), 0.0);
        for (std::size_t k = 0; k < weights.size(); ++k) {
            const std::vector<float>& band = image.channel(radiance_channel(k, weights.size()));
            for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += weights[k][c] * band[i];
        }
        std::vector<float>& out = image.add_channel(names[c]);
        for (std::size_t i = 0; i < sum.size(); ++i) out[i] = static_cast<float>(sum[i]);
    }
}

/// For each band: the channels "L" and "L.se" of an image, filled by f(pixel index, band) ->
/// Estimate in parallel over rows; then R, G, B (grey for one band, colour for several).
template <class PixelEstimate>
Image radiance_image(int width, int height, const std::vector<double>& wavelengths_nm, unsigned threads,
                     PixelEstimate&& f) {
    const std::size_t bands = wavelengths_nm.size();
    Image image(width, height);
    for (std::size_t k = 0; k < bands; ++k) {
        const std::string name = radiance_channel(k, bands);
        std::string se_name = name;
        se_name += ".se";
        image.add_channel(name);
        image.add_channel(se_name);
        std::vector<float>& value = image.channel(name);
        std::vector<float>& se = image.channel(se_name);
        parallel_for(static_cast<std::size_t>(height), threads, [&](std::size_t y) {
            for (std::size_t x = 0; x < static_cast<std::size_t>(width); ++x) {
                const std::size_t i = y * static_cast<std::size_t>(width) + x;
                const Estimate e = f(i, static_cast<unsigned>(k));
                value[i] = static_cast<float>(e.value);
                se[i] = static_cast<float>(e.se);
            }
        });
    }
    if (bands == 1)
        for (const char* c : {"R", "G", "B"}) image.add_channel(c) = image.channel("L");
    else if (colour_bands(wavelengths_nm))
        add_colour(image, wavelengths_nm);
    return image;
}
}  // namespace detail

/// The camera's image of the radiance the estimator sees (any RadianceEstimator).
template <class Estimator>
Image render(const Estimator& est, const PinholeCamera& camera, const RenderSettings& settings = {}) {
    require(settings.samples_per_pixel >= 1, "samples per pixel", settings.samples_per_pixel, "must be >= 1");
    const auto& map = est.map();
    return detail::radiance_image(camera.width(), camera.height(), map.wavelengths_nm(), settings.threads,
                                  [&](std::size_t i, unsigned band) {
                                      const int x = static_cast<int>(i % camera.width()), y = static_cast<int>(i / camera.width());
                                      RadianceSum sum(map.batches());
                                      if (settings.samples_per_pixel == 1) {
                                          est.add(camera.ray(x, y), band, 1.0, sum);
                                          return sum.estimate();
                                      }
                                      PhotonRng rng(settings.seed, i);
                                      for (unsigned s = 0; s < settings.samples_per_pixel; ++s) {
                                          const double u = rng.uniform(), v = rng.uniform();
                                          est.add(camera.ray(x, y, u, v), band, 1.0, sum);
                                      }
                                      return sum.estimate(settings.samples_per_pixel);
                                  });
}

}  // namespace secchi
