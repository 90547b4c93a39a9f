// The phase-function models of manual section 5.8 beyond Petzold: Schlick (eq. 4.73), the
// "hgpf" and "schlick" mixtures (eq. 5.28), the Rayleigh-based model (eq. 5.29) and pure
// water (eq. 5.2), Fournier-Forand (Mobley et al. 2002), user tables on mu samples (5.8.2)
// and the run-time variant AnyPhase. For each: normalisation, pdf == eval, a chi-square
// sampling histogram (manual 7.3.4, spfhist), moments, and invalid input.
#include <catch2/catch.hpp>
#include "phase_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/phase/fournier_forand.hpp"
#include "secchi/optics/phase/mixture.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh_like.hpp"
#include "secchi/optics/phase/schlick.hpp"
#include "secchi/optics/phase/tabulated_samples.hpp"
#include "secchi/solver/phase_choice.hpp"

using namespace secchi;
using namespace secchi::test;
using Catch::Matchers::Contains;

namespace {

/// Probability that cos(psi) < mu, numerically from eval.
template <class P>
double cdf_in_mu(const P& p, double mu) {
    return integrate_solid_angle(pdf_of_psi(p), std::acos(mu), pi, breakpoints_of(p));
}

}  // namespace

TEST_CASE("Schlick phase function (manual eq. 4.73)") {
    std::uint64_t seed = 100;
    for (double k : {0.0, 0.3, 0.8, -0.6, 0.95}) {
        const SchlickPhase s(k);
        INFO("k = " << k);
        check_phase_function(s, ++seed);
        const auto m = phase_moments(s);
        // Mean cosine from eval vs the closed form; k is only approximately g (2k/3 for small k).
        CHECK(m.mean_cosine == Approx(s.mean_cosine()).epsilon(1e-6).margin(1e-9));
        CHECK(s.eval(0.2) == Approx((1 - k * k) / (four_pi * std::pow(1 - k * 0.2, 2))).epsilon(1e-14));
        // The Moebius inverse CDF: F(mu(u)) = u.
        for (double u : {0.01, 0.3, 0.5, 0.9, 0.999})
            CHECK(cdf_in_mu(s, s.sample(u, 0.5).cos_psi) == Approx(u).epsilon(1e-9));
    }
    CHECK(SchlickPhase(0.5).mean_cosine() == Approx(2.0 - 3.0 * std::atanh(0.5)).epsilon(1e-14));  // 1/k - (1-k^2) atanh(k)/k^2
    CHECK(SchlickPhase(1e-4).mean_cosine() == Approx(2e-4 / 3.0).epsilon(1e-8));
    CHECK(SchlickPhase(0.9).mean_cosine() < 0.9);  // k > g for k > 0
    CHECK_THAT(input_error_message([] { SchlickPhase(1.0); }), Contains("invalid k = 1"));
    CHECK_THAT(input_error_message([] { SchlickPhase(-1.2); }), Contains("invalid k = -1.2"));
    CHECK_THAT(input_error_message([] { (void)SchlickPhase{std::numeric_limits<double>::quiet_NaN()}; }),
               Contains("invalid k = nan"));
}

TEST_CASE("Henyey-Greenstein mixture (manual eq. 5.28, hgpf)") {
    const std::vector<double> g{0.9, -0.3, 0.5}, w{2.0, 1.0, 1.0};
    const auto mix = hg_mixture(g, w);
    check_phase_function(mix, 201);
    const std::vector<double> wn{0.5, 0.25, 0.25};
    for (std::size_t i = 0; i < 3; ++i) CHECK(mix.weights()[i] == Approx(wn[i]).epsilon(1e-15));
    double g_mix = 0.0, b_mix = 0.0;
    for (std::size_t i = 0; i < 3; ++i) {
        g_mix += wn[i] * g[i];
        b_mix += wn[i] * hg_backscatter(g[i]);
    }
    const auto m = phase_moments(mix);
    CHECK(m.mean_cosine == Approx(g_mix).epsilon(1e-6));
    CHECK(m.backscatter_fraction == Approx(b_mix).epsilon(1e-6));
    for (double mu : {-1.0, 0.0, 0.7, 1.0}) {
        double p = 0.0;
        for (std::size_t i = 0; i < 3; ++i) p += wn[i] * HenyeyGreensteinPhase(g[i]).eval(mu);
        CHECK(mix.eval(mu) == Approx(p).epsilon(1e-14));
    }
    // A single component is that function.
    const auto one = hg_mixture(std::vector<double>{0.7}, std::vector<double>{3.0});
    CHECK(one.eval(0.4) == Approx(HenyeyGreensteinPhase(0.7).eval(0.4)).epsilon(1e-15));
}

