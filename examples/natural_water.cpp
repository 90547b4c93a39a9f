// Natural water in a few lines: a Case-1 water column composed at compile time from the
// manual's chapter-5 models, or read from a DIRSIG material file, sampled at one wavelength
// into the transport's depth profile, and solved (both passes) for Ed, Eou and Lu.
//   natural_water [MATERIAL_FILE [ENTRY]]      (default: the composed medium below)
#include <secchi/io/cli.hpp>
#include <secchi/io/material_medium.hpp>
#include <secchi/optics/iop/absorption.hpp>
#include <secchi/optics/iop/scattering.hpp>
#include <secchi/solver/plane_parallel.hpp>
#include <cstdio>
#include <string>
#include <vector>

namespace {
constexpr const char* usage = R"(usage: natural_water [MATERIAL_FILE [ENTRY]]
Solves a Case-1 water column at 490 nm (sun at 60 deg, flat surface, black sky, infinitely
deep; depth importance where the water absorbs an optical depth of ln 2 or more down to 20 m)
for Ed, Eou and Lu at 1, 5, 10 and 20 m: the medium composed in this file, or the
IOP_MODEL of MATERIAL_FILE (DIRSIG material-file syntax, e.g. examples/materials/*.mat; in a
file of MATERIAL_ENTRY sections, the entry whose ID or NAME is ENTRY, by default the only one
with BULK_PROPERTIES).
)";
}  // namespace

int main(int argc, char** argv) {
    using namespace secchi;
    return run_program(argc, argv, "natural_water", usage, [&] {
        const CommandLine cl(argc, argv, {}, {}, 2);
        const std::vector<std::string>& args = cl.positional();
        const double wavelength = 490.0;  // nm
        const auto depths = iop::uniform_depths(/*max m=*/100.0, /*spacing m=*/0.05);
        // Compile time: pure water plus chlorophyll-bearing particles (manual eq. 5.3-5.6).
        const iop::GaussianConcentration chl;  // eq. 5.30 with the manual's defaults (Celtic Sea)
        const auto model = iop::LinearIopModel(
            std::tuple{iop::HybridPureWaterAbsorption(), iop::MorelConcentrationAbsorption(chl)},
            std::tuple{iop::Scatterer{iop::BuiteveldScattering(), pure_water_phase()},
                       iop::Scatterer{iop::GordonMorelScattering(chl), petzold_m93()}});
        // Run time: the same kind of medium from a material file.
        const auto water = !args.empty() ? iop::stratify(io::read_iop_model(args[0], 1, args.size() > 1 ? args[1] : ""),
                                                         wavelength, depths)
                                    : iop::stratify(model, wavelength, depths);

        PlaneParallelConfig cfg;  // sun at 60 deg, flat surface, black sky, infinitely deep
        cfg.transport.photons = cfg.transport.map_photons = 100'000;
        cfg.transport.depths = {1.0, 5.0, 10.0, 20.0};
        cfg.transport.threads = 2;
        cfg.auto_importance = true;  // depth importance where the water absorbs tau_a >= ln 2 above 20 m
        const auto r = solve_stratified(water, cfg);
        std::printf("%s water at %.0f nm (%s)\n", !args.empty() ? args[0].c_str() : "composed Case-1", wavelength,
                    r.phase_name.c_str());
        std::printf("depth importance: %s\n", r.importance_choice.c_str());
        std::printf("%6s %21s %21s %21s   (value +- standard error)\n", "z (m)", "Ed", "Eou", "Lu");
        for (const auto& d : r.depths) {
            std::printf("%6.1f", d.depth);
            for (const Estimate& e : {d.irradiance[Ed], d.irradiance[Eou], d.lu}) std::printf(" %11.4e +- %7.1e", e.value, e.se);
            std::printf("\n");
        }
        return 0;
    });
}
