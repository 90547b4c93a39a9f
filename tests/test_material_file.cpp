// The material-file syntax layer (secchi/io/material_file.hpp): parsing, locations, typed
// parameter access, unknown-parameter detection, relative FILENAMEs and data files.
#include <catch2/catch.hpp>
#include "secchi/io/material_file.hpp"
#include <filesystem>
#include <fstream>
#include <string>

using namespace secchi;
using namespace secchi::io;
using Catch::Contains;

namespace {

// Manual 5.6: the Morel concentration absorption example, inside the IOP_MODEL of 5.3.
constexpr const char* morelconc_example = R"(BULK_PROPERTIES {
    IOP_MODEL {
        BASE_MEDIUM = purewater
        ADD_ABSORPTION_MODEL {
	TYPE = morelconc
	ID = example
	CONCID = chlConc
	PRENORM = 1
	ABS = 1.0
	K = 0.04
	Q = 0.602
}
    }
}
)";

// Manual 5.10: three concentration models (the manual's "..." replaced by the closing brace).
constexpr const char* concentration_example = R"(IOP_MODEL {
ADD_CONCENTRATION_MODEL {
      TYPE = gauss
      ID = chlConc
      BG = 0.2
      S = 9
      H = 144
      DMAX = 17
      ZLEVEL = 0
      SIGMA = 0
}
ADD_CONCENTRATION_MODEL {
    TYPE = constant
    ID = ssConc
    CONC = 0.1
}
ADD_CONCENTRATION_MODEL {
    TYPE = constant
ID = cdomConc
CONC = 0.5
}
}
)";

/// A fresh scratch folder under the system temp directory.
std::filesystem::path scratch_dir(const std::string& name) {
    const auto dir = std::filesystem::temp_directory_path() / "secchi_test_material_file" / name;
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    return dir;
}

void write_file(const std::filesystem::path& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary);
    out << text;
}

/// The only section of a one-section text, as a reader.
ParameterReader reader_of(const std::string& body, const std::string& file = "m.mat") {
    const auto root = parse_material("SEC {\n" + body + "}\n", file);
    return ParameterReader(root.sections.at(0));
}

}  // namespace

TEST_CASE("material file: the manual's morelconc example (5.6)") {
    const auto root = parse_material(morelconc_example, "example.mat");
    REQUIRE(root.name.empty());
    REQUIRE(root.sections.size() == 1);
    const auto& bulk = root.sections[0];
    CHECK(bulk.name == "BULK_PROPERTIES");
    REQUIRE(bulk.sections.size() == 1);
    const auto& iop = bulk.sections[0];
    CHECK(iop.name == "IOP_MODEL");
    REQUIRE(iop.parameters.size() == 1);
    CHECK(iop.parameters[0].name == "BASE_MEDIUM");
    CHECK(iop.parameters[0].value == "purewater");
    REQUIRE(iop.all("ADD_ABSORPTION_MODEL").size() == 1);

    ParameterReader abs(*iop.all("ADD_ABSORPTION_MODEL")[0]);
    CHECK(abs.context() == "ADD_ABSORPTION_MODEL (TYPE = morelconc)");
    CHECK(abs.text("TYPE") == "morelconc");
    CHECK(abs.text("ID", "morelconc") == "example");
    CHECK(abs.text("CONCID", "chlorophyll") == "chlConc");
    CHECK(abs.flag("PRENORM", false));
    CHECK(abs.number("ABS", 0.0) == 1.0);
    CHECK(abs.number_in("K", 0.0, 0.0, 1.0) == 0.04);
    CHECK(abs.number("Q", 0.0) == 0.602);
    CHECK(abs.number("SIGMA", 0.0) == 0.0);  // a default
    CHECK_NOTHROW(abs.finish());
}

TEST_CASE("material file: the manual's concentration example (5.10)") {
    const auto root = parse_material(concentration_example, "conc.mat");
    REQUIRE(root.sections.size() == 1);
    const auto models = root.sections[0].all("ADD_CONCENTRATION_MODEL");
    REQUIRE(models.size() == 3);

    ParameterReader gauss(*models[0]);
    CHECK(gauss.text("TYPE") == "gauss");
    CHECK(gauss.text("ID") == "chlConc");
    CHECK(gauss.number("BG", 0.2) == 0.2);
    CHECK(gauss.number("S", 0.0) == 9.0);
    CHECK(gauss.number("H", 0.0) == 144.0);
    CHECK(gauss.number("DMAX", 0.0) == 17.0);
    CHECK(gauss.number("ZLEVEL", 1.0) == 0.0);
    CHECK(gauss.number("SIGMA", 1.0) == 0.0);
    CHECK_NOTHROW(gauss.finish());

    ParameterReader ss(*models[1]), cdom(*models[2]);
    CHECK(ss.text("ID") == "ssConc");
    CHECK(ss.number("CONC", 2.0) == 0.1);
    CHECK(cdom.text("ID") == "cdomConc");
    CHECK(cdom.number("CONC", 2.0) == 0.5);
    CHECK(models[2]->parameters[1].loc.line == 19);  // "ID = cdomConc", unindented
}

