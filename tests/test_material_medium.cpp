// The binding of a material file's IOP_MODEL to secchi's models (secchi/io/material_medium.hpp):
// the file form of canonical problem 3 against its compile-time form, the base media of
// manual 5.3, binding errors (file:line and the parameter), EXCLUSIVE, the default phase
// function, SIGMA noise, and every example material file.
#include <catch2/catch.hpp>
#include "../conformance/problem3.hpp"
#include "secchi/io/material_medium.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace secchi;
using namespace secchi::io;
using Catch::Contains;

namespace {

namespace fs = std::filesystem;

const fs::path materials_dir = fs::path(__FILE__).parent_path().parent_path() / "examples" / "materials";

/// Equal to 1e-12 relative (exactly equal when both are zero).
bool same(double a, double b) { return std::abs(a - b) <= 1e-12 * std::max(std::abs(a), std::abs(b)); }

constexpr double wavelengths[] = {400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0};
constexpr double cosines[] = {-1.0, -0.7, -0.2, 0.0, 0.3, 0.8, 0.95, 0.999, 1.0};

vec3 at_depth(double z) { return {0.0, 0.0, z}; }

fs::path scratch_dir() {
    const auto dir = fs::temp_directory_path() / "secchi_test_material_medium";
    fs::create_directories(dir);
    return dir;
}

/// Writes text to a scratch file and returns its path.
fs::path write_material(const std::string& name, const std::string& text) {
    const auto path = scratch_dir() / name;
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

/// A purewater IOP_MODEL with `body` inside it: body line k is file line 3 + k.
std::string purewater_with(const std::string& body) {
    return "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = purewater\n" + body + "  }\n}\n";
}

/// Binds `text` written to the scratch file `name`.
iop::RuntimeIopModel bind_text(const std::string& name, const std::string& text, std::uint64_t seed = 1) {
    return read_iop_model(write_material(name, text), seed);
}

/// "path/name:line", as the binding errors write it.
std::string where(const std::string& name, int line) { return (scratch_dir() / name).string() + ":" + std::to_string(line); }

double scattering_of(const iop::RuntimeIopModel& m, std::size_t i, double z, double wl) {
    return m.scatterers.at(i).coefficient.coefficient(at_depth(z), wl);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Canonical problem 3: the composed model and the material file give the same medium.

TEST_CASE("material medium: canonical_problem3.mat equals the composed problem-3 model at 500 nm") {
    const auto from_file = read_iop_model(materials_dir / "canonical_problem3.mat");
    const auto composed = conformance::problem3_model();
    const auto depths = iop::uniform_depths(100.0, 1.0);
    const auto wf = iop::stratify(from_file, conformance::problem3_wavelength_nm, depths);
    const auto wc = iop::stratify(composed, conformance::problem3_wavelength_nm, depths);
    REQUIRE(wf.components() == 2);
    REQUIRE(wc.components() == 2);
    // At the nodes and between them (0, 0.5, 1, ..., 100 m).
    for (int k = 0; k <= 200; ++k) {
        const double z = 0.5 * k;
        for (auto c : {Coefficient::absorption, Coefficient::scattering, Coefficient::attenuation}) {
            INFO("z = " << z << " m, coefficient " << static_cast<int>(c));
            CHECK(same(wf.coefficient(c, z), wc.coefficient(c, z)));
        }
        for (std::size_t i = 0; i < 2; ++i) {
            INFO("z = " << z << " m, component " << i);
            CHECK(same(wf.component_scattering(i, z), wc.component_scattering(i, z)));
        }
        for (double mu : cosines) CHECK(same(wf.eval_phase(z, mu), wc.eval_phase(z, mu)));
    }
    for (std::size_t i = 0; i < 2; ++i)
        for (double mu : cosines) {
            INFO("component " << i << ", cos psi = " << mu);
            CHECK(same(wf.phases()[i].eval(mu), wc.phases()[i].eval(mu)));
        }
    // The water is M93's: a = 0.0257 + 0.04 C^0.602 and b = 0.0029 + 0.33 C^0.62 at the peak.
    const double c17 = 0.2 + 144.0 / (9.0 * std::sqrt(two_pi));
    CHECK(wf.coefficient(Coefficient::absorption, 17.0) == Approx(0.0257 + 0.04 * std::pow(c17, 0.602)).epsilon(1e-12));
    CHECK(wf.coefficient(Coefficient::scattering, 17.0) == Approx(0.0029 + 0.33 * std::pow(c17, 0.62)).epsilon(1e-12));
    CHECK(from_file.refractive_index(500.0) == 1.34);
}

// ---------------------------------------------------------------------------------------------
// Base media (manual 5.3), from the example files.

TEST_CASE("material medium: purewater base (sbpf absorption, Buiteveld scattering, eq. 5.2 phase, IAPWS)") {
    struct Case {
        const char* file;
        iop::AnyCoefficient absorption;
    };
    const std::vector<Case> cases{{"purewater.mat", iop::HybridPureWaterAbsorption()},
                                  {"sbpurewater.mat", iop::SmithBakerAbsorption()},
                                  {"pspurewater.mat", iop::PrieurSathyAbsorption()}};
    const auto phase = pure_water_phase();
    const auto ior = iop::pure_water_refractive_index();
    for (const auto& c : cases) {
        INFO(c.file);
        const auto m = read_iop_model(materials_dir / c.file);
        REQUIRE(m.absorbers.size() == 1);
        REQUIRE(m.scatterers.size() == 1);
        for (double wl : {400.0, 500.0, 600.0, 700.0}) {
            INFO("wavelength " << wl << " nm");
            CHECK(m.absorption(at_depth(3.0), wl) == c.absorption.coefficient(at_depth(3.0), wl));
            CHECK(iop::scattering(m, at_depth(3.0), wl) == iop::BuiteveldScattering().coefficient(at_depth(3.0), wl));
            CHECK(m.refractive_index(wl) == ior.refractive_index(wl));
        }
        for (double mu : cosines) CHECK(m.scatterers[0].phase.eval(mu) == phase.eval(mu));
    }
    // Spot values: b_w(500) = 2.0997e-3 1/m (eq. 5.1), n(500) = 1.337354 (IAPWS, 286 K).
    const auto m = read_iop_model(materials_dir / "purewater.mat");
    CHECK(iop::scattering(m, at_depth(0.0), 500.0) == Approx(2.0997e-3).epsilon(1e-4));
    CHECK(m.refractive_index(500.0) == Approx(1.337354).epsilon(1e-6));
    // The three absorption tables differ (500 nm: Pope-Fry 0.0204, Smith-Baker 0.0257).
    CHECK(m.absorption(at_depth(0.0), 500.0) != read_iop_model(materials_dir / "sbpurewater.mat").absorption(at_depth(0.0), 500.0));
}

TEST_CASE("material medium: null and air bases have no absorption or scattering, n = 1 and 1.0003") {
    const auto null = read_iop_model(materials_dir / "null.mat");
    const auto air = read_iop_model(materials_dir / "air.mat");
    for (const auto* m : {&null, &air}) {
        CHECK(m->absorbers.empty());
        CHECK(m->scatterers.empty());
        for (double wl : wavelengths) {
            CHECK(m->absorption(at_depth(1.0), wl) == 0.0);
            CHECK(iop::scattering(*m, at_depth(1.0), wl) == 0.0);
        }
    }
    for (double wl : wavelengths) {
        CHECK(null.refractive_index(wl) == 1.0);
        CHECK(air.refractive_index(wl) == 1.0003);
    }
}

// ---------------------------------------------------------------------------------------------
// Binding errors: each names the file:line and the parameter or section.

TEST_CASE("material medium: an unknown TYPE is rejected in every section kind") {
    const std::vector<std::pair<std::string, std::string>> sections{
        {"conc", "    ADD_CONCENTRATION_MODEL {\n      TYPE = cubic\n    }\n"},
        {"abs", "    ADD_ABSORPTION_MODEL {\n      TYPE = bogus\n    }\n"},
        {"scat", "    ADD_SCATTERING_MODEL {\n      TYPE = bogus\n    }\n"},
        {"phase", "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = bogus\n      SCATID = purewater\n    }\n"},
        {"ior", "    REFRACTIVE_INDEX_MODEL {\n      TYPE = bogus\n    }\n"}};
    for (const auto& [tag, body] : sections) {
        const std::string name = "type_" + tag + ".mat";
        INFO(name);
        CHECK_THROWS_WITH(bind_text(name, purewater_with(body)), Contains(where(name, 5)) && Contains("TYPE"));
    }
    // An unknown base medium, on the BASE_MEDIUM line.
    const std::string text = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = seawater\n  }\n}\n";
    CHECK_THROWS_WITH(bind_text("base.mat", text), Contains(where("base.mat", 3)) && Contains("BASE_MEDIUM"));
}

TEST_CASE("material medium: unknown parameters, missing files and dangling IDs are rejected") {
    SECTION("unknown parameter") {
        const auto text = purewater_with("    ADD_ABSORPTION_MODEL {\n      TYPE = constant\n      ABSS = 0.1\n    }\n");
        CHECK_THROWS_WITH(bind_text("param.mat", text), Contains(where("param.mat", 6)) && Contains("ABSS"));
    }
    SECTION("unknown parameter in IOP_MODEL and BULK_PROPERTIES") {
        const auto text = purewater_with("    DEPTH = 3\n");
        CHECK_THROWS_WITH(bind_text("top.mat", text), Contains(where("top.mat", 4)) && Contains("DEPTH"));
        const std::string bulk = "BULK_PROPERTIES {\n  COLOUR = blue\n  IOP_MODEL {\n    BASE_MEDIUM = null\n  }\n}\n";
        CHECK_THROWS_WITH(bind_text("bulk.mat", bulk), Contains(where("bulk.mat", 2)) && Contains("COLOUR"));
    }
    SECTION("missing FILENAME file") {
        const auto text =
            purewater_with("    ADD_ABSORPTION_MODEL {\n      TYPE = constant\n      FILENAME = not_there.txt\n    }\n");
        CHECK_THROWS_WITH(bind_text("file.mat", text),
                          Contains(where("file.mat", 6)) && Contains("FILENAME") && Contains("not_there.txt"));
    }
    SECTION("dangling CONCID") {
        const auto text = purewater_with("    ADD_ABSORPTION_MODEL {\n      TYPE = morelconc\n      CONCID = nope\n    }\n");
        CHECK_THROWS_WITH(bind_text("concid.mat", text), Contains(where("concid.mat", 6)) && Contains("CONCID"));
    }
    SECTION("absent CONCID with no chlorophyll model: the section's line") {
        const auto text = purewater_with("    ADD_SCATTERING_MODEL {\n      TYPE = gordonmorel\n    }\n");
        CHECK_THROWS_WITH(bind_text("concid2.mat", text), Contains(where("concid2.mat", 4)) && Contains("CONCID"));
    }
    SECTION("dangling SCATID") {
        const auto text = purewater_with("    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = uniform\n      SCATID = nope\n    }\n");
        CHECK_THROWS_WITH(bind_text("scatid.mat", text), Contains(where("scatid.mat", 6)) && Contains("SCATID"));
    }
    SECTION("dangling ABSID") {
        const auto text = purewater_with("    ADD_ABSORPTION_MODEL {\n      TYPE = morelcovar\n      ABSID = nope\n    }\n");
        CHECK_THROWS_WITH(bind_text("absid.mat", text), Contains(where("absid.mat", 6)) && Contains("ABSID"));
    }
}

TEST_CASE("material medium: values out of range name the parameter's line") {
    const std::string chl = "    ADD_CONCENTRATION_MODEL {\n      TYPE = constant\n      CONC = 1\n    }\n";  // lines 4-7
    SECTION("negative K (gordonmorel)") {
        const auto text = purewater_with(chl + "    ADD_SCATTERING_MODEL {\n      TYPE = gordonmorel\n      K = -0.3\n    }\n");
        CHECK_THROWS_WITH(bind_text("k.mat", text), Contains(where("k.mat", 10)) && Contains("K = -0.3"));
    }
    SECTION("negative K (morelconc)") {
        const auto text = purewater_with(chl + "    ADD_ABSORPTION_MODEL {\n      TYPE = morelconc\n      K = -1\n    }\n");
        CHECK_THROWS_WITH(bind_text("k2.mat", text), Contains(where("k2.mat", 10)) && Contains("K = -1"));
    }
    SECTION("|G| >= 1 in hgpf") {
        const auto text = purewater_with(
            "    ADD_SCATTERING_MODEL {\n      TYPE = constant\n    }\n"
            "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = hgpf\n      SCATID = constant\n      G = 0.5, 1.0\n"
            "      W = 0.5, 0.5\n    }\n");
        CHECK_THROWS_WITH(bind_text("g.mat", text), Contains(where("g.mat", 10)) && Contains("g = 1"));
    }
    SECTION("SIGMA < 0") {
        const auto text = purewater_with("    ADD_CONCENTRATION_MODEL {\n      TYPE = constant\n      SIGMA = -0.1\n    }\n");
        CHECK_THROWS_WITH(bind_text("sigma.mat", text), Contains(where("sigma.mat", 6)) && Contains("SIGMA"));
    }
    SECTION("IOR < 1") {
        const auto text = purewater_with("    REFRACTIVE_INDEX_MODEL {\n      TYPE = constant\n      IOR = 0.5\n    }\n");
        CHECK_THROWS_WITH(bind_text("ior.mat", text), Contains(where("ior.mat", 6)) && Contains("IOR"));
    }
    SECTION("a flag that is not 0 or 1") {
        const auto text = purewater_with(chl + "    ADD_SCATTERING_MODEL {\n      TYPE = gordonmorel\n      EXCLUSIVE = yes\n    }\n");
        CHECK_THROWS_WITH(bind_text("flag.mat", text), Contains(where("flag.mat", 10)) && Contains("EXCLUSIVE"));
    }
}

TEST_CASE("material medium: structural errors name file:line") {
    SECTION("a section never closed: the line that opened it") {
        const std::string text = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = null\n    ADD_ABSORPTION_MODEL {\n"
                                 "      TYPE = constant\n  }\n}\n";
        CHECK_THROWS_WITH(bind_text("open.mat", text), Contains(where("open.mat", 1)) && Contains("BULK_PROPERTIES"));
    }
    SECTION("a stray '}'") {
        const std::string text = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = null\n  }\n}\n}\n";
        CHECK_THROWS_WITH(bind_text("stray.mat", text), Contains(where("stray.mat", 6)) && Contains("'}'"));
    }
    SECTION("two phase functions for one SCATID: the second one's SCATID") {
        const auto text = purewater_with(
            "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = uniform\n      SCATID = purewater\n    }\n"
            "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = petzold\n      SCATID = purewater\n    }\n");
        // The base medium's water already has the phase function of eq. 5.2, so the first
        // one is already a second: line 6.
        CHECK_THROWS_WITH(bind_text("twophase.mat", text), Contains(where("twophase.mat", 6)) && Contains("SCATID"));
        const auto text2 = purewater_with(
            "    ADD_SCATTERING_MODEL {\n      TYPE = constant\n    }\n"
            "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = uniform\n    }\n"
            "    ADD_PHASE_FUNCTION_MODEL {\n      TYPE = hgpf\n      G = 0.9\n      SCATID = constant\n    }\n");
        CHECK_THROWS_WITH(bind_text("twophase2.mat", text2),
                          Contains(where("twophase2.mat", 13)) && Contains("SCATID") &&
                              Contains("already has a phase function"));
    }
    SECTION("missing BASE_MEDIUM: the IOP_MODEL line") {
        const std::string text = "BULK_PROPERTIES {\n  IOP_MODEL {\n    ADD_ABSORPTION_MODEL {\n      TYPE = constant\n"
                                 "    }\n  }\n}\n";
        CHECK_THROWS_WITH(bind_text("nobase.mat", text), Contains(where("nobase.mat", 2)) && Contains("BASE_MEDIUM"));
    }
    SECTION("unknown sections") {
        const auto in_iop = purewater_with("    ADD_FLUORESCENCE_MODEL {\n      TYPE = chl\n    }\n");
        CHECK_THROWS_WITH(bind_text("sec1.mat", in_iop), Contains(where("sec1.mat", 4)) && Contains("ADD_FLUORESCENCE_MODEL"));
        const std::string in_bulk = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = null\n  }\n  EMISSION {\n  }\n}\n";
        CHECK_THROWS_WITH(bind_text("sec2.mat", in_bulk), Contains(where("sec2.mat", 5)) && Contains("EMISSION"));
        const auto in_model =
            purewater_with("    ADD_ABSORPTION_MODEL {\n      TYPE = constant\n      EXTRA {\n      }\n    }\n");
        CHECK_THROWS_WITH(bind_text("sec3.mat", in_model), Contains(where("sec3.mat", 6)) && Contains("EXTRA"));
    }
    SECTION("not exactly one BULK_PROPERTIES or IOP_MODEL") {
        const std::string two = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = null\n  }\n}\n"
                                "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = air\n  }\n}\n";
        CHECK_THROWS_WITH(bind_text("bulk2.mat", two), Contains(where("bulk2.mat", 6)) && Contains("BULK_PROPERTIES"));
        const std::string none = "# nothing\nIOP_MODEL {\n  BASE_MEDIUM = null\n}\n";
        CHECK_THROWS_WITH(bind_text("bulk0.mat", none), Contains(where("bulk0.mat", 3)) && Contains("BULK_PROPERTIES"));
        const std::string two_iop = "BULK_PROPERTIES {\n  IOP_MODEL {\n    BASE_MEDIUM = null\n  }\n"
                                    "  IOP_MODEL {\n    BASE_MEDIUM = null\n  }\n}\n";
        CHECK_THROWS_WITH(bind_text("iop2.mat", two_iop), Contains(where("iop2.mat", 5)) && Contains("IOP_MODEL"));
    }
}

