// Depth-varying water (optics/stratified_water.hpp) and depth importance
// (transport/importance.hpp): exact optical depths and their inverse, free-path sampling
// against the analytic two-layer Beer-Lambert law, the mixture phase function's component
// choice, and unbiasedness of every transport option against a reference run. Statistical
// checks use 4 measured standard errors, fixed in advance.
#include <catch2/catch.hpp>
#include "phase_checks.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/optics/stratified_water.hpp"
#include "secchi/transport/tracer.hpp"
#include <algorithm>
#include <cmath>
#include <array>
#include <bit>
#include <cstdint>
#include <numbers>
#include <random>
#include <tuple>
#include <type_traits>

using namespace secchi;

namespace {
bool within_se(const Estimate& e, double exact, double k = 4.0) {
    INFO("estimate " << e.value << " +- " << e.se << " vs exact " << exact);
    return std::abs(e.value - exact) <= k * e.se && e.se > 0;
}
bool agree(const Estimate& a, const Estimate& b, double k = 4.0) {
    INFO(a.value << " +- " << a.se << " vs " << b.value << " +- " << b.se);
    return std::abs(a.value - b.value) <= k * std::hypot(a.se, b.se);
}

/// Two homogeneous layers: (a1, b1) on [0, z_step), (a2, b2) below, as a jump (repeated node).
template <class Phase>
StratifiedWater<Phase> two_layers(double a1, double b1, double a2, double b2, double z_step, Phase phase) {
    DepthProfile p{{0.0, z_step, z_step, 1000.0}, {a1, a1, a2, a2}, {{b1, b1, b2, b2}}};
    return StratifiedWater<Phase>(p, {phase});
}

template <class M>
TransportResult<CompactRecord> trace(const M& medium, TransportSettings s, double zenith = 0.0, double escape = 40.0) {
    const Slab slab(1.0, Bottom{}, escape);
    return PhotonTracer<M, CompactRecord>(medium, slab, FlatSurface(1.0), CollimatedSun(zenith), s).run();
}
}  // namespace

TEST_CASE("stratified water: a constant profile is homogeneous water") {
    const auto hom = HomogeneousWater<IsotropicPhase>(0.3, 0.7, {});
    DepthProfile p{{0.0, 1.0, 2.0}, {0.3, 0.3, 0.3}, {{0.7, 0.7, 0.7}}};
    const StratifiedWater<IsotropicPhase> str(p, {IsotropicPhase{}});
    for (auto k : {Coefficient::absorption, Coefficient::scattering, Coefficient::attenuation})
        for (double z : {0.0, 0.5, 1.7, 5.0})
            for (double uz : {1.0, 0.3, -0.4, 1e-8}) {
                CHECK(str.coefficient(k, z) == Approx(hom.coefficient(k, z)).epsilon(1e-14));
                CHECK(str.optical_path(k, z, uz, 0.8) == Approx(hom.optical_path(k, z, uz, 0.8)).epsilon(1e-12));
                if (z + uz * 3.0 >= 0.0)
                    CHECK(str.distance_to(k, z, uz, 0.9) == Approx(hom.distance_to(k, z, uz, 0.9)).epsilon(1e-12));
            }
}