TEST_CASE("material file: nested sections, comments and line numbers") {
    const std::string text =
        "# a comment line\n"                    // 1
        "\n"                                    // 2
        "BULK_PROPERTIES {  # trailing\n"       // 3
        "    IOP_MODEL{\n"                      // 4
        "        BASE_MEDIUM =   purewater   \n"  // 5
        "\n"                                    // 6
        "        ADD_SCATTERING_MODEL {\r\n"    // 7  (CRLF tolerated)
        "            TYPE = gordonmorel\n"      // 8
        "            EXCLUSIVE = 0 # no\n"      // 9
        "        }\n"                           // 10
        "        ADD_PHASE_FUNCTION_MODEL {\n"  // 11
        "            TYPE = petzold\n"          // 12
        "            SCATID = chlScat\n"        // 13
        "        }\n"                           // 14
        "    }\n"                               // 15
        "}\n"                                   // 16
        "OTHER {\n"                             // 17
        "}";                                    // 18, no final newline
    const auto root = parse_material(text, "dir/water.mat");
    REQUIRE(root.sections.size() == 2);
    const auto& bulk = root.sections[0];
    CHECK(bulk.loc.line == 3);
    CHECK(bulk.loc.where() == "dir/water.mat:3");
    const auto& iop = bulk.sections.at(0);
    CHECK(iop.loc.line == 4);
    CHECK(iop.parameters.at(0).value == "purewater");
    CHECK(iop.parameters.at(0).loc.line == 5);
    REQUIRE(iop.sections.size() == 2);
    CHECK(iop.sections[0].name == "ADD_SCATTERING_MODEL");
    CHECK(iop.sections[0].loc.line == 7);
    CHECK(iop.sections[0].parameters.at(1).value == "0");
    CHECK(iop.sections[0].parameters.at(1).loc.line == 9);
    CHECK(iop.sections[1].describe() == "ADD_PHASE_FUNCTION_MODEL (TYPE = petzold)");
    CHECK(iop.sections[1].find("SCATID")->loc.where() == "dir/water.mat:13");
    CHECK(root.sections[1].name == "OTHER");
    CHECK(root.sections[1].loc.line == 17);
    CHECK(root.sections[1].parameters.empty());
}

TEST_CASE("material file: syntax errors name the file, the line and the name") {
    SECTION("unclosed section names the line where it opened") {
        CHECK_THROWS_AS(parse_material("A {\n  B {\n  X = 1\n}\n", "u.mat"), input_error);
        CHECK_THROWS_WITH(parse_material("A {\n  B {\n  X = 1\n}\n", "u.mat"),
                          Contains("u.mat:1") && Contains("A") && Contains("not closed"));
        CHECK_THROWS_WITH(parse_material("A {\n}\nB {\n", "u.mat"), Contains("u.mat:3") && Contains("B"));
    }
    SECTION("stray closing brace names its line") {
        CHECK_THROWS_WITH(parse_material("A {\n}\n}\n", "s.mat"), Contains("s.mat:3") && Contains("stray"));
    }
    SECTION("malformed lines") {
        CHECK_THROWS_WITH(parse_material("A {\n  just words\n}\n", "m.mat"),
                          Contains("m.mat:2") && Contains("just words") && Contains("malformed"));
        CHECK_THROWS_WITH(parse_material("A {\n  = 3\n}\n", "m.mat"), Contains("m.mat:2") && Contains("malformed"));
        CHECK_THROWS_WITH(parse_material("A {\n  MY NAME = 3\n}\n", "m.mat"), Contains("m.mat:2"));
        CHECK_THROWS_WITH(parse_material("BAD NAME {\n}\n", "m.mat"), Contains("m.mat:1") && Contains("BAD NAME"));
        CHECK_THROWS_WITH(parse_material("A { }\n", "m.mat"), Contains("m.mat:1") && Contains("malformed"));
        CHECK_THROWS_WITH(parse_material("A {\n}}\n", "m.mat"), Contains("m.mat:2"));
    }
    SECTION("empty value") {
        CHECK_THROWS_WITH(parse_material("A {\n  K =   # nothing\n}\n", "e.mat"),
                          Contains("e.mat:2") && Contains("K") && Contains("empty value") && Contains("section A"));
    }
    SECTION("duplicate parameter names both lines") {
        CHECK_THROWS_WITH(
            parse_material("ADD_ABSORPTION_MODEL {\n  TYPE = morelconc\n  K = 0.04\n\n  K = 0.05\n}\n", "d.mat"),
            Contains("d.mat:5") && Contains("d.mat:3") && Contains("K = 0.05") && Contains("duplicate") &&
                Contains("ADD_ABSORPTION_MODEL (TYPE = morelconc)"));
        // the same name in two sections is fine
        CHECK_NOTHROW(parse_material("A {\n K = 1\n}\nB {\n K = 2\n}\n", "d.mat"));
    }
}

