// The name registries (core/names.hpp, optics/phase/phase_names.hpp, map/store_names.hpp and
// the small NamedValue tables): every name and alias works on a command line and, for phase
// functions, in a material file, building the same function; the usage texts and the error
// messages list exactly the registry's names; unknown names are rejected naming the value.
#include <catch2/catch.hpp>

#include "secchi/io/cli.hpp"
#include "secchi/io/material_medium.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/solver/plane_parallel.hpp"

#include <cmath>
#include <map>
#include <string>
#include <vector>

using namespace secchi;
using Catch::Contains;

namespace {

/// Splits "a|b|c" at the separators.
std::vector<std::string> split(const std::string& text, char separator = '|') {
    std::vector<std::string> parts(1);
    for (char c : text) {
        if (c == separator) parts.emplace_back();
        else parts.back() += c;
    }
    return parts;
}

/// A material file whose one scattering model has the phase function TYPE = type plus
/// `parameters` (lines "NAME = value"); the phase section's TYPE is on line 8.
std::string material_with_phase(const std::string& type, const std::string& parameters) {
    std::string text = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = null\n";
    text += "    ADD_SCATTERING_MODEL {\n      TYPE = constant\n    }\n";
    text += "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = ";
    text += type;
    text += "\n";
    text += parameters;
    text += "    }\n  }\n}\n";
    return text;
}

AnyPhase phase_from_file(const std::string& type, const std::string& parameters) {
    const auto model = io::bind_iop_model(io::parse_material(material_with_phase(type, parameters), "names.mat"));
    REQUIRE(model.scatterers.size() == 1);
    return model.scatterers[0].phase.p;
}

/// The command line's parameter and a material file's for each model that takes one.
struct ParameterForms {
    std::string cli;   ///< the X of name:X
    std::string file;  ///< the file's lines
};
const std::map<std::string, ParameterForms> parameter_forms{
    {"hg", {"0.7", "      G = 0.7\n"}},
    {"schlick", {"0.4", "      G = 0.4\n"}},
    {"ff", {"0.02", "      BB = 0.02\n"}},
};

/// The same function: equal values and sampled directions (exactly, or within `tolerance`
/// relative where the two forms are different types of the same function).
void check_same_function(const AnyPhase& a, const AnyPhase& b, double tolerance) {
    const AnyPhaseFunction fa{a}, fb{b};
    for (int i = 0; i <= 200; ++i) {
        const double mu = -1.0 + i / 100.0;
        CHECK(fa.eval(mu) == Approx(fb.eval(mu)).epsilon(tolerance).margin(0.0));
        CHECK(fa.pdf(mu) == Approx(fb.pdf(mu)).epsilon(tolerance).margin(0.0));
    }
    for (double u1 : {0.0, 0.1, 0.37, 0.5, 0.77, 0.999})
        for (double u2 : {0.0, 0.3, 0.9}) {
            const auto da = fa.sample_direction(u1, u2), db = fb.sample_direction(u1, u2);
            CHECK(da.cos_psi == Approx(db.cos_psi).epsilon(tolerance).margin(tolerance));
            CHECK(da.phi == Approx(db.phi).epsilon(tolerance).margin(tolerance));
        }
}

}  // namespace

TEST_CASE("phase registry: every name and alias builds the same function on the command line and in a file") {
    for (const PhaseModel& m : phase_models()) {
        std::vector<std::string_view> spellings{m.naming.name};
        spellings.insert(spellings.end(), m.naming.aliases.begin(), m.naming.aliases.end());
        const auto forms = parameter_forms.find(std::string(m.naming.name));
        CHECK(m.cli_parameter.empty() == (forms == parameter_forms.end()));
        const std::string cli_x = forms == parameter_forms.end() ? "" : ":" + forms->second.cli;
        const std::string file_lines = forms == parameter_forms.end() ? "" : forms->second.file;
        for (const auto spelling : spellings) {
            INFO(spelling);
            if (!m.on_command_line) {  // data: files only
                CHECK_THROWS_WITH(parse_phase(std::string(spelling)), Contains("phase") && Contains(std::string(spelling)));
                continue;
            }
            REQUIRE(m.in_file);
            const AnyPhase cli = parse_phase(std::string(spelling) + cli_x);
            const AnyPhase file = phase_from_file(std::string(spelling), file_lines);
            // Each form builds what it always built (phase_names.hpp): rayleigh is
            // RayleighPhase on the command line and RayleighLikePhase(1) in a file (the same
            // function, computed differently), hg and schlick one function and a mixture of one.
            const bool same_type = m.naming.name != "rayleigh" && m.naming.name != "hg" && m.naming.name != "schlick";
            CHECK(same_type == (cli.index() == file.index()));
            check_same_function(cli, file, m.naming.name == "rayleigh" ? 1e-12 : 0.0);
            if (same_type) CHECK(AnyPhaseFunction{cli}.name() == AnyPhaseFunction{file}.name());
        }
    }
}