TEST_CASE("mixture sampling reuses the rescaled u1 within the chosen component") {
    const std::vector<double> g{0.8, -0.5}, w{1.0, 3.0};  // intervals [0, 0.25) and [0.25, 1)
    const auto mix = hg_mixture(g, w);
    const HenyeyGreensteinPhase a(0.8), b(-0.5);
    CHECK(mix.sample(0.1, 0.3).cos_psi == Approx(a.sample(0.4, 0.3).cos_psi).epsilon(1e-14));
    CHECK(mix.sample(0.5, 0.3).cos_psi == Approx(b.sample(1.0 / 3.0, 0.3).cos_psi).epsilon(1e-14));
    CHECK(mix.sample(0.5, 0.3).phi == Approx(two_pi * 0.3));
    CHECK(mix.sample(0.5, 0.3).pdf == mix.eval(mix.sample(0.5, 0.3).cos_psi));
    // Zero-weight components are never chosen, also at the ends of (0, 1).
    const auto z = hg_mixture(std::vector<double>{0.9, 0.2, -0.9}, std::vector<double>{0.0, 1.0, 0.0});
    for (double u : {0.0, 1e-12, 0.5, 1.0 - 1e-12, 1.0})
        CHECK(z.sample(u, 0.5).cos_psi == Approx(HenyeyGreensteinPhase(0.2).sample(u, 0.5).cos_psi).margin(1e-12));
    check_phase_function(z, 202);
}

TEST_CASE("Schlick mixture (manual eq. 5.28, schlick)") {
    const std::vector<double> k{0.95, 0.2, -0.4}, w{0.6, 0.3, 0.1};
    const auto mix = schlick_mixture(k, w);
    check_phase_function(mix, 301);
    double g_mix = 0.0;
    for (std::size_t i = 0; i < 3; ++i) g_mix += w[i] * SchlickPhase(k[i]).mean_cosine();
    CHECK(phase_moments(mix).mean_cosine == Approx(g_mix).epsilon(1e-6));
    double wsum = 0.0;
    for (double x : mix.weights()) wsum += x;
    CHECK(wsum == Approx(1.0).epsilon(1e-15));
}

TEST_CASE("mixtures reject bad weights") {
    using V = std::vector<double>;
    CHECK_THAT(input_error_message([] { hg_mixture(V{0.5, 0.2}, V{1.0, -0.1}); }),
               Contains("weights[1] = -0.1") && Contains("non-negative"));
    CHECK_THAT(input_error_message([] { hg_mixture(V{0.5, 0.2}, V{0.0, 0.0}); }), Contains("sum of weights = 0"));
    CHECK_THAT(input_error_message([] { schlick_mixture(V{0.5, 0.2}, V{1.0}); }), Contains("W.size() = 1"));
    CHECK_THAT(input_error_message([] { hg_mixture(V{}, V{}); }), Contains("components.size() = 0"));
    CHECK_THAT(input_error_message([] { schlick_mixture(V{1.5}, V{1.0}); }), Contains("invalid k = 1.5"));
    CHECK_THAT(input_error_message([] {
                   PhaseMixture<SchlickPhase>({SchlickPhase(0.1)}, V{std::numeric_limits<double>::infinity()});
               }),
               Contains("weights[0] = inf"));
}