TEST_CASE("material file: numbers, ranges, flags and arrays") {
    auto r = reader_of("  TYPE = hg\n  A = 0.5\n  BAD = 0.1x\n  NAN = nan\n  INF = inf\n  BIG = 2.5\n"
                       "  F1 = 1\n  F0 = 0\n  F2 = 2\n  FT = true\n  G = 0.9, 0.5 0.1\n  W = 0.2,0.3\n"
                       "  GBAD = 0.9,,0.5\n  GX = 0.9 x\n  NEG = -1e-3\n  PLUS = +2\n",
                       "n.mat");  // lines 2..17 (line 1 is "SEC {")
    CHECK(r.number("A", 0.0) == 0.5);
    CHECK(r.number("MISSING", 7.0) == 7.0);
    CHECK_FALSE(r.optional_number("MISSING").has_value());
    CHECK(r.number("NEG") == -1e-3);
    CHECK(r.number("PLUS") == 2.0);
    CHECK_THROWS_WITH(r.number("BAD", 0.0), Contains("n.mat:4") && Contains("BAD = 0.1x") && Contains("SEC (TYPE = hg)"));
    CHECK_THROWS_WITH(r.number("NAN", 0.0), Contains("n.mat:5") && Contains("NAN"));
    CHECK_THROWS_WITH(r.number("INF", 0.0), Contains("n.mat:6") && Contains("INF"));
    CHECK(r.number_in("A", 0.0, 0.0, 1.0) == 0.5);
    CHECK(r.number_in("ABSENT", 3.0, 0.0, 1.0) == 3.0);  // defaults are not range checked
    CHECK_THROWS_WITH(r.number_in("BIG", 0.0, -1.0, 1.0),
                      Contains("n.mat:7") && Contains("BIG = 2.5") && Contains("SEC (TYPE = hg)") && Contains("[-1, 1]"));

    CHECK(r.flag("F1", false));
    CHECK_FALSE(r.flag("F0", true));
    CHECK(r.flag("ABSENT", true));
    CHECK_THROWS_WITH(r.flag("F2", false), Contains("n.mat:10") && Contains("F2 = 2") && Contains("0 or 1"));
    CHECK_THROWS_WITH(r.flag("FT", false), Contains("n.mat:11") && Contains("FT = true"));

    CHECK(r.numbers("G", {}) == std::vector<double>{0.9, 0.5, 0.1});
    CHECK(r.numbers("W") == std::vector<double>{0.2, 0.3});
    CHECK(r.numbers("A") == std::vector<double>{0.5});  // a single number is an array of one
    CHECK(r.numbers("ABSENT", {1.0}) == std::vector<double>{1.0});
    CHECK_THROWS_WITH(r.numbers("GBAD", {}), Contains("n.mat:14") && Contains("GBAD"));
    CHECK_THROWS_WITH(r.numbers("GX", {}), Contains("n.mat:15") && Contains("'x'"));

    CHECK_THROWS_WITH(r.number("REQUIRED"), Contains("REQUIRED") && Contains("missing") && Contains("n.mat:1"));
    CHECK_THROWS_WITH(r.text("REQUIRED"), Contains("REQUIRED") && Contains("SEC (TYPE = hg)"));
}

TEST_CASE("material file: unknown parameters are rejected by finish()") {
    const auto root = parse_material(morelconc_example, "u.mat");
    ParameterReader abs(root.sections[0].sections[0].sections[0]);
    CHECK(abs.text("TYPE") == "morelconc");
    (void)abs.text("ID", "");
    (void)abs.text("CONCID", "");
    (void)abs.flag("PRENORM", false);
    (void)abs.number("ABS", 1.0);
    (void)abs.number("K", 0.0);
    CHECK(abs.has("Q"));  // has() alone does not count as reading
    CHECK_THROWS_WITH(abs.finish(), Contains("unknown parameter Q") &&
                                        Contains("ADD_ABSORPTION_MODEL (TYPE = morelconc)") && Contains("u.mat:11") &&
                                        Contains("known parameters:") && Contains("CONCID"));
    (void)abs.number("Q", 0.0);
    CHECK_NOTHROW(abs.finish());

    // names are case-sensitive: a lower-case name is unknown
    auto lower = reader_of("  TYPE = constant\n  conc = 0.5\n", "c.mat");
    CHECK(lower.number("CONC", 2.0) == 2.0);
    (void)lower.text("TYPE");
    CHECK_THROWS_WITH(lower.finish(), Contains("unknown parameter conc") && Contains("c.mat:3") && Contains("CONC"));

    // the binding's own rejections carry the same context
    auto type = reader_of("  TYPE = nosuchmodel\n", "t.mat");
    CHECK_THROWS_WITH(type.reject_value("TYPE", "unknown absorption model type"),
                      Contains("t.mat:2") && Contains("TYPE = nosuchmodel") && Contains("unknown absorption model"));
}

