#pragma once
// The run-time form of a medium: the IOP_MODEL of a DIRSIG material file (manual chapter 5)
// bound to secchi's model types, as an iop::RuntimeIopModel (type-erased, used only to
// sample the depth profile; the transport runs on the resulting StratifiedWater).
//
//   BULK_PROPERTIES {            (alone, as in the manual, or inside a DIRSIG MATERIAL_ENTRY {
//     IOP_MODEL {                 ID = ... NAME = ... }: bind_iop_model below)
//       BASE_MEDIUM = null | air | purewater | sbpurewater | pspurewater      (5.3)
//       ADD_CONCENTRATION_MODEL  { TYPE = constant | linear | gaussian ... }   (5.10)
//       ADD_ABSORPTION_MODEL     { TYPE = constant | specific | morelconc | morelcovar | raman
//                                         | sbpf | smithbaker | prieursathy
//                                         | bricaud1995 | bricaud1998 | cdom ... }  (5.6)
//       ADD_SCATTERING_MODEL     { TYPE = constant | specific | gordonmorel | kopelevich
//                                         | buiteveld ... }                          (5.7)
//       ADD_PHASE_FUNCTION_MODEL { TYPE = uniform | data | hgpf | schlick | rayleigh | petzold
//                                         | petzold-trapezoid | petzold-linear | pure-water
//                                         | fournierforand ... SCATID = ... }        (5.8)
//                                 (names and parameters: optics/phase/phase_names.hpp)
//       REFRACTIVE_INDEX_MODEL   { TYPE = constant | iapws ... }                   (5.9)
//     }
//   }
// Parameter names and defaults are the manual's tables (see each model's header). Beyond the
// manual: bricaud1995 / bricaud1998 (CONCID; bricaud1998 FRACTION = particles|phytoplankton),
// cdom (A440, REFWL, S), the phase functions fournierforand (BB = b_b/b, N = 1.10),
// pure-water and the Petzold readings, and the command line's phase names (isotropic, hg, ff)
// as aliases of the manual's.
// Cross-references: CONCID names an ADD_CONCENTRATION_MODEL's ID, ABSID an absorption model's,
// SCATID a scattering model's; each must exist (and a scattering model takes at most one
// phase function; one without gets the uniform one). A gordonmorel model with EXCLUSIVE = 1
// removes every other scattering model, the base medium's included.
// Every error names the file, line, section and parameter. SIGMA noise is keyed by the run's
// seed and the model's position in the file (optics/iop/noise.hpp).
#include "secchi/core/config.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/io/material_file.hpp"
#include "secchi/optics/iop/absorption.hpp"
#include "secchi/optics/iop/coefficient.hpp"
#include "secchi/optics/iop/concentration.hpp"
#include "secchi/optics/iop/linear_model.hpp"
#include "secchi/optics/iop/refractive_index.hpp"
#include "secchi/optics/iop/scattering.hpp"
#include "secchi/optics/phase/phase_names.hpp"
#include <limits>
#include <map>
#include <optional>

namespace secchi::SECCHI_ISA::io {

namespace detail {

/// Where a model's own error "invalid NAME = value: ..." points in the file: the line of the
/// parameter NAME (matched ignoring case: the models say "g" for the file's G), else the
/// section's line.
inline std::string culprit_location(const ParameterReader& r, std::string_view message) {
    constexpr std::string_view prefix = "invalid ";
    const auto eq = message.find(" = ");
    if (message.substr(0, prefix.size()) == prefix && eq != std::string_view::npos) {
        const std::string_view name = message.substr(prefix.size(), eq - prefix.size());
        const auto same = [&](const MaterialParameter& p) {
            return std::equal(p.name.begin(), p.name.end(), name.begin(), name.end(), [](char a, char b) {
                return std::toupper(static_cast<unsigned char>(a)) == std::toupper(static_cast<unsigned char>(b));
            });
        };
        const auto& ps = r.section().parameters;
        if (const auto it = std::find_if(ps.begin(), ps.end(), same); it != ps.end()) return it->loc.where();
    }
    return r.section().loc.where();
}

/// Runs f(); an input_error from a model's own checks gets the file:line of the parameter it
/// names (or of the section) and the section appended.
template <class F>
auto in_section(const ParameterReader& r, F&& f) {
    try {
        return f();
    } catch (const input_error& e) {
        throw input_error(std::string(e.what()) + " in section " + r.context() + " at " + culprit_location(r, e.what()));
    }
}

class MaterialBinder {
public:
    MaterialBinder(std::uint64_t seed) : seed_(seed) {}