TEST_CASE("stratified water: optical depth of linear and stepped profiles, and its inverse") {
    // a(z) linear from 0.1 at 0 to 0.5 at 4 m, then constant; b = 0 (no scattering).
    DepthProfile p{{0.0, 2.0, 4.0}, {0.1, 0.3, 0.5}, {{0.0, 0.0, 0.0}}};
    const StratifiedWater<IsotropicPhase> w(p, {IsotropicPhase{}});
    auto exact_depth = [](double z) {  // int_0^z a dz'
        if (z <= 4.0) return 0.1 * z + 0.05 * z * z;
        return 0.1 * 4.0 + 0.05 * 16.0 + 0.5 * (z - 4.0);
    };
    for (double z : {0.0, 0.7, 2.0, 3.3, 4.0, 9.0})
        CHECK(w.optical_depth(Coefficient::absorption, z) == Approx(exact_depth(z)).epsilon(1e-13).margin(1e-15));
    // A slanted flight from 1 m to 6 m with uz = 0.5 (10 m of path).
    CHECK(w.optical_path(Coefficient::absorption, 1.0, 0.5, 10.0) ==
          Approx((exact_depth(6.0) - exact_depth(1.0)) / 0.5).epsilon(1e-13));
    // Round trips through the quadratic inverse (manual 3.3.4), up and down, across nodes.
    std::mt19937_64 gen(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int i = 0; i < 2000; ++i) {
        const double z = 8.0 * u(gen), uz = 2.0 * u(gen) - 1.0, s = 6.0 * u(gen);
        if (std::abs(uz) < 1e-3 || z + uz * s < 0.0) continue;
        const double tau = w.optical_path(Coefficient::absorption, z, uz, s);
        CHECK(w.distance_to(Coefficient::absorption, z, uz, tau) == Approx(s).epsilon(1e-9).margin(1e-9));
    }
    // Upward past the surface: never reached.
    CHECK(std::isinf(w.distance_to(Coefficient::absorption, 1.0, -1.0, 5.0)));
    // A jump: two layers.
    const auto two = two_layers(0.2, 0.0, 1.5, 0.0, 3.0, IsotropicPhase{});
    CHECK(two.optical_path(Coefficient::absorption, 2.0, 1.0, 2.0) == Approx(0.2 + 1.5).epsilon(1e-13));
    CHECK(two.coefficient(Coefficient::absorption, 2.999) == 0.2);
    CHECK(two.coefficient(Coefficient::absorption, 3.0) == 1.5);
}

TEST_CASE("stratified water: invalid profiles are rejected") {
    CHECK_THROWS_AS(StratifiedWater<IsotropicPhase>(DepthProfile{{0.0, 1.0}, {0.1, -0.1}, {{0.1, 0.1}}}, {IsotropicPhase{}}),
                    input_error);
    CHECK_THROWS_AS(StratifiedWater<IsotropicPhase>(DepthProfile{{0.0, 2.0, 1.0}, {0.1, 0.1, 0.1}, {{0.1, 0.1, 0.1}}},
                                                    {IsotropicPhase{}}),
                    input_error);
    CHECK_THROWS_AS(StratifiedWater<IsotropicPhase>(DepthProfile{{0.5, 1.0}, {0.1, 0.1}, {{0.1, 0.1}}}, {IsotropicPhase{}}),
                    input_error);
    CHECK_THROWS_AS(StratifiedWater<IsotropicPhase>(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {{0.1, 0.1}}}, {}), input_error);
}

TEST_CASE("stratified water: free paths follow the two-layer Beer-Lambert law") {
    // Pure absorber (analog: every interaction absorbs), c = 0.5 /m above 2 m and 2 /m below,
    // sun at the zenith, no interface: Ed(z) / Ed(0) = exp(-tau(z)) exactly.
    const auto water = two_layers(0.5, 0.0, 2.0, 0.0, 2.0, IsotropicPhase{});
    TransportSettings s;
    s.photons = 400000;
    s.depths = {1.0, 2.5, 3.0};
    s.absorption = AbsorptionMode::analog;
    const auto r = trace(water, s);
    const double tau[] = {0.5, 1.0 + 2.0 * 0.5, 1.0 + 2.0 * 1.0};
    for (std::size_t i = 0; i < 3; ++i) CHECK(within_se(r.irradiance[i][Ed], std::exp(-tau[i])));
    // Continuous absorption is exact here: no scattering, weight exp(-tau).
    s.absorption = AbsorptionMode::continuous;
    const auto c = trace(water, s);
    for (std::size_t i = 0; i < 3; ++i) CHECK(c.irradiance[i][Ed].value == Approx(std::exp(-tau[i])).epsilon(1e-12));
}

