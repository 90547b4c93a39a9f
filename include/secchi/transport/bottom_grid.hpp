#pragma once
// The plane irradiance Ed arriving on the bottom, resolved horizontally: n x n square bins
// over the section [0, W) x [0, W) of the slab (scene/slab.hpp), bin (ix, iy) covering
// [ix W / n, (ix + 1) W / n) x [iy W / n, (iy + 1) W / n). A photon arriving on the bottom
// adds its weight to the bin of its (wrapped) position; the bin's Ed is that flux over the
// bin's area, W^2 / n^2: per batch, Ed_bin = E0 n^2 sum(w) / N for N photons of the source's
// plane irradiance E0 (each carries E0 W^2 / N), a surface-crossing estimate as the planes'
// (transport/irradiance_planes.hpp), with its standard error over the batches. The bins sum to
// the section's bottom Ed: mean over bins = TransportResult::bottom_ed.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <algorithm>
#include <cstddef>

namespace secchi::SECCHI_ISA {

class BottomGrid {
public:
    /// n bins per side (0: none) over a section of width W (m).
    BottomGrid(unsigned n, double width) : n_(n), per_metre_(n / width) {}

    [[nodiscard]] unsigned per_side() const { return n_; }
    [[nodiscard]] std::size_t size() const { return static_cast<std::size_t>(n_) * n_; }
    /// The bin of a wrapped position (x, y) in [0, W)^2: index iy n + ix.
    [[nodiscard]] std::size_t bin(double x, double y) const {
        const auto last = static_cast<std::size_t>(n_ - 1);
        const std::size_t ix = std::min(last, static_cast<std::size_t>(x * per_metre_));
        const std::size_t iy = std::min(last, static_cast<std::size_t>(y * per_metre_));
        return iy * n_ + ix;
    }
    /// The section's area over a bin's: n^2.
    [[nodiscard]] double area_ratio() const { return static_cast<double>(size()); }

private:
    unsigned n_;
    double per_metre_;  ///< n / W
};

}  // namespace secchi