TEST_CASE("material medium: DIRSIG MATERIAL_ENTRY files: the entry by ID or NAME, or the only one with BULK_PROPERTIES") {
    const std::string bulk = "  BULK_PROPERTIES {\n    IOP_MODEL {\n      BASE_MEDIUM = purewater\n"
                             "      ADD_ABSORPTION_MODEL {\n        TYPE = constant\n        ABS = 0.25\n      }\n"
                             "    }\n  }\n";
    const std::string sand = "MATERIAL_ENTRY {\n  ID = 1\n  NAME = Sand\n  EDITOR_COLOR = 0.8, 0.7, 0.5\n"
                             "  SURFACE_PROPERTIES {\n    REFLECTANCE_PROP_NAME = LambertianReflectance\n  }\n}\n";
    const std::string lake = "MATERIAL_ENTRY {\n  ID = 2\n  NAME = Lake\n  SURFACE_PROPERTIES {\n  }\n" + bulk + "}\n";
    const std::string file = "DIRSIG_MAT = 1.0\n\n" + sand + lake;
    const auto bare = bind_text("bare.mat", bulk);  // the same BULK_PROPERTIES, alone
    const double a_bare = bare.absorption(at_depth(1.0), 500.0);
    for (const std::string material : {"", "2", "Lake"}) {
        INFO("material '" << material << "'");
        const auto m = read_iop_model(write_material("entries.mat", file), 1, material);
        CHECK(m.absorption(at_depth(1.0), 500.0) == a_bare);
        CHECK(m.absorption(at_depth(1.0), 500.0) > 0.25);
    }
    const auto path = write_material("entries.mat", file);
    // The Sand entry has no BULK_PROPERTIES: the error points at its last line (8).
    CHECK_THROWS_WITH(read_iop_model(path, 1, "Sand"),
                      Contains("MATERIAL_ENTRY needs exactly one") && Contains(where("entries.mat", 8)));
    CHECK_THROWS_WITH(read_iop_model(path, 1, "Ocean"),
                      Contains("material = Ocean") && Contains("ID 1 (NAME = Sand)") && Contains("ID 2 (NAME = Lake)"));
    const auto two = write_material("two_entries.mat", lake + lake);
    CHECK_THROWS_WITH(read_iop_model(two), Contains("several MATERIAL_ENTRY") && Contains(where("two_entries.mat", 16)));
    CHECK_THROWS_WITH(read_iop_model(two, 1, "2"), Contains("more than one MATERIAL_ENTRY"));
    CHECK_THROWS_WITH(read_iop_model(write_material("plain.mat", bulk), 1, "Lake"),
                      Contains("material = Lake") && Contains("has none"));
    CHECK_THROWS_WITH(read_iop_model(write_material("both.mat", bulk + lake)),
                      Contains("BULK_PROPERTIES") && Contains("put it inside its entry") && Contains(where("both.mat", 1)));
}