TEST_CASE("stratified water: the mixture picks component i with probability b_i / b") {
    // b_1 = 1 - z/10, b_2 = z/10 on [0, 10]; HG g = 0.8 and g = -0.5: mean cosine at z is
    // (b_1 0.8 - b_2 0.5) / b.
    DepthProfile p{{0.0, 10.0}, {0.1, 0.1}, {{1.0, 0.0}, {0.0, 1.0}}};
    const StratifiedWater<HenyeyGreensteinPhase> w(p, {HenyeyGreensteinPhase(0.8), HenyeyGreensteinPhase(-0.5)});
    PhotonRng rng(5, 0);
    for (double z : {1.0, 5.0, 8.5}) {
        const int n = 200000;
        double sum = 0.0, sum2 = 0.0;
        for (int i = 0; i < n; ++i) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const double mu = w.sample_phase(z, u1, u2).cos_psi;
            sum += mu;
            sum2 += mu * mu;
        }
        const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
        const double exact = (1.0 - z / 10.0) * 0.8 - z / 10.0 * 0.5;
        CHECK(std::abs(mean - exact) <= 4.0 * se);
        // eval is the same mixture.
        const double mix = (1.0 - z / 10.0) * HenyeyGreensteinPhase(0.8).eval(0.3) + z / 10.0 * HenyeyGreensteinPhase(-0.5).eval(0.3);
        CHECK(w.eval_phase(z, 0.3) == Approx(mix).epsilon(1e-13));
    }
}

TEST_CASE("stratified water: sample_direction is the direction of sample_phase, bit for bit; its pdf is the mixture's") {
    // Problem 3's kind of water: pure water (Rayleigh-like) and Petzold particles, b_i varying
    // with depth and a jump at 4 m; and a single component (the branch without a choice).
    DepthProfile p{{0.0, 2.0, 4.0, 4.0, 10.0},
                   {0.05, 0.05, 0.05, 0.05, 0.05},
                   {{0.003, 0.003, 0.003, 0.003, 0.003}, {0.0, 0.4, 1.2, 0.1, 0.3}}};
    const StratifiedWater<AnyPhaseFunction> mix(p, {AnyPhaseFunction{pure_water_phase()}, AnyPhaseFunction{petzold_m93()}});
    DepthProfile q{{0.0, 10.0}, {0.05, 0.05}, {{0.2, 0.5}}};
    const StratifiedWater<TabulatedPhase> one(q, {petzold_m93()});
    const auto same = test::same_bits;
    const auto check = [&](const auto& w, double z) {
        INFO("z = " << z);
        PhotonRng rng(17, 0);
        int mismatches = 0;
        for (int k = 0; k < 10000; ++k) {
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const PhaseSample s = w.sample_phase(z, u1, u2);
            const PhaseDirection d = w.sample_direction(z, u1, u2);
            const PhaseDirection t = scattering_direction(w, z, u1, u2);  // what the tracer calls
            if (!same(d.cos_psi, s.cos_psi) || !same(d.phi, s.phi) || !same(t.cos_psi, d.cos_psi) || !same(t.phi, d.phi))
                ++mismatches;
            if (!same(s.pdf, w.eval_phase(z, s.cos_psi))) ++mismatches;  // the mixture's density, eq. 5.6
        }
        CHECK(mismatches == 0);
    };
    for (double z : {0.0, 0.7, 2.0, 3.3, 4.0, 6.5, 10.0, 25.0}) {
        check(mix, z);
        check(one, z);
    }
}

// The typed form holds each component on its own type: no variant between the sampler and
// the phase functions (the single-type form of AnyPhaseFunction is the run-time one).
using TypedMix = StratifiedWater<IsotropicPhase, HenyeyGreensteinPhase, RayleighPhase>;
static_assert(std::is_same_v<TypedMix::storage_type, std::tuple<IsotropicPhase, HenyeyGreensteinPhase, RayleighPhase>>);
static_assert(TypedMix::components() == 3);
static_assert(Medium<TypedMix> && Medium<StratifiedWater<AnyPhaseFunction>>);
static_assert(std::is_same_v<StratifiedWater<HenyeyGreensteinPhase>::storage_type, std::vector<HenyeyGreensteinPhase>>);
static_assert(std::is_same_v<StratifiedWater<HenyeyGreensteinPhase>::phase_type, HenyeyGreensteinPhase>);