TEST_CASE("Rayleigh-like phase function (manual eq. 5.29) and pure water (eq. 5.2)") {
    std::uint64_t seed = 400;
    for (double k2 : {0.835, 1.0, 0.0, -0.5, -0.99, 5.0, 1e4}) {
        const RayleighLikePhase r(k2);
        INFO("k2 = " << k2);
        check_phase_function(r, ++seed);
        const auto m = phase_moments(r);
        CHECK(m.mean_cosine == Approx(0.0).margin(1e-12));
        CHECK(m.backscatter_fraction == Approx(0.5).epsilon(1e-12));
        CHECK(r.k1() == Approx(1.0 / (four_pi * (1.0 + k2 / 3.0))).epsilon(1e-15));
        // The sampled mu solves the CDF cubic k2 mu^3 + 3 mu = (2u - 1)(3 + k2).
        for (double u : {1e-9, 0.01, 0.25, 0.5, 0.75, 0.99, 1.0 - 1e-9}) {
            const double mu = r.sample(u, 0.5).cos_psi;
            CHECK(k2 * mu * mu * mu + 3.0 * mu - (2.0 * u - 1.0) * (3.0 + k2) == Approx(0.0).margin(1e-12 * (3.0 + k2)));
        }
    }
    // k2 = 1 is M93's Rayleigh function, value and sampler.
    const RayleighLikePhase one(1.0);
    const RayleighPhase ray;
    for (double u : {0.001, 0.2, 0.5, 0.8, 0.999}) {
        CHECK(one.sample(u, 0.1).cos_psi == Approx(ray.sample(u, 0.1).cos_psi).margin(1e-14));
        CHECK(one.eval(2 * u - 1) == Approx(ray.eval(2 * u - 1)).epsilon(1e-14));
    }
    // Pure water as published: k1 = 0.06225 is normalised to 1e-5.
    const RayleighLikePhase w = pure_water_phase();
    CHECK(std::abs(phase_moments(w).normalisation - 1.0) < 1e-4);
    for (double mu : {-1.0, 0.0, 0.5, 1.0}) CHECK(w.eval(mu) == Approx(0.06225 * (1 + 0.835 * mu * mu)).epsilon(1e-4));
    CHECK(four_pi * 0.06225 * (1.0 + 0.835 / 3.0) == Approx(1.0).epsilon(1e-4));
    // The user's k1 must be normalised within 1 %; k2 > -1.
    CHECK_NOTHROW(RayleighLikePhase::from_k1_k2(3.0 / (16.0 * pi) * 1.009, 1.0));
    CHECK_THAT(input_error_message([] { RayleighLikePhase::from_k1_k2(0.07, 0.835); }),
               Contains("invalid K1 = 0.07") && Contains("0.06225"));
    CHECK_THAT(input_error_message([] { RayleighLikePhase(-1.0); }), Contains("invalid k2 = -1"));
    CHECK_THAT(input_error_message([] { RayleighLikePhase::from_k1_k2(0.1, -2.0); }), Contains("invalid k2 = -2"));
}

TEST_CASE("Fournier-Forand analytic form (Mobley et al. 2002)") {
    const double n = 1.10, mu = 3.5835;  // Mobley et al.: Petzold's b_b/b = 0.0183
    const auto analytic = [&](double psi) { return FournierForandPhase::analytic_at(n, mu, psi); };
    // The closed form is normalised and its backscatter fraction is the closed-form B.
    CHECK(integrate_solid_angle(analytic, 0.0, pi) == Approx(1.0).epsilon(1e-6));
    const double b = FournierForandPhase::backscatter_fraction(n, mu);
    CHECK(integrate_solid_angle(analytic, 0.5 * pi, pi) == Approx(b).epsilon(1e-8));
    CHECK(b == Approx(0.0183).epsilon(2e-3));
    // Mobley's Ocean Optics Web Book, table of (n, mu) -> B (mu given to 4-5 digits).
    CHECK(FournierForandPhase::backscatter_fraction(1.08, 3.483) == Approx(0.01).epsilon(5e-3));
    CHECK(FournierForandPhase::backscatter_fraction(1.175, 4.065) == Approx(0.1).epsilon(5e-3));
    CHECK(FournierForandPhase::backscatter_fraction(1.15, 4.874) == Approx(0.4).epsilon(5e-3));
    for (double nn : {1.02, 1.2, 1.5})
        for (double mm : {3.1, 4.0, 5.0}) {
            INFO("n = " << nn << ", mu = " << mm);
            const auto f = [&](double psi) { return FournierForandPhase::analytic_at(nn, mm, psi); };
            CHECK(integrate_solid_angle(f, 0.0, pi) == Approx(1.0).epsilon(1e-5));
        }
    // Across d = 1 (sin^2(psi/2) = 3 (n-1)^2 / 4) the series and the direct form join smoothly.
    const double psi1 = 2.0 * std::asin(std::sqrt(0.75 * (n - 1) * (n - 1)));
    for (double f : {std::exp(-1.0) * (1 + 1e-9), std::exp(1.0) * (1 - 1e-9), 1.0 + 1e-9}) {
        const double x = f * 0.75 * (n - 1) * (n - 1), psi = 2.0 * std::asin(std::sqrt(x));
        const double left = analytic(psi * (1 - 1e-7)), right = analytic(psi * (1 + 1e-7));
        CHECK(analytic(psi) == Approx(0.5 * (left + right)).epsilon(1e-6));
    }
    CHECK(std::isfinite(analytic(psi1)));
    // Small angles: the power law psi^-(5 - mu).
    CHECK(analytic(1e-5) / analytic(1e-6) == Approx(std::pow(10.0, mu - 5.0)).epsilon(1e-4));
}