TEST_CASE("material file: reading files and relative FILENAMEs") {
    const auto dir = scratch_dir("relative");
    std::filesystem::create_directories(dir / "data");
    write_file(dir / "data" / "abs.txt", "# wavelength_nm  a [1/m]\n400 0.01\n500, 0.02\n\n600\t0.3 # red\n");
    write_file(dir / "water.mat",
               "IOP_MODEL {\n"
               "  ADD_ABSORPTION_MODEL {\n"
               "    TYPE = constant\n"
               "    FILENAME = data/abs.txt\n"
               "    OTHER = data/missing.txt\n"
               "  }\n"
               "}\n");
    const auto root = read_material_file(dir / "water.mat");
    CHECK(root.sections.at(0).loc.file == (dir / "water.mat").string());
    ParameterReader r(root.sections[0].sections.at(0));
    const auto file = r.file("FILENAME");
    CHECK(std::filesystem::equivalent(file, dir / "data" / "abs.txt"));
    CHECK_THROWS_WITH(r.file("OTHER"), Contains((dir / "water.mat").string() + ":5") && Contains("OTHER") &&
                                           Contains("missing.txt") && Contains("does not exist"));
    CHECK_FALSE(r.optional_file("ABSENT").has_value());

    // an absolute FILENAME is used as is
    auto abs_reader = reader_of("  FILENAME = " + (dir / "data" / "abs.txt").string() + "\n", "elsewhere/x.mat");
    CHECK(abs_reader.file("FILENAME") == dir / "data" / "abs.txt");

    const auto data = read_spectral_file(file);
    CHECK(data.wavelength_nm == std::vector<double>{400, 500, 600});
    CHECK(data.value == std::vector<double>{0.01, 0.02, 0.3});
    CHECK(data.path == file);

    // a missing material file names its path
    CHECK_THROWS_WITH(read_material_file(dir / "nope.mat"), Contains("nope.mat"));
    CHECK_THROWS_AS(read_material_file(dir / "nope.mat"), input_error);
    CHECK_THROWS_WITH(read_material_file(dir), Contains(dir.string()));  // a directory is not a file
}

TEST_CASE("material file: data-file errors name path:line") {
    const auto dir = scratch_dir("spectral");
    const auto check_error = [&](const std::string& name, const std::string& text, const std::string& expect) {
        write_file(dir / name, text);
        const std::string path = (dir / name).string();
        CHECK_THROWS_AS(read_spectral_file(dir / name), input_error);
        CHECK_THROWS_WITH(read_spectral_file(dir / name), Contains(path + expect));
    };
    check_error("garbage.txt", "400 0.1\n500 0.1x\n", ":2");
    check_error("one_column.txt", "# header\n400 0.1\n500\n", ":3");
    check_error("nan.txt", "400 nan\n500 0.2\n", ":1");
    check_error("words.txt", "wavelength value\n400 0.1\n500 0.2\n", ":1");
    check_error("decreasing.txt", "400 0.1\n500 0.2\n450 0.3\n", ":3");
    check_error("repeated.txt", "400 0.1\n400 0.2\n", ":2");
    check_error("ragged.txt", "400 0.1 7\n500 0.2\n", ":2");
    check_error("one_row.txt", "# only one\n400 0.1\n", "");
    check_error("empty.txt", "", "");
    CHECK_THROWS_WITH(read_spectral_file(dir / "one_row.txt"), Contains("at least 2"));
    CHECK_THROWS_WITH(read_spectral_file(dir / "absent.txt"), Contains("absent.txt"));

    // phase-function tables: mu from -1 to 1, three columns allowed (extra ignored)
    write_file(dir / "phase.txt", "-1, 0.5, 9\n0, 1.0, 9\n1, 20.0, 9\n");
    const auto phase = read_spectral_file(dir / "phase.txt");
    CHECK(phase.wavelength_nm == std::vector<double>{-1, 0, 1});
    CHECK(phase.value == std::vector<double>{0.5, 1.0, 20.0});
}
