#pragma once
// The coastal scene of examples/underwater_camera.cpp and bench/camera_bench.cpp: water with
// a = 0.1, b = 0.3 /m (c = 0.4 /m, w0 = 0.75) and Petzold's particle phase function, a
// Lambertian bottom of albedo 0.3 at 8 m, a flat surface (n = 1.34), the sun at 30 deg
// (E_perp = 1) and a uniform sky of plane irradiance 0.2; every traced photon stored.
#include <secchi/optics/phase/petzold.hpp>
#include <secchi/solver/plane_parallel.hpp>
#include <cstdint>

namespace secchi::examples {

inline HomogeneousWater<TabulatedPhase> coastal_water() { return {0.1, 0.3, petzold_m93()}; }

inline PlaneParallelConfig coastal_config(std::uint64_t map_photons, unsigned threads) {
    PlaneParallelConfig cfg;
    cfg.sun_zenith_deg = 30.0;
    cfg.sky_irradiance = 0.2;
    cfg.bottom = Bottom::lambertian_at(8.0, 0.3);
    cfg.transport.photons = cfg.transport.map_photons = map_photons;
    cfg.transport.depths = {0.0, 4.0};
    cfg.transport.threads = threads;
    return cfg;
}

}  // namespace secchi::examples