    iop::RuntimeIopModel bind(const MaterialSection& iop_model) {
        ParameterReader top(iop_model);
        reject_unknown_sections(iop_model);
        const std::string base = top.text("BASE_MEDIUM");
        for (const auto* s : iop_model.all("ADD_CONCENTRATION_MODEL")) add_concentration(*s);
        add_base_medium(base, top);
        for (const auto* s : iop_model.all("ADD_ABSORPTION_MODEL")) add_absorption(*s, false);
        for (const auto* s : iop_model.all("ADD_ABSORPTION_MODEL")) add_absorption(*s, true);  // covariant ones
        for (const auto* s : iop_model.all("ADD_SCATTERING_MODEL")) add_scattering(*s);
        for (const auto* s : iop_model.all("ADD_PHASE_FUNCTION_MODEL")) add_phase(*s);
        const auto ior = iop_model.all("REFRACTIVE_INDEX_MODEL");
        if (ior.size() > 1) ParameterReader(*ior[1]).reject_value("TYPE", "only one REFRACTIVE_INDEX_MODEL is allowed");
        if (!ior.empty()) set_refractive_index(*ior[0]);
        top.finish();
        return finish();
    }

private:
    struct NamedScatterer {
        std::string id;
        iop::AnyCoefficient coefficient;
        std::optional<AnyPhaseFunction> phase;
        bool exclusive = false;
    };

    /// A model section holds parameters only: a nested section would otherwise be ignored.
    static void reject_subsections(const MaterialSection& s) {
        for (const auto& sub : s.sections)
            reject("section", sub.name, "unexpected section inside " + s.describe(), sub.loc.where());
    }

    static void reject_unknown_sections(const MaterialSection& s) {
        static const std::vector<std::string> known{"ADD_CONCENTRATION_MODEL", "ADD_ABSORPTION_MODEL",
                                                    "ADD_SCATTERING_MODEL", "ADD_PHASE_FUNCTION_MODEL",
                                                    "REFRACTIVE_INDEX_MODEL"};
        for (const auto& sub : s.sections)
            if (std::find(known.begin(), known.end(), sub.name) == known.end())
                reject("section", sub.name, "unknown section in IOP_MODEL", sub.loc.where());
    }

    iop::Noise noise(ParameterReader& r) {
        const double sigma = r.number_in("SIGMA", 0.0, 0.0, std::numeric_limits<double>::max());
        return iop::Noise(sigma, seed_, next_key_++);
    }

    void add_base_medium(const std::string& base, ParameterReader& r) {
        if (base == "null" || base == "air") {
            n_ = [v = base == "air" ? 1.0003 : 1.0](double) { return v; };
            return;
        }
        if (base == "purewater") absorbers_.emplace_back("purewater", iop::HybridPureWaterAbsorption());
        else if (base == "sbpurewater") absorbers_.emplace_back("sbpurewater", iop::SmithBakerAbsorption());
        else if (base == "pspurewater") absorbers_.emplace_back("pspurewater", iop::PrieurSathyAbsorption());
        else r.reject_value("BASE_MEDIUM", "must be null, air, purewater, sbpurewater or pspurewater");
        // Every pure water: Buiteveld scattering (eq. 5.1) with the Rayleigh-like phase
        // function of eq. 5.2, and the IAPWS index at 286 K (5.3.3).
        scatterers_.push_back({base, iop::BuiteveldScattering(), AnyPhaseFunction{pure_water_phase()}, false});
        n_ = [ior = iop::pure_water_refractive_index()](double wl) { return ior.refractive_index(wl); };
    }

    void add_concentration(const MaterialSection& s) {
        reject_subsections(s);
        ParameterReader r(s);
        const std::string type = r.text("TYPE");
        const std::string id = r.text("ID", "chlorophyll");
        const auto nz = noise(r);
        auto model = in_section(r, [&]() -> iop::AnyConcentration {
            if (type == "constant") return iop::ConstantConcentration({r.number("CONC", 2.0)}, nz);
            if (type == "linear")
                return iop::LinearConcentration({r.number("ATZERO", 2.0), r.number("ZLEVEL", 0.0), r.number("RATE", -0.1)},
                                                nz);
            if (type == "gaussian" || type == "gauss")  // the manual's 5.10 example writes "gauss"
                return iop::GaussianConcentration({r.number("ZLEVEL", 0.0), r.number("DMAX", 17.0),
                                                   r.number("BG", 0.2), r.number("H", 144.0), r.number("S", 9.0)},
                                                  nz);
            r.reject_value("TYPE", "unknown concentration model (constant, linear, gaussian)");
        });
        if (concentrations_.count(id)) r.reject_value("ID", "a concentration model with this ID already exists");
        concentrations_.emplace(id, std::move(model));
        r.finish();
    }