TEST_CASE("phase registry: the command line builds what the names always built") {
    CHECK(std::holds_alternative<IsotropicPhase>(parse_phase("isotropic")));
    CHECK(std::holds_alternative<RayleighPhase>(parse_phase("rayleigh")));
    CHECK(std::get<TabulatedPhase>(parse_phase("petzold")).name() == "petzold");
    CHECK(std::get<TabulatedPhase>(parse_phase("petzold-trapezoid")).name() == "petzold-trapezoid");
    CHECK(std::get<TabulatedPhase>(parse_phase("petzold-linear")).name() == "petzold-linear");
    CHECK(std::get<RayleighLikePhase>(parse_phase("pure-water")).k2() == pure_water_phase().k2());
    CHECK(std::get<HenyeyGreensteinPhase>(parse_phase("hg:0.9")).name() == HenyeyGreensteinPhase(0.9).name());
    CHECK(std::get<SchlickPhase>(parse_phase("schlick:0.5")).name() == SchlickPhase(0.5).name());
    CHECK(std::get<FournierForandPhase>(parse_phase("ff:0.02")).name() ==
          FournierForandPhase::from_backscatter_fraction(0.02).name());
    // A file's hgpf keeps its lists: a mixture of two.
    const auto mixture = phase_from_file("hgpf", "      G = 0.9, -0.3\n      W = 3, 1\n");
    CHECK(std::get<PhaseMixture<HenyeyGreensteinPhase>>(mixture).weights() == std::vector<double>{0.75, 0.25});
}

TEST_CASE("phase registry: the usage list and the error messages hold exactly the registry's names") {
    std::vector<std::string> cli, file, aliases;
    for (const PhaseModel& m : phase_models()) {
        if (m.on_command_line) cli.push_back(cli_spelling(m));
        if (m.in_file) file.emplace_back(m.naming.name);
        aliases.insert(aliases.end(), m.naming.aliases.begin(), m.naming.aliases.end());
    }
    CHECK(split(phase_usage()) == cli);
    CHECK(cli == std::vector<std::string>{"isotropic", "rayleigh", "petzold", "petzold-trapezoid", "petzold-linear",
                                          "pure-water", "hg:G", "schlick:K", "ff:BB"});
    CHECK(file == std::vector<std::string>{"isotropic", "rayleigh", "petzold", "petzold-trapezoid", "petzold-linear",
                                           "pure-water", "hg", "schlick", "ff", "data"});
    CHECK(aliases == std::vector<std::string>{"uniform", "hgpf", "fournierforand"});
    // The DIRSIG manual's TYPE names (5.8) stay accepted.
    for (const char* manual : {"uniform", "data", "hgpf", "schlick", "rayleigh", "petzold"})
        CHECK(find_named(phase_models(), manual) != nullptr);

    const std::string cli_reason = must_be_one_of(phase_models(), cli);
    CHECK(cli_reason ==
          "must be isotropic, rayleigh, petzold, petzold-trapezoid, petzold-linear, pure-water, hg:G, schlick:K or "
          "ff:BB (also: uniform = isotropic, hgpf = hg, fournierforand = ff)");
    CHECK_THROWS_WITH(parse_phase("bogus"), Contains("invalid phase = bogus") && Contains(cli_reason));
    const std::string file_reason = must_be_one_of(phase_models(), file);
    CHECK_THROWS_WITH(phase_from_file("bogus", ""),
                      Contains("names.mat:8") && Contains("TYPE = bogus") && Contains(file_reason));
    // Every line of the help text starts with a model's spelling.
    const auto lines = split(phase_help(), '\n');
    REQUIRE(lines.size() == phase_models().size() + 1);
    for (std::size_t i = 0; i < phase_models().size(); ++i) {
        const PhaseModel& m = phase_models()[i];
        CHECK(lines[i].rfind("  " + (m.on_command_line ? cli_spelling(m) : std::string(m.naming.name)), 0) == 0);
        CHECK(lines[i].find(m.naming.description) != std::string::npos);
    }
}

