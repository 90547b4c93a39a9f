// A spectral run of Case-1 water from a material file: every band of 400-700 nm (10 nm apart by
// default) in one photon map, each band's photons traced through the water's IOPs at its
// wavelength (solver/spectral.hpp), then per band: Ed(lambda, z) from the first pass, the nadir
// radiance Lu(lambda, z) and the water-leaving radiance Lw(lambda) (seen from just above the
// surface looking straight down: with the black sky nothing is reflected into it) from the map,
// and the remote-sensing reflectance Rrs(lambda) = Lw / Ed(0+) (Mobley 1994, "Light and Water",
// eq. 3.7; sr^-1), each with its SE (Ed(0+) is exact: the source's plane irradiance).
// Sun at 30 deg, flat surface, black sky, infinitely deep water; the source's spectrum is flat
// (E_perp = 1 per nm in every band: radiances are per unit E_perp, Rrs does not depend on it).
// With --spectral-radius R, Lu(lambda, z) also with spectral bias compensation (manual 3.5.2,
// estimate/spectral_compensation.hpp): the core search over all bands at the collection radius,
// each band's share from the search of radius R.
#include <secchi/estimate/radiance.hpp>
#include <secchi/estimate/spectral_compensation.hpp>
#include <secchi/io/cli.hpp>
#include <secchi/io/material_medium.hpp>
#include <secchi/solver/spectral.hpp>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace {
constexpr const char* usage = R"(usage: spectral_case1 [options]
  --material FILE     DIRSIG material file (default examples/materials/case1_chlorophyll.mat)
  --wavelengths R     nm, START:STOP:STEP or one value (default 400:700:10)
  --depths R          m, for Ed and Lu (default 0:10:5)
  --photons N         photons per band, all stored in the map (default 100000)
  --threads T         (default 2)
  --spectral-radius R m, also Lu with spectral bias compensation (manual 3.5.2): the core
                      search of all bands at 0.05 m, each band's share from radius R
                      (0.05 <= R < 0.5); CSV rows Lu_compensated, and a table at the
                      depth shown
  --csv FILE          write rows wavelength_nm, depth_m, quantity, value, se: Ed and Lu at
                      each depth, Lw and Rrs at -0.01 (the view 1 cm above the surface), to
                      FILE (default spectral_case1.csv)
)";
}  // namespace

