// The Python module `secchi` (pybind11): plane-parallel problems, material files and photon
// maps queried along rays, with numpy arrays in and out. Everything is the library's own code
// (solver/plane_parallel.hpp, io/material_medium.hpp, estimate/radiance.hpp); this file only
// converts arguments and results. docs/python.md is the user's guide.
//
// Contracts:
//  - Invalid input raises secchi.InputError, a ValueError, carrying secchi's message (it names
//    the parameter, the value and the reason).
//  - The GIL is released while C++ traces photons, builds maps and queries rays.
//  - One phase type for every phase function: AnyPhaseFunction (optics/phase/any_phase.hpp)
//    forwards every call to the held function, so the numbers are bit-identical to the
//    programs', which visit the variant first (python/tests: against `slab`), while the
//    solver is compiled once instead of once per phase type.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <secchi/io/material_medium.hpp>
#include <secchi/solver/phase_choice.hpp>
#include <secchi/solver/plane_parallel.hpp>

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace py = pybind11;

namespace {

using Phase = secchi::AnyPhaseFunction;
using Water = secchi::HomogeneousWater<Phase>;
using Stratified = secchi::StratifiedWater<Phase>;
using MapStore = secchi::VoiGridStore<secchi::CompactRecord>;

/// A water column read from a material file at one wavelength: the solver's StratifiedWater
/// (shared: a photon map's optics refer to it).
struct Material {
    std::shared_ptr<const Stratified> water;
    std::string path;
    double wavelength_nm = 0.0;
};

/// The water a problem runs in: homogeneous (phase, albedo, attenuation) or a material's.
struct WaterChoice {
    std::optional<std::string> phase;
    std::optional<double> albedo, attenuation;
    const Material* material = nullptr;

    /// The homogeneous water's phase function (default Petzold's, as slab's).
    [[nodiscard]] Phase phase_function() const { return Phase{secchi::parse_phase(phase.value_or("petzold"))}; }
    /// input_error where a material's water comes with homogeneous water's parameters.
    void check() const {
        if (!material) return;
        if (phase) secchi::reject("phase", *phase, "conflicts with water (a material brings its own phase functions)");
        if (albedo) secchi::reject("albedo", *albedo, "conflicts with water (a material brings its own IOPs)");
        if (attenuation)
            secchi::reject("attenuation", *attenuation, "conflicts with water (a material brings its own IOPs)");
    }
};

/// The keywords every problem shares, as PlaneParallelConfig (slab's defaults; depths in m).
struct ProblemArgs {
    double sun_zenith = 60.0, sky = 0.0;
    std::optional<double> water_index, wind, bottom_depth, map_depth;
    double bottom_albedo = 0.0;
    std::vector<double> depths;
    std::uint64_t photons = 1'000'000;
    std::optional<std::uint64_t> map_photons;
    std::uint64_t seed = 1;
    unsigned threads = 1, batches = 32;
    std::string absorption = "continuous";
    double radius = 0.05, omega = 0.005;
    std::optional<double> importance_cosine;  ///< None: slab's auto (PlaneParallelConfig::auto_importance)
    double backscatter_bias = 0.0;
    std::string tracer = "photon";

    [[nodiscard]] secchi::PlaneParallelConfig config(const WaterChoice& water) const {
        water.check();
        secchi::PlaneParallelConfig cfg;
        cfg.attenuation = water.attenuation.value_or(1.0);
        cfg.albedo = water.albedo.value_or(0.9);
        cfg.sun_zenith_deg = sun_zenith;
        cfg.sky_irradiance = sky;
        // Unset: the material's own index (or 1.34); homogeneous water: 1.34, as slab's default.
        cfg.water_index = water.material ? water_index : std::optional<double>(water_index.value_or(1.34));
        if (wind) cfg.slopes = secchi::FacetSlopes::isotropic_at_wind(*wind);
        if (bottom_depth) cfg.bottom = secchi::Bottom::lambertian_at(*bottom_depth, bottom_albedo);
        else if (bottom_albedo != 0.0)
            secchi::reject("bottom_albedo", bottom_albedo, "needs bottom_depth (without it the water is infinitely deep)");
        auto& t = cfg.transport;
        t.depths = depths;
        t.photons = photons;
        t.map_photons = map_photons.value_or(std::min<std::uint64_t>(photons, 2'000'000));
        t.map_depth = map_depth.value_or(INFINITY);
        t.seed = seed;
        t.threads = threads;
        t.batches = batches;
        t.absorption = secchi::parse_absorption(absorption);
        cfg.radius = radius;
        cfg.omega = omega;
        cfg.auto_importance = !importance_cosine;
        if (importance_cosine && *importance_cosine != 0.0)
            t.importance = {*importance_cosine, t.deepest_detector()};
        t.backscatter_bias = backscatter_bias;
        cfg.tracer = secchi::parse_tracer(tracer);
        return cfg;
    }
};

py::array_t<double> array_of(const std::vector<double>& v) {
    py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
    std::copy(v.begin(), v.end(), a.mutable_data());
    return a;
}

/// A problem's results as numpy arrays, one entry per depth.
struct Result {
    py::array_t<double> depths, ed, ed_se, eu, eu_se, eod, eod_se, eou, eou_se;
    py::object lu, lu_se;  ///< None where no second pass ran (a photon map's first pass)
    std::string phase, source, depth_importance;
    std::uint64_t photons_traced = 0, photons_stored = 0;
    double seconds = 0.0;

