// Images of the 3-D scenes of the manual's chapter 7, each an OpenEXR file and a PNG preview:
//  - caustics_*: the manual's validation wave (amplitude 0.4 m, wavelength 5 m, along x) under a
//    vertical sun, water c = 0.2 1/m (w0 0.5, HG g = 0.5), a Lambertian bottom (A 0.3) at the
//    crest's focal depth, 6.2 m, in a section of one wavelength: the photon map projected on
//    the x-z plane from the crests down (the volume caustics, as the manual's Fig. 7.18; W m^-3
//    per unit sun irradiance), the bottom's Ed in 128 x 128 bins (the surface caustics, as Fig.
//    7.16), and a camera 1 m deep looking down at 40 degrees from the vertical (as Figs. 7.17 and
//    7.19: the bottom's caustics, the bright columns of the volume caustics between);
//  - shadow_*: a grey box (Lambertian, A 0.4) 1 m x 1 m x 0.5 m, 2 m deep, above a Lambertian
//    bottom (A 0.5) at 5 m in a 4 m section, water c = 0.2 1/m (w0 0.5, HG g = 0.5), sun at 30
//    degrees through a flat surface: the bottom's Ed (its shadow, filled in by scattering) and
//    a camera view of box and shadow, the box's light from the surface photon map;
//  - terrain_*: a rippled sand terrain (HeightField, A 0.3; ripples 0.1 m high, 0.625 m apart
//    along x, on a 1.4 m swell of the seabed along y, 5.5-7.0 m deep) under the manual's wave,
//    water and sun as for caustics_*: the terrain's irradiance from the surface photon map seen
//    from above (the crest's caustic splitting where the seabed lies below its focus, 6.2 m),
//    and the camera of caustics_view over it;
//  - baffle_detector: manual 7.3.1 (tests/test_baffle.cpp): a black baffle 2 m x 2 m halfway
//    between a unidirectional source (the sun at the zenith through an index-matched surface)
//    and a black detector plane at 4 m, isotropic scattering (c 0.5 1/m, w0 0.9): the
//    detector's Ed in 90 x 90 bins, as Fig. 7.2.
// The camera views use the second pass over the scene (estimate/scene_radiance.hpp): the water's
// path radiance from the photon map, the bottom's light from its bins, the box's A E / pi with E
// gathered from the surface photon map (estimate/surface_irradiance.hpp) within 0.1 m.
// Periodic sections: the images show the neighbouring copies of box and wave.
#include <secchi/estimate/render.hpp>
#include <secchi/estimate/scene_radiance.hpp>
#include <secchi/io/cli.hpp>
#include <secchi/io/exr.hpp>
#include <secchi/io/png_preview.hpp>
#include <secchi/map/projection.hpp>
#include <secchi/map/voi_grid.hpp>
#include <secchi/optics/phase/cone_average.hpp>
#include <secchi/optics/phase/henyey_greenstein.hpp>
#include <secchi/optics/phase/isotropic.hpp>
#include <secchi/scene/height_field.hpp>
#include <secchi/scene/shapes.hpp>
#include <secchi/scene/wave_surface.hpp>
#include <secchi/transport/tracer.hpp>
#include <cstdio>
#include <map>
#include <memory>
#include <numbers>
#include <string>

namespace {
constexpr const char* usage = R"(usage: littoral_scenes [options]
  --photons N   photons traced per scene (default 2e6; half of them stored in the maps)
  --size N      camera image height in pixels (default 200; the views are 3:2)
  --spp N       rays per pixel, jittered (default 2)
  --threads N   (default 2)
  --out PREFIX  output file prefix (default "scene_")
Writes PREFIX{caustics_projection,caustics_bottom,caustics_view,shadow_bottom,shadow_view,
terrain_irradiance,terrain_view,baffle_detector}.exr and .png.
)";

using namespace secchi;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
using Store = VoiGridStore<CompactRecord>;
const Radius radius(0.1);

TransportSettings settings(std::uint64_t photons, unsigned bins, unsigned threads) {
    TransportSettings s;
    s.photons = photons;
    s.map_photons = photons / 2;
    s.depths = {1.0};  // below the wave's troughs
    s.bottom_bins = bins;
    s.threads = threads;
    return s;
}

/// The bottom's Ed bins (n x n, index iy n + ix) as an image, row iy: channel "Ed" (W m^-2
/// per unit source irradiance) and "Ed.se".
Image bins_image(const std::vector<Estimate>& bins) {
    const auto n = static_cast<int>(std::lround(std::sqrt(static_cast<double>(bins.size()))));
    Image image(n, n);
    std::vector<float>& v = image.add_channel("Ed");
    std::vector<float>& se = image.add_channel("Ed.se");
    for (std::size_t i = 0; i < bins.size(); ++i) {
        v[i] = static_cast<float>(bins[i].value);
        se[i] = static_cast<float>(bins[i].se);
    }
    return image;
}
}  // namespace

