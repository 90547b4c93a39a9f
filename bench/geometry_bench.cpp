// The cost of geometry in the first pass: photons per second of PhotonTracer without objects,
// with one analytic sphere (scene/shapes.hpp), with the same sphere as a mesh of about 1e5
// triangles through Embree (scene/embree_mesh.hpp), and with 100 mesh rocks of 988 triangles
// each (98,800 in all) spread over the section, and a terrain (scene/height_field.hpp) of
// 224 x 224 nodes (100,352 triangles) covering the section at 4.5-5.5 m. Water c = 0.5 1/m, w0 = 0.8, HG g = 0.9; a
// Lambertian bottom (A 0.2) at 6 m; sun at 30 degrees; a 2 m section; objects Lambertian
// (A 0.3). The variants run in paired rounds (each round runs all of them), and each row
// gives the median photons/s and the median of the rounds' time ratios to the run without
// objects. Also printed: the ledger's share absorbed by the objects (the same sphere as shape
// and as mesh: nearly equal; the mesh is inscribed, slightly smaller).
#include "bench_timing.hpp"
#include <secchi/io/cli.hpp>
#include <secchi/optics/phase/henyey_greenstein.hpp>
#include <secchi/scene/embree_mesh.hpp>
#include <secchi/scene/height_field.hpp>
#include <secchi/scene/shapes.hpp>
#include <secchi/transport/tracer.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

namespace {
constexpr const char* usage = R"(usage: geometry_bench [options]
  --photons N   photons per run (default 2e5)
  --rounds R    paired rounds (default 5)
  --threads T   (default 2)
)";

using namespace secchi;
using Water = HomogeneousWater<HenyeyGreensteinPhase>;
constexpr double width = 2.0;

template <SceneGeometry G>
TransportResult<CompactRecord> trace(const G& g, std::uint64_t photons, unsigned threads) {
    TransportSettings s;
    s.photons = photons;
    s.map_photons = 0;
    s.depths = {0.0, 2.0, 4.0};
    s.threads = threads;
    return PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, G>(
               Water::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.9)), Slab(width, Bottom::lambertian_at(6.0, 0.2)),
               FlatSurface(1.34), SunAndSky(CollimatedSun(30.0)), s, g)
        .run();
}

/// 10 x 10 rocks of radius 0.08 m (20 rings, 26 segments: 988 triangles each, 98,800 in all)
/// on a grid over the section, at 3 to 5 m.
std::vector<TriangleMesh> rocks() {
    std::vector<TriangleMesh> out;
    for (int i = 0; i < 10; ++i)
        for (int j = 0; j < 10; ++j) {
            const vec3 c((i + 0.5) * width / 10.0, (j + 0.5) * width / 10.0, 3.0 + 0.2 * ((i * 7 + j * 3) % 11));
            out.push_back(sphere_mesh(c, 0.08, 20, 26, ObjectMaterial::lambertian(0.3)));
        }
    return out;
}
}  // namespace

int main(int argc, char** argv) {
    return run_program(argc, argv, "geometry_bench", usage, [&] {
        const CommandLine cl(argc, argv, {"photons", "rounds", "threads"});
        const std::uint64_t photons = cl.count("photons", 200'000);
        const int rounds = static_cast<int>(cl.count("rounds", 5, 1, 1000));
        const unsigned threads = cl.threads(2);

        const vec3 centre(1.0, 1.0, 3.0);
        const double radius = 0.5;
        Shapes sphere;
        sphere.add(Sphere(centre, radius), ObjectMaterial::lambertian(0.3));
        const EmbreeMesh sphere_mesh_1e5({sphere_mesh(centre, radius, 224, 224, ObjectMaterial::lambertian(0.3))});
        const EmbreeMesh rock_field(rocks());
        const HeightField terrain = HeightField::from_function(
            224, 224, width, 6.0,
            [](double x, double y) { return 5.0 + 0.3 * std::sin(two_pi * x / width) * std::cos(two_pi * 2.0 * y / width) + 0.2 * std::cos(two_pi * 3.0 * x / width); },
            ObjectMaterial::lambertian(0.3));

        struct Variant {
            const char* name;
            std::size_t triangles;
            std::function<TransportResult<CompactRecord>()> run;
            std::vector<double> seconds, ratio;
            double absorbed = 0.0;
        };
        std::vector<Variant> variants;
        variants.push_back({"no objects", 0, [&] { return trace(NoGeometry{}, photons, threads); }, {}, {}});
        variants.push_back({"sphere (analytic shape)", 0, [&] { return trace(sphere, photons, threads); }, {}, {}});
        variants.push_back({"sphere (Embree mesh)", sphere_mesh_1e5.triangle_count(),
                            [&] { return trace(sphere_mesh_1e5, photons, threads); }, {}, {}});
        variants.push_back({"100 rocks (Embree meshes)", rock_field.triangle_count(),
                            [&] { return trace(rock_field, photons, threads); }, {}, {}});
        variants.push_back({"terrain (height field)", 2u * 224u * 224u, [&] { return trace(terrain, photons, threads); }, {}, {}});
        for (int round = 0; round < rounds; ++round)
            for (Variant& v : variants) {
                TransportResult<CompactRecord> r;
                v.seconds.push_back(bench::seconds([&] { r = v.run(); }));
                v.ratio.push_back(v.seconds.back() / variants.front().seconds.back());
                v.absorbed = r.ledger.absorbed_objects / r.ledger.incident;
            }
        std::printf("%s; %llu photons per run, %u threads, %d paired rounds\n", EmbreeMesh::version().c_str(),
                    static_cast<unsigned long long>(photons), threads, rounds);
        std::printf("| geometry | triangles | photons/s | time / no objects' | absorbed by objects |\n|---|---|---|---|---|\n");
        for (const Variant& v : variants)
            std::printf("| %-26s | %9zu | %9.0f | %5.2f [%.2f-%.2f] | %.4f |\n", v.name, v.triangles,
                        static_cast<double>(photons) / bench::median(v.seconds), bench::median(v.ratio),
                        *std::min_element(v.ratio.begin(), v.ratio.end()), *std::max_element(v.ratio.begin(), v.ratio.end()),
                        v.absorbed);
        return 0;
    });
}
