#pragma once
// The problem every benchmark program traces: homogeneous water with c = 1 /m and albedo w0
// under a flat surface, a slab 1 m wide (periodic) and 42 m deep without a bottom, irradiance
// detectors at 1, 5 and 10 m. Problem 2a is (Petzold, w0 = 0.9, sun at 60 deg, n = 1.34,
// continuous absorption); the propagation figures use (HG or Petzold, w0 = 0.9, sun at zenith,
// n = 1, analog absorption).
#include "secchi/solver/plane_parallel.hpp"
#include "secchi/transport/lane_tracer.hpp"

namespace secchi::bench {

/// The width W (m) of the slab's periodic section.
inline constexpr double section_width = 1.0;

/// The slab: W wide, no bottom, photons escaping below 42 m.
inline Slab bench_slab() { return Slab(section_width, Bottom{}, 42.0); }

/// The scene trace_slab traces in, as its photon maps record it: the slab, the flat surface of
/// index n_water, the sun at zenith_deg under a black sky.
inline MapScene slab_scene(double zenith_deg, double n_water) {
    return {bench_slab(), FlatSurface(n_water), SkyLight::of(SunAndSky(CollimatedSun(zenith_deg)))};
}

/// Traced by PhotonTracer, or by another tracer of the same interface (LaneTracer).
template <class Record, template <class...> class Tracer = PhotonTracer, class Phase>
TransportResult<Record> trace_slab(const Phase& phase, double w0, double zenith_deg, double n_water,
                                   std::uint64_t photons, unsigned threads, AbsorptionMode mode,
                                   std::vector<Record> storage = {}) {
    const auto water = HomogeneousWater<Phase>::from_albedo(1.0, w0, phase);
    TransportSettings s;
    s.photons = s.map_photons = photons;
    s.threads = threads;
    s.absorption = mode;
    s.depths = {1.0, 5.0, 10.0};
    return Tracer<HomogeneousWater<Phase>, Record>(water, bench_slab(), FlatSurface(n_water), CollimatedSun(zenith_deg), s)
        .run(std::move(storage));
}

/// The photon map of a trace_slab result in `scene`: its records (copied) in a Store built
/// with store_args, with the result's flux, batches and bottom Ed.
template <class Store, class Record, class... StoreArgs>
PhotonMap<Store> photon_map(const TransportResult<Record>& first, const MapScene& scene, const StoreArgs&... store_args) {
    return PhotonMap<Store>(Store(first.records, store_args...), first.map_flux, first.batches, scene, first.bottom_ed);
}

/// The radiance estimator every collection benchmark times: `volume` in `map` at `radius`,
/// the problem-2a water (c = 1 /m, b = 0.9 /m) and the cone-averaged phase function `cone`.
template <class Store, class Volume, class Cone>
auto radiance_estimator(const PhotonMap<Store>& map, const Volume& volume, const Cone& cone, double radius) {
    return PathRadianceEstimator(map, volume, HomogeneousRayOptics(cone, 1.0, 0.9), Radius(radius));
}
/// The estimator refers to the map: a temporary one would be gone before the first estimate.
template <class Store, class Volume, class Cone>
void radiance_estimator(const PhotonMap<Store>&&, const Volume&, const Cone&, double) = delete;

}  // namespace secchi::bench