    iop::AnyConcentration concentration(ParameterReader& r, const std::string& fallback = "chlorophyll") {
        const std::string id = r.text("CONCID", fallback);
        if (id == "none") return iop::NoConcentration{};
        const auto it = concentrations_.find(id);
        if (it == concentrations_.end()) r.reject_value("CONCID", "no ADD_CONCENTRATION_MODEL has this ID");
        return it->second;
    }

    iop::SpectralTable spectral_file(ParameterReader& r) {
        const auto data = read_spectral_file(r.file("FILENAME"));
        return in_section(r, [&] { return iop::SpectralTable(data.path.string(), data.wavelength_nm, data.value); });
    }

    /// constant: ABS/SCAT, or FILENAME (which overrides the constant, manual 5.6.1).
    iop::AnyCoefficient constant_coefficient(ParameterReader& r, const char* value_name, const iop::Noise& nz) {
        if (r.has("FILENAME")) return iop::ConstantCoefficient(spectral_file(r), nz);
        return iop::ConstantCoefficient(r.number(value_name, 0.1), nz);
    }

    void add_absorption(const MaterialSection& s, bool covariant_pass) {
        reject_subsections(s);
        ParameterReader r(s);
        const std::string type = r.text("TYPE");
        if ((type == "morelcovar") != covariant_pass) return;
        const std::string id = r.text("ID", type == "morelcovar" ? "morelcov" : type);
        const auto nz = noise(r);
        auto model = in_section(r, [&]() -> iop::AnyCoefficient {
            if (type == "constant") return constant_coefficient(r, "ABS", nz);
            if (type == "specific") return iop::SpecificCoefficient(spectral_file(r), concentration(r), nz);
            if (type == "morelconc") return morel_concentration(r, nz);
            if (type == "morelcovar") return morel_covariant(r, nz);
            if (type == "raman")
                return iop::RamanAbsorption({r.number("REFWL", 488.0), r.number("REFABS", 0.00026), r.number("Q", 5.5)},
                                            nz);
            if (type == "sbpf") return iop::HybridPureWaterAbsorption(nz);
            if (type == "smithbaker") return iop::SmithBakerAbsorption(nz);
            if (type == "prieursathy") return iop::PrieurSathyAbsorption(nz);
            if (type == "bricaud1995") return iop::Bricaud1995Absorption(concentration(r), nz);
            if (type == "bricaud1998") return bricaud1998(r, nz);
            if (type == "cdom")
                return iop::CdomAbsorption({r.number("A440", 0.012), r.number("REFWL", 440.0), r.number("S", 0.014)}, nz);
            r.reject_value("TYPE",
                           "unknown absorption model (constant, specific, morelconc, morelcovar, raman, sbpf, "
                           "smithbaker, prieursathy, bricaud1995, bricaud1998, cdom)");
        });
        for (const auto& [existing, m] : absorbers_)
            if (existing == id) r.reject_value("ID", "an absorption model with this ID already exists");
        absorbers_.emplace_back(id, std::move(model));
        r.finish();
    }

    iop::AnyCoefficient morel_concentration(ParameterReader& r, const iop::Noise& nz) {
        iop::MorelConcentrationParams p;
        if (r.has("FILENAME")) p.table = spectral_file(r);
        else if (r.has("ABS")) p.table.reset();  // a constant specific absorption instead of the default table
        p.abs = r.number("ABS", p.abs);
        p.refwl = r.number("REFWL", p.refwl);
        p.prenorm = r.flag("PRENORM", p.prenorm);
        p.k = r.number("K", p.k);
        p.q = r.number("Q", p.q);
        return iop::MorelConcentrationAbsorption(concentration(r), std::move(p), nz);
    }

