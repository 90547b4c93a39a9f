// Absorption models of the DIRSIG water manual 5.6 (and Bricaud 1995/1998, CDOM), the spectral
// table and the embedded data. Expected values are typed in from the CSVs of /work/shared/data
// (not read from the headers' arrays), so a mis-copied number or a wrong formula fails.
#include <catch2/catch.hpp>
#include "secchi/optics/iop/absorption.hpp"
#include "secchi/optics/iop/spectral_table.hpp"
#include <cmath>
#include <string>
#include <vector>

using namespace secchi;
using namespace secchi::iop;
using Catch::Matchers::Contains;

namespace {

const vec3 origin(0.0, 0.0, 0.0);

/// A constant chlorophyll concentration (mg m^-3).
struct FixedConc {
    double c;
    [[nodiscard]] double concentration(vec3) const { return c; }
};

/// Chlorophyll growing with depth: C = 1 + z (mg m^-3).
struct LinearConc {
    [[nodiscard]] double concentration(vec3 x) const { return 1.0 + x.z; }
};

std::string message_of(auto&& f) {
    try {
        f();
    } catch (const input_error& e) {
        return e.what();
    }
    return "no input_error";
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// SpectralTable

TEST_CASE("SpectralTable interpolates linearly and is exact on nodes") {
    const std::vector<double> wl{400.0, 410.0, 430.0}, v{1.0, 2.0, 0.0};
    const SpectralTable t("test", wl, v);
    CHECK(t.min_wavelength() == 400.0);
    CHECK(t.max_wavelength() == 430.0);
    CHECK(t.size() == 3);
    CHECK(t.at(400.0) == 1.0);
    CHECK(t.at(410.0) == 2.0);
    CHECK(t.at(430.0) == 0.0);
    CHECK(t.at(405.0) == Approx(1.5).epsilon(1e-15));
    CHECK(t.at(415.0) == Approx(1.5).epsilon(1e-15));
    CHECK(t.at(427.5) == Approx(0.25).epsilon(1e-15));
}

TEST_CASE("SpectralTable from {wavelength, value} pairs equals the one from two spans") {
    const std::vector<SpectralPoint> pts{{300.0, 3.0}, {350.0, -1.0}, {360.0, 5.0}};
    const std::vector<double> wl{300.0, 350.0, 360.0}, v{3.0, -1.0, 5.0};
    const SpectralTable a("pairs", pts), b("spans", wl, v);
    for (double w : {300.0, 310.0, 349.0, 350.0, 355.5, 360.0}) CHECK(a.at(w) == b.at(w));
    CHECK(a.at(325.0) == Approx(1.0));  // negative values are allowed (e.g. Bricaud B)
}

TEST_CASE("SpectralTable outside its range throws naming the table, the wavelength and the range") {
    const SmithBakerAbsorption sb;
    CHECK(message_of([&] { (void)sb.coefficient(origin, 900.0); })
              .starts_with("invalid wavelength (nm) = 900: outside the Smith-Baker 1981 table, 200-800 nm"));
    const SpectralTable t("my file.txt", std::vector<double>{400.0, 727.5}, std::vector<double>{1.0, 2.0});
    CHECK(message_of([&] { (void)t.at(399.9); }).starts_with("invalid wavelength (nm) = 399.9: outside the my file.txt table, 400-727.5 nm"));
    CHECK_THROWS_AS(t.at(727.6), input_error);
    CHECK_THROWS_AS(t.at(std::nan("")), input_error);
    CHECK_FALSE(t.covers(std::nan("")));
}

TEST_CASE("SpectralTable rejects malformed tables") {
    using V = std::vector<double>;
    const double nan = std::nan(""), inf = INFINITY;
    CHECK_THROWS_AS(SpectralTable("t", V{400, 400}, V{1, 2}), input_error);     // not strictly increasing
    CHECK_THROWS_AS(SpectralTable("t", V{400, 390, 500}, V{1, 2, 3}), input_error);
    CHECK_THROWS_AS(SpectralTable("t", V{400, 410}, V{1}), input_error);        // size mismatch
    CHECK_THROWS_AS(SpectralTable("t", V{400}, V{1}), input_error);             // one node
    CHECK_THROWS_AS(SpectralTable("t", V{}, V{}), input_error);
    CHECK_THROWS_AS(SpectralTable("t", V{400, nan}, V{1, 2}), input_error);
    CHECK_THROWS_AS(SpectralTable("t", V{400, 410}, V{1, inf}), input_error);
    CHECK_THAT(message_of([] { SpectralTable("user.txt", V{400, 410, 405}, V{1, 2, 3}); }),
               Contains("user.txt") && Contains("row 3") && Contains("strictly increasing"));
}

// ---------------------------------------------------------------------------------------------
// Embedded data (spot values from the CSVs and the data README's checks)

TEST_CASE("embedded tables have the CSVs' grids and values") {
    CHECK(data::pope_fry_1997_absorption.size() == 140);
    CHECK(data::smith_baker_1981_absorption.size() == 61);
    CHECK(data::hybrid_sbpf_absorption.size() == 166);
    CHECK(data::morel_prieur_1977_absorption.size() == 33);
    CHECK(data::prieur_sathyendranath_1981_achl_normalized.size() == 61);
    CHECK(data::bricaud_1995_A.size() == 152);
    CHECK(data::bricaud_1998_E_phi.size() == 151);

    const SpectralTable pf = pope_fry_1997_absorption_table();
    CHECK(pf.at(440.0) == 0.00635);  // README section 1 checks
    CHECK(pf.at(550.0) == 0.0565);
    CHECK(pf.max_wavelength() == 727.5);
    // README section 2: interpolated check values of Smith & Baker a and b
    const SpectralTable sbb("SB b", data::smith_baker_1981_scattering);
    CHECK(sbb.at(500.0) == 0.0029);
    CHECK(sbb.at(417.0) == Approx(0.00631).epsilon(1e-12));
    CHECK(sbb.at(486.0) == Approx(0.00322).epsilon(1e-12));
    CHECK(sbb.at(800.0) == 0.0004);
    const SpectralTable mpb("MP b", data::morel_prieur_1977_scattering);
    CHECK(mpb.at(700.0) == 0.00052);
    // README section 9: Bricaud 1998 at 440 nm
    CHECK(SpectralTable("", data::bricaud_1998_A_p).at(440.0) == 0.052019);
    CHECK(SpectralTable("", data::bricaud_1998_E_p).at(440.0) == 0.634965);
    CHECK(SpectralTable("", data::bricaud_1998_A_phi).at(440.0) == 0.037824);
    CHECK(SpectralTable("", data::bricaud_1998_E_phi).at(440.0) == 0.626633);
    CHECK(SpectralTable("", data::bricaud_1995_B).at(700.0) == -0.034);
}

// ---------------------------------------------------------------------------------------------
// Pure-water models

TEST_CASE("smithbaker: Smith & Baker 1981 a_w, interpolated, 200-800 nm") {
    const SmithBakerAbsorption m;
    CHECK(std::string(SmithBakerAbsorption::type_name) == "smithbaker");
    CHECK(m.coefficient(origin, 500.0) == 0.0257);
    CHECK(m.coefficient(origin, 200.0) == 3.07);
    CHECK(m.coefficient(origin, 800.0) == 2.07);
    CHECK(m.coefficient(origin, 417.0) == Approx(0.01557).epsilon(1e-12));  // README check value
    CHECK(m.coefficient(origin, 486.0) == Approx(0.0188).epsilon(1e-12));
    CHECK(m.coefficient(origin, 415.0) == Approx(0.5 * (0.0162 + 0.0153)).epsilon(1e-12));
    CHECK_THROWS_AS(m.coefficient(origin, 199.0), input_error);
    CHECK_THROWS_AS(m.coefficient(origin, 801.0), input_error);
}

TEST_CASE("sbpf: Pope & Fry inside 380-727.5 nm, Smith & Baker outside") {
    const HybridPureWaterAbsorption m;
    CHECK(std::string(HybridPureWaterAbsorption::type_name) == "sbpf");
    CHECK(m.coefficient(origin, 440.0) == 0.00635);       // Pope & Fry
    CHECK(m.coefficient(origin, 380.0) == 0.01137);       // Pope & Fry preferred over SB's 0.0220
    CHECK(m.coefficient(origin, 370.0) == 0.0300);        // Smith & Baker
    CHECK(m.coefficient(origin, 730.0) == 1.799);
    CHECK(m.coefficient(origin, 200.0) == 3.07);
    CHECK(m.coefficient(origin, 800.0) == 2.07);
    CHECK(m.coefficient(origin, 375.0) == Approx(0.5 * (0.0300 + 0.01137)).epsilon(1e-12));
    CHECK(m.coefficient(origin, 381.25) == Approx(0.5 * (0.01137 + 0.01044)).epsilon(1e-12));
    CHECK(m.coefficient(origin, 728.75) == Approx(0.5 * (1.678 + 1.799)).epsilon(1e-12));
    CHECK(m.coefficient(origin, 735.0) == Approx(0.5 * (1.799 + 2.38)).epsilon(1e-12));
    CHECK_THROWS_AS(m.coefficient(origin, 850.0), input_error);
}

TEST_CASE("prieursathy: the Morel & Prieur 1977 stand-in, 380-700 nm") {
    const PrieurSathyAbsorption m;
    CHECK(std::string(PrieurSathyAbsorption::type_name) == "prieursathy");
    CHECK(m.coefficient(origin, 400.0) == 0.018);
    CHECK(m.coefficient(origin, 700.0) == 0.650);
    CHECK(m.coefficient(origin, 405.0) == Approx(0.0175).epsilon(1e-12));
    CHECK(m.coefficient(origin, 417.5) == Approx(0.25 * 0.017 + 0.75 * 0.016).epsilon(1e-12));
    CHECK_THROWS_AS(m.coefficient(origin, 375.0), input_error);
    CHECK_THROWS_AS(m.coefficient(origin, 710.0), input_error);
}

// ---------------------------------------------------------------------------------------------
// morelconc (eq. 5.16)

TEST_CASE("morelconc defaults are the manual's") {
    const MorelConcentrationParams p;
    CHECK(p.abs == 0.1);
    CHECK(p.refwl == 440.0);
    CHECK(p.prenorm == false);
    CHECK(p.k == 0.06);
    CHECK(p.q == 0.65);
    REQUIRE(p.table.has_value());
    CHECK(p.table->min_wavelength() == 400.0);
    CHECK(p.table->max_wavelength() == 700.0);
    CHECK(std::string(MorelConcentrationAbsorption<FixedConc>::type_name) == "morelconc");
}

TEST_CASE("morelconc with defaults is eq. 5.14: 0.06 a*_c'(lambda) C^0.65") {
    const MorelConcentrationAbsorption m(FixedConc{2.0});
    const double c = std::pow(2.0, 0.65);
    CHECK(m.coefficient(origin, 440.0) == Approx(0.06 * 1.000 * c).epsilon(1e-14));
    CHECK(m.coefficient(origin, 435.0) == Approx(0.06 * 1.001 * c).epsilon(1e-14));
    CHECK(m.coefficient(origin, 675.0) == Approx(0.06 * 0.544 * c).epsilon(1e-14));
    CHECK(m.coefficient(origin, 400.0) == Approx(0.06 * 0.687 * c).epsilon(1e-14));
    CHECK(m.coefficient(origin, 402.0) == Approx(0.06 * (0.687 + 0.4 * (0.781 - 0.687)) * c).epsilon(1e-14));
    CHECK_THROWS_AS(m.coefficient(origin, 395.0), input_error);
    CHECK_THROWS_AS(m.coefficient(origin, 701.0), input_error);
}

TEST_CASE("morelconc follows the concentration with position") {
    const MorelConcentrationAbsorption m(LinearConc{});
    for (double z : {0.0, 1.0, 4.5})
        CHECK(m.coefficient(vec3(0.3, -2.0, z), 550.0) == Approx(0.06 * 0.357 * std::pow(1.0 + z, 0.65)).epsilon(1e-14));
}

TEST_CASE("morelconc normalises a user table at REFWL unless PRENORM") {
    const SpectralTable user("astar.txt", std::vector<double>{400.0, 440.0, 500.0}, std::vector<double>{0.02, 0.04, 0.01});
    MorelConcentrationParams p;
    p.table = user;
    p.k = 1.0;
    p.q = 1.0;
    const MorelConcentrationAbsorption normed(FixedConc{3.0}, p);
    CHECK(normed.coefficient(origin, 400.0) == Approx(0.5 * 3.0).epsilon(1e-14));
    CHECK(normed.coefficient(origin, 470.0) == Approx(0.625 * 3.0).epsilon(1e-14));
    p.refwl = 500.0;
    const MorelConcentrationAbsorption at500(FixedConc{3.0}, p);
    CHECK(at500.coefficient(origin, 440.0) == Approx(4.0 * 3.0).epsilon(1e-14));
    p.prenorm = true;
    const MorelConcentrationAbsorption raw(FixedConc{3.0}, p);
    CHECK(raw.coefficient(origin, 400.0) == Approx(0.02 * 3.0).epsilon(1e-14));
}

TEST_CASE("morelconc without a table uses the constant ABS") {
    MorelConcentrationParams p;
    p.table.reset();
    const MorelConcentrationAbsorption m(FixedConc{2.0}, p);
    CHECK(m.coefficient(origin, 300.0) == Approx(0.06 * 0.1 * std::pow(2.0, 0.65)).epsilon(1e-14));
    CHECK(m.coefficient(origin, 900.0) == Approx(0.06 * 0.1 * std::pow(2.0, 0.65)).epsilon(1e-14));
    p.abs = 0.5;
    CHECK(MorelConcentrationAbsorption(FixedConc{1.0}, p).coefficient(origin, 500.0) == Approx(0.03));
}

TEST_CASE("morelconc rejects invalid parameters") {
    auto with = [](auto change) {
        MorelConcentrationParams p;
        change(p);
        return [p] { MorelConcentrationAbsorption m(FixedConc{1.0}, p); };
    };
    CHECK_THROWS_AS(with([](auto& p) { p.k = -0.06; })(), input_error);
    CHECK_THROWS_AS(with([](auto& p) { p.q = -0.5; })(), input_error);
    CHECK_THROWS_AS(with([](auto& p) { p.q = std::nan(""); })(), input_error);
    CHECK_THROWS_AS(with([](auto& p) { p.abs = -1.0; })(), input_error);
    CHECK_THROWS_AS(with([](auto& p) { p.refwl = 380.0; })(), input_error);  // outside the P-S table
    CHECK_THAT(message_of(with([](auto& p) { p.k = -1.0; })), Contains("invalid K = -1"));
    CHECK_THAT(message_of(with([](auto& p) { p.refwl = 380.0; })), Contains("REFWL"));
    using V = std::vector<double>;
    CHECK_THROWS_AS(with([](auto& p) { p.table = SpectralTable("z", V{400, 440, 480}, V{1, 0, 1}); })(), input_error);
    CHECK_THROWS_AS(with([](auto& p) { p.table = SpectralTable("n", V{400, 440}, V{-1, 1}); })(), input_error);
    CHECK_NOTHROW(with([](auto& p) { p.refwl = 380.0; p.prenorm = true; })());
}

// ---------------------------------------------------------------------------------------------
// morelcovar (eq. 5.17)

TEST_CASE("morelcovar defaults are the manual's") {
    const MorelCovariantParams p;
    CHECK(p.refwl == 440.0);
    CHECK(p.usewl == false);
    CHECK(p.k == 0.2);
    CHECK(p.q == -0.014);
    CHECK(std::string(MorelCovariantAbsorption<CdomAbsorption>::type_name) == "morelcovar");
}

TEST_CASE("morelcovar with defaults over morelconc is eq. 5.15: 0.2 a_p(440) e^{-0.014 (lambda - 440)}") {
    const MorelConcentrationAbsorption ap(LinearConc{});
    const MorelCovariantAbsorption ay(ap);
    for (double z : {0.0, 2.0}) {
        const vec3 x(0.0, 0.0, z);
        const double ap440 = 0.06 * std::pow(1.0 + z, 0.65);  // a*_c'(440) = 1
        for (double wl : {400.0, 440.0, 550.0, 700.0, 800.0})
            CHECK(ay.coefficient(x, wl) == Approx(0.2 * ap440 * std::exp(-0.014 * (wl - 440.0))).epsilon(1e-13));
    }
    // CDOM-like: decays with wavelength (this fails for the sign as printed in eq. 5.17)
    CHECK(ay.coefficient(origin, 500.0) < ay.coefficient(origin, 440.0));
    CHECK(ay.coefficient(origin, 540.0) == Approx(0.2 * 0.06 * std::exp(-1.4)).epsilon(1e-13));
    // covariance at lambda_0 only: outside a_p's table, a_y still exists (its base is read at 440)
    CHECK_NOTHROW(ay.coefficient(origin, 350.0));
}

TEST_CASE("morelcovar with other parameters") {
    MorelCovariantParams p;
    p.k = 0.5;
    p.q = 0.01;
    p.refwl = 500.0;
    p.usewl = true;  // no effect: the base is a continuous function of wavelength
    const MorelCovariantAbsorption m(SmithBakerAbsorption{}, p);
    CHECK(m.coefficient(origin, 600.0) == Approx(0.5 * 0.0257 * std::exp(1.0)).epsilon(1e-13));
    auto bad = [](auto change) {
        MorelCovariantParams q;
        change(q);
        return [q] { MorelCovariantAbsorption m(CdomAbsorption{}, q); };
    };
    CHECK_THROWS_AS(bad([](auto& q) { q.k = -0.2; })(), input_error);
    CHECK_THROWS_AS(bad([](auto& q) { q.q = INFINITY; })(), input_error);
    CHECK_THROWS_AS(bad([](auto& q) { q.refwl = 0.0; })(), input_error);
    CHECK_THROWS_AS(m.coefficient(origin, -5.0), input_error);
}

// ---------------------------------------------------------------------------------------------
// raman (eq. 5.18)

TEST_CASE("raman: a0 (lambda0/lambda)^q with the manual's defaults and q = 5.5") {
    const RamanParams p;
    CHECK(p.refwl == 488.0);
    CHECK(p.refabs == 0.00026);
    CHECK(p.q == 5.5);
    const RamanAbsorption m;
    CHECK(std::string(RamanAbsorption::type_name) == "raman");
    CHECK(m.coefficient(origin, 488.0) == Approx(0.00026).epsilon(1e-15));
    CHECK(m.coefficient(origin, 400.0) == Approx(0.00026 * std::pow(488.0 / 400.0, 5.5)).epsilon(1e-14));
    CHECK(m.coefficient(origin, 400.0) == Approx(7.762e-4).epsilon(1e-3));  // 2.6e-4 x 1.22^5.5 = 2.6e-4 x 2.985
    CHECK(m.coefficient(origin, 600.0) == Approx(0.00026 * std::pow(488.0 / 600.0, 5.5)).epsilon(1e-14));
    CHECK_THROWS_AS(m.coefficient(origin, 0.0), input_error);
    CHECK_THROWS_AS(RamanAbsorption(RamanParams{.refwl = -1.0}), input_error);
    CHECK_THROWS_AS(RamanAbsorption(RamanParams{.refabs = -1e-4}), input_error);
    CHECK_THROWS_AS(RamanAbsorption(RamanParams{.q = std::nan("")}), input_error);
}

// ---------------------------------------------------------------------------------------------
// Beyond the manual

TEST_CASE("bricaud1995: a_ph = C A(lambda) C^-B(lambda)") {
    const Bricaud1995Absorption one(FixedConc{1.0}), tenth(FixedConc{0.1});
    CHECK(one.coefficient(origin, 440.0) == 0.0403);
    CHECK(tenth.coefficient(origin, 440.0) == Approx(0.1 * 0.0403 * std::pow(0.1, -0.332)).epsilon(1e-14));
    CHECK(tenth.coefficient(origin, 675.0) == Approx(0.1 * 0.0201 * std::pow(0.1, -0.158)).epsilon(1e-14));
    // 441 nm: A and B interpolated separately
    const double a = 0.5 * (0.0403 + 0.0398), b = 0.5 * (0.332 + 0.339);
    CHECK(tenth.coefficient(origin, 441.0) == Approx(0.1 * a * std::pow(0.1, -b)).epsilon(1e-13));
    CHECK(FixedConc{0.0}.concentration(origin) == 0.0);
    CHECK(Bricaud1995Absorption(FixedConc{0.0}).coefficient(origin, 700.0) == 0.0);
    CHECK_THROWS_AS(one.coefficient(origin, 399.0), input_error);
}

TEST_CASE("bricaud1998: a_p = A_p C^E_p, or a_phi = A_phi C^E_phi") {
    const Bricaud1998Absorption ap(FixedConc{2.0});
    const Bricaud1998Absorption aphi(FixedConc{2.0}, Bricaud1998Fraction::phytoplankton);
    CHECK(ap.coefficient(origin, 440.0) == Approx(0.052019 * std::pow(2.0, 0.634965)).epsilon(1e-14));
    CHECK(aphi.coefficient(origin, 440.0) == Approx(0.037824 * std::pow(2.0, 0.626633)).epsilon(1e-14));
    CHECK(ap.coefficient(origin, 441.0) ==
          Approx(0.5 * (0.052019 + 0.051398) * std::pow(2.0, 0.5 * (0.634965 + 0.629752))).epsilon(1e-13));
    CHECK(aphi.coefficient(origin, 700.0) == Approx(0.00248126 * std::pow(2.0, 1.028608)).epsilon(1e-14));
    CHECK(aphi.fraction() == Bricaud1998Fraction::phytoplankton);
    CHECK_THROWS_AS(ap.coefficient(origin, 702.0), input_error);
}

TEST_CASE("cdom: a(440) e^{-S (lambda - 440)}") {
    const CdomParams p;
    CHECK(p.a_ref == 0.012);
    CHECK(p.refwl == 440.0);
    CHECK(p.slope == 0.014);
    const CdomAbsorption m;
    CHECK(m.coefficient(origin, 440.0) == 0.012);
    CHECK(m.coefficient(origin, 540.0) == Approx(0.012 * std::exp(-1.4)).epsilon(1e-14));
    CHECK(m.coefficient(origin, 340.0) == Approx(0.012 * std::exp(1.4)).epsilon(1e-14));
    CHECK_THROWS_AS(CdomAbsorption(CdomParams{.a_ref = -0.1}), input_error);
    CHECK_THROWS_AS(CdomAbsorption(CdomParams{.slope = -0.014}), input_error);
    CHECK_THROWS_AS(CdomAbsorption(CdomParams{.refwl = std::nan("")}), input_error);
}

// ---------------------------------------------------------------------------------------------
// Noise (SIGMA)

TEST_CASE("noise is reproducible, depends on position and wavelength, and is the model's value plus sigma N") {
    const Noise noise(0.001, 7, 3);
    const SmithBakerAbsorption m(noise);
    const vec3 x(0.1, 0.2, 3.0);
    const double v = m.coefficient(x, 500.0);
    CHECK(v == m.coefficient(x, 500.0));
    CHECK(v == SmithBakerAbsorption(Noise(0.001, 7, 3)).coefficient(x, 500.0));
    CHECK(v != m.coefficient(vec3(0.1, 0.2, 3.5), 500.0));
    CHECK(v != SmithBakerAbsorption(Noise(0.001, 8, 3)).coefficient(x, 500.0));
    CHECK(v == Approx(std::max(0.0, 0.0257 + 0.001 * noise.deviate(x, 500.0))).epsilon(1e-14));
    CHECK(v != 0.0257);

    CdomAbsorption cdom;
    CHECK(cdom.coefficient(x, 500.0) == Approx(0.012 * std::exp(-0.014 * 60.0)));
    cdom.set_noise(noise);
    CHECK(cdom.noise().sigma() == 0.001);
    CHECK(cdom.coefficient(x, 500.0) ==
          Approx(0.012 * std::exp(-0.014 * 60.0) + 0.001 * noise.deviate(x, 500.0)).epsilon(1e-14));
}

TEST_CASE("noise averages to the model's value and is clamped at zero") {
    const RamanAbsorption small(RamanParams{}, Noise(1e-5, 11));
    const RamanAbsorption big(RamanParams{}, Noise(1e-3, 11));  // sigma ~ 4 times the value
    double sum = 0.0;
    int zeros = 0;
    const int n = 20000;
    for (int i = 0; i < n; ++i) {
        const vec3 x(0.0, 0.0, 0.001 * i);
        sum += small.coefficient(x, 488.0);
        const double b = big.coefficient(x, 488.0);
        CHECK(b >= 0.0);
        zeros += (b == 0.0);
    }
    // mean: SE = 1e-5 / sqrt(2e4) = 7e-8; 5 SE bound
    CHECK(std::abs(sum / n - 0.00026) < 3.5e-7);
    // P(N < -0.26) = 0.397: about 7900 of 20000 clamped
    CHECK(zeros > 7500);
    CHECK(zeros < 8400);
    CHECK_THROWS_AS(Noise(-0.1), input_error);
}
