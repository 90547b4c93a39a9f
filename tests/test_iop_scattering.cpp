// Coefficient and scattering models of manual 5.6.1, 5.6.2, 5.7: values against the
// equations (recomputed here), the manual's defaults, validation, SIGMA noise, and the
// type-erased AnyCoefficient.
#include <catch2/catch.hpp>
#include "secchi/core/error.hpp"
#include "secchi/optics/iop/coefficient.hpp"
#include "secchi/optics/iop/concentration.hpp"
#include "secchi/optics/iop/scattering.hpp"
#include "secchi/optics/iop/spectral_table.hpp"
#include <cmath>
#include <string_view>
#include <vector>

using namespace secchi;
using namespace secchi::iop;

namespace {
vec3 at_depth(double z) { return vec3(-0.4, 2.5, z); }

// A small specific-coefficient spectrum: 0.02 at 400 nm, 0.01 at 500 nm, 0.004 at 700 nm.
SpectralTable test_spectrum() {
    const std::vector<double> wl{400.0, 500.0, 700.0}, v{0.02, 0.01, 0.004};
    return SpectralTable("test spectrum", wl, v);
}
}  // namespace

TEST_CASE("scattering and coefficient defaults are the manual's tables") {
    CHECK(std::string_view(ConstantCoefficient::type_name) == "constant");
    CHECK(std::string_view(SpecificCoefficient<ConstantConcentration>::type_name) == "specific");
    CHECK(std::string_view(GordonMorelScattering<ConstantConcentration>::type_name) == "gordonmorel");
    CHECK(std::string_view(KopelevichScattering<>::type_name) == "kopelevich");
    CHECK(std::string_view(BuiteveldScattering::type_name) == "buiteveld");

    // ABS (5.6.1) and SCAT (5.7.1): 0.1 1/m
    CHECK(ConstantCoefficient().coefficient(at_depth(3.0), 500.0) == 0.1);
    CHECK(ConstantCoefficient::default_value == 0.1);
    CHECK_FALSE(ConstantCoefficient().spectral());

    const GordonMorelScattering gm{ConstantConcentration{}};
    CHECK(gm.params().refwl == 550.0);
    CHECK(gm.params().k == 0.30);
    CHECK(gm.params().q == 0.62);
    CHECK_FALSE(gm.exclusive());
    CHECK(gm.noise().sigma() == 0.0);

    const KopelevichScattering kop;
    CHECK(kop.params().refwl == 550.0);
    CHECK(kop.params().k == 0.30);
    CHECK(kop.params().q == 0.62);
    CHECK(kop.noise().sigma() == 0.0);

    // eq. 5.1 (not the table's K 0.30, Q 0.62 copied from kopelevich)
    const BuiteveldScattering bu;
    CHECK(bu.params().k == 3.4123664e8);
    CHECK(bu.params().q == -4.1537676);
    CHECK(bu.noise().sigma() == 0.0);
}

TEST_CASE("constant coefficient: a value or a spectrum, the same at every depth (eq. 5.7, 5.8, 5.19)") {
    const ConstantCoefficient scalar(0.37);
    const ConstantCoefficient spectral(test_spectrum());
    CHECK(spectral.spectral());
    for (double z : {0.0, 10.0, 80.0}) {
        CHECK(scalar.coefficient(at_depth(z), 412.0) == 0.37);
        CHECK(scalar.coefficient(at_depth(z), 680.0) == 0.37);
        CHECK(spectral.coefficient(at_depth(z), 500.0) == 0.01);
        CHECK(spectral.coefficient(at_depth(z), 450.0) == Approx(0.015).epsilon(1e-14));
        CHECK(spectral.coefficient(at_depth(z), 600.0) == Approx(0.007).epsilon(1e-14));
    }
    CHECK_THROWS_AS(spectral.coefficient(at_depth(1.0), 800.0), input_error);  // outside the file
}