    iop::AnyCoefficient morel_covariant(ParameterReader& r, const iop::Noise& nz) {
        const std::string base_id = r.text("ABSID", "morelconc");
        const auto it = std::find_if(absorbers_.begin(), absorbers_.end(), [&](const auto& a) { return a.first == base_id; });
        if (it == absorbers_.end()) r.reject_value("ABSID", "no (non-covariant) absorption model has this ID");
        return iop::MorelCovariantAbsorption(it->second, {r.number("REFWL", 440.0), r.flag("USEWL", false),
                                                          r.number("K", 0.2), r.number("Q", -0.014)},
                                             nz);
    }

    iop::AnyCoefficient bricaud1998(ParameterReader& r, const iop::Noise& nz) {
        const std::string fraction = r.text("FRACTION", "particles");
        if (fraction != "particles" && fraction != "phytoplankton")
            r.reject_value("FRACTION", "must be particles or phytoplankton");
        return iop::Bricaud1998Absorption(concentration(r),
                                          fraction == "particles" ? iop::Bricaud1998Fraction::particles
                                                                  : iop::Bricaud1998Fraction::phytoplankton,
                                          nz);
    }

    void add_scattering(const MaterialSection& s) {
        reject_subsections(s);
        ParameterReader r(s);
        const std::string type = r.text("TYPE");
        static const std::map<std::string, std::string> default_id{{"constant", "constant"},  {"specific", "specific"},
                                                                   {"gordonmorel", "gmconc"}, {"kopelevich", "kconc"},
                                                                   {"buiteveld", "buiteveld"}};
        const auto def = default_id.find(type);
        if (def == default_id.end())
            r.reject_value("TYPE", "unknown scattering model (constant, specific, gordonmorel, kopelevich, buiteveld)");
        const std::string id = r.text("ID", def->second);
        const auto nz = noise(r);
        bool exclusive = false;
        auto model = in_section(r, [&]() -> iop::AnyCoefficient {
            if (type == "constant") return constant_coefficient(r, "SCAT", nz);
            if (type == "specific") return iop::SpecificCoefficient(spectral_file(r), concentration(r), nz);
            if (type == "gordonmorel") {
                exclusive = r.flag("EXCLUSIVE", false);
                return iop::GordonMorelScattering(
                    concentration(r), {r.number("REFWL", 550.0), r.number("K", 0.30), r.number("Q", 0.62), exclusive},
                    nz);
            }
            if (type == "kopelevich")
                return iop::KopelevichScattering(concentration(r, "none"),
                                                 {r.number("REFWL", 550.0), r.number("K", 0.30), r.number("Q", 0.62)},
                                                 nz);
            return iop::BuiteveldScattering({r.number("K", 3.4123664e8), r.number("Q", -4.1537676)}, nz);
        });
        for (const auto& sc : scatterers_)
            if (sc.id == id) r.reject_value("ID", "a scattering model with this ID already exists");
        scatterers_.push_back({id, std::move(model), std::nullopt, exclusive});
        r.finish();
    }

    void add_phase(const MaterialSection& s) {
        reject_subsections(s);
        ParameterReader r(s);
        const std::string type = r.text("TYPE");
        const std::string scat_id = r.text("SCATID", "constant");
        (void)r.text("ID", type);
        auto phase = in_section(r, [&]() -> AnyPhaseFunction { return AnyPhaseFunction{phase_model(type, r)}; });
        const auto it = std::find_if(scatterers_.begin(), scatterers_.end(), [&](const auto& sc) { return sc.id == scat_id; });
        if (it == scatterers_.end()) r.reject_value("SCATID", "no ADD_SCATTERING_MODEL has this ID");
        if (it->phase) r.reject_value("SCATID", "this scattering model already has a phase function");
        it->phase = std::move(phase);
        r.finish();
    }

    /// A phase model's parameters, read from the section (optics/phase/phase_names.hpp).
    class FileParameters final : public PhaseFileParameters {
    public:
        explicit FileParameters(ParameterReader& r) : r_(r) {}
        double number(const std::string& name, double fallback) override { return r_.number(name, fallback); }
        std::optional<double> optional_number(const std::string& name) override { return r_.optional_number(name); }
        std::vector<double> numbers(const std::string& name, std::vector<double> fallback) override {
            return r_.numbers(name, std::move(fallback));
        }
        bool flag(const std::string& name, bool fallback) override { return r_.flag(name, fallback); }
        std::pair<std::vector<double>, std::vector<double>> columns(const std::string& name) override {
            auto data = read_spectral_file(r_.file(name));
            return {std::move(data.wavelength_nm), std::move(data.value)};
        }

