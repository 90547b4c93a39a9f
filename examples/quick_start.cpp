// Quick start (shown in the README): compose a medium from policies, trace photons from the
// sun, build a VOI photon map and estimate radiance along rays from it.
#include <secchi/estimate/radiance.hpp>
#include <secchi/map/photon_map.hpp>
#include <secchi/map/voi_octree.hpp>
#include <secchi/optics/phase/cone_average.hpp>
#include <secchi/optics/phase/petzold.hpp>
#include <secchi/transport/tracer.hpp>
#include <cmath>
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
    const RadianceEstimator est(map, VoiCylinder(0.0, 10.0), optics, Radius(0.05));
    // The whole radiance along a ray (eq. 3.18): light scattered into it on the way, plus what
    // it sees where it ends (here the bottom's reflected light; looking up, the surface).
    const Estimate lu = est.average(nadir_ray_grid(/*z=*/5.0, INFINITY, /*k=*/10, slab.width()), /*band=*/0, 2);
    const Ray up{{0.5, 0.5, 5.0}, {std::sin(40 * deg), 0.0, -std::cos(40 * deg)}, INFINITY};  // 40 deg from the zenith

    std::printf("Ed(5 m) = %.4e +- %.1e W m^-2 nm^-1\n", first.irradiance[1][Ed].value, first.irradiance[1][Ed].se);
    std::printf("Lu(5 m) = %.4e +- %.1e W m^-2 sr^-1 nm^-1\n", lu.value, lu.se);
    std::printf("L(5 m, looking up 40 deg from the zenith) = %.4e +- %.1e W m^-2 sr^-1 nm^-1\n", est.radiance(up).value,
                est.radiance(up).se);
}
