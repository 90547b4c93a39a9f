#pragma once
// The surface photon map's record: a map photon's arrival on an opaque surface, an object in
// the water (scene/geometry.hpp) or the bottom, kept by the first pass when
// TransportSettings::surface_map is set. Like a volume record it carries an equal share of the
// incident flux, times its weight on arrival: Phi = w Ed(0+) A / N_map (manual 3.3.2.4;
// RecordFlux::per_record of the same pass). A density estimate of these arrivals on the
// surface gives its irradiance, and with it the light a Lambertian surface sends back
// (estimate/surface_irradiance.hpp): the light from lit objects and the bottom's caustics in
// the second pass.
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include <cstdint>
#include <limits>

namespace secchi::SECCHI_ISA {

struct SurfacePhoton {
    /// The `surface` of an arrival on the bottom (objects carry their material index).
    static constexpr std::uint32_t bottom = std::numeric_limits<std::uint32_t>::max();

    vec3 point;             ///< where it arrived (m), x and y wrapped into the section
    vec3 normal;            ///< the surface's unit normal there, facing the water it came from
    double weight;          ///< the photon's weight on arrival (before reflection or absorption)
    std::uint32_t surface;  ///< the object's material index, or `bottom`
    std::uint8_t batch;     ///< the map batch of the photon
};

}  // namespace secchi