// ---------------------------------------------------------------------------------------------
// EXCLUSIVE, the default phase function, SIGMA.

TEST_CASE("material medium: EXCLUSIVE = 1 on gordonmorel removes every other scattering model") {
    const std::string body =
        "    ADD_CONCENTRATION_MODEL {\n      TYPE = constant\n      CONC = 2\n    }\n"
        "    ADD_SCATTERING_MODEL {\n      TYPE = constant\n      SCAT = 0.5\n    }\n"
        "    ADD_SCATTERING_MODEL {\n      TYPE = gordonmorel\n      EXCLUSIVE = ";
    const auto tail = std::string("\n    }\n");
    const auto shared = bind_text("shared.mat", purewater_with(body + "0" + tail));
    const auto exclusive = bind_text("exclusive.mat", purewater_with(body + "1" + tail));
    REQUIRE(shared.scatterers.size() == 3);  // water, constant, gordonmorel
    REQUIRE(exclusive.scatterers.size() == 1);
    for (double wl : wavelengths) {
        // Eq. 5.22 alone: (550 / lambda) 0.30 2^0.62.
        const double gm = 550.0 / wl * 0.30 * std::pow(2.0, 0.62);
        CHECK(iop::scattering(exclusive, at_depth(2.0), wl) == Approx(gm).epsilon(1e-14));
        CHECK(iop::scattering(shared, at_depth(2.0), wl) ==
              Approx(gm + 0.5 + iop::BuiteveldScattering().coefficient(at_depth(2.0), wl)).epsilon(1e-14));
    }
    // Absorption is untouched: EXCLUSIVE concerns scattering models only.
    CHECK(exclusive.absorption(at_depth(2.0), 500.0) == shared.absorption(at_depth(2.0), 500.0));
}