TEST_CASE("stratified water: a typed mixture samples and evaluates as the same mixture of AnyPhaseFunction, bit for bit") {
    // Isotropic, HG and Rayleigh components whose weights change with depth, a jump at 4 m, and
    // a depth (1.5 m) where the isotropic one alone scatters.
    DepthProfile p{{0.0, 1.5, 4.0, 4.0, 10.0},
                   {0.05, 0.05, 0.05, 0.1, 0.1},
                   {{0.5, 0.5, 0.2, 0.7, 0.1}, {0.0, 0.0, 0.9, 0.1, 0.4}, {0.0, 0.0, 0.0, 0.3, 0.02}}};
    const IsotropicPhase iso;
    const HenyeyGreensteinPhase hg(0.85);
    const RayleighPhase ray;
    const TypedMix typed(p, {iso, hg, ray}, 1.34);
    const StratifiedWater<AnyPhaseFunction> any(p, {AnyPhaseFunction{iso}, AnyPhaseFunction{hg}, AnyPhaseFunction{ray}}, 1.34);
    const auto same = test::same_bits;
    CHECK(typed.refractive_index() == any.refractive_index());
    for (double z : {0.0, 0.7, 1.5, 2.9, 4.0, 6.5, 10.0, 25.0}) {
        INFO("z = " << z);
        for (auto k : {Coefficient::absorption, Coefficient::scattering, Coefficient::attenuation}) {
            CHECK(same(typed.coefficient(k, z), any.coefficient(k, z)));
            CHECK(same(typed.optical_path(k, z, 0.6, 3.0), any.optical_path(k, z, 0.6, 3.0)));
        }
        CHECK(test::phase_mismatches_at(typed, any, z, 23, 20000) == 0);
    }
    // Each component on its own type, in order.
    CHECK(typed.visit_phase(1, [](const auto& ph) { return std::string(ph.name()); }) == hg.name());
    std::string names;
    typed.for_each_phase([&](const auto& ph) { names += std::string(ph.name()) + ";"; });
    std::string expected;
    for (const auto& ph : any.phases()) expected += ph.name() + ";";
    CHECK(names == expected);
}

TEST_CASE("stratified water: the typed form rejects invalid profiles as the single-type form does") {
    using Two = StratifiedWater<IsotropicPhase, HenyeyGreensteinPhase>;
    const Two::storage_type phases{IsotropicPhase{}, HenyeyGreensteinPhase(0.5)};
    const std::vector<double> b{0.1, 0.1};
    CHECK_NOTHROW(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b, b}}, phases));
    // Negative absorption, decreasing depths, a first depth below the surface.
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 1.0}, {0.1, -0.1}, {b, b}}, phases), input_error);
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 2.0, 1.0}, {0.1, 0.1, 0.1}, {{0.1, 0.1, 0.1}, {0.1, 0.1, 0.1}}}, phases),
                    input_error);
    CHECK_THROWS_AS(Two(DepthProfile{{0.5, 1.0}, {0.1, 0.1}, {b, b}}, phases), input_error);
    // One scattering profile for two phase functions; a profile of the wrong length; negative or NaN b.
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b}}, phases), input_error);
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b, {0.1}}}, phases), input_error);
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b, {0.1, -0.2}}}, phases), input_error);
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b, {0.1, NAN}}}, phases), input_error);
    CHECK_THROWS_AS(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b, b}}, phases, 0.9), input_error);  // refractive index < 1
    using Catch::Matchers::Contains;
    CHECK_THROWS_WITH(Two(DepthProfile{{0.0, 1.0}, {0.1, 0.1}, {b}}, phases), Contains("scattering components") && Contains("1"));
}

TEST_CASE("stratified water: analog, implicit capture and continuous absorption agree with scattering") {
    const auto water = two_layers(0.3, 0.7, 0.1, 1.5, 1.5, HenyeyGreensteinPhase(0.7));
    TransportSettings s;
    s.photons = 300000;
    s.depths = {0.5, 2.0, 4.0};
    s.absorption = AbsorptionMode::analog;
    const auto a = trace(water, s, 30.0);
    s.absorption = AbsorptionMode::continuous;
    const auto c = trace(water, s, 30.0);
    s.absorption = AbsorptionMode::implicit_capture;
    const auto ic = trace(water, s, 30.0);
    for (std::size_t i = 0; i < s.depths.size(); ++i)
        for (int k : {Ed, Eu, Eod, Eou}) {
            INFO("depth " << s.depths[i] << " quantity " << k);
            CHECK(agree(a.irradiance[i][k], c.irradiance[i][k]));
            CHECK(agree(a.irradiance[i][k], ic.irradiance[i][k]));
        }
}