    Result(const secchi::PlaneParallelResult& r, bool with_lu)
        : phase(r.phase_name), source(r.source_name), depth_importance(r.importance_choice),
          photons_traced(r.photons_traced), photons_stored(r.photons_stored), seconds(r.seconds) {
        std::vector<double> z;
        std::array<std::vector<double>, 4> value, se;
        std::vector<double> lu_value, lu_err;
        for (const auto& d : r.depths) {
            z.push_back(d.depth);
            for (std::size_t k = 0; k < 4; ++k) {
                value[k].push_back(d.irradiance[k].value);
                se[k].push_back(d.irradiance[k].se);
            }
            lu_value.push_back(d.lu.value);
            lu_err.push_back(d.lu.se);
        }
        depths = array_of(z);
        ed = array_of(value[secchi::Ed]), ed_se = array_of(se[secchi::Ed]);
        eu = array_of(value[secchi::Eu]), eu_se = array_of(se[secchi::Eu]);
        eod = array_of(value[secchi::Eod]), eod_se = array_of(se[secchi::Eod]);
        eou = array_of(value[secchi::Eou]), eou_se = array_of(se[secchi::Eou]);
        lu = with_lu ? py::object(array_of(lu_value)) : py::none();
        lu_se = with_lu ? py::object(array_of(lu_err)) : py::none();
    }
};

/// Both passes of a plane-parallel problem (solve_plane_parallel, or solve_stratified in a
/// material's water).
Result solve(const WaterChoice& water, const ProblemArgs& args, const std::string& store) {
    secchi::PlaneParallelConfig cfg = args.config(water);
    cfg.store = secchi::parse_store(store);
    secchi::PlaneParallelResult r;
    if (water.material) {
        py::gil_scoped_release release;
        r = secchi::solve_stratified(*water.material->water, cfg);
    } else {
        const Phase phase = water.phase_function();
        py::gil_scoped_release release;
        r = secchi::solve_plane_parallel(phase, cfg);
    }
    return Result(r, true);
}

/// The radiance queries of one photon map (its optics' type depends on the water).
struct RayQueries {
    virtual ~RayQueries() = default;
    [[nodiscard]] virtual secchi::Estimate radiance(const secchi::Ray& ray, unsigned band) const = 0;
    [[nodiscard]] virtual const secchi::PlaneParallelResult& first_pass() const = 0;
    [[nodiscard]] virtual std::size_t stored() const = 0;
};

/// A traced map (trace_photon_map into a VOI grid) and its estimator with the VOI cylinder:
/// the estimator refers to the map (and a material's optics to the water), so this object
/// owns both and never moves.
template <class Optics>
struct MapQueries final : RayQueries {
    secchi::MappedWater<MapStore> mapped;
    std::shared_ptr<const Stratified> water;  ///< a material's water, which the optics refer to
    secchi::RadianceEstimator<MapStore, secchi::VoiCylinder, Optics> estimator;

    MapQueries(secchi::MappedWater<MapStore> m, std::shared_ptr<const Stratified> w, const Optics& optics,
               const secchi::PlaneParallelConfig& cfg)
        : mapped(std::move(m)), water(std::move(w)),
          estimator(mapped.map, secchi::VoiCylinder(0.0, cfg.bottom.depth()), optics, secchi::Radius(cfg.radius),
                    secchi::RadianceSettings{cfg.ray_transmittance}) {}
    MapQueries(const MapQueries&) = delete;
    MapQueries& operator=(const MapQueries&) = delete;