TEST_CASE("material medium: a scattering model without a phase function scatters uniformly") {
    const auto m = bind_text("uniform.mat", purewater_with("    ADD_SCATTERING_MODEL {\n      TYPE = constant\n"
                                                          "      SCAT = 0.2\n    }\n"));
    REQUIRE(m.scatterers.size() == 2);
    CHECK(std::holds_alternative<IsotropicPhase>(m.scatterers[1].phase.p));
    for (double mu : cosines) CHECK(m.scatterers[1].phase.eval(mu) == Approx(1.0 / (4.0 * pi)).epsilon(1e-15));
    // The water keeps its own (eq. 5.2).
    CHECK(std::holds_alternative<RayleighLikePhase>(m.scatterers[0].phase.p));
    CHECK(scattering_of(m, 1, 4.0, 500.0) == 0.2);
}

TEST_CASE("material medium: SIGMA noise is reproducible for a seed and differs between seeds") {
    const auto text = purewater_with(
        "    ADD_CONCENTRATION_MODEL {\n      TYPE = constant\n      CONC = 1\n      SIGMA = 0.1\n    }\n"
        "    ADD_ABSORPTION_MODEL {\n      TYPE = constant\n      ABS = 0.2\n      SIGMA = 0.02\n    }\n"
        "    ADD_SCATTERING_MODEL {\n      TYPE = gordonmorel\n      SIGMA = 0.05\n    }\n");
    const auto a = bind_text("noise.mat", text, 7);
    const auto b = bind_text("noise.mat", text, 7);
    const auto c = bind_text("noise.mat", text, 8);
    const auto quiet = bind_text("quiet.mat", purewater_with(
        "    ADD_CONCENTRATION_MODEL {\n      TYPE = constant\n      CONC = 1\n    }\n"
        "    ADD_ABSORPTION_MODEL {\n      TYPE = constant\n      ABS = 0.2\n    }\n"
        "    ADD_SCATTERING_MODEL {\n      TYPE = gordonmorel\n    }\n"), 7);
    int differ_seed = 0, differ_quiet = 0, n = 0;
    for (double z = 0.0; z <= 20.0; z += 2.5)
        for (double wl : wavelengths) {
            const vec3 x = at_depth(z);
            CHECK(a.absorption(x, wl) == b.absorption(x, wl));
            CHECK(scattering_of(a, 1, z, wl) == scattering_of(b, 1, z, wl));
            CHECK(a.absorption(x, wl) >= 0.0);
            differ_seed += a.absorption(x, wl) != c.absorption(x, wl);
            differ_seed += scattering_of(a, 1, z, wl) != scattering_of(c, 1, z, wl);
            differ_quiet += a.absorption(x, wl) != quiet.absorption(x, wl);
            n += 2;
        }
    CHECK(differ_seed == n);       // a continuous deviate: another seed changes every value
    CHECK(differ_quiet == n / 2);  // and SIGMA does add noise
    // The water (no SIGMA) is not noisy.
    CHECK(scattering_of(a, 0, 5.0, 500.0) == scattering_of(c, 0, 5.0, 500.0));
}