TEST_CASE("Fournier-Forand from the backscatter fraction, tabulated for sampling") {
    std::uint64_t seed = 500;
    for (double bb : {0.0183, 0.01}) {
        const auto ff = FournierForandPhase::from_backscatter_fraction(bb);
        INFO(ff.name());
        CHECK(ff.index() == 1.10);
        CHECK(ff.backscatter_fraction() == Approx(bb).epsilon(1e-12));
        const auto m = phase_moments(ff);  // of the sampled (tabulated) density
        CHECK(m.backscatter_fraction == Approx(bb).epsilon(1e-3));
        check_phase_function(ff, ++seed);
        // The table against the closed form: raw integral and pointwise relative error.
        CHECK(ff.table().raw_integral() == Approx(1.0).epsilon(1e-5));
        INFO("raw integral - 1 = " << ff.table().raw_integral() - 1.0);
        double worst = 0.0;
        for (int i = 0; i <= 20000; ++i) {
            const double psi = i <= 10000 ? 1e-4 * deg * std::pow(1e5, i / 10000.0) : (10.0 + 170.0 * (i - 10000) / 10000.0) * deg;
            const double mu = std::cos(psi);
            if (mu >= 1.0) continue;
            worst = std::max(worst, std::abs(ff.eval(mu) / ff.analytic(mu) - 1.0));
        }
        INFO("max relative interpolation error " << worst);
        CHECK(worst < 1e-5);
        if (bb == 0.0183) CHECK(ff.junge_slope() == Approx(3.5835).epsilon(1e-3));
    }
    CHECK(FournierForandPhase::from_backscatter_fraction(0.5).junge_slope() == Approx(5.0).epsilon(1e-12));
    CHECK_THAT(input_error_message([] { FournierForandPhase::from_backscatter_fraction(0.6); }),
               Contains("invalid bb_over_b = 0.6"));
    CHECK_THAT(input_error_message([] { FournierForandPhase::from_backscatter_fraction(0.0); }),
               Contains("invalid bb_over_b = 0"));
    CHECK_THAT(input_error_message([] { FournierForandPhase::from_backscatter_fraction(0.02, 1.0); }),
               Contains("invalid n = 1"));
    CHECK_THAT(input_error_message([] { FournierForandPhase(1.1, 3.0); }), Contains("invalid mu = 3"));
    CHECK_THAT(input_error_message([] { FournierForandPhase(1.1, 5.5); }), Contains("invalid mu = 5.5"));
    CHECK_THAT(input_error_message([] { FournierForandPhase(1.6, 4.0); }), Contains("invalid n = 1.6"));
}

TEST_CASE("user tables on mu samples (manual 5.8.2, MUSAMPLES)") {
    // Pure water's eq. 5.2 on 201 equally spaced cosines, increasing and decreasing.
    const RayleighLikePhase w = pure_water_phase();
    std::vector<double> mu, p, mu_rev, p_rev;
    for (int i = 0; i <= 200; ++i) {
        mu.push_back(-1.0 + i / 100.0);
        p.push_back(0.06225 * (1.0 + 0.835 * mu.back() * mu.back()));
    }
    mu.back() = 1.0;
    mu_rev.assign(mu.rbegin(), mu.rend());
    p_rev.assign(p.rbegin(), p.rend());
    const TabulatedPhase t = tabulated_from_mu_samples(mu, p), t_rev = tabulated_from_mu_samples(mu_rev, p_rev);
    CHECK(t.raw_integral() == Approx(1.0).epsilon(1e-4));
    CHECK(t.breakpoints().front() == 0.0);
    CHECK(t.breakpoints().back() == pi);
    for (double x : {-1.0, -0.995, -0.73, 0.0, 0.31, 0.999, 0.9999, 1.0}) {
        CHECK(t.eval(x) == Approx(w.eval(x)).epsilon(2e-5));  // linear in mu: exact at nodes
        CHECK(t_rev.eval(x) == t.eval(x));
    }
    check_phase_function(t, 601);
    // Off by 3 %: accepted and normalised; off by 10 %: rejected.
    std::vector<double> p3(p), p10(p);
    for (double& x : p3) x *= 1.03;
    for (double& x : p10) x *= 1.10;
    CHECK(phase_moments(tabulated_from_mu_samples(mu, p3)).normalisation == Approx(1.0).epsilon(1e-9));
    CHECK_THAT(input_error_message([&] { tabulated_from_mu_samples(mu, p10); }), Contains("unnormalised table"));
    CHECK_THAT(input_error_message([] { check_normalisation(0.94); }), Contains("unnormalised table"));
    CHECK_NOTHROW(check_normalisation(1.049));
    // Petzold's table (raw 1.020 with p linear in angle) passes.
    std::vector<double> a, v;
    for (std::size_t i = 1; i < petzold_m93_table.size(); ++i) {
        a.push_back(petzold_m93_table[i].angle_deg);
        v.push_back(petzold_m93_table[i].value);
    }
    CHECK_NOTHROW(tabulated_from_theta_samples(a, v));
    // Malformed input.
    const std::vector<double> two{-1.0, 1.0}, bad{-1.0, 1.5}, same{0.5, 0.5}, one{0.1};
    CHECK_THAT(input_error_message([&] { tabulated_from_mu_samples(two, one); }), Contains("p.size() = 1"));
    CHECK_THAT(input_error_message([&] { tabulated_from_mu_samples(bad, std::vector<double>{1.0, 1.0}); }),
               Contains("invalid mu = 1.5"));
    CHECK_THAT(input_error_message([&] { tabulated_from_mu_samples(same, std::vector<double>{1.0, 1.0}); }),
               Contains("strictly monotone"));
}

