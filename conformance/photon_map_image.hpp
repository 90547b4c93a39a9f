#pragma once
// The photon map projected on a vertical plane (like the manual's Fig. 7.18): stored
// photons binned by horizontal position x (across the periodic section) and depth z, as the
// scattered-flux density per unit volume (W m^-3 nm^-1), written as a one-channel ("Y")
// float OpenEXR image: row 0 at the surface, depth increasing downward.
#include "secchi/map/record.hpp"
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <string>
#include <vector>

namespace secchi::conformance {

struct DensityImage {
    int width = 0, height = 0;
    std::vector<float> pixels;  ///< row-major, row 0 at the surface
};

inline DensityImage project_photon_map(const std::vector<CompactRecord>& map, double section_width, double depth,
                                       double flux_per_photon, int width = 256, int height = 512) {
    DensityImage img{width, height, std::vector<float>(static_cast<std::size_t>(width) * height, 0.0f)};
    const double voxel = (section_width / width) * (depth / height) * section_width;  // y spans the section
    for (const auto& r : map) {
        const int i = static_cast<int>(r.x / section_width * width);
        const int j = static_cast<int>(r.z / depth * height);
        if (i >= 0 && i < width && j >= 0 && j < height)
            img.pixels[static_cast<std::size_t>(j) * width + i] += static_cast<float>(flux_per_photon / voxel);
    }
    return img;
}

inline void write_exr(const DensityImage& img, const std::string& path) {
    Imf::Header header(img.width, img.height);
    header.channels().insert("Y", Imf::Channel(Imf::FLOAT));
    Imf::OutputFile file(path.c_str(), header);
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(img.pixels.data())),
                              sizeof(float), sizeof(float) * img.width));
    file.setFrameBuffer(fb);
    file.writePixels(img.height);
}

inline DensityImage read_exr(const std::string& path) {
    Imf::InputFile file(path.c_str());
    const auto dw = file.header().dataWindow();
    DensityImage img{dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1, {}};
    img.pixels.resize(static_cast<std::size_t>(img.width) * img.height);
    Imf::FrameBuffer fb;
    fb.insert("Y", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(img.pixels.data()), sizeof(float),
                              sizeof(float) * img.width));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    return img;
}

}  // namespace secchi::conformance