// ---------------------------------------------------------------------------------------------
// Every example material file.

TEST_CASE("material medium: every example material file binds and gives finite a, b >= 0 at 400-700 nm") {
    int files = 0;
    for (const auto& entry : fs::directory_iterator(materials_dir)) {
        if (entry.path().extension() != ".mat") continue;
        ++files;
        INFO(entry.path().string());
        iop::RuntimeIopModel m;
        REQUIRE_NOTHROW(m = read_iop_model(entry.path()));
        for (double wl = 400.0; wl <= 700.0; wl += 10.0)
            for (double z = 0.0; z <= 60.0; z += 5.0) {
                const double a = m.absorption(at_depth(z), wl), b = iop::scattering(m, at_depth(z), wl);
                INFO("wavelength " << wl << " nm, depth " << z << " m: a = " << a << ", b = " << b);
                CHECK((std::isfinite(a) && a >= 0.0));
                CHECK((std::isfinite(b) && b >= 0.0));
            }
        const double n = m.refractive_index(550.0);
        CHECK((std::isfinite(n) && n >= 1.0));
    }
    CHECK(files >= 7);
}

TEST_CASE("material medium: case1_chlorophyll.mat is eq. 5.13 and eq. 5.21 with a Gaussian chlorophyll profile") {
    const auto m = read_iop_model(materials_dir / "case1_chlorophyll.mat");
    REQUIRE(m.absorbers.size() == 3);   // water, phytoplankton, CDOM
    REQUIRE(m.scatterers.size() == 2);  // water, particles
    CHECK(std::holds_alternative<TabulatedPhase>(m.scatterers[1].phase.p));
    const double c20 = 0.1 + 20.0 / (8.0 * std::sqrt(two_pi));  // the peak, at 20 m
    const vec3 x = at_depth(20.0);
    // At 440 nm, where a*_c' = 1: a = a_w + 0.06 C^0.65 (1 + 0.2), eq. 5.14-5.15.
    const double aw440 = iop::HybridPureWaterAbsorption().coefficient(x, 440.0);
    CHECK(m.absorption(x, 440.0) == Approx(aw440 + 1.2 * 0.06 * std::pow(c20, 0.65)).epsilon(1e-12));
    // b = b_w + (550 / lambda) 0.30 C^0.62 (eq. 5.21).
    const double bw = iop::BuiteveldScattering().coefficient(x, 500.0);
    CHECK(iop::scattering(m, x, 500.0) == Approx(bw + 550.0 / 500.0 * 0.30 * std::pow(c20, 0.62)).epsilon(1e-12));
    // More chlorophyll at the peak than at the surface: more absorption and scattering.
    CHECK(m.absorption(x, 440.0) > m.absorption(at_depth(0.0), 440.0));
    CHECK(iop::scattering(m, x, 500.0) > iop::scattering(m, at_depth(0.0), 500.0));
}