    secchi::Estimate radiance(const secchi::Ray& ray, unsigned band) const override {
        return estimator.radiance(ray, band);
    }
    const secchi::PlaneParallelResult& first_pass() const override { return mapped.first_pass; }
    std::size_t stored() const override { return mapped.map.store().records().size(); }
};

/// secchi.PhotonMap: a first pass's photon map, queried along any rays.
struct PhotonMapHandle {
    std::unique_ptr<RayQueries> queries;
    unsigned threads = 1;
};

PhotonMapHandle trace_map(const WaterChoice& water, const ProblemArgs& args) {
    const secchi::PlaneParallelConfig cfg = args.config(water);
    const secchi::Radius radius(cfg.radius);
    PhotonMapHandle handle{nullptr, cfg.transport.threads};
    if (water.material) {
        const auto& shared = water.material->water;
        py::gil_scoped_release release;
        std::vector<secchi::ConeAveragedPhase<Phase>> cones;
        for (const auto& p : shared->phases()) cones.emplace_back(p, cfg.omega, cfg.cone_peak, secchi::cone_table(cfg));
        const secchi::StratifiedRayOptics optics(*shared, cones);
        handle.queries = std::make_unique<MapQueries<std::remove_cvref_t<decltype(optics)>>>(
            secchi::trace_photon_map<MapStore>(*shared, cfg, radius), shared, optics, cfg);
    } else {
        const Phase phase = water.phase_function();
        py::gil_scoped_release release;
        const auto medium = Water::from_albedo(cfg.attenuation, cfg.albedo, phase);
        const secchi::ConeAveragedPhase cone(phase, cfg.omega, cfg.cone_peak, secchi::cone_table(cfg));
        const secchi::HomogeneousRayOptics optics(cone, medium.attenuation(), medium.scattering());
        handle.queries = std::make_unique<MapQueries<secchi::HomogeneousRayOptics>>(
            secchi::trace_photon_map<MapStore>(medium, cfg, radius), nullptr, optics, cfg);
    }
    return handle;
}

/// The rows of an (N, 3) array, or the one vector of a (3,) array; input_error naming the
/// array otherwise.
std::vector<secchi::vec3> vectors_of(const py::array_t<double, py::array::c_style | py::array::forcecast>& a,
                                     const char* name) {
    const bool one = a.ndim() == 1 && a.shape(0) == 3;
    if (!one && !(a.ndim() == 2 && a.shape(1) == 3)) {
        std::string shape;
        for (py::ssize_t k = 0; k < a.ndim(); ++k) shape.append(k ? ", " : "").append(std::to_string(a.shape(k)));
        secchi::reject(name, std::string("an array of shape (").append(shape).append(")"), "must be of shape (N, 3) or (3,)");
    }
    std::vector<secchi::vec3> v(one ? 1 : static_cast<std::size_t>(a.shape(0)));
    const double* p = a.data();
    for (auto& x : v) {
        x = {p[0], p[1], p[2]};
        p += 3;
    }
    return v;
}

/// Radiance along rays: origins and directions (N, 3) (either may be one (3,) for all rays),
/// lengths (N,) or one number; returns (values, standard errors), each of shape (N,).
py::tuple radiance(const PhotonMapHandle& m, const py::array_t<double, py::array::c_style | py::array::forcecast>& origins,
                   const py::array_t<double, py::array::c_style | py::array::forcecast>& directions,
                   const std::optional<py::array_t<double, py::array::c_style | py::array::forcecast>>& lengths,
                   unsigned band, std::optional<unsigned> threads) {
    auto o = vectors_of(origins, "origins");
    auto d = vectors_of(directions, "directions");
    std::vector<double> t{INFINITY};
    if (lengths) {
        const auto& l = *lengths;
        if (l.ndim() > 1) secchi::reject("lengths", l.ndim(), "must be one number or of shape (N,) (ndim given)");
        t.assign(l.data(), l.data() + l.size());
    }
    std::size_t n = 1;
    for (std::size_t k : {o.size(), d.size(), t.size()})
        if (k != 1) {
            if (n != 1 && k != n)
                secchi::reject("rays", k, "origins, directions and lengths must have the same count N (or be one for all)");
            n = k;
        }
    for (std::size_t i = 0; i < d.size(); ++i) {
        const double len = glm::length(d[i]);
        if (!(len > 0.0) || !std::isfinite(len)) secchi::reject(secchi::indexed_name("directions", i), len, "must have a finite, nonzero length");
        d[i] /= len;  // any length: the rays' directions are the unit vectors along them
    }
    py::array_t<double> values(static_cast<py::ssize_t>(n)), ses(static_cast<py::ssize_t>(n));
    double* v = values.mutable_data();
    double* s = ses.mutable_data();
    {
        py::gil_scoped_release release;
        const auto pick = [](const auto& xs, std::size_t i) { return xs[xs.size() == 1 ? 0 : i]; };
        secchi::parallel_for(n, threads.value_or(m.threads), [&](std::size_t i) {
            const secchi::Estimate e = m.queries->radiance(secchi::Ray{pick(o, i), pick(d, i), pick(t, i)}, band);
            v[i] = e.value;
            s[i] = e.se;
        });
    }
    return py::make_tuple(values, ses);
}

Material read_material(const std::filesystem::path& path, double wavelength_nm, std::optional<std::vector<double>> depths,
                       const std::string& entry, std::uint64_t seed) {
    secchi::require(std::isfinite(wavelength_nm) && wavelength_nm > 0.0, "wavelength_nm", wavelength_nm,
                    "must be finite and > 0");
    const std::vector<double> z = depths ? *depths : secchi::iop::uniform_depths(100.0, 0.05);
    py::gil_scoped_release release;
    return {std::make_shared<const Stratified>(
                secchi::iop::stratify(secchi::io::read_iop_model(path, seed, entry), wavelength_nm, z)),
            path.string(), wavelength_nm};
}

/// Material's coefficient k at its depth nodes.
py::array_t<double> coefficient_at_nodes(const Material& m, secchi::Coefficient k) {
    std::vector<double> v;
    for (double z : m.water->depths()) v.push_back(m.water->coefficient(k, z));
    return array_of(v);
}

/// A Python function of the problem keywords (in the order of `keywords` in the module below)
/// and then Extra..., calling f(water, problem, extra...).
template <class... Extra, class F>
auto problem_function(F f) {
    return [f](std::optional<std::string> phase, std::optional<double> albedo, std::optional<double> attenuation,
               const Material* water, double sun_zenith, double sky, std::optional<double> water_index,
               std::optional<double> wind, std::optional<double> bottom_depth, double bottom_albedo,
               std::vector<double> depths, std::uint64_t photons, std::optional<std::uint64_t> map_photons,
               std::optional<double> map_depth, std::uint64_t seed, unsigned threads, unsigned batches,
               std::string absorption, double radius, double omega, std::optional<double> importance_cosine,
               double backscatter_bias, std::string tracer, Extra... extra) {
        return f(WaterChoice{std::move(phase), albedo, attenuation, water},
                 ProblemArgs{sun_zenith, sky, water_index, wind, bottom_depth, map_depth, bottom_albedo,
                             std::move(depths), photons, map_photons, seed, threads, batches, std::move(absorption),
                             radius, omega, importance_cosine, backscatter_bias, std::move(tracer)},
                 std::move(extra)...);
    };
}

/// The problem keywords' help, the names of phase functions and absorption modes from their
/// registries.
std::string problem_help() {
    std::string s(R"(
Water (homogeneous, c = attenuation, w0 = albedo; or a material's):
  phase="petzold"      a phase function by name (slab's --phase): )");
    s.append(secchi::phase_usage()).append(R"(
  albedo=0.9           single-scattering albedo w0 = b / c
  attenuation=1.0      c (1/m): depths in metres are then optical depths tau = c z
  water=None           a Material (read_material) instead of phase, albedo and attenuation
Light and boundaries:
  sun_zenith=60        degrees; the sun's E_perp = 1 above the surface
  sky=0.0              a uniform sky's plane irradiance beside the sun (0: black)
  water_index=None     the water's refractive index (1.0: no interface); None: the
                       material's own, else 1.34
  wind=None            m/s: a wind-blown surface of Cox-Munk's isotropic slopes; None: flat
  bottom_depth=None    m: a Lambertian bottom there; None: infinitely deep
  bottom_albedo=0.0    the bottom's irradiance reflectance (needs bottom_depth)
Monte Carlo:
  depths=[1, 5, 10]    m: where Ed, Eu, Eod, Eou (and Lu) are estimated
  photons=1000000      photons traced; map_photons=None: min(photons, 2000000) of them stored
  map_depth=None       m: events deeper than this are not stored (None: all)
  seed=1, threads=1, batches=32 (independent batches for the standard errors)
  absorption="continuous"  )");
    s.append(secchi::usage_names(secchi::absorption_names())).append(R"(
  radius=0.05          the collection radius (m); omega=0.005: the collection solid angle (sr)
  importance_cosine=None  depth importance's mu_i (0: off); None: slab's auto, mu_i = 1
                       where the water absorbs an optical depth of ln 2 or more down to the
                       deepest of `depths` (Result.depth_importance says what was used)
  backscatter_bias=0.0 a share of the scattering angles drawn from the phase function's
                       backward part, the weights corrected (the upwelling irradiances at
                       depth; Henyey-Greenstein and tables such as petzold; not with
                       absorption="analog")
  tracer="photon"      the first pass's tracer (slab's --tracer): )");
    s.append(secchi::usage_names(secchi::tracer_names())).append(R"(
                       photons one at a time, in SIMD lanes of doubles, or of floats
                       (the same physics; the lanes split weighted photons only)
Invalid values raise InputError (a ValueError) naming the parameter.)");
    return s;
}

}  // namespace

PYBIND11_MODULE(secchi, m) {
    m.doc() = "secchi: radiative transfer in natural waters by volumetric photon mapping (docs/python.md)";
    py::register_exception<secchi::input_error>(m, "InputError", PyExc_ValueError);

    py::class_<Result>(m, "Result", "A plane-parallel problem's estimates: numpy arrays, one entry per depth; "
                                    "every value has its standard error (..._se).")
        .def_readonly("depths", &Result::depths, "m")
        .def_readonly("ed", &Result::ed, "downwelling plane irradiance Ed (per unit solar E_perp)")
        .def_readonly("ed_se", &Result::ed_se)
        .def_readonly("eu", &Result::eu, "upwelling plane irradiance Eu")
        .def_readonly("eu_se", &Result::eu_se)
        .def_readonly("eod", &Result::eod, "downwelling scalar irradiance Eod")
        .def_readonly("eod_se", &Result::eod_se)
        .def_readonly("eou", &Result::eou, "upwelling scalar irradiance Eou")
        .def_readonly("eou_se", &Result::eou_se)
        .def_readonly("lu", &Result::lu, "nadir (upwelling) radiance Lu; None for a photon map's first pass")
        .def_readonly("lu_se", &Result::lu_se)
        .def_readonly("phase", &Result::phase, "the phase function's name")
        .def_readonly("source", &Result::source, "the light source's name")
        .def_readonly("photons_traced", &Result::photons_traced)
        .def_readonly("photons_stored", &Result::photons_stored)
        .def_readonly("seconds", &Result::seconds)
        .def_readonly("depth_importance", &Result::depth_importance, "the depth importance the first pass used, and why")
        .def("__repr__", [](const Result& r) {
            std::string s("<secchi.Result ");
            s.append(r.phase).append(", ").append(std::to_string(r.depths.size())).append(" depths, ");
            s.append(std::to_string(r.photons_traced)).append(" photons>");
            return s;
        });

    py::class_<Material>(m, "Material", "A material file's water at one wavelength: the IOPs at depth nodes, "
                                        "linear in between (pass it to solve or trace_map as water=).")
        .def_property_readonly("depths", [](const Material& w) { return array_of(w.water->depths()); }, "m")
        .def_property_readonly("absorption", [](const Material& w) { return coefficient_at_nodes(w, secchi::Coefficient::absorption); }, "a (1/m) at the depths")
        .def_property_readonly("scattering", [](const Material& w) { return coefficient_at_nodes(w, secchi::Coefficient::scattering); }, "b (1/m) at the depths")
        .def_property_readonly("attenuation", [](const Material& w) { return coefficient_at_nodes(w, secchi::Coefficient::attenuation); }, "c = a + b (1/m)")
        .def_property_readonly(
            "component_scattering",
            [](const Material& w) {
                const auto& z = w.water->depths();
                py::array_t<double> a({static_cast<py::ssize_t>(w.water->components()), static_cast<py::ssize_t>(z.size())});
                auto r = a.mutable_unchecked<2>();
                for (std::size_t i = 0; i < w.water->components(); ++i)
                    for (std::size_t k = 0; k < z.size(); ++k)
                        r(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(k)) = w.water->component_scattering(i, z[k]);
                return a;
            },
            "b_i (1/m): one row per scattering component, one column per depth")
        .def_property_readonly("phases", [](const Material& w) {
            std::vector<std::string> names;
            for (const auto& p : w.water->phases()) names.push_back(p.name());
            return names;
        }, "the scattering components' phase functions, by name")
        .def_property_readonly("refractive_index", [](const Material& w) { return w.water->refractive_index(); },
                               "the water's index at the wavelength, or None")
        .def_readonly("path", &Material::path)
        .def_readonly("wavelength_nm", &Material::wavelength_nm)
        .def("__repr__", [](const Material& w) {
            std::string s("<secchi.Material ");
            s.append(w.path).append(" at ").append(std::to_string(w.wavelength_nm)).append(" nm>");
            return s;
        });

    m.def("read_material", &read_material, py::arg("path"), py::arg("wavelength_nm"), py::kw_only(),
          py::arg("depths") = py::none(), py::arg("entry") = "", py::arg("seed") = 1,
          "The IOP_MODEL of a DIRSIG material file (docs/natural-waters.md) sampled at wavelength_nm at the "
          "depth nodes `depths` (m; default 0 to 100 m every 0.05 m). entry: the MATERIAL_ENTRY's ID or NAME "
          "(default: the only one with BULK_PROPERTIES); seed: SIGMA noise.");

    py::class_<PhotonMapHandle>(m, "PhotonMap", "A first pass's photons in a VOI grid, queried along rays.")
        .def("radiance", &radiance, py::arg("origins"), py::arg("directions"), py::kw_only(),
             py::arg("lengths") = py::none(), py::arg("band") = 0, py::arg("threads") = py::none(),
             "Radiance arriving at each origin against its direction (z down, the surface at z = 0; "
             "directions need not be unit vectors), along the ray up to its length (default: unbounded; "
             "the surface, the bottom or the ray's transmittance 1e-4 end it) plus what it sees there. "
             "origins, directions: (N, 3) or one (3,) for every ray; lengths: (N,) or one number. "
             "Returns (values, standard errors), each of shape (N,). threads: default the map's.")
        .def_property_readonly("first_pass", [](const PhotonMapHandle& h) { return Result(h.queries->first_pass(), false); },
                               "the first pass's irradiances at the depths asked for (lu is None)")
        .def_property_readonly("stored", [](const PhotonMapHandle& h) { return h.queries->stored(); },
                               "scattering events in the map");

    // The keywords of solve and trace_map, in problem_function's order.
    const auto keywords = [](auto&&... extra) {
        return std::tuple{py::kw_only(), py::arg("phase") = py::none(), py::arg("albedo") = py::none(),
                          py::arg("attenuation") = py::none(), py::arg("water") = py::none(),
                          py::arg("sun_zenith") = 60.0, py::arg("sky") = 0.0, py::arg("water_index") = py::none(),
                          py::arg("wind") = py::none(), py::arg("bottom_depth") = py::none(),
                          py::arg("bottom_albedo") = 0.0, py::arg("depths") = std::vector<double>{1.0, 5.0, 10.0},
                          py::arg("photons") = 1'000'000, py::arg("map_photons") = py::none(),
                          py::arg("map_depth") = py::none(), py::arg("seed") = 1, py::arg("threads") = 1,
                          py::arg("batches") = 32, py::arg("absorption") = "continuous", py::arg("radius") = 0.05,
                          py::arg("omega") = 0.005, py::arg("importance_cosine") = py::none(),
                          py::arg("backscatter_bias") = 0.0, py::arg("tracer") = "photon", extra...};
    };
    const auto define = [&m](const char* name, auto function, const std::string& doc, auto arguments) {
        std::apply([&](auto&&... args) { m.def(name, function, args..., doc.c_str()); }, arguments);
    };
    define("solve", problem_function<std::string>([](const WaterChoice& w, const ProblemArgs& a, const std::string& store) {
               return solve(w, a, store);
           }),
           std::string("A plane-parallel problem, both passes (slab's): Ed, Eu, Eod, "
                       "Eou and nadir Lu with standard errors at each depth.\n"
                       "  store=\"voi\"          the photon store: ")
               .append(secchi::store_usage())
               .append(problem_help()),
           keywords(py::arg("store") = "voi"));
    define("trace_map", problem_function<>([](const WaterChoice& w, const ProblemArgs& a) { return trace_map(w, a); }),
           std::string("A plane-parallel problem's first pass, its photons stored "
                       "in a VOI grid for radiance along any rays (PhotonMap.radiance); the first pass's irradiances "
                       "at `depths`: PhotonMap.first_pass.")
               .append(problem_help()),
           keywords());
}