TEST_CASE("specific coefficient: a*(lambda) C(z) (eq. 5.11, 5.20)") {
    const GaussianConcentration chl;
    const SpecificCoefficient spec(test_spectrum(), chl);
    for (double z : {0.0, 9.0, 17.0, 30.0}) {
        const double c = 0.2 + 144.0 / (9.0 * std::sqrt(2.0 * 3.14159265358979323846)) *
                                   std::exp(-(z - 17.0) * (z - 17.0) / (2.0 * 81.0));
        CHECK(spec.coefficient(at_depth(z), 400.0) == Approx(0.02 * c).epsilon(1e-13));
        CHECK(spec.coefficient(at_depth(z), 550.0) == Approx(0.0085 * c).epsilon(1e-13));
    }
    CHECK(spec.coefficient(at_depth(17.0), 500.0) == Approx(0.01 * 6.583).epsilon(1e-4));
    const SpecificCoefficient linear(test_spectrum(), LinearConcentration{});
    CHECK(linear.coefficient(at_depth(30.0), 500.0) == 0.0);  // C clamped at 0 below 20 m
}

TEST_CASE("Gordon-Morel scattering: (lambda0/lambda) k C^q (eq. 5.22)") {
    SECTION("defaults, constant concentration") {
        const GordonMorelScattering gm{ConstantConcentration({.conc = 2.0})};
        for (double wl : {400.0, 550.0, 700.0})
            CHECK(gm.coefficient(at_depth(4.0), wl) == Approx(550.0 / wl * 0.30 * std::pow(2.0, 0.62)).epsilon(1e-14));
        CHECK(gm.coefficient(at_depth(4.0), 550.0) == Approx(0.4610).epsilon(1e-3));  // 0.3 * 2^0.62
        CHECK(GordonMorelScattering{ConstantConcentration({.conc = 1.0})}.coefficient(at_depth(0.0), 550.0) ==
              Approx(0.30));
        CHECK(GordonMorelScattering{ConstantConcentration({.conc = 0.0})}.coefficient(at_depth(0.0), 550.0) == 0.0);
    }
    SECTION("other parameters, Gaussian chlorophyll") {
        const GordonMorelScattering gm(GaussianConcentration{}, {.refwl = 500.0, .k = 0.33, .q = 0.5, .exclusive = true});
        CHECK(gm.exclusive());
        for (double z : {0.0, 17.0, 40.0}) {
            const double c = GaussianConcentration().concentration(at_depth(z));
            CHECK(gm.coefficient(at_depth(z), 440.0) == Approx(500.0 / 440.0 * 0.33 * std::sqrt(c)).epsilon(1e-14));
        }
    }
}

TEST_CASE("Kopelevich scattering: k C (lambda0/lambda)^q (eq. 5.24)") {
    SECTION("CONCID none: C = 1") {
        const KopelevichScattering kop;
        for (double z : {0.0, 50.0})
            for (double wl : {400.0, 550.0, 700.0})
                CHECK(kop.coefficient(at_depth(z), wl) == Approx(0.30 * std::pow(550.0 / wl, 0.62)).epsilon(1e-14));
        CHECK(kop.coefficient(at_depth(0.0), 550.0) == Approx(0.30).epsilon(1e-14));
    }
    SECTION("Kopelevich's small-particle term (eq. 5.23): 1.34 v_s (550/lambda)^1.7") {
        const KopelevichScattering kop(LinearConcentration({.atzero = 0.5, .rate = 0.01}), {.k = 1.34, .q = 1.7});
        for (double z : {0.0, 10.0, 30.0}) {
            const double vs = 0.5 + 0.01 * z;
            CHECK(kop.coefficient(at_depth(z), 450.0) == Approx(1.34 * vs * std::pow(550.0 / 450.0, 1.7)).epsilon(1e-14));
        }
        const KopelevichScattering none({.refwl = 500.0, .k = 2.0, .q = -1.0});  // C = 1, negative q allowed
        CHECK(none.coefficient(at_depth(0.0), 250.0) == Approx(2.0 * 0.5).epsilon(1e-14));
    }
}