TEST_CASE("depth importance: the level of random depths is the formula's, in layered and homogeneous water") {
    // L(z) = floor(tau_a(z) / s) down to z_max, L(z_max) - floor((tau_a(z) - tau_a(z_max)) / s)
    // below (s = mu_i ln 2; transport/importance.hpp), evaluated from the medium's optical depth;
    // depths within 1e-9 s of a level change, where rounding may decide, are skipped.
    const auto layered = two_layers(0.37, 0.5, 0.91, 0.5, 2.3, IsotropicPhase{});
    const auto homogeneous = HomogeneousWater<IsotropicPhase>::from_albedo(1.0, 0.2, IsotropicPhase{});
    std::mt19937_64 gen(29);
    // Depths drawn uniformly from [lo, hi] (default: -1 m to 3 z_max + 1 m).
    auto check = [&](const auto& water, DepthImportance imp, const char* name, double lo = NAN, double hi = NAN) {
        const ImportanceLevels levels(imp, water);
        const double s = imp.cosine * std::numbers::ln2;
        const double tau_max = water.optical_path(Coefficient::absorption, 0.0, 1.0, imp.max_depth);
        std::uniform_real_distribution<double> depth(std::isnan(lo) ? -1.0 : lo, std::isnan(hi) ? 3.0 * imp.max_depth + 1.0 : hi);
        int checked = 0, mismatches = 0;
        for (int n = 0; n < 200000; ++n) {
            const double z = n < 4 ? std::array{-5.0, 0.0, imp.max_depth, 1e5}[n] : depth(gen);
            const double tau = water.optical_path(Coefficient::absorption, 0.0, 1.0, std::max(z, 0.0));
            const double x = z <= imp.max_depth ? tau / s : (tau - tau_max) / s;
            if (z > 0.0 && std::abs(x - std::round(x)) < 1e-9) continue;
            const int expected = z <= imp.max_depth ? static_cast<int>(std::floor(tau / s))
                                                    : static_cast<int>(std::floor(tau_max / s) - std::min(63.0, std::floor(x)));
            ++checked;
            if (levels.level(z) != expected || levels.factor(z) != std::ldexp(1.0, expected)) {
                if (++mismatches <= 5) FAIL_CHECK(name << ": z = " << z << " level " << levels.level(z) << ", formula " << expected);
            }
            // span(z): z inside it, the same level at its ends and at a random depth inside; and
            // the same span by its index (index_of, as the lanes keep it).
            const auto span = levels.span(z);
            const auto indexed = levels.span_at(levels.index_of(z));
            const double last = std::nextafter(span.hi, -INFINITY);
            const double inside = std::isfinite(span.lo) && std::isfinite(span.hi)
                                      ? std::min(last, span.lo + (span.hi - span.lo) * std::generate_canonical<double, 53>(gen))
                                      : z;
            const bool span_right = span.lo <= z && z < span.hi && span.level == expected &&
                                    indexed.lo == span.lo && indexed.hi == span.hi && indexed.level == span.level &&
                                    span.factor == std::ldexp(1.0, expected) && levels.level(inside) == expected &&
                                    (!std::isfinite(span.lo) || levels.level(span.lo) == expected) &&
                                    (!std::isfinite(span.hi) || levels.level(last) == expected);
            if (!span_right && ++mismatches <= 5)
                FAIL_CHECK(name << ": z = " << z << " span [" << span.lo << ", " << span.hi << ") level " << span.level);
        }
        INFO(name << ": " << checked << " depths checked");
        CHECK(checked > 199000);
        CHECK(mismatches == 0);
    };
    check(layered, {0.6, 7.0}, "layered, mu_i = 0.6");
    check(layered, {1.0, 2.3}, "layered, z_max on the layer boundary");
    check(homogeneous, {1.0, 10.0}, "homogeneous a = 0.8, mu_i = 1");
    check(homogeneous, {0.05, 3.0}, "homogeneous, many levels");
    // Levels 1.4e-5 m apart below 20 m under 14 m without any: more than the guide's buckets
    // can separate, so that buckets hold several boundaries.
    const auto dense = two_layers(0.05, 0.5, 5e4, 0.5, 20.0, IsotropicPhase{});
    check(dense, {1.0, 20.0005}, "a dense layer", 19.9995, 20.0025);
    check(dense, {1.0, 20.0005}, "a dense layer, all depths");
    CHECK(ImportanceLevels{}.level(5.0) == 0);
    CHECK(ImportanceLevels{}.factor(5.0) == 1.0);
}

