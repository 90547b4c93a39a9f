// Images of the light in a coastal water body, from one photon map: a pinhole camera 2 m under
// the water looking up (Snell's window: the sky compressed into a 97 deg cone, the water's
// own light reflected beyond it), one at 4 m looking level, one above the water looking down at
// 45 deg (the sky reflected, the water-leaving radiance), and the radiance distribution at
// 4 m as a latitude-longitude map. Each image is an OpenEXR file (radiance
// and its SE per pixel, W m^-2 sr^-1 nm^-1 per unit E_perp of the sun) and a PNG preview.
//
// The scene (coastal_scene.hpp): a = 0.1, b = 0.3 /m (c = 0.4 /m, w0 = 0.75), Petzold, a
// Lambertian bottom of albedo 0.3 at 8 m; flat surface (n = 1.34); sun at 30 deg (E_perp = 1)
// and a uniform sky of plane irradiance 0.2.
#include "coastal_scene.hpp"
#include <secchi/estimate/radiance_distribution.hpp>
#include <secchi/estimate/render.hpp>
#include <secchi/io/cli.hpp>
#include <secchi/io/exr.hpp>
#include <secchi/io/png_preview.hpp>
#include <secchi/solver/plane_parallel.hpp>
#include <chrono>
#include <map>
#include <memory>
#include <cstdint>
#include <cstdio>
#include <string>

namespace {
constexpr const char* usage = R"(usage: underwater_camera [options]
  --map-photons N   photons whose scattering events are stored (default 1e6)
  --size N          image height in pixels (default 256; the level view is 3:2)
  --spp N           rays per pixel, jittered (default 4)
  --threads N       (default 2)
  --out PREFIX      output file prefix (default "camera_")
Writes PREFIX{up,level,above,distribution}.exr and .png.
)";
}

int main(int argc, char** argv) {
    using namespace secchi;
    return run_program(argc, argv, "underwater_camera", usage, [&] {
        const CommandLine cl(argc, argv, {"map-photons", "size", "spp", "threads", "out"});
        const auto threads = cl.threads(2);
        const int size = static_cast<int>(cl.count("size", 256, 1, 8192));
        const auto spp = static_cast<unsigned>(cl.count("spp", 4, 1, 4096));
        const std::string out = cl.text("out", "camera_");
        // Every output checked (and written whole or not at all) before the work.
        std::map<std::string, std::unique_ptr<OutputFile>> files;
        for (const char* view : {"up", "level", "above", "distribution"})
            for (const char* ext : {".exr", ".png"}) {
                std::string name(view);
                name += ext;
                files[name] = std::make_unique<OutputFile>("--out", out + name);
            }

        const auto water = examples::coastal_water();
        const PlaneParallelConfig cfg = examples::coastal_config(cl.count("map-photons", 1'000'000), threads);
        const Radius radius(0.05);
        const auto t0 = std::chrono::steady_clock::now();
        const auto mapped = trace_photon_map<VoiGridStore<CompactRecord>>(water, cfg, radius);
        const ConeAveragedPhase cone(water.phase(), 0.005, ConePeak::transmitted, cone_table(cfg));
        const HomogeneousRayOptics optics(cone, water.attenuation(), water.scattering());
        const RadianceEstimator est(mapped.map, VoiCylinder(0.0, cfg.bottom.depth()), optics, radius);
        std::printf("map: %zu photons stored in %.1f s\n", mapped.map.store().records().size(),
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());

        const RenderSettings render_settings{spp, threads, 1};
        const auto save = [&](const Image& image, const std::string& name) {
            OutputFile& exr = *files.at(name + ".exr");
            OutputFile& png = *files.at(name + ".png");
            write_exr(image, exr.partial_path());
            const double white = write_png_preview(image, "L", png.partial_path());
            exr.commit();
            png.commit();
            std::printf("%-13s %4d x %-4d  white = %.3g W m^-2 sr^-1 nm^-1  -> %s%s.exr\n", name.c_str(), image.width(),
                        image.height(), white, out.c_str(), name.c_str());
        };
        const auto shoot = [&](const std::string& name, const PinholeCameraSpec& spec) {
            const auto t = std::chrono::steady_clock::now();
            const Image image = render(est, PinholeCamera(spec), render_settings);
            std::printf("%s: %.1f s\n", name.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count());
            save(image, name);
        };
        shoot("up", {{0.5, 0.5, 2.0}, {0.0, 0.0, -1.0}, {1.0, 0.0, 0.0}, 120.0, size, size});
        shoot("level", {{0.5, 0.5, 4.0}, {1.0, 0.0, 0.0}, {0.0, 0.0, -1.0}, 70.0, size * 3 / 2, size});
        shoot("above", {{0.5, 0.5, -3.0}, {1.0, 0.0, 1.0}, {0.0, 0.0, -1.0}, 60.0, size * 3 / 2, size});
        save(radiance_distribution(est, 4.0, {2 * size, size, render_settings.samples_per_pixel, threads, 1}),
             "distribution");
        const DirectBeam sun = est.direct_sun({0.5, 0.5, 4.0});
        std::printf("direct sun at 4 m: E_perp %.4g along (%.3f, %.3f, %.3f)\n", sun.e_perp, sun.direction.x,
                    sun.direction.y, sun.direction.z);
        return 0;
    });
}
