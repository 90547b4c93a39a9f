#pragma once
// An 8-bit PNG preview of an Image channel (core/image.hpp), for documentation: the channel
// scaled so that its `percentile` value maps to white (or by a fixed `white` radiance),
// clipped, then sRGB-encoded (IEC 61966-2-1 transfer curve), written as a greyscale PNG
// (ISO/IEC 15948: signature, IHDR, one zlib-compressed IDAT of filter-0 rows, IEND; CRC-32
// and deflate from zlib). The numbers live in the OpenEXR file; this is a picture of them.
// Needs zlib (a dependency of OpenEXR; link secchi::exr).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/image.hpp"
#include <zlib.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

struct PreviewScale {
    double percentile = 0.995;  ///< this quantile of the channel maps to white ...
    double white = 0.0;         ///< ... unless this is > 0: the value that maps to white
};

namespace detail {
inline void put_u32(std::vector<unsigned char>& out, std::uint32_t v) {
    for (int s = 24; s >= 0; s -= 8) out.push_back(static_cast<unsigned char>(v >> s));
}
inline void png_chunk(std::ofstream& file, const char* type, const std::vector<unsigned char>& data) {
    std::vector<unsigned char> head;
    put_u32(head, static_cast<std::uint32_t>(data.size()));
    head.insert(head.end(), type, type + 4);
    uLong crc = crc32(0L, reinterpret_cast<const Bytef*>(type), 4);
    if (!data.empty()) crc = crc32(crc, data.data(), static_cast<uInt>(data.size()));
    std::vector<unsigned char> tail;
    put_u32(tail, static_cast<std::uint32_t>(crc));
    file.write(reinterpret_cast<const char*>(head.data()), static_cast<std::streamsize>(head.size()));
    file.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size()));
    file.write(reinterpret_cast<const char*>(tail.data()), static_cast<std::streamsize>(tail.size()));
}
/// The sRGB encoding of a linear value in [0, 1].
inline double srgb(double x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055; }
}  // namespace detail

/// Writes channel `name` of `image` as a greyscale PNG; returns the value mapped to white.
inline double write_png_preview(const Image& image, const std::string& name, const std::string& path,
                                const PreviewScale& scale = {}) {
    const std::vector<float>& pixels = image.channel(name);
    double white = scale.white;
    if (white <= 0.0) {
        require(scale.percentile > 0.0 && scale.percentile <= 1.0, "preview percentile", scale.percentile, "must lie in (0, 1]");
        std::vector<float> sorted(pixels);
        const auto at = static_cast<std::size_t>(scale.percentile * static_cast<double>(sorted.size() - 1));
        std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(at), sorted.end());
        white = sorted[at] > 0.0f ? sorted[at] : 1.0;
    }
    std::vector<unsigned char> raw;
    raw.reserve(pixels.size() + static_cast<std::size_t>(image.height()));
    for (int y = 0; y < image.height(); ++y) {
        raw.push_back(0);  // filter type 0: none
        for (int x = 0; x < image.width(); ++x) {
            const double v = std::clamp(pixels[static_cast<std::size_t>(y) * image.width() + x] / white, 0.0, 1.0);
            raw.push_back(static_cast<unsigned char>(std::lround(255.0 * detail::srgb(v))));
        }
    }
    uLongf packed_size = compressBound(static_cast<uLong>(raw.size()));
    std::vector<unsigned char> packed(packed_size);
    if (compress2(packed.data(), &packed_size, raw.data(), static_cast<uLong>(raw.size()), 9) != Z_OK)
        reject("PNG preview", path, "could not be compressed");
    packed.resize(packed_size);

    std::ofstream file(path, std::ios::binary);
    if (!file) reject("PNG preview", path, "cannot be opened for writing");
    const unsigned char signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    file.write(reinterpret_cast<const char*>(signature), 8);
    std::vector<unsigned char> header;
    detail::put_u32(header, static_cast<std::uint32_t>(image.width()));
    detail::put_u32(header, static_cast<std::uint32_t>(image.height()));
    header.insert(header.end(), {8, 0, 0, 0, 0});  // 8 bits, greyscale, deflate, filter 0, no interlace
    detail::png_chunk(file, "IHDR", header);
    detail::png_chunk(file, "IDAT", packed);
    detail::png_chunk(file, "IEND", {});
    if (!file) reject("PNG preview", path, "could not be written");
    return white;
}

}  // namespace secchi