int main(int argc, char** argv) {
    using namespace secchi;
    return run_program(argc, argv, "spectral_case1", usage, [&] {
        const CommandLine cl(argc, argv, {"material", "wavelengths", "depths", "photons", "threads", "csv", "spectral-radius"});
        const std::string material = cl.text("material", "examples/materials/case1_chlorophyll.mat");
        const std::vector<double> wavelengths = cl.range("wavelengths", "400:700:10");
        const std::vector<double> depths = cl.range("depths", "0:10:5", 0.0);
        const auto threads = cl.threads(2);
        const std::uint64_t photons = cl.count("photons", 100'000);
        require(photons >= 1, "--photons", photons, "must be >= 1");
        const double spectral_radius = cl.number("spectral-radius", 0.0);  // 0: no compensation
        if (cl.has("spectral-radius"))
            require(spectral_radius >= 0.05 && spectral_radius < 0.5, "--spectral-radius", spectral_radius,
                    "must lie in [0.05, 0.5) m: at least the collection radius, under half the section width");
        require(wavelengths.size() <= max_spectral_bands, "--wavelengths", cl.text("wavelengths", "400:700:10"),
                "gives more bands than a spectral run holds (256)");
        OutputFile csv_file("--csv", cl.text("csv", "spectral_case1.csv"));  // checked before the work
        std::ostream& csv = csv_file.stream();

        PlaneParallelConfig cfg;
        cfg.sun_zenith_deg = 30.0;
        cfg.transport.photons = cfg.transport.map_photons = photons;
        cfg.transport.depths = depths;
        cfg.transport.threads = threads;
        require_first_pass_fits_in_memory<CompactRecord>(cfg.transport, static_cast<double>(wavelengths.size()));

        // The water at each band's wavelength, sampled every 5 cm to 300 m.
        const auto model = io::read_iop_model(material, 1, "");
        const auto profile_depths = iop::uniform_depths(300.0, 0.05);
        std::vector<decltype(iop::stratify(model, 500.0, profile_depths))> media;
        for (double wl : wavelengths) media.push_back(iop::stratify(model, wl, profile_depths));
        // Each band's ray optics: the components' cone-averaged phase functions (eq. 5.5).
        using Water = decltype(media)::value_type;
        using Cone = ConeAveragedPhase<std::decay_t<decltype(media[0].phases()[0])>>;
        std::vector<StratifiedRayOptics<Water>> optics;
        for (const auto& water : media) {
            std::vector<Cone> cones;
            for (const auto& p : water.phases()) cones.emplace_back(p, 0.005, ConePeak::transmitted, ConeTable{.threads = threads});
            optics.emplace_back(water, cones);
        }

        // The map holds every band's events down to where the deepest nadir ray of the clearest
        // band has faded to 1e-4, plus the collection radius.
        const Radius radius(0.05);
        for (const auto& o : optics)
            for (double z : depths)
                cfg.transport.map_depth = std::max(std::isfinite(cfg.transport.map_depth) ? cfg.transport.map_depth : 0.0,
                                                   z + detail::nadir_ray_length(o, z, cfg) + radius.value());
        const auto run = trace_spectral_map<VoiGridStore<CompactRecord>>(media, wavelengths, cfg, radius);
        const RadianceEstimator est(run.map, VoiCylinder(0.0, INFINITY), optics, radius);

        // Compensated Lu(lambda) per depth, every band at once (the rays as for Lu below).
        std::vector<std::vector<Estimate>> lu_compensated;
        if (cl.has("spectral-radius")) {
            const SpectralCompensationEstimator compensated(run.map, VoiCylinder(0.0, INFINITY), optics,
                                                            SpectralCompensation{radius.value(), spectral_radius});
            for (double z : depths) lu_compensated.push_back(compensated.average(nadir_ray_grid(z, INFINITY, 10, run.map.section_width()), threads));
        }

        csv << "wavelength_nm,depth_m,quantity,value,se\n";
        std::printf("%7s %22s %22s %22s\n", "lambda", "Lw (W m^-2 sr^-1 nm^-1)", "Rrs (sr^-1)", "Ed(5 m) or first depth");
        for (std::size_t k = 0; k < wavelengths.size(); ++k) {
            const auto band = static_cast<unsigned>(k);
            const double ed0 = run.first_pass[k].source_irradiance;  // Ed(0+), exact
            // Lw: a 10 x 10 grid of nadir views 1 cm above the surface.
            std::vector<Ray> above;
            for (const Ray& r : nadir_ray_grid(-0.01, INFINITY, 10, run.map.section_width())) above.push_back(r);
            const Estimate lw = est.average(above, band, threads);
            for (std::size_t i = 0; i < depths.size(); ++i) {
                const Estimate ed = run.first_pass[k].depths[i].irradiance[Ed];
                const Estimate lu = est.average(nadir_ray_grid(depths[i], INFINITY, 10, run.map.section_width()), band, threads);
                csv << wavelengths[k] << ',' << depths[i] << ",Ed," << ed.value << ',' << ed.se << '\n';
                csv << wavelengths[k] << ',' << depths[i] << ",Lu," << lu.value << ',' << lu.se << '\n';
                if (!lu_compensated.empty())
                    csv << wavelengths[k] << ',' << depths[i] << ",Lu_compensated," << lu_compensated[i][k].value << ','
                        << lu_compensated[i][k].se << '\n';
            }
            csv << wavelengths[k] << ",-0.01,Lw," << lw.value << ',' << lw.se << '\n';
            csv << wavelengths[k] << ",-0.01,Rrs," << lw.value / ed0 << ',' << lw.se / ed0 << '\n';
            const Estimate ed_shown = run.first_pass[k].depths[std::min<std::size_t>(1, depths.size() - 1)].irradiance[Ed];
            std::printf("%7.0f %12.4e +- %7.1e %12.4e +- %7.1e %12.4e +- %7.1e\n", wavelengths[k], lw.value, lw.se,
                        lw.value / ed0, lw.se / ed0, ed_shown.value, ed_shown.se);
        }
        if (!lu_compensated.empty()) {
            const std::size_t i = std::min<std::size_t>(1, depths.size() - 1);
            std::printf("\nLu(lambda) at %g m (W m^-2 sr^-1 nm^-1): per band, and compensated (manual 3.5.2, r_spectral %g m)\n",
                        depths[i], spectral_radius);
            for (std::size_t k = 0; k < wavelengths.size(); ++k) {
                const Estimate lu = est.average(nadir_ray_grid(depths[i], INFINITY, 10, run.map.section_width()),
                                                static_cast<unsigned>(k), threads);
                const Estimate& c = lu_compensated[i][k];
                std::printf("%7.0f %12.4e +- %7.1e %12.4e +- %7.1e\n", wavelengths[k], lu.value, lu.se, c.value, c.se);
            }
        }
        csv_file.commit();
        return 0;
    });
}