TEST_CASE("Buiteveld scattering: eq. 5.1 with the negative exponent") {
    const BuiteveldScattering bu;
    // data README section 6 (the DIRSIG fit column)
    CHECK(bu.coefficient(at_depth(0.0), 500.0) == Approx(2.0997e-3).epsilon(5e-5));
    CHECK(bu.coefficient(at_depth(0.0), 400.0) == Approx(5.3052e-3).epsilon(5e-5));
    CHECK(bu.coefficient(at_depth(0.0), 600.0) == Approx(9.8460e-4).epsilon(5e-5));
    CHECK(bu.coefficient(at_depth(9.0), 700.0) == Approx(5.1901e-4).epsilon(5e-5));
    CHECK(bu.coefficient(at_depth(0.0), 450.0) == Approx(3.4123664e8 * std::pow(450.0, -4.1537676)).epsilon(1e-14));
    // and within 0.6 % of the Buiteveld formula at 20 C (data README)
    CHECK(bu.coefficient(at_depth(0.0), 500.0) == Approx(2.1051e-3).epsilon(6e-3));
    const BuiteveldScattering custom({.k = 2.0, .q = -1.0});
    CHECK(custom.coefficient(at_depth(0.0), 400.0) == Approx(0.005).epsilon(1e-14));
}

TEST_CASE("invalid coefficient and scattering parameters are input errors naming the parameter") {
    CHECK_THROWS_WITH(ConstantCoefficient(-0.1), Catch::Contains("ABS/SCAT"));
    CHECK_THROWS_AS(ConstantCoefficient(std::nan("")), input_error);
    const std::vector<double> wl{400.0, 500.0}, neg{0.1, -0.1};
    CHECK_THROWS_WITH(ConstantCoefficient(SpectralTable("neg", wl, neg)), Catch::Contains("FILENAME"));
    CHECK_THROWS_AS(SpecificCoefficient(SpectralTable("neg", wl, neg), NoConcentration{}), input_error);
    CHECK_THROWS_WITH(ConstantCoefficient(0.1, Noise(-1.0)), Catch::Contains("SIGMA"));

    const ConstantConcentration c;
    CHECK_THROWS_WITH(GordonMorelScattering(c, {.refwl = 0.0}), Catch::Contains("REFWL"));
    CHECK_THROWS_WITH(GordonMorelScattering(c, {.k = -0.3}), Catch::Contains("K = -0.3"));
    CHECK_THROWS_WITH(GordonMorelScattering(c, {.q = -0.62}), Catch::Contains("Q = -0.62"));
    CHECK_THROWS_WITH(KopelevichScattering(KopelevichParams{.refwl = -550.0}), Catch::Contains("REFWL"));
    CHECK_THROWS_WITH(KopelevichScattering(KopelevichParams{.k = std::nan("")}), Catch::Contains("K"));
    CHECK_THROWS_WITH(KopelevichScattering(KopelevichParams{.q = INFINITY}), Catch::Contains("Q"));
    CHECK_THROWS_WITH(BuiteveldScattering({.k = -1.0}), Catch::Contains("K = -1"));
    CHECK_THROWS_WITH(BuiteveldScattering({.q = std::nan("")}), Catch::Contains("Q"));

    // wavelengths must be positive
    CHECK_THROWS_WITH(BuiteveldScattering().coefficient(at_depth(0.0), 0.0), Catch::Contains("wavelength"));
    CHECK_THROWS_AS(KopelevichScattering().coefficient(at_depth(0.0), -500.0), input_error);
    CHECK_THROWS_AS(GordonMorelScattering(c).coefficient(at_depth(0.0), std::nan("")), input_error);
}