TEST_CASE("depth importance: a depth inside a span's inner bounds has the span's level, and so has its float rounding") {
    // inner_span (transport/importance.hpp), LaneTracer's test of whether a lane's level still
    // holds: the span of an earlier depth (beside a level change, or anywhere) against a float
    // or double depth within 4e-6 (relative) of that change, or anywhere. Inside the inner
    // bounds the depth's own level must be the span's and, with a margin of 1e-6, so must the
    // level of the depth a float record stores; a depth left outside must lie outside the span
    // or within twice the margin of a bound (no needless look-ups).
    const auto layered = two_layers(0.37, 0.5, 0.91, 0.5, 2.3, IsotropicPhase{});
    const auto homogeneous = HomogeneousWater<IsotropicPhase>::from_albedo(1.0, 0.2, IsotropicPhase{});
    std::mt19937_64 gen(37);
    auto check = [&]<class Real>(const auto& water, DepthImportance imp, double margin, Real, const char* name) {
        const ImportanceLevels levels(imp, water);
        std::vector<double> bounds;
        for (double b = levels.span(-1.0).hi; std::isfinite(b); b = levels.span(b).hi) bounds.push_back(b);
        REQUIRE(bounds.size() > 4);
        std::uniform_int_distribution<std::size_t> pick(0, bounds.size() - 1);
        std::uniform_real_distribution<double> near(-4e-6, 4e-6), anywhere(-1.0, 1.2 * bounds.back());
        int inside = 0, outside = 0, wrong = 0;
        for (int n = 0; n < 100000; ++n) {
            // A span held from an earlier depth (the lane's), and a new depth near its bounds or anywhere.
            const double bound = bounds[pick(gen)];
            const double earlier = n % 5 == 0 ? anywhere(gen) : bound * (1.0 + (n % 2 ? 1e-5 : -1e-5));
            const double z = n % 5 == 0 ? anywhere(gen) : bound * (1.0 + near(gen));
            const Real y = static_cast<Real>(z);
            const double depth = y, stored = static_cast<float>(y);
            const auto span = levels.span(earlier);
            const InnerSpan<Real> in = inner_span<Real>(span, margin);
            bool right;
            if (in.lo <= y && y < in.hi) {
                ++inside;
                right = levels.level(depth) == span.level && (margin == 0.0 || levels.level(stored) == span.level);
            } else {  // outside the span, or within the margin of a bound
                ++outside;
                right = !(span.lo <= depth && depth < span.hi) ||
                        std::abs(depth - span.lo) <= 2.0 * margin * std::abs(span.lo) ||
                        std::abs(depth - span.hi) <= 2.0 * margin * std::abs(span.hi);
            }
            if (!right && ++wrong <= 5)
                FAIL_CHECK(name << ": depth " << depth << " span [" << span.lo << ", " << span.hi << ") level " << span.level);
        }
        INFO(name << ": " << inside << " inside, " << outside << " outside");
        CHECK(wrong == 0);
        CHECK(inside > 20000);
        CHECK(outside > 40000);
    };
    for (const double margin : {0.0, 1e-6}) {
        check(layered, {0.6, 7.0}, margin, 0.0f, "layered, float");
        check(layered, {0.6, 7.0}, margin, 0.0, "layered, double");
        check(homogeneous, {0.05, 3.0}, margin, 0.0f, "homogeneous, many levels, float");
        check(homogeneous, {0.05, 3.0}, margin, 0.0, "homogeneous, many levels, double");
    }
}

