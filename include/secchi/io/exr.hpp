#pragma once
// OpenEXR files of an Image (core/image.hpp): one 32-bit float channel per image channel,
// ZIP-compressed, row 0 at the top (OpenEXR's increasing-y line order). Needs OpenEXR 3
// (link secchi::exr in CMake). A file that cannot be written or read raises input_error
// naming it.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/image.hpp"
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <exception>
#include <string>

namespace secchi::SECCHI_ISA {

inline void write_exr(const Image& image, const std::string& path) {
    try {
        Imf::Header header(image.width(), image.height());
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::FrameBuffer frame;
        for (const auto& c : image.channels()) {
            header.channels().insert(c.name, Imf::Channel(Imf::FLOAT));
            frame.insert(c.name, Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(const_cast<float*>(c.pixels.data())),
                                            sizeof(float), sizeof(float) * image.width()));
        }
        Imf::OutputFile file(path.c_str(), header);
        file.setFrameBuffer(frame);
        file.writePixels(image.height());
    } catch (const std::exception& e) {
        reject("OpenEXR file", path, std::string("cannot be written: ") + e.what());
    }
}

/// Every channel of an OpenEXR file, as floats.
inline Image read_exr(const std::string& path) {
    try {
        Imf::InputFile file(path.c_str());
        const auto window = file.header().dataWindow();
        Image image(window.max.x - window.min.x + 1, window.max.y - window.min.y + 1);
        Imf::FrameBuffer frame;
        for (auto it = file.header().channels().begin(); it != file.header().channels().end(); ++it) {
            std::vector<float>& pixels = image.add_channel(it.name());
            // The slice's base is where pixel (0, 0) would be: the data window may not start there.
            char* base = reinterpret_cast<char*>(pixels.data()) -
                         (static_cast<std::ptrdiff_t>(window.min.y) * image.width() + window.min.x) *
                             static_cast<std::ptrdiff_t>(sizeof(float));
            frame.insert(it.name(), Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * image.width()));
        }
        file.setFrameBuffer(frame);
        file.readPixels(window.min.y, window.max.y);
        return image;
    } catch (const input_error&) {
        throw;
    } catch (const std::exception& e) {
        reject("OpenEXR file", path, std::string("cannot be read: ") + e.what());
    }
}

}  // namespace secchi
