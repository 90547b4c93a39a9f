// Quick start (shown in the README): compose a medium from policies, trace photons from the
// sun, build a VOI photon map and estimate the nadir radiance at 5 m from it.
#include <secchi/estimate/path_radiance.hpp>
#include <secchi/map/photon_map.hpp>
#include <secchi/map/voi_octree.hpp>
#include <secchi/optics/phase/cone_average.hpp>
#include <secchi/optics/phase/petzold.hpp>
#include <secchi/transport/tracer.hpp>
#include <cstdio>

int main() {
    using namespace secchi;
    using Water = HomogeneousWater<TabulatedPhase>;
    const Water water(/*a=*/0.1, /*b=*/0.4, petzold_m93());        // 1/m, Petzold particles
    const Slab slab(/*section width=*/1.0, Bottom::lambertian_at(/*depth=*/10.0, /*albedo=*/0.3));
    const FlatSurface surface(/*water index=*/1.34);
    const CollimatedSun sun(/*zenith deg=*/30.0);

    TransportSettings run;                                          // first pass (manual 3.3)
    run.photons = run.map_photons = 500'000;
    run.depths = {0.0, 5.0};
    run.threads = 2;
    run.absorption = AbsorptionMode::implicit_capture;
    const auto first = PhotonTracer<Water, CompactRecord>(water, slab, surface, sun, run).run();

    // Second pass (manual 3.5): the photons in a VOI octree with the flux they carry, their
    // batches and the scene they were traced in (or VoiGridStore<CompactRecord>(first.records,
    // Radius(0.05)): the same query, faster).
    const PhotonMap map(VoiOctreeStore<CompactRecord>(first.records), first.map_flux, first.batches,
                        MapScene{slab, surface, SkyLight::of(SunAndSky(sun))}, first.bottom_ed);
    const ConeAveragedPhase cone(water.phase(), /*omega=*/0.005);   // its forward peak travels on along the ray
    const HomogeneousRayOptics optics{cone, water.attenuation(), water.scattering()};  // pbar_omega(psi) exp(-c' t), eq. 3.18
    const PathRadianceEstimator lu(map, VoiCylinder{}, optics, Radius(0.05));
    const Ray down{{0.5, 0.5, 5.0}, {0.0, 0.0, 1.0}, 5.0};               // from 5 m to the bottom
    const auto in_water = lu.estimate(nadir_ray_grid(down.origin.z, down.t_max, /*k=*/10, slab.width()), 2);
    // plus the bottom's reflected radiance A Ed(bottom) / pi, carried up the 5 m by the ray's transmittance
    const double from_bottom = 0.3 * map.bottom_ed().value / pi * optics.transmittance(down, down.t_max);

    std::printf("Ed(5 m) = %.4e +- %.1e W m^-2 nm^-1\n", first.irradiance[1][Ed].value, first.irradiance[1][Ed].se);
    std::printf("Lu(5 m) = %.4e +- %.1e W m^-2 sr^-1 nm^-1 (%.4e of it from the bottom)\n",
                in_water.radiance.value + from_bottom, in_water.radiance.se, from_bottom);
}