TEST_CASE("AnyPhase holds every phase model and is itself a PhaseFunction") {
    const std::vector<double> g{0.9, 0.1}, w{1.0, 1.0};
    const std::vector<AnyPhase> all{IsotropicPhase{},
                                    RayleighPhase{},
                                    HenyeyGreensteinPhase(0.8),
                                    petzold_m93(),
                                    SchlickPhase(0.7),
                                    hg_mixture(g, w),
                                    schlick_mixture(g, w),
                                    pure_water_phase(),
                                    FournierForandPhase::from_backscatter_fraction(0.0183)};
    CHECK(all.size() == std::variant_size_v<AnyPhase>);
    for (std::size_t i = 0; i < all.size(); ++i) {
        const AnyPhaseFunction f{all[i]};
        INFO(f.name());
        CHECK(all[i].index() == i);
        CHECK(std::abs(phase_moments(f).normalisation - 1.0) < 1e-6);
        std::visit(
            [&](const auto& p) {
                CHECK(f.name() == p.name());
                for (double mu : {-1.0, 0.0, 0.95}) CHECK(f.eval(mu) == p.eval(mu));
                CHECK(f.sample(0.37, 0.6).cos_psi == Approx(p.sample(0.37, 0.6).cos_psi).epsilon(1e-15));
                CHECK(f.breakpoints() == breakpoints_of(p));
                static_assert(HasDirectionSampler<std::decay_t<decltype(p)>>);
            },
            all[i]);
        check_direction_sampler(f, 800 + i);  // the visited sample_direction is sample()'s direction
    }
    static_assert(HasDirectionSampler<AnyPhaseFunction>);
    check_sampling(AnyPhaseFunction{SchlickPhase(0.6)}, 701);
    // The command-line names of the new models.
    CHECK(std::holds_alternative<SchlickPhase>(parse_phase("schlick:0.5")));
    CHECK(std::holds_alternative<RayleighLikePhase>(parse_phase("pure-water")));
    CHECK(std::get<FournierForandPhase>(parse_phase("ff:0.01")).backscatter_fraction() == Approx(0.01).epsilon(1e-12));
    CHECK(std::get<HenyeyGreensteinPhase>(parse_phase("hg:0.3")).g() == 0.3);
    CHECK_THAT(input_error_message([] { parse_phase("schlick:x"); }), Contains("phase schlick:K"));
    CHECK_THAT(input_error_message([] { parse_phase("mie"); }), Contains("invalid phase = mie"));
    // A narrower choice: the named model if it is one of the listed types, else an error naming
    // the option, the value and what it may be; a misspelling is parse_phase's error.
    using Two = std::variant<RayleighPhase, HenyeyGreensteinPhase>;
    const Two hg = parse_phase_among<RayleighPhase, HenyeyGreensteinPhase>("--p", "hg:0.4", "rayleigh or hg:G");
    CHECK(std::get<HenyeyGreensteinPhase>(hg).g() == 0.4);
    CHECK(std::holds_alternative<RayleighPhase>(parse_phase_among<RayleighPhase, HenyeyGreensteinPhase>("--p", "rayleigh", "")));
    CHECK_THAT(input_error_message([] { parse_phase_among<RayleighPhase>("--p", "petzold", "rayleigh"); }),
               Contains("invalid --p = petzold: must be rayleigh"));
    CHECK_THAT(input_error_message([] { parse_phase_among<RayleighPhase>("--p", "mie", "rayleigh"); }),
               Contains("invalid phase = mie"));
}
