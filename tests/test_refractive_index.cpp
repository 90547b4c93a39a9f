// Refractive index models of the DIRSIG water manual 5.9: constant and IAPWS R9-97.
// Reference values from /work/shared/data/iapws_1997_refractive_index_check_values.csv and
// iapws_1997_refractive_index_286K_1atm.csv, typed in.
#include <catch2/catch.hpp>
#include "secchi/optics/iop/refractive_index.hpp"
#include <cmath>
#include <string>

using namespace secchi;
using namespace secchi::iop;

TEST_CASE("constant refractive index: IOR, default 1.0") {
    CHECK(std::string(ConstantRefractiveIndex::type_name) == "constant");
    CHECK(ConstantRefractiveIndex().refractive_index(500.0) == 1.0);
    const ConstantRefractiveIndex water(1.34);
    CHECK(water.refractive_index(400.0) == 1.34);
    CHECK(water.refractive_index(2000.0) == 1.34);
    CHECK(ConstantRefractiveIndex(1.0003).ior() == 1.0003);  // the "air" base medium
    CHECK_THROWS_AS(ConstantRefractiveIndex(0.75), input_error);
    CHECK_THROWS_AS(ConstantRefractiveIndex(std::nan("")), input_error);
}

TEST_CASE("iapws defaults are the manual's: 273.15 K, 1000 kg/m^3") {
    const IapwsRefractiveIndex m;
    CHECK(std::string(IapwsRefractiveIndex::type_name) == "iapws");
    CHECK(m.temperature_K() == 273.15);
    CHECK(m.density() == 1000.0);
    // reduced state (1, 1, 1): A = a0 + a1 + a2 + a3 + a4 + a5/(1 - uv^2) + a6/(1 - ir^2) + a7
    const double uv = 0.2292020, ir = 5.432937;
    const double a = 0.244257733 + 9.74634476e-3 - 3.73234996e-3 + 2.68678472e-4 + 1.58920570e-3 +
                     2.45934259e-3 / (1.0 - uv * uv) + 0.900704920 / (1.0 - ir * ir) - 1.66626219e-2;
    CHECK(m.refractive_index(589.0) == Approx(std::sqrt((1.0 + 2.0 * a) / (1.0 - a))).epsilon(1e-15));
}

TEST_CASE("iapws reproduces the check values to 1e-7") {
    struct Row {
        double t, rho, wl_um, n;
    };
    // iapws_1997_refractive_index_check_values.csv: n_reference where published, else n_computed_here
    const Row rows[] = {
        {298.15, 997.047435, 0.2265, 1.39277824},  // IAPWS R9-97, quoted by python iapws 1.5.5
        {773.15, 30.4758534, 0.5893, 1.00949307},  // idem (steam)
        {298.15, 997.047435, 0.5893, 1.3328581926},
        {293.15, 1000.0, 0.589, 1.33394299},
        {293.15, 998.2072, 0.589, 1.33335848},
        {286.0, 999.3989, 0.589, 1.33390874},
    };
    for (const Row& r : rows) {
        CAPTURE(r.t, r.rho, r.wl_um);
        CHECK(std::abs(IapwsRefractiveIndex(r.t, r.rho).refractive_index(1000.0 * r.wl_um) - r.n) < 1e-7);
    }
}

TEST_CASE("pure water index: IAPWS at 286 K, 999.3989 kg/m^3 (the purewater base medium)") {
    const IapwsRefractiveIndex m = pure_water_refractive_index();
    CHECK(m.temperature_K() == 286.0);
    CHECK(m.density() == 999.3989);
    // iapws_1997_refractive_index_286K_1atm.csv (6 decimals)
    const double table[][2] = {{200.0, 1.424922}, {400.0, 1.344133}, {500.0, 1.337354},
                               {590.0, 1.333878}, {700.0, 1.331060}, {1100.0, 1.324428}};
    for (const auto& row : table) {
        CAPTURE(row[0]);
        CHECK(std::abs(m.refractive_index(row[0]) - row[1]) < 5.1e-7);
    }
    // normal dispersion: n decreases with wavelength through the visible
    CHECK(m.refractive_index(450.0) > m.refractive_index(550.0));
}

TEST_CASE("iapws enforces the release's range of validity") {
    CHECK_THROWS_AS(IapwsRefractiveIndex(261.0, 1000.0), input_error);
    CHECK_THROWS_AS(IapwsRefractiveIndex(774.0, 30.0), input_error);
    CHECK_THROWS_AS(IapwsRefractiveIndex(300.0, -1.0), input_error);
    CHECK_THROWS_AS(IapwsRefractiveIndex(300.0, 1061.0), input_error);
    CHECK_THROWS_AS(IapwsRefractiveIndex(std::nan(""), 1000.0), input_error);
    CHECK_NOTHROW(IapwsRefractiveIndex(261.15, 0.0));
    CHECK(IapwsRefractiveIndex(500.0, 0.0).refractive_index(500.0) == 1.0);  // vacuum
    const IapwsRefractiveIndex m;
    CHECK_THROWS_AS(m.refractive_index(199.0), input_error);
    CHECK_THROWS_AS(m.refractive_index(1101.0), input_error);
    CHECK_THROWS_AS(m.refractive_index(std::nan("")), input_error);
    try {
        (void)m.refractive_index(1500.0);
        FAIL("no input_error");
    } catch (const input_error& e) {
        CHECK(std::string(e.what()).starts_with("invalid wavelength (nm) = 1500: outside the IAPWS R9-97 range"));
    }
}

TEST_CASE("refractive index noise is a reproducible function of wavelength") {
    ConstantRefractiveIndex m(1.34);
    m.set_noise(Noise(0.01, 5));
    const double n500 = m.refractive_index(500.0);
    CHECK(n500 == m.refractive_index(500.0));
    CHECK(n500 != 1.34);
    CHECK(n500 == Approx(1.34 + 0.01 * Noise(0.01, 5).deviate(vec3(0.0), 500.0)).epsilon(1e-15));
    CHECK(n500 != m.refractive_index(501.0));
    const IapwsRefractiveIndex w = pure_water_refractive_index(Noise(1e-4, 9));
    CHECK(std::abs(w.refractive_index(500.0) - 1.337354) < 6e-4);
    CHECK(w.noise().sigma() == 1e-4);
}