    private:
        ParameterReader& r_;
    };

    /// The registry's model named by TYPE (canonical name or alias), built from the section.
    static AnyPhase phase_model(const std::string& type, ParameterReader& r) {
        const PhaseModel* model = find_named(phase_models(), type);
        if (!model || !model->in_file)
            r.reject_value("TYPE", std::string("unknown phase function model: ")
                                       .append(must_be_one_of(phase_models(), file_phase_types())));
        FileParameters parameters(r);
        return model->in_file(parameters);
    }

    void set_refractive_index(const MaterialSection& s) {
        reject_subsections(s);
        ParameterReader r(s);
        const std::string type = r.text("TYPE");
        (void)r.text("ID", type);
        const auto nz = noise(r);
        if (type == "constant") {
            const iop::ConstantRefractiveIndex m = in_section(r, [&] { return iop::ConstantRefractiveIndex(r.number("IOR", 1.0), nz); });
            n_ = [m](double wl) { return m.refractive_index(wl); };
        } else if (type == "iapws") {
            const auto m = in_section(r, [&] {
                return iop::IapwsRefractiveIndex(r.number("TEMP", 273.15), r.number("DENSITY", 1000.0), nz);
            });
            n_ = [m](double wl) { return m.refractive_index(wl); };
        } else {
            r.reject_value("TYPE", "unknown refractive index model (constant, iapws)");
        }
        r.finish();
    }

    iop::RuntimeIopModel finish() {
        iop::RuntimeIopModel m;
        for (auto& [id, a] : absorbers_) m.absorbers.push_back(std::move(a));
        const bool exclusive = std::any_of(scatterers_.begin(), scatterers_.end(), [](const auto& s) { return s.exclusive; });
        for (auto& s : scatterers_) {
            if (exclusive && !s.exclusive) continue;  // EXCLUSIVE = 1 (manual 5.7.3)
            m.scatterers.push_back({std::move(s.coefficient), s.phase ? std::move(*s.phase) : AnyPhaseFunction{IsotropicPhase{}}});
        }
        m.n = std::move(n_);
        return m;
    }