// ---------------------------------------------------------------------------------------------
// The material's refractive index reaches the surface: the sun's light reflected by a flat
// surface is Fresnel's R(theta, 1, n) for the water's n at the run's wavelength (the ledger
// books R exactly: weighted photons from the air take the expected value), unless the run
// names an override.
TEST_CASE("material medium: REFRACTIVE_INDEX_MODEL sets the surface's index; PlaneParallelConfig::water_index overrides it") {
    const auto depths = iop::uniform_depths(20.0, 0.5);
    PlaneParallelConfig cfg;  // sun at 60 deg, flat surface, continuous absorption
    cfg.transport.photons = 2000;
    cfg.transport.depths = {1.0};
    const double mu = std::cos(cfg.sun_zenith_deg * deg);
    for (const double n : {1.20, 1.337354}) {
        const std::string ior = n == 1.20 ? "    REFRACTIVE_INDEX_MODEL {\n      TYPE = constant\n      IOR = 1.2\n    }\n" : "";
        const auto water = iop::stratify(bind_text("ior.mat", purewater_with(ior)), 500.0, depths);
        REQUIRE(water.refractive_index());
        CHECK(*water.refractive_index() == Approx(n).epsilon(1e-6));  // IAPWS at 500 nm without a model
        const auto r = solve_stratified(water, cfg);
        CHECK(r.ledger.surface_reflected == Approx(fresnel_reflectance(mu, 1.0, *water.refractive_index())).epsilon(1e-12));
        auto named = cfg;
        named.water_index = 1.34;
        CHECK(solve_stratified(water, named).ledger.surface_reflected == Approx(fresnel_reflectance(mu, 1.0, 1.34)).epsilon(1e-12));
    }
}
