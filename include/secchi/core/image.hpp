#pragma once
// A float raster of named channels (radiance per band, its SE, R G B): what the second pass's
// images are made of (estimate/render.hpp, estimate/radiance_distribution.hpp) and what
// io/exr.hpp writes. Row 0 is the image's top; pixel (x, y) of channel c is at
// channels[c].pixels[y * width + x].
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <cstddef>
#include <deque>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

struct ImageChannel {
    std::string name;
    std::vector<float> pixels;
};

class Image {
public:
    Image(int width, int height) : width_(width), height_(height) {
        require(width > 0 && height > 0 && width <= 1 << 15 && height <= 1 << 15, "image size",
                static_cast<double>(width) * height, "must be 1 to 32768 pixels each way");
    }
    [[nodiscard]] int width() const { return width_; }
    [[nodiscard]] int height() const { return height_; }
    [[nodiscard]] std::size_t pixels() const { return static_cast<std::size_t>(width_) * height_; }

    /// Adds a channel of zeros (names unique) and returns its pixels (the reference stays valid
    /// while the image lives: channels are never moved).
    std::vector<float>& add_channel(const std::string& name) {
        for (const auto& c : channels_) require(c.name != name, "image channel", name, "exists already");
        channels_.push_back({name, std::vector<float>(pixels(), 0.0f)});
        return channels_.back().pixels;
    }
    [[nodiscard]] const std::deque<ImageChannel>& channels() const { return channels_; }
    [[nodiscard]] const std::vector<float>& channel(const std::string& name) const {
        for (const auto& c : channels_)
            if (c.name == name) return c.pixels;
        reject("image channel", name, "is not in the image");
    }
    [[nodiscard]] std::vector<float>& channel(const std::string& name) {
        return const_cast<std::vector<float>&>(static_cast<const Image&>(*this).channel(name));
    }

private:
    int width_, height_;
    std::deque<ImageChannel> channels_;
};

}  // namespace secchi