    std::uint64_t seed_, next_key_ = 0;
    std::map<std::string, iop::AnyConcentration> concentrations_;
    std::vector<std::pair<std::string, iop::AnyCoefficient>> absorbers_;
    std::vector<NamedScatterer> scatterers_;
    iop::RefractiveIndexFunction n_ = [](double) { return 1.0; };
};

}  // namespace detail

namespace detail {
/// The last line holding anything of s (its own, a parameter's or a nested section's).
inline int last_line(const MaterialSection& s) {
    int line = s.loc.line;
    for (const auto& p : s.parameters) line = std::max(line, p.loc.line);
    for (const auto& sub : s.sections) line = std::max(line, last_line(sub));
    return line;
}
}  // namespace detail

namespace detail {
/// The IOP_MODEL of the one BULK_PROPERTIES section in `holder` (the file's top level, or a
/// MATERIAL_ENTRY).
inline iop::RuntimeIopModel bind_bulk(const MaterialSection& holder, std::uint64_t seed) {
    const auto bulk = holder.all("BULK_PROPERTIES");
    if (bulk.size() != 1)  // the second one's place, or the holder's end when there is none
        reject("BULK_PROPERTIES sections", bulk.size(),
               holder.name.empty() ? "a material file needs exactly one" : "a MATERIAL_ENTRY needs exactly one",
               bulk.empty() ? holder.loc.file + ":" + std::to_string(last_line(holder)) : bulk[1]->loc.where());
    const auto models = bulk[0]->all("IOP_MODEL");
    if (models.size() != 1)
        reject("IOP_MODEL sections", models.size(), "BULK_PROPERTIES needs exactly one",
               models.empty() ? bulk[0]->loc.where() : models[1]->loc.where());
    for (const auto& sub : bulk[0]->sections)
        if (sub.name != "IOP_MODEL") reject("section", sub.name, "unknown section in BULK_PROPERTIES", sub.loc.where());
    ParameterReader(*bulk[0]).finish();  // BULK_PROPERTIES takes no parameters of its own
    return MaterialBinder(seed).bind(*models[0]);
}

/// "ID 1 (NAME = Water)" for a MATERIAL_ENTRY, from whichever of the two it has.
inline std::string entry_label(const MaterialSection& entry) {
    const auto* id = entry.find("ID");
    const auto* name = entry.find("NAME");
    std::string label = id ? "ID " + id->value : "(no ID)";
    if (name) label += " (NAME = " + name->value + ")";
    return label + " at " + entry.loc.where();
}

/// The MATERIAL_ENTRY among `root`'s to read: the one whose ID or NAME is `material`, or
/// (material empty) the only one with a BULK_PROPERTIES section.
inline const MaterialSection& choose_entry(const MaterialSection& root, std::string_view material) {
    const auto entries = root.all("MATERIAL_ENTRY");
    std::vector<const MaterialSection*> chosen;
    std::string known;
    for (const MaterialSection* e : entries) {
        const auto* id = e->find("ID");
        const auto* name = e->find("NAME");
        const bool named = (id && id->value == material) || (name && name->value == material);
        if (material.empty() ? !e->all("BULK_PROPERTIES").empty() : named) chosen.push_back(e);
        known += (known.empty() ? "" : "; ") + entry_label(*e);
    }
    const std::string given = material.empty() ? std::string("(none given)") : std::string(material);
    if (chosen.empty())
        reject("material", given,
               (material.empty() ? "no MATERIAL_ENTRY has BULK_PROPERTIES" : "names no MATERIAL_ENTRY by ID or NAME") +
                   std::string("; the entries: ") + known,
               entries.front()->loc.where());
    if (chosen.size() > 1)
        reject("material", given,
               material.empty() ? "several MATERIAL_ENTRY sections have BULK_PROPERTIES: name one by ID or NAME; "
                                  "the entries: " + known
                                : "matches more than one MATERIAL_ENTRY: " + entry_label(*chosen[0]) + "; " +
                                      entry_label(*chosen[1]),
               chosen[1]->loc.where());
    return *chosen.front();
}
}  // namespace detail

/// The IOP_MODEL of a parsed material file (root = parse_material's result), in either form:
///  - the manual's (5.3): one BULK_PROPERTIES { IOP_MODEL { ... } } at the file's top level;
///  - a DIRSIG material file: MATERIAL_ENTRY { ID = ... NAME = ... BULK_PROPERTIES { ... } }
///    sections, of which the one whose ID or NAME is `material` is read (with `material`
///    empty: the only entry that has BULK_PROPERTIES). The entry's other parameters and
///    sections (SURFACE_PROPERTIES, RAD_SOLVER, ...) describe DIRSIG's surfaces and solvers,
///    not the water: they are not read, and neither are other entries nor top-level parameters
///    (DIRSIG_MAT = ...).
/// A file with both forms, or `material` given for a file without entries, is rejected.
inline iop::RuntimeIopModel bind_iop_model(const MaterialSection& root, std::uint64_t seed = 1,
                                           std::string_view material = {}) {
    const bool entries = !root.all("MATERIAL_ENTRY").empty();
    if (!entries) {
        if (!material.empty())
            reject("material", std::string(material), "selects a MATERIAL_ENTRY, but the file has none",
                   root.loc.file + ":" + std::to_string(detail::last_line(root)));
        return detail::bind_bulk(root, seed);
    }
    if (const auto top = root.all("BULK_PROPERTIES"); !top.empty())
        reject("section", "BULK_PROPERTIES",
               "at the top level of a file of MATERIAL_ENTRY sections: put it inside its entry", top[0]->loc.where());
    return detail::bind_bulk(detail::choose_entry(root, material), seed);
}

/// Reads and binds a material file (`material`: the MATERIAL_ENTRY's ID or NAME, see bind_iop_model).
inline iop::RuntimeIopModel read_iop_model(const std::filesystem::path& path, std::uint64_t seed = 1,
                                           std::string_view material = {}) {
    return bind_iop_model(read_material_file(path), seed, material);
}

/// The material file the programs' options name: --material FILE, --material-entry ID|NAME
/// and SIGMA's --seed (default 1). --material-entry without --material is rejected.
inline iop::RuntimeIopModel read_iop_model_from_options(const CommandLine& cl) {
    if (cl.has("material-entry") && !cl.has("material"))
        reject("--material-entry", cl.text("material-entry"), "selects an entry of --material FILE, which is missing");
    return read_iop_model(cl.required_text("material"), cl.count("seed", 1), cl.text("material-entry"));
}

}  // namespace secchi::io
