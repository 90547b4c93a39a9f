#pragma once
// slab's command line (examples/slab.cpp): its usage text, its options and their reading into a
// PlaneParallelConfig, without the run. Shared with the fuzz target fuzz/fuzz_cli.cpp, which
// parses command lines as slab does.
#include "secchi/io/cli.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <algorithm>
#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace secchi::examples::slab {

inline constexpr const char* usage_text = R"(usage: slab --phase {phases} --albedo W
            --sun-zenith DEG [--sky E | --source parametric-sky [--direct E --diffuse E]
            | --source atmosphere [--rayleigh-tau T --aerosol-tau T --aerosol-g G --aerosol-albedo W
            --aerosol-scale-height KM]] --water-index N [--wind U [--slopes {slopes} --wind-azimuth DEG]
            | --slope-variance S2] [--facets {facets}] [--shadowing {shadowings}]
            [--bottom-depth TAU --bottom-albedo A]
            --depths 0,1,5,10 --photons N --seed S --threads T --store {stores}
            [--radius R] [--steps K] [--importance-cosine MU] [--backscatter-bias EPS]
            [--upward-importance EPS [--upward-lobe G]] --json FILE
Phase functions (--phase NAME, or NAME:X with the parameter X; the same names are a material
file's ADD_PHASE_FUNCTION_MODEL TYPEs):
{phase-table}Depths and lengths are optical (c = 1 /m). Defaults:
  --phase petzold  --albedo 0.9  --sun-zenith 60  --water-index 1.34 (1.0: no interface)
  --sky 0 (a uniform sky of this downward plane irradiance beside the sun's E_perp = 1;
           0: a black sky, as in M93's problems)
  --source sun (default: the sun, E_perp = 1 at the surface, and --sky), parametric-sky (a
           0.53 deg sun disk and Harrison and Coombes' clear sky at the surface, scaled to
           --direct 0.4158 and --diffuse 0.2729, the downward plane irradiances just above the
           surface, default the manual's Gregg-Carder split for problem 4) or atmosphere (a
           traced plane-parallel atmosphere, E_perp = 1 at its top, coupled to the water:
           --rayleigh-tau 0.145 --aerosol-tau 0.264 (M93 problem 4), Henyey-Greenstein aerosol
           --aerosol-g 0.7 --aerosol-albedo 1, exponential profiles of scale heights 8 km and
           --aerosol-scale-height 2 km). Irradiances are per unit of the source's E_perp.
  --depths 1,5,10  --photons 1000000  --map-photons min(photons, 2000000)  --seed 1
  --threads 1  --batches 32  --store voi  --radius 0.05  --steps 64  --omega 0.005 (sr)
  --ray-transmittance 1e-4 (Lu's rays end where their transmittance falls to this, or at
               the bottom)  --ray-grid 10 (10 x 10 vertical rays per depth)  --section-width 1
  --cone-peak {cone-peaks} (default transmitted: the phase function's peak within the
               collection cone travels on along the ray; averaged: the manual's eq. 3.5)
  --absorption {absorptions} (default continuous: free paths from b, weight
               exp(-a s) along each flight; implicit: weight x w0 per collision; analog)
  --bottom-albedo 0 (with --bottom-depth: a Lambertian bottom)
  --wind U     (m/s; default: none, a flat surface) a wind-blown surface of Cox-Munk's
               isotropic slopes, sigma^2 = 0.003 + 0.00512 U (U = 7.23: M93 problem 5), or
               --slope-variance S2 directly; --slopes cox-munk [--wind-azimuth DEG]: Cox and
               Munk's anisotropic slopes instead, 0.00316 U along the wind and 0.003 +
               0.00192 U across it, the wind blowing towards DEG (default 0: +x);
               --facets projected-area (default: facets met in proportion to the area they
               show the photon, M93's weighting) or redraw (the manual's DIRSIG);
               --shadowing none (default, M93) or smith: light leaving the surface is hidden
               by the other waves with Smith's probability 1 - G1 and meets it again
  --shards 1   (the second pass's maps, each of an equal range of the batches: a divisor of
               --batches; a run with S shards gives the same bits on 1 process as on any
               number dividing S under mpirun (slab_mpi, docs/distributed.md))
  --tracer {tracers} (default photon; lanes: photons in SIMD lanes, the same
               estimates, faster when built for AVX2 or better, e.g. -march=native;
               lanes-float: in float lanes, twice as many per vector)
Variance reduction (transport/importance.hpp):
  --importance-cosine auto (depth importance: photons split each time the absorption optical
               depth grows by mu_i ln 2, down to the deepest of --depths, and are rouletted
               below it; auto: mu_i = 1 where the water absorbs an optical depth of ln 2 or more
               down to the deepest detector, else off; 0: off; in the lanes tracers with
               weighted photons only: not with --absorption analog)
The others are off by default:
  --backscatter-bias 0 (a share of the scattering angles drawn from the phase function's
               backward part: the upwelling irradiances at depth; weighted photons only: not
               with --absorption analog)
  --upward-importance 0 --upward-lobe 0.9 (PhotonTracer only: a share of the scattering
               directions drawn from a
               lobe of this Henyey-Greenstein g about straight up, the map stored by direction:
               the nadir radiance where the phase function's peak is broad; not with
               --backscatter-bias)
)";

/// How --wind sets the facet slopes: Cox and Munk's isotropic fit or their anisotropic one.
enum class SlopeModel { isotropic, cox_munk };

inline const std::vector<secchi::NamedValue<SlopeModel>>& slope_model_names() {
    static const std::vector<secchi::NamedValue<SlopeModel>> names{
        {{"isotropic", {}, "sigma^2 = 0.003 + 0.00512 U in every direction"}, SlopeModel::isotropic},
        {{"cox-munk", {}, "0.00316 U along the wind, 0.003 + 0.00192 U across it"}, SlopeModel::cox_munk},
    };
    return names;
}

/// The surface's facet slopes: none (flat) without --wind or --slope-variance.
inline secchi::FacetSlopes facet_slopes(const secchi::CommandLine& cl) {
    using secchi::FacetSlopes;
    if (cl.has("wind") && cl.has("slope-variance"))
        secchi::reject("--slope-variance", cl.text("slope-variance"), "conflicts with --wind (give one of them)");
    const std::string kind = cl.text("slopes", "isotropic");
    const SlopeModel model = secchi::parse_named(slope_model_names(), "--slopes", kind);
    if (model == SlopeModel::cox_munk && !cl.has("wind")) secchi::reject("--slopes", kind, "needs --wind");
    if (cl.has("wind-azimuth") && model != SlopeModel::cox_munk)
        secchi::reject("--wind-azimuth", cl.text("wind-azimuth"), "needs --slopes cox-munk");
    if (cl.has("slope-variance")) return FacetSlopes::isotropic(cl.number("slope-variance", 0));
    if (!cl.has("wind")) return {};
    const double wind = cl.number("wind", 0);
    return model == SlopeModel::cox_munk ? FacetSlopes::cox_munk(wind, cl.number("wind-azimuth", 0.0))
                                         : FacetSlopes::isotropic_at_wind(wind);
}

inline secchi::PlaneParallelConfig config_from(const secchi::CommandLine& cl) {
    secchi::PlaneParallelConfig cfg;
    cfg.albedo = cl.number("albedo", 0.9);
    cfg.sun_zenith_deg = cl.number("sun-zenith", 60.0);
    cfg.sky_irradiance = cl.number("sky", 0.0);
    cfg.source = secchi::parse_source(cl.text("source", "sun"));
    if (cfg.source != secchi::SourceKind::sun_and_sky && cl.has("sky"))
        secchi::reject("--sky", cl.text("sky"), "is the uniform sky beside the sun (--source sun)");
    for (const char* option : {"direct", "diffuse"})
        if (cl.has(option) && cfg.source != secchi::SourceKind::parametric_sky)
            secchi::reject(std::string("--") + option, cl.text(option), "needs --source parametric-sky");
    for (const char* option : {"rayleigh-tau", "aerosol-tau", "aerosol-g", "aerosol-albedo", "aerosol-scale-height"})
        if (cl.has(option) && cfg.source != secchi::SourceKind::atmosphere)
            secchi::reject(std::string("--") + option, cl.text(option), "needs --source atmosphere");
    cfg.parametric_sky.direct = cl.number("direct", cfg.parametric_sky.direct);
    cfg.parametric_sky.diffuse = cl.number("diffuse", cfg.parametric_sky.diffuse);
    auto& atm = cfg.atmosphere;
    atm.rayleigh_tau = cl.number("rayleigh-tau", atm.rayleigh_tau);
    atm.aerosol_tau = cl.number("aerosol-tau", atm.aerosol_tau);
    atm.aerosol_g = cl.number("aerosol-g", atm.aerosol_g);
    atm.aerosol_albedo = cl.number("aerosol-albedo", atm.aerosol_albedo);
    atm.aerosol_scale_height_km = cl.number("aerosol-scale-height", atm.aerosol_scale_height_km);
    cfg.water_index = cl.number("water-index", 1.34);
    cfg.slopes = facet_slopes(cl);
    cfg.facets = secchi::parse_facets(cl.text("facets", "projected-area"));
    cfg.shadowing = secchi::parse_shadowing(cl.text("shadowing", "none"));
    for (const char* option : {"facets", "shadowing"})  // the facets' options: nothing to change on a flat surface
        if (cl.has(option) && cfg.slopes.flat()) secchi::reject(std::string("--") + option, cl.text(option), "needs --wind or --slope-variance");
    if (cl.has("bottom-depth"))
        cfg.bottom = secchi::Bottom::lambertian_at(cl.number("bottom-depth", 0), cl.number("bottom-albedo", 0.0));
    else if (cl.has("bottom-albedo"))
        secchi::reject("--bottom-albedo", cl.text("bottom-albedo"), "needs --bottom-depth");
    auto& t = cfg.transport;
    t.depths = cl.numbers("depths", {1, 5, 10});
    t.photons = cl.count("photons", 1'000'000);
    t.map_photons = cl.count("map-photons", std::min<std::uint64_t>(t.photons, 2'000'000));
    t.seed = cl.count("seed", 1);
    t.threads = cl.threads(1);
    t.batches = cl.unsigned_count("batches", 32);
    t.absorption = secchi::parse_absorption(cl.text("absorption", "continuous"));
    cfg.store = secchi::parse_store(cl.text("store", "voi"));
    cfg.tracer = secchi::parse_tracer(cl.text("tracer", "photon"));
    cfg.radius = cl.number("radius", 0.05);
    cfg.steps = cl.unsigned_count("steps", 64);
    cfg.omega = cl.number("omega", 0.005);
    cfg.ray_transmittance = cl.number("ray-transmittance", 1e-4);
    cfg.cone_peak = secchi::parse_cone_peak(cl.text("cone-peak", "transmitted"));
    cfg.ray_grid = cl.unsigned_count("ray-grid", 10);
    cfg.section_width = cl.number("section-width", 1.0);
    cfg.shards = cl.unsigned_count("shards", 1);
    cfg.auto_importance = cl.text("importance-cosine", "auto") == "auto";
    if (!cfg.auto_importance)
        if (const double mu_i = cl.number("importance-cosine", 0.0); mu_i != 0.0)
            t.importance = {mu_i, t.deepest_detector()};
    t.backscatter_bias = cl.number("backscatter-bias", 0.0);
    t.upward_importance = cl.number("upward-importance", 0.0);
    t.upward_lobe = cl.number("upward-lobe", t.upward_lobe);
    if (cl.has("upward-lobe") && !(t.upward_importance > 0.0))
        secchi::reject("--upward-lobe", cl.text("upward-lobe"), "needs --upward-importance > 0");
    return cfg;
}

/// slab's usage text with the registries' names filled in.
inline std::string usage() {
    return secchi::fill_usage(usage_text, {{"phases", secchi::phase_usage()},
                                           {"phase-table", secchi::phase_help()},
                                           {"stores", secchi::store_usage()},
                                           {"slopes", secchi::usage_names(slope_model_names())},
                                           {"facets", secchi::usage_names(secchi::facet_sampling_names())},
                                           {"shadowings", secchi::usage_names(secchi::shadowing_names())},
                                           {"cone-peaks", secchi::usage_names(secchi::cone_peak_names())},
                                           {"tracers", secchi::usage_names(secchi::tracer_names())},
                                           {"absorptions", secchi::usage_names(secchi::absorption_names())}});
}

/// slab's command line: its options (--json FILE among them) checked as CommandLine does.
inline secchi::CommandLine command_line(int argc, char** argv) {
    return secchi::CommandLine(argc, argv,
                               {"phase", "albedo", "sun-zenith", "sky", "source", "direct", "diffuse", "rayleigh-tau",
                                "aerosol-tau", "aerosol-g", "aerosol-albedo", "aerosol-scale-height",
                                "water-index", "wind", "slope-variance", "slopes",
                                "wind-azimuth", "facets", "shadowing", "bottom-depth", "bottom-albedo",
                                "depths", "photons", "map-photons", "seed", "threads", "batches", "absorption",
                                "store", "radius", "steps", "omega", "ray-transmittance", "cone-peak", "ray-grid", "section-width",
                                "tracer", "shards", "importance-cosine", "backscatter-bias", "upward-importance", "upward-lobe",
                                "json"});
}

}  // namespace secchi::examples::slab