TEST_CASE("depth importance by default: on from an absorption optical depth of ln 2 to the deepest detector") {
    // default_depth_importance (transport/importance.hpp): mu_i = 1 down to the deepest
    // detector z where tau_a(z) >= ln 2, else off. Random depths on both sides, in layered and
    // homogeneous water, against that definition from the medium's optical depth.
    const auto layered = two_layers(0.37, 0.5, 0.91, 0.5, 2.3, IsotropicPhase{});  // tau_a = ln 2 at 2.89 m
    const auto homogeneous = HomogeneousWater<IsotropicPhase>::from_albedo(1.0, 0.2, IsotropicPhase{});  // at 0.87 m
    std::mt19937_64 gen(31);
    std::uniform_real_distribution<double> depth(0.0, 4.0);
    auto check = [&](const auto& water, const char* name) {
        int on = 0, wrong = 0;
        for (int n = 0; n < 20000; ++n) {
            const double z = depth(gen);
            const DepthImportance imp = default_depth_importance(water, z);
            const bool deep = water.optical_path(Coefficient::absorption, 0.0, 1.0, z) >= std::numbers::ln2;
            on += imp.enabled();
            const bool right = imp.enabled() == deep && (!deep || (imp.cosine == 1.0 && imp.max_depth == z));
            if (!right && ++wrong <= 5) FAIL_CHECK(name << ": z = " << z << " gave cosine " << imp.cosine << " to " << imp.max_depth);
        }
        INFO(name << ": " << on << " of 20000 depths on");
        CHECK(wrong == 0);
        CHECK(on > 2000);
        CHECK(on < 18000);
    };
    check(layered, "layered");
    check(homogeneous, "homogeneous");
    // At the boundary: the depth where tau_a reaches ln 2 (the medium's inverse) and just above it.
    const double edge = homogeneous.distance_to(Coefficient::absorption, 0.0, 1.0, std::numbers::ln2);
    CHECK(default_depth_importance(homogeneous, edge * (1.0 + 1e-12)).enabled());
    CHECK_FALSE(default_depth_importance(homogeneous, edge * (1.0 - 1e-12)).enabled());
}

TEST_CASE("depth importance: splitting and roulette leave irradiances and the map's flux unbiased") {
    const auto water = two_layers(0.4, 0.6, 0.2, 1.0, 2.0, HenyeyGreensteinPhase(0.8));
    TransportSettings s;
    s.photons = s.map_photons = 200000;
    s.depths = {1.0, 4.0, 8.0};
    const auto plain = trace(water, s, 30.0);
    s.importance = {0.5, 6.0};
    const ImportanceLevels levels(s.importance, water);
    CHECK(levels.level(0.5) == 0);
    CHECK(levels.level(6.0) > levels.level(3.0));
    CHECK(levels.level(30.0) < levels.level(6.0));  // falls again below z_max
    const auto split = trace(water, s, 30.0);
    for (std::size_t i = 0; i < s.depths.size(); ++i)
        for (int k : {Ed, Eu, Eod, Eou}) {
            INFO("depth " << s.depths[i] << " quantity " << k);
            CHECK(agree(plain.irradiance[i][k], split.irradiance[i][k]));
        }
    CHECK(std::abs(split.ledger.imbalance()) < 1e-9);
    // Stored flux per depth bin: records x 1/I(z) (importance) against plain records; the
    // deep bins hold many more records with importance.
    auto flux_in = [&](const auto& recs, const ImportanceLevels& lv, double lo, double hi) {
        double f = 0.0, n = 0.0;
        for (const auto& r : recs)
            if (r.position().z >= lo && r.position().z < hi) {
                f += 1.0 / lv.factor(r.position().z);
                n += 1.0;
            }
        return std::pair{f, n};
    };
    for (auto [lo, hi] : {std::pair{0.0, 1.0}, {3.0, 4.0}, {5.0, 6.0}}) {
        const auto [fp, np] = flux_in(plain.records, ImportanceLevels{}, lo, hi);
        const auto [fs, ns] = flux_in(split.records, levels, lo, hi);
        INFO("bin " << lo << "-" << hi << ": plain " << fp << " (" << np << " records), importance " << fs << " ("
                    << ns << " records)");
        CHECK(std::abs(fs - fp) <= 4.0 * std::sqrt(np + fs));  // counts are Poisson-like
        if (lo >= 3.0) CHECK(ns > 2.0 * np);
    }
}