TEST_CASE("phase registry: malformed command-line spellings are rejected naming the value") {
    for (const char* bad : {"", "bogus", "Isotropic", "hg", "hg:", "hg:x", "hg:0.5x", "isotropic:1", "data",
                            "data:f.txt", "ff:0.02:1", ":0.5"}) {
        INFO(bad);
        CHECK_THROWS_AS(parse_phase(bad), input_error);
        CHECK_THROWS_WITH(parse_phase(bad), Contains("phase") && Contains(std::string("= ") + bad + ":"));
    }
    CHECK_THROWS_WITH(parse_phase("hg"), Contains("needs its parameter: hg:G"));
    CHECK_THROWS_WITH(parse_phase("isotropic:1"), Contains("isotropic takes no parameter"));
    CHECK_THROWS_WITH(parse_phase("hgpf:x"), Contains("phase hg:G") && Contains("must be a number"));
    CHECK_THROWS_WITH(parse_phase("hg:1.2"), Contains("1.2"));  // the model's own check
}

namespace {
/// Every name of a NamedValue family parses to its value and back, the usage text is the
/// names, and an unknown name is rejected with all of them.
template <class Value, class Parse>
void check_named_values(const std::vector<NamedValue<Value>>& family, Parse parse, const std::string& parameter) {
    const auto names = canonical_names(family);
    CHECK(split(usage_names(family)) == names);
    for (const auto& entry : family) {
        CHECK(parse(std::string(entry.naming.name)) == entry.value);
        CHECK(name_of(family, entry.value) == entry.naming.name);
        for (const auto alias : entry.naming.aliases) CHECK(parse(std::string(alias)) == entry.value);
    }
    CHECK_THROWS_WITH(parse("nosuchname"),
                      Contains("invalid " + parameter + " = nosuchname") && Contains(must_be_one_of(family, names)));
    for (const auto& n : names) CHECK_THROWS_WITH(parse("nosuchname"), Contains(n));
}
}  // namespace

TEST_CASE("store registry: names, usage and errors") {
    check_named_values(store_names(), parse_store, "store");
    CHECK(store_usage() == "kdtree|voi|voi-grid|nanoflann|brute-force");
    for (StoreKind k : {StoreKind::kdtree, StoreKind::voi, StoreKind::voi_grid, StoreKind::nanoflann, StoreKind::brute_force})
        CHECK(parse_store(to_string(k)) == k);
    CHECK_THROWS_WITH(parse_store("octree"),
                      Contains("must be kdtree, voi, voi-grid, nanoflann or brute-force"));
}

TEST_CASE("tracer, source, facet, shadowing, cone-peak and absorption registries: names, usage and errors") {
    check_named_values(tracer_names(), parse_tracer, "tracer");
    check_named_values(source_names(), parse_source, "source");
    check_named_values(facet_sampling_names(), parse_facets, "facets");
    check_named_values(shadowing_names(), parse_shadowing, "shadowing");
    check_named_values(cone_peak_names(), parse_cone_peak, "cone peak");
    check_named_values(absorption_names(), parse_absorption, "absorption");
    CHECK(usage_names(tracer_names()) == "photon|lanes|lanes-float");
    CHECK(usage_names(absorption_names()) == "continuous|implicit|analog");
    CHECK(parse_absorption("implicit-capture") == AbsorptionMode::implicit_capture);
}

TEST_CASE("fill_usage replaces every placeholder by its list") {
    CHECK(fill_usage("--store {stores} [--store {stores}] --x {none}", {{"stores", store_usage()}}) ==
          "--store kdtree|voi|voi-grid|nanoflann|brute-force [--store kdtree|voi|voi-grid|nanoflann|brute-force] --x {none}");
}

TEST_CASE("CommandLine: a count kept in an unsigned is rejected above 2^32 - 1, not wrapped") {
    // fuzz/corpus/cli/regression_batches_6e9: slab took --batches 6e9 as 6e9 mod 2^32.
    const auto parse = [](std::vector<std::string> words) {
        words.insert(words.begin(), "slab");
        std::vector<char*> argv;
        for (auto& w : words) argv.push_back(w.data());
        return CommandLine(static_cast<int>(argv.size()), argv.data(), {"batches"});
    };
    CHECK(parse({}).unsigned_count("batches", 32) == 32);
    CHECK(parse({"--batches", "4294967295"}).unsigned_count("batches", 32) == 4294967295u);
    CHECK_THROWS_WITH(parse({"--batches", "6e9"}).unsigned_count("batches", 32),
                      Contains("--batches = 6e9") && Contains("[0, 4294967295]"));
    CHECK_THROWS_WITH(parse({"--batches", "4294967296"}).unsigned_count("batches", 32), Contains("4294967296"));
}