TEST_CASE("coefficient noise is reproducible, varies with position and wavelength, never negative") {
    const BuiteveldScattering quiet;
    const BuiteveldScattering noisy({}, Noise(1e-4, /*seed=*/5, /*key=*/1));
    const BuiteveldScattering other_key({}, Noise(1e-4, /*seed=*/5, /*key=*/2));
    std::vector<double> values;
    double sum_dev = 0.0;
    const int n = 1000;
    for (int i = 0; i < n; ++i) {
        const vec3 x(0.0, 0.0, 0.05 * i);
        const double v = noisy.coefficient(x, 500.0);
        CHECK(v == noisy.coefficient(x, 500.0));  // same point and wavelength, same value
        CHECK(v != noisy.coefficient(x, 510.0));  // another wavelength, another deviate
        values.push_back(v);
        sum_dev += v - quiet.coefficient(x, 500.0);
    }
    for (int i = 1; i < n; ++i) REQUIRE(values[i] != values[i - 1]);  // different points differ
    CHECK(noisy.coefficient(at_depth(1.0), 500.0) != other_key.coefficient(at_depth(1.0), 500.0));
    CHECK(std::abs(sum_dev / n) < 5 * 1e-4 / std::sqrt(double(n)));  // zero-mean (no clamping: 21 sigma)

    // sigma 10x the value: clamped at zero about half the time, never negative
    const KopelevichScattering kop({.k = 0.01}, Noise(0.1, 9));
    const GordonMorelScattering gm(ConstantConcentration({.conc = 0.01}), {}, Noise(0.1, 9));
    int zeros = 0;
    for (int i = 0; i < 500; ++i) {
        const double a = kop.coefficient(vec3(0.1 * i, 0, 1), 550.0), b = gm.coefficient(vec3(0.1 * i, 0, 1), 550.0);
        REQUIRE(a >= 0.0);
        REQUIRE(b >= 0.0);
        zeros += (a == 0.0) + (b == 0.0);
    }
    CHECK(zeros > 400);
    CHECK(zeros < 600);
}

TEST_CASE("AnyCoefficient equals the wrapped models") {
    const GaussianConcentration chl({}, Noise(0.3, 2, 7));
    const ConstantCoefficient cst(0.25, Noise(0.05, 4));
    const ConstantCoefficient cst_spectral(test_spectrum());
    const SpecificCoefficient spec(test_spectrum(), AnyConcentration(chl), Noise(0.001, 4, 1));
    const GordonMorelScattering gm(chl, {.k = 0.33});
    const KopelevichScattering kop;
    const BuiteveldScattering bu({}, Noise(1e-4, 6));
    const std::vector<AnyCoefficient> any{cst, cst_spectral, spec, gm, kop, bu};
    CHECK(any[0].type() == "constant");
    CHECK(any[2].type() == "specific");
    CHECK(any[3].type() == "gordonmorel");
    CHECK(any[4].type() == "kopelevich");
    CHECK(any[5].type() == "buiteveld");
    for (double z : {0.0, 12.0, 17.0})
        for (double wl : {420.0, 500.0, 650.0}) {
            const vec3 x = at_depth(z);
            CHECK(any[0].coefficient(x, wl) == cst.coefficient(x, wl));
            CHECK(any[1].coefficient(x, wl) == cst_spectral.coefficient(x, wl));
            CHECK(any[2].coefficient(x, wl) == spec.coefficient(x, wl));
            CHECK(any[3].coefficient(x, wl) == gm.coefficient(x, wl));
            CHECK(any[4].coefficient(x, wl) == kop.coefficient(x, wl));
            CHECK(any[5].coefficient(x, wl) == bu.coefficient(x, wl));
        }
    const AnyCoefficient copy = any[3];
    CHECK(copy.coefficient(at_depth(17.0), 550.0) == gm.coefficient(at_depth(17.0), 550.0));
}
