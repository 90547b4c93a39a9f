#pragma once
// The photon map projected on a vertical plane (the manual's Fig. 7.18): the stored photons
// binned by horizontal position x across the periodic section and by depth z, as the
// scattered-flux density per unit volume, W m^-3 nm^-1 (each record's flux, RecordFlux::at(z),
// over the bin's volume: dx dz times the section's width in y). One channel "Y", row 0 at
// depth `top` (default 0, the mean surface; a wave's crests lie above it, at minus its
// amplitude), depth increasing downward to `depth`; photons outside [top, depth] are not shown.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/image.hpp"
#include "secchi/map/photon_map.hpp"
#include "secchi/transport/record_flux.hpp"
#include <cmath>
#include <ranges>

namespace secchi::SECCHI_ISA {

template <std::ranges::input_range Records>
Image project_photon_map(const Records& records, const RecordFlux& flux, double section_width, double depth,
                         int width = 256, int height = 512, double top = 0.0) {
    require(std::isfinite(top) && top <= 0.0, "projection top depth (m)", top, "must be finite and <= 0");
    require(std::isfinite(depth) && depth > 0.0, "projection depth (m)", depth, "must be finite and > 0");
    require(std::isfinite(section_width) && section_width > 0.0, "section width", section_width, "must be > 0");
    Image image(width, height);
    std::vector<float>& y = image.add_channel("Y");
    const double voxel = (section_width / width) * ((depth - top) / height) * section_width;
    for (const auto& r : records) {
        const vec3 p = r.position();
        const auto i = static_cast<long>(std::floor(p.x / section_width * width));
        const auto j = static_cast<long>(std::floor((p.z - top) / (depth - top) * height));
        if (i >= 0 && i < width && j >= 0 && j < height)
            y[static_cast<std::size_t>(j) * width + static_cast<std::size_t>(i)] += static_cast<float>(flux.at(p.z, r.direction().z) / voxel);
    }
    return image;
}

/// The projection of a photon map's own records, with its flux and section.
template <class Store>
Image project_photon_map(const PhotonMap<Store>& map, double depth, int width = 256, int height = 512, double top = 0.0) {
    return project_photon_map(map.store().records(), map.flux(), map.section_width(), depth, width, height, top);
}

}  // namespace secchi