int main(int argc, char** argv) {
    return run_program(argc, argv, "littoral_scenes", usage, [&] {
        const CommandLine cl(argc, argv, {"photons", "size", "spp", "threads", "out"});
        const auto threads = cl.threads(2);
        const ConeTable tables{.threads = threads};  // the cone-averaged phase functions' tables
        const std::uint64_t photons = cl.count("photons", 2'000'000, 1000, 10'000'000'000);
        const int size = static_cast<int>(cl.count("size", 200, 1, 8192));
        const auto spp = static_cast<unsigned>(cl.count("spp", 2, 1, 4096));
        const std::string out = cl.text("out", "scene_");
        // Every output checked (and written whole or not at all) before the work.
        std::map<std::string, std::unique_ptr<OutputFile>> files;
        for (const char* name : {"caustics_projection", "caustics_bottom", "caustics_view", "shadow_bottom", "shadow_view",
                                 "terrain_irradiance", "terrain_view", "baffle_detector"})
            for (const char* ext : {".exr", ".png"}) files[std::string(name) + ext] = std::make_unique<OutputFile>("--out", out + name + ext);
        const auto save = [&](const Image& image, const std::string& name, const char* channel) {
            OutputFile& exr = *files.at(name + ".exr");
            OutputFile& png = *files.at(name + ".png");
            write_exr(image, exr.partial_path());
            const double white = write_png_preview(image, channel, png.partial_path());
            exr.commit();
            png.commit();
            std::printf("%-20s %4d x %-4d white = %.3g  -> %s%s.exr\n", name.c_str(), image.width(), image.height(), white,
                        out.c_str(), name.c_str());
        };
        const RenderSettings render_settings{spp, threads, 1};

        {  // Caustics under the manual's wave.
            const double bottom = 6.2, amplitude = 0.4, wavelength = 5.0;
            const HgWater water = HgWater::from_albedo(0.2, 0.5, HenyeyGreensteinPhase(0.5));
            const Slab slab(wavelength, Bottom::lambertian_at(bottom, 0.3));
            const SunAndSky sun(CollimatedSun(0.0));
            auto first = PhotonTracer<HgWater, CompactRecord, SinusoidalWave>(
                             water, slab, SinusoidalWave(amplitude, wavelength, 0.0, std::numbers::pi), sun,
                             settings(photons, 128, threads))
                             .run();
            const std::vector<Estimate> bins = first.bottom_ed_bins;
            const PhotonMap map = PhotonMap<Store>::from_first_pass(std::move(first), MapScene{slab, std::nullopt, SkyLight::of(sun)}, radius);
            save(project_photon_map(map, bottom, 256, 330, -amplitude), "caustics_projection", "Y");
            save(bins_image(bins), "caustics_bottom", "Ed");
            const RadianceEstimator est(map, VoiCylinder(-amplitude, bottom),
                                        HomogeneousRayOptics(ConeAveragedPhase(water.phase(), 0.005, ConePeak::transmitted, tables), water.attenuation(),
                                                             water.scattering()),
                                        radius);
            const SceneRadianceEstimator scene(est, NoGeometry{}, bins);
            const PinholeCamera camera({{0.0, 2.5, 1.0}, {std::sin(40.0 * deg), 0.0, std::cos(40.0 * deg)}, {0.0, 0.0, -1.0}, 70.0,
                                        size * 3 / 2, size});
            save(render(scene, camera, render_settings), "caustics_view", "L");
        }
        {  // A grey box and its shadow.
            const double bottom = 5.0, width = 4.0;
            const HgWater water = HgWater::from_albedo(0.2, 0.5, HenyeyGreensteinPhase(0.5));
            const Slab slab(width, Bottom::lambertian_at(bottom, 0.5));
            const SunAndSky sun(CollimatedSun(30.0));
            Shapes box;
            box.add(AxisBox(vec3(1.5, 1.5, 2.0), vec3(2.5, 2.5, 2.5)), ObjectMaterial::lambertian(0.4));
            TransportSettings s = settings(photons, 128, threads);
            s.surface_map = true;
            auto first = PhotonTracer<HgWater, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, Shapes>(
                             water, slab, FlatSurface(1.34), sun, s, box)
                             .run();
            const std::vector<Estimate> bins = first.bottom_ed_bins;
            const auto surface = std::make_shared<const SurfaceIrradiance>(first.surface_photons, first.map_flux.per_record,
                                                                           first.batches, width, radius);
            const PhotonMap map = PhotonMap<Store>::from_first_pass(std::move(first), MapScene{slab, FlatSurface(1.34), SkyLight::of(sun)}, radius);
            save(bins_image(bins), "shadow_bottom", "Ed");
            const RadianceEstimator est(map, VoiCylinder(0.0, bottom),
                                        HomogeneousRayOptics(ConeAveragedPhase(water.phase(), 0.005, ConePeak::transmitted, tables), water.attenuation(),
                                                             water.scattering()),
                                        radius);
            const SceneRadianceEstimator scene(est, box, bins, surface);
            const PinholeCamera camera({{2.0, -0.5, 1.0}, {0.0, 0.6, 0.8}, {0.0, 0.0, -1.0}, 70.0, size * 3 / 2, size});
            save(render(scene, camera, render_settings), "shadow_view", "L");
        }
        {  // Caustics on a rippled terrain under the manual's wave.
            const double amplitude = 0.4, wavelength = 5.0, floor = 7.5;
            const HgWater water = HgWater::from_albedo(0.2, 0.5, HenyeyGreensteinPhase(0.5));
            const Slab slab(wavelength, Bottom::lambertian_at(floor, 0.3));
            const SunAndSky sun(CollimatedSun(0.0));
            const HeightField terrain = HeightField::from_function(
                160, 160, wavelength, floor,
                [&](double x, double y) {
                    return 6.25 - 0.7 * std::cos(two_pi * y / wavelength) + 0.05 * std::sin(two_pi * 8.0 * x / wavelength);
                },
                ObjectMaterial::lambertian(0.3));
            TransportSettings s = settings(photons, 0, threads);
            s.surface_map = true;
            auto first = PhotonTracer<HgWater, CompactRecord, SinusoidalWave, SunAndSky, IrradiancePlanes, Bottom, HeightField>(
                             water, slab, SinusoidalWave(amplitude, wavelength, 0.0, std::numbers::pi), sun, s, terrain)
                             .run();
            const auto surface = std::make_shared<const SurfaceIrradiance>(first.surface_photons, first.map_flux.per_record,
                                                                           first.batches, wavelength, radius);
            // The terrain's irradiance seen from above: E at the terrain point under each pixel.
            const int n = 160;
            Image top(n, n);
            std::vector<float>& e = top.add_channel("E");
            for (int j = 0; j < n; ++j)
                for (int i = 0; i < n; ++i) {
                    const double x = wavelength * (i + 0.5) / n, y = wavelength * (j + 0.5) / n;
                    const auto hit = terrain.closest_hit({x, y, 0.0}, {0.0, 0.0, 1.0}, INFINITY);
                    e[static_cast<std::size_t>(j * n + i)] = hit ? static_cast<float>(surface->irradiance(hit->point, hit->normal).value) : 0.0f;
                }
            save(top, "terrain_irradiance", "E");
            const PhotonMap map = PhotonMap<Store>::from_first_pass(std::move(first), MapScene{slab, std::nullopt, SkyLight::of(sun)}, radius);
            const RadianceEstimator est(map, VoiCylinder(-amplitude, floor),
                                        HomogeneousRayOptics(ConeAveragedPhase(water.phase(), 0.005, ConePeak::transmitted, tables), water.attenuation(),
                                                             water.scattering()),
                                        radius);
            const SceneRadianceEstimator scene(est, terrain, {}, surface);
            const PinholeCamera camera({{0.0, 2.5, 1.0}, {std::sin(40.0 * deg), 0.0, std::cos(40.0 * deg)}, {0.0, 0.0, -1.0}, 70.0,
                                        size * 3 / 2, size});
            save(render(scene, camera, render_settings), "terrain_view", "L");
        }
        {  // The baffle of manual 7.3.1.
            using IsoWater = HomogeneousWater<IsotropicPhase>;
            Shapes baffle;
            baffle.add(AxisBox(vec3(2.0, 2.0, 1.95), vec3(4.0, 4.0, 2.05)), ObjectMaterial::absorbing());
            TransportSettings s = settings(photons, 90, threads);
            s.map_photons = 0;
            const auto r = PhotonTracer<IsoWater, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, Shapes>(
                               IsoWater::from_albedo(0.5, 0.9, IsotropicPhase{}), Slab(6.0, Bottom::lambertian_at(4.0, 0.0)),
                               FlatSurface(1.0), SunAndSky(CollimatedSun(0.0)), s, baffle)
                               .run();
            save(bins_image(r.bottom_ed_bins), "baffle_detector", "Ed");
        }
        return 0;
    });
}
