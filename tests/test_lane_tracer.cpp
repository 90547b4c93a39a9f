// Photons in lanes (core/lanes.hpp, map/record_lanes.hpp, transport/lane_tracer.hpp): the
// vector kernels against their scalar counterparts, and LaneTracer against PhotonTracer on
// the same problems (PhotonTracer's estimate first, LaneTracer's second). Statistical checks:
// within 4 combined standard errors (fixed in advance; transport_checks.hpp).
#include <catch2/catch.hpp>
#include "secchi/core/stats.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/phase/fournier_forand.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/optics/phase/rayleigh_like.hpp"
#include "secchi/optics/phase/schlick.hpp"
#include "secchi/optics/stratified_water.hpp"
#include "secchi/scene/wind_blown_surface.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/transport/lane_tracer.hpp"
#include "transport_checks.hpp"
#include <algorithm>
#include <cmath>
#include <limits>
#include <cstring>
#include <numbers>
#include <vector>

#if SECCHI_HAS_LANES
using namespace secchi;
using lanes::lane_width;
using lanes::Reals;

// PhotonTracer and LaneTracer (double and float lanes) share one signature.
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
static_assert(FirstPassTracer<PhotonTracer<HgWater, CompactRecord>>);
static_assert(FirstPassTracer<LaneTracer<HgWater, CompactRecord>>);
static_assert(FirstPassTracer<FloatLaneTracer<HgWater, FullRecord, WindBlownSurface>>);

namespace {
using lanes::Floats;
constexpr int float_width = lanes::width_of<float>;
constexpr double float_unit = 0x1p-24;  ///< float's unit roundoff (half an ulp of 1)

/// Lane l's value of `f(l)` as a vector (of doubles, or of the lanes V).
template <class V = Reals, class F>
V lanes_of(F&& f) {
    using T = typename V::value_type;
    return V([&](auto l) { return static_cast<T>(f(static_cast<int>(l))); });
}

/// |a - b| in units of the last place of b.
double ulps(double a, double b) {
    if (a == b) return 0.0;
    const double ulp = std::nextafter(std::abs(b), INFINITY) - std::abs(b);
    return std::abs(a - b) / ulp;
}

/// n uniform doubles in (0, 1) from one stream.
std::vector<double> uniforms(std::size_t n, std::uint64_t stream) {
    PhotonRng rng(7, stream);
    std::vector<double> u(n);
    for (double& x : u) x = rng.uniform();
    return u;
}

/// The absolute difference: a bound of 1 for worst_in_lanes.
struct Absolute {
    double operator()(double) const { return 1.0; }
};

/// A lane sampler of cosines against its scalar reference: the largest |in_lanes(v)[l] -
/// reference(v_l)| / bound(reference(v_l)) over the uniforms u taken a vector V at a time, v_l
/// each lane's uniform as V holds it (rounded to float in float lanes); every lane's value
/// must be a cosine. u.size() is a multiple of V's width.
template <class V, class InLanes, class Reference, class Bound = Absolute>
double worst_in_lanes(const std::vector<double>& u, InLanes&& in_lanes, Reference&& reference, Bound&& bound = {}) {
    double worst = 0;
    for (std::size_t i = 0; i < u.size(); i += V::size()) {
        const V v = lanes_of<V>([&](int l) { return u[i + l]; });
        const V mu = in_lanes(v);
        for (std::size_t l = 0; l < V::size(); ++l) {
            REQUIRE(std::abs(double(mu[l])) <= 1.0);
            const double exact = reference(double(v[l]));
            worst = std::max(worst, std::abs(double(mu[l]) - exact) / bound(exact));
        }
    }
    return worst;
}

/// A unit direction from two uniforms (uniform on the sphere).
vec3 direction_of(double u1, double u2) {
    const double mu = 2.0 * u1 - 1.0, phi = two_pi * u2, s = std::sqrt(std::max(0.0, 1.0 - mu * mu));
    return {s * std::cos(phi), s * std::sin(phi), mu};
}
}  // namespace

TEMPLATE_TEST_CASE("select and unit_with_sign_of in lanes do lane by lane what they do for one value", "", double,
                   float) {
    // The lanes' kernels rest on masked assignment (select: where(m, b) = a) picking lane by
    // lane; clang 14 with libstdc++ 12's AVX-512 masks leaves b unchanged (core/lanes.hpp).
    using V = lanes::LanesOf<TestType>;
    const auto u = uniforms(4000, 11);
    for (std::size_t i = 0; i + 2 * V::size() <= u.size(); i += 2 * V::size()) {
        const V a = lanes_of<V>([&](int l) { return u[i + l] - 0.5; });
        const V b = lanes_of<V>([&](int l) { return u[i + V::size() + l]; });
        const auto m = a < b;
        const V picked = select(m, a, b), sign = unit_with_sign_of(a);
        for (std::size_t l = 0; l < V::size(); ++l) {
            const TestType al = a[l], bl = b[l];
            REQUIRE(picked[l] == select(al < bl, al, bl));
            REQUIRE(sign[l] == unit_with_sign_of(al));
        }
    }
    const V zeros = lanes_of<V>([](int l) { return l % 2 ? -0.0 : 0.0; });
    for (std::size_t l = 0; l < V::size(); ++l) REQUIRE(unit_with_sign_of(zeros)[l] == (l % 2 ? -1 : 1));
}

TEST_CASE("log, sin_cos and the rotation in lanes compute what they compute for doubles") {
    const auto u = uniforms(4096, 1);
    std::vector<double> x = u;  // the free path's arguments, and the extremes of (0, 1)
    x.insert(x.end(), {uniform_from_bits(0), uniform_from_bits(0xffffffffu), 0.5, 1.0, 2.0, 1e300, 1e-300});
    while (x.size() % lane_width) x.push_back(0.75);
    double worst_log = 0;
    for (std::size_t i = 0; i < x.size(); i += lane_width) {
        const Reals v = lanes::log(lanes_of([&](int l) { return x[i + l]; }));
        for (int l = 0; l < lane_width; ++l) worst_log = std::max(worst_log, ulps(v[l], std::log(x[i + l])));
    }
    INFO("lanes::log: worst " << worst_log << " ulp from std::log");
    CHECK(worst_log <= 2.0);

    double worst_sin_cos = 0, worst_rotation = 0;
    for (std::size_t i = 0; i + 3 * lane_width <= u.size(); i += 3 * lane_width) {
        const Reals phi = lanes_of([&](int l) { return two_pi * u[i + l]; });
        const Reals cos_psi = lanes_of([&](int l) { return 2.0 * u[i + lane_width + l] - 1.0; });
        std::vector<vec3> dirs(lane_width);
        for (int l = 0; l < lane_width; ++l) dirs[l] = direction_of(u[i + 2 * lane_width + l], u[i + l]);
        const SinCosOf<Reals> sc = sin_cos(phi);
        const lanes::Vec3 out = rotate_direction(
            {lanes_of([&](int l) { return dirs[l].x; }), lanes_of([&](int l) { return dirs[l].y; }),
             lanes_of([&](int l) { return dirs[l].z; })},
            cos_psi, phi);
        for (int l = 0; l < lane_width; ++l) {
            const SinCos s = sin_cos(phi[l]);
            worst_sin_cos = std::max({worst_sin_cos, ulps(sc.sin[l], s.sin), ulps(sc.cos[l], s.cos)});
            const vec3 r = rotate_direction(dirs[l], cos_psi[l], phi[l]);
            worst_rotation = std::max({worst_rotation, std::abs(out.x[l] - r.x), std::abs(out.y[l] - r.y),
                                       std::abs(out.z[l] - r.z)});
        }
    }
    INFO("sin_cos in lanes: worst " << worst_sin_cos << " ulp; rotation: worst " << worst_rotation);
    CHECK(worst_sin_cos <= 1.0);   // the same operations (a fused multiply-add may round once less)
    CHECK(worst_rotation <= 1e-15);
}

// Float lanes: each kernel against its double form on the same (float) arguments, within a
// bound from float's unit roundoff u = 2^-24 set by the kernel's operations.
TEST_CASE("log, sin_cos and the rotation in float lanes are within float rounding of the doubles'") {
    const auto u = uniforms(8192, 1);
    std::vector<float> x;  // the free path's arguments: float uniforms, and their extremes
    for (const double v : u) x.push_back(static_cast<float>(v));
    x.insert(x.end(), {uniform_float_from_bits(0), uniform_float_from_bits(0xffffffffu), 0.5f, 1.0f, 2.0f});
    while (x.size() % float_width) x.push_back(0.75f);
    double worst_log = 0;
    for (std::size_t i = 0; i < x.size(); i += float_width) {
        const Floats v = lanes::log(lanes_of<Floats>([&](int l) { return x[i + l]; }));
        for (int l = 0; l < float_width; ++l) {
            const double exact = std::log(double(x[i + l]));
            const double ulp = std::nextafter(std::abs(float(exact)), INFINITY) - std::abs(float(exact));
            if (exact != 0.0) worst_log = std::max(worst_log, std::abs(v[l] - exact) / ulp);
            else CHECK(v[l] == 0.0f);
        }
    }
    INFO("lanes::log in floats: worst " << worst_log << " float ulp from log");
    CHECK(worst_log <= 2.0);  // f's division and the final sums each round once, as for doubles

    double worst_sin_cos = 0, worst_rotation = 0;
    for (std::size_t i = 0; i + 3 * float_width <= u.size(); i += 3 * float_width) {
        const Floats phi = lanes_of<Floats>([&](int l) { return two_pi * u[i + l]; });
        const Floats cos_psi = lanes_of<Floats>([&](int l) { return 2.0 * u[i + float_width + l] - 1.0; });
        std::vector<vec3> dirs(float_width);
        for (int l = 0; l < float_width; ++l) dirs[l] = direction_of(u[i + 2 * float_width + l], u[i + l]);
        const SinCosOf<Floats> sc = sin_cos(phi);
        const lanes::Vec3F out = rotate_direction(
            {lanes_of<Floats>([&](int l) { return dirs[l].x; }), lanes_of<Floats>([&](int l) { return dirs[l].y; }),
             lanes_of<Floats>([&](int l) { return dirs[l].z; })},
            cos_psi, phi);
        for (int l = 0; l < float_width; ++l) {
            const SinCos s = sin_cos(double(phi[l]));
            worst_sin_cos = std::max({worst_sin_cos, std::abs(sc.sin[l] - s.sin), std::abs(sc.cos[l] - s.cos)});
            const vec3 d(float(dirs[l].x), float(dirs[l].y), float(dirs[l].z));
            const vec3 r = rotate_direction(d, double(cos_psi[l]), double(phi[l]));
            worst_rotation = std::max({worst_rotation, std::abs(out.x[l] - r.x), std::abs(out.y[l] - r.y),
                                       std::abs(out.z[l] - r.z)});
        }
    }
    INFO("sin_cos in float lanes: worst " << worst_sin_cos << "; rotation: worst " << worst_rotation);
    CHECK(worst_sin_cos <= 4 * float_unit);  // x - k pi/2 (exact first part), r^2 and the sums: a few u
    CHECK(worst_rotation <= 16 * float_unit);  // the frame's products of unit components, renormalised
}

TEST_CASE("exp in lanes equals exp_table lane by lane") {
    const auto u = uniforms(8192, 3);
    std::vector<double> x;
    for (const double v : u) x.push_back(-707.9 + 1416.8 * v);  // inside exp_table's range
    for (const double v : u) x.push_back(-8.0 * v);              // the transmittances' usual range
    x.insert(x.end(), {0.0, -0.0, 1e-300, -1e-300, -707.99, 708.99, 0.5 * std::numbers::ln2, -std::numbers::ln2 / 128});
    while (x.size() % lane_width) x.push_back(-1.0);
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); i += lane_width) {
        const Reals v = lanes::exp(lanes_of([&](int l) { return x[i + l]; }));
        for (int l = 0; l < lane_width; ++l) worst = std::max(worst, ulps(v[l], exp_table(x[i + l])));
    }
    INFO("lanes::exp: worst " << worst << " ulp from exp_table");
    CHECK(worst == 0.0);  // the same operations: the estimator's sums rely on it (test_estimate.cpp)
}

TEST_CASE("exp in float lanes is within a few float ulp of exp") {
    // The weights' decay exp(-a s) (with continuous absorption a s <= -ln(2^-24) a / b, so
    // beyond -17 where a > b): the whole range of normal results, and [-17, 0] densely; the
    // reduction's ends; below -87, zero.
    const auto u = uniforms(8192, 4);
    std::vector<float> x;
    for (const double v : u) x.push_back(static_cast<float>(-87.0 + 175.0 * v));
    for (const double v : u) x.push_back(static_cast<float>(-17.0 * v));
    x.insert(x.end(), {0.0f, -0.0f, 1e-30f, -1e-30f, -87.0f, 88.0f, 0.5f * std::numbers::ln2_v<float>,
                       -0.5f * std::numbers::ln2_v<float>, -std::numbers::ln2_v<float>, 1.0f, -1.0f});
    while (x.size() % float_width) x.push_back(-2.0f);
    double worst = 0;
    for (std::size_t i = 0; i < x.size(); i += float_width) {
        const Floats v = lanes::exp(lanes_of<Floats>([&](int l) { return x[i + l]; }));
        for (int l = 0; l < float_width; ++l) {
            const double exact = std::exp(double(x[i + l]));
            const double ulp = std::nextafter(float(exact), INFINITY) - float(exact);
            worst = std::max(worst, std::abs(v[l] - exact) / ulp);
        }
    }
    INFO("lanes::exp in floats: worst " << worst << " float ulp from exp");
    CHECK(worst <= 4.0);  // the product r n ln2_lo, the series' sums and the scaling: a few roundings
    const Floats under = lanes::exp(Floats(-87.5f)), far = lanes::exp(Floats(-1e4f));
    for (int l = 0; l < float_width; ++l) CHECK((under[l] == 0.0f && far[l] == 0.0f));
}

TEMPLATE_TEST_CASE("LaneAbsorption's transmittance is exp(-a s), and 0 for long flights in strongly absorbing water",
                   "", double, float) {
    // Continuous absorption's free paths are -ln u / b, so a s reaches beyond exp's range where
    // a >> b: there the transmittance is 0 (below e^-87 in floats, e^-707 in doubles), not
    // whatever lanes::exp computes outside its range. Elsewhere within LaneAbsorption's bound:
    // floats (a s + 8) 2^-24 relative; doubles exp_table's 2 ulp and std::exp's 1 (6 2^-53).
    using T = TestType;
    using V = lanes::LanesOf<T>;
    constexpr int width = lanes::width_of<T>;
    const LaneAbsorption<T> absorption{T(50.0)};
    const std::vector<double> lengths{0.0, 1e-3, 0.1, 1.0, 1.7, 14.0, 14.2, 20.0, 100.0, 1e4, 1e30};
    for (const double s : lengths) {
        const V got = absorption.transmittance(V(T(0)), V(T(1)), V(T(s)));
        const double exact = std::exp(-50.0 * double(T(s)));
        const double bound = std::is_same_v<T, float> ? (50.0 * s + 8.0) * float_unit * exact : 6 * 0x1p-53 * exact;
        for (int l = 0; l < width; ++l) {
            INFO("s = " << s << ": " << got[l] << " against " << exact);
            CHECK(std::abs(got[l] - exact) <= std::max(bound, std::is_same_v<T, float> ? 1.2e-38 : 1e-307));
            CHECK(got[l] >= 0.0);
        }
    }
}

TEST_CASE("lookup_rows gives every lane its own row, column by column") {
    std::vector<Row8> rows(1000);
    for (std::size_t j = 0; j < rows.size(); ++j)
        for (int c = 0; c < 8; ++c) rows[j].v[c] = static_cast<double>(j) + 0.125 * c;  // exact, unique
    const auto u = uniforms(4096, 11);
    for (std::size_t i = 0; i + lane_width <= u.size(); i += lane_width) {
        const Reals index = lanes_of([&](int l) { return std::floor(u[i + l] * static_cast<double>(rows.size())); });
        const std::array<Reals, 8> got = lanes::lookup_rows(rows, index);
        for (int l = 0; l < lane_width; ++l)
            for (int c = 0; c < 8; ++c) REQUIRE(got[c][l] == rows[static_cast<std::size_t>(index[l])].v[c]);
    }
}

// Doubles: PhotonRng's uniforms; floats: the top 24 bits of the same words. Both within (0, 1).
TEMPLATE_TEST_CASE("Philox uniforms and words in lanes equal PhotonRng's words, bit for bit", "", double, float) {
    using T = TestType;
    constexpr int width = lanes::width_of<T>;
    const auto uniform_of = [](std::uint32_t w) -> T {
        if constexpr (std::is_same_v<T, float>) return uniform_float_from_bits(w);
        else return uniform_from_bits(w);
    };
    const std::array<std::uint32_t, 2> key{0x9abcdef0u, 0x12345678u};
    for (std::uint64_t first : {0ull, 1ull << 31, (1ull << 32) - 3, 0xfedcba9876543210ull}) {
        alignas(64) std::uint64_t block[width], stream[width];
        alignas(64) T u[4][width];
        for (int l = 0; l < width; ++l) block[l] = first + 977 * l, stream[l] = ~first - 13 * l;
        alignas(64) std::uint32_t bits[4][width];
        lanes::philox_uniforms(block, stream, lanes::PhiloxKey(key), {u[0], u[1], u[2], u[3]});
        lanes::philox_words<width>(block, stream, lanes::PhiloxKey(key), {bits[0], bits[1], bits[2], bits[3]});
        for (int l = 0; l < width; ++l) {
            const auto words = philox_block(block[l], stream[l], key);
            PhotonRng rng(0x123456789abcdef0ull, stream[l], block[l]);
            for (int k = 0; k < 4; ++k) {
                REQUIRE(bits[k][l] == words[k]);
                REQUIRE(rng.bits() == words[k]);
                REQUIRE(u[k][l] == uniform_of(words[k]));
                REQUIRE((u[k][l] > T(0) && u[k][l] < T(1)));
            }
        }
    }
    CHECK(uniform_float_from_bits(0) == 0x1p-25f);
    CHECK(uniform_float_from_bits(0xffffffffu) == 1.0f);  // 2^24 - 1/2 rounds to 2^24 (core/rng.hpp)
    CHECK(uniform_float_from_bits(0xfffffeffu) == 1.0f - 0x1p-23f);
}

TEST_CASE("Henyey-Greenstein's inverse CDF in float lanes is within float rounding of the double's") {
    const HenyeyGreensteinPhase hg(0.9);
    const double worst = worst_in_lanes<Floats>(
        uniforms(4096, 2), [&](const Floats& v) { return hg.cos_psi(v); }, [&](double v) { return hg.cos_psi(v); });
    INFO("worst " << worst);
    // Near s = -1 num's four terms (sum of magnitudes 1 + 2 g + g^2 + g^3 at most) cancel to
    // -(1 - g)^2 and are divided by den = (1 + g s)^2 >= (1 - g)^2: num's rounding (a few u of
    // that sum, 4 u taken) is amplified by 1/(1 - g)^2 = 100; s = 2 u1 - 1 rounds by u/2, times
    // d mu/ds = (1 + g)^3/(1 - g^2) = 36 there.
    const double g = 0.9;
    const double bound = 4 * float_unit * (1 + 2 * g + g * g + g * g * g) / ((1 - g) * (1 - g)) +
                         0.5 * float_unit * std::pow(1 + g, 3) / (1 - g * g);
    CHECK(worst <= bound);
}

// Rayleigh's inverse CDF (Cardano's root) in lanes takes its cube root from a cubic guess and
// Halley's steps (rayleigh.hpp) instead of std::cbrt. Uniforms over (0, 1), packed near both
// ends and around u = 1/2 (mu = 0), and u = 1 itself.
static std::vector<double> rayleigh_uniforms() {
    auto u = uniforms(4096, 3);
    for (int k = 1; k <= 40; ++k) {
        const double e = std::ldexp(1.0, -k);
        for (double x : {e, 1.0 - e, 0.5 - e / 4, 0.5 + e / 4}) u.push_back(x);
    }
    u.push_back(0.5);
    u.push_back(1.0);
    while (u.size() % 16 != 0) u.push_back(0.25);
    return u;
}

// Doubles: A within 5.6e-16 relative of the cube root (two Halley steps), and mu = A - 1/A
// moves by (A + 1/A) times that, A + 1/A <= sqrt 5 (A <= the golden ratio): 1.3e-15, with
// std::cbrt's own rounding and that of the subtraction 2e-15.
TEST_CASE("Rayleigh's inverse CDF in lanes is sample_direction's, to 2e-15") {
    const RayleighPhase rayleigh;
    const double worst = worst_in_lanes<Reals>(
        rayleigh_uniforms(), [&](const Reals& v) { return rayleigh.cos_psi(v); },
        [&](double v) { return rayleigh.sample_direction(v, 0.5).cos_psi; });
    INFO("worst " << worst);
    CHECK(worst <= 2e-15);
}

// Floats: q = 8 u - 4 rounds by 4 u_f (half an ulp of 4) and moves mu by a third of it; the
// argument of the cube root by about 3 u_f, a third of it in A; the guess leaves 0.6 u_f
// after one Halley step, whose own operations add about 4 u_f: A within about 6 u_f, mu within
// sqrt 5 times that plus the last two roundings: 20 u_f.
TEST_CASE("Rayleigh's inverse CDF in float lanes is within float rounding of the double's") {
    const RayleighPhase rayleigh;
    const double worst = worst_in_lanes<Floats>(
        rayleigh_uniforms(), [&](const Floats& v) { return rayleigh.cos_psi(v); },
        [&](double v) { return rayleigh.cos_psi(v); });
    INFO("worst " << worst);
    CHECK(worst <= 20 * float_unit);
}

// Rayleigh-like functions (pure water, k2 = 0.835, and beyond): the root's Newton steps in
// lanes, each lane stopping where its own root stops. Double lanes give sample_direction's root
// (4e-16 allowed for a build that fuses multiply-adds differently in the two); float lanes stop
// at a root in float: the residual's rounding, about 8 u_f of mu (k2 mu^2 + 3), over
// h' = 3 (1 + k2 mu^2), plus the result's own rounding.
TEST_CASE("Rayleigh-like inverse CDFs in lanes are sample_direction's, to rounding") {
    const auto u = rayleigh_uniforms();
    for (double k2 : {0.835, 1.0, 0.0, -0.5, -0.99, 5.0, 1e4}) {
        const RayleighLikePhase r(k2);
        INFO("k2 = " << k2);
        const double worst = worst_in_lanes<Reals>(
            u, [&](const Reals& v) { return r.cos_psi(v); }, [&](double v) { return r.sample_direction(v, 0.5).cos_psi; });
        // the float lanes' error as a share of its bound
        const double worst_float = worst_in_lanes<Floats>(
            u, [&](const Floats& v) { return r.cos_psi(v); }, [&](double v) { return r.cos_psi(v); },
            [&](double mu) { return 8 * float_unit * (std::abs(mu) * (k2 * mu * mu + 3) / (3 * (1 + k2 * mu * mu)) + 1); });
        INFO("worst " << worst << ", float lanes " << worst_float << " of their bound");
        CHECK(worst <= 4e-16);
        CHECK(worst_float <= 1.0);
    }
}

// Isotropic, mu = 2 u - 1: double lanes exact (2 u exact, one rounding), float lanes within
// the float's rounding of the double mu (u_f at most; exact where u is a multiple of 2^-24).
TEST_CASE("The isotropic inverse CDF in lanes is sample_direction's") {
    const IsotropicPhase iso;
    const auto u = rayleigh_uniforms();
    CHECK(worst_in_lanes<Reals>(
              u, [&](const Reals& v) { return iso.cos_psi(v); }, [&](double v) { return iso.sample_direction(v, 0.5).cos_psi; }) == 0.0);
    const double worst = worst_in_lanes<Floats>(
        u, [&](const Floats& v) { return iso.cos_psi(v); }, [](double v) { return 2.0 * v - 1.0; });
    INFO("worst " << worst);
    CHECK(worst <= float_unit);
}

// Schlick, mu = (s + k) / (1 + k s), s = 2 u - 1: to first order in the unit roundoff u, s
// and k (in floats) round by u each, s + k by u |s + k|, k s by u |k s| and 1 + k s by u (1 +
// k s), the quotient by u |mu|: |d mu| <= u (3 |mu| + (2 + 3 |mu|) / (1 + k s)), and 1 + k s
// >= 1 - |k|. Double lanes: the same operations as sample_direction (a build may fuse k s + 1
// in one and not the other), within that bound in double's u; float lanes within it in u_f.
TEST_CASE("Schlick's inverse CDF in lanes is sample_direction's, to rounding") {
    const auto u = rayleigh_uniforms();
    const auto bound = [](double unit, double k, double mu) {
        return unit * (3 * std::abs(mu) + (2 + 3 * std::abs(mu)) / (1 - std::abs(k)));
    };
    for (double k : {0.6, 0.9, 0.99, 0.0, -0.5, -0.95}) {
        const SchlickPhase schlick(k);
        INFO("k = " << k);
        // as shares of the bound
        const double worst = worst_in_lanes<Reals>(
            u, [&](const Reals& v) { return schlick.cos_psi(v); },
            [&](double v) { return schlick.sample_direction(v, 0.5).cos_psi; }, [&](double mu) { return bound(0x1p-53, k, mu); });
        const double worst_float = worst_in_lanes<Floats>(
            u, [&](const Floats& v) { return schlick.cos_psi(v); }, [&](double v) { return schlick.cos_psi(v); },
            [&](double mu) { return bound(float_unit, k, mu); });
        INFO("worst " << worst << " (double lanes), " << worst_float << " (float lanes) of the bound");
        CHECK(worst <= 1.0);
        CHECK(worst_float <= 1.0);
    }
}

TEST_CASE("Henyey-Greenstein's inverse CDF and the slab's wrap are the same in lanes") {
    const HenyeyGreensteinPhase hg(0.9);
    const Slab slab(1.0, Bottom{}, 10.0);
    const auto u = uniforms(1024, 2);
    for (std::size_t i = 0; i < u.size(); i += lane_width) {
        const Reals v = lanes_of([&](int l) { return u[i + l]; });
        const Reals cos_psi = hg.cos_psi(v);
        const Reals x = lanes_of([&](int l) { return 40.0 * u[i + l] - 20.0; });
        const Reals wrapped = slab.wrap(x);
        for (int l = 0; l < lane_width; ++l) {
            CHECK(std::abs(cos_psi[l] - hg.sample_direction(u[i + l], 0.5).cos_psi) <= 1e-15);
            CHECK(wrapped[l] == slab.wrap(x[l]));
        }
    }
}

// A phase function's scattering angles in the lanes (EventPhysics::angles), its type known
// and erased: AnyPhaseFunction samples with the held type's lane sampler, or its scalar sampler
// lane by lane, and the lanes take phi = 2 pi u_phi whatever the type, so the two give the same
// bits in double and in float lanes (the Python module's phase functions are erased; slab's are
// not: tests python_tests, "bit-identical to slab"). Mixtures of HG and of Schlick included.
TEMPLATE_TEST_CASE("A phase function's angles in the lanes are the same whether its type is known or erased", "",
                   Reals, Floats) {
    using V = TestType;
    constexpr int width = static_cast<int>(V::size());
    const auto u = uniforms(64 * width, 5);
    std::vector<AnyPhase> phases;
    for (const char* spec : {"isotropic", "rayleigh", "pure-water", "hg:0.9", "schlick:0.6", "ff:0.0183", "petzold"})
        phases.push_back(parse_phase(spec));
    phases.emplace_back(PhaseMixture<HenyeyGreensteinPhase>({HenyeyGreensteinPhase(0.95), HenyeyGreensteinPhase(-0.3)}, {0.8, 0.2}));
    phases.emplace_back(PhaseMixture<SchlickPhase>({SchlickPhase(0.8), SchlickPhase(-0.2)}, {0.7, 0.3}));
    for (const AnyPhase& any : phases) {
        std::visit(
            [&](const auto& typed) {
                const HomogeneousWater<std::decay_t<decltype(typed)>> known(0.1, 0.4, typed);
                const HomogeneousWater<AnyPhaseFunction> erased(0.1, 0.4, AnyPhaseFunction{any});
                INFO(erased.phase().name());
                int differing = 0;
                for (std::size_t i = 0; i + 2 * width <= u.size(); i += 2 * width) {
                    const V z = lanes_of<V>([&](int l) { return 3.0 * u[i + l]; });
                    const V u_psi = lanes_of<V>([&](int l) { return u[i + l]; });
                    const V u_phi = lanes_of<V>([&](int l) { return u[i + width + l]; });
                    const auto a = EventPhysics::angles(known, z, u_psi, u_phi);
                    const auto b = EventPhysics::angles(erased, z, u_psi, u_phi);
                    for (int l = 0; l < width; ++l)
                        differing += (a.cos_psi[l] != b.cos_psi[l] || a.phi[l] != b.phi[l]) ? 1 : 0;
                }
                CHECK(differing == 0);
            },
            any);
    }
}

// Petzold as a table (M93's trapezoid with its power law, and the linear-p convention): the
// vector search and root against sample_direction, at uniforms spread over (0, 1) and packed
// into the power law's mass near 0 (down to u = 0) and the backward tail near 1. The same
// operations but cos by sin_cos (2 ulp of 1 at most, 2.2e-16 x 2) rather than std::cos; in the
// power law, pow as exp(log(.) / (2 - k)), which moves cos psi by < 1e-19 (tabulated.hpp).
TEST_CASE("A tabulated phase function's inverse CDF in lanes is sample_direction's, to cos's rounding") {
    for (const TabulatedPhase& phase : {petzold_m93(), petzold_m93(PetzoldReading::trapezoid)}) {
        std::vector<double> u = uniforms(8192, 9);
        for (double v : {0.0, 1e-300, 1e-9, 1e-6, 1e-4, 1e-3, 0.01, 0.05, 0.5, 0.999, 1.0 - 1e-9}) u.push_back(v);
        for (std::size_t k = 0; k < 2048; ++k) u.push_back(0.1 * u[k]);  // the forward peak
        while (u.size() % lane_width) u.push_back(0.25);
        double worst = 0;
        for (std::size_t i = 0; i < u.size(); i += lane_width) {
            const Reals mu = phase.cos_psi(lanes_of([&](int l) { return u[i + l]; }));
            for (int l = 0; l < lane_width; ++l)
                worst = std::max(worst, std::abs(mu[l] - phase.sample_direction(u[i + l], 0.5).cos_psi));
        }
        INFO(phase.name() << ": worst " << worst);
        CHECK(worst <= 4.5e-16);
    }
}

// Random linear_p tables, segments narrower than 0.2 rad (the vector root) or up to 180 deg
// wide (lane by lane through sample_direction), nodes at 0 and 180 deg or not, at random
// uniforms and at every node's own u. Both roots stop within 1e-12 of the segment's width of
// the root of their own rounded residual; with FMA contracted differently in the vectors (a
// -march=native build) the residuals differ by rounding, a few ulp of the cumulative
// probability (<= 1), which moves the root by that over the normalised density f = 2 pi p sin
// psi: with the values over six decades f can be small. So the lanes' cos psi lies within
// cos's rounding (4.5e-16) + sin psi (2e-12 x 0.2 + 16 eps / f) of sample_direction's.
TEST_CASE("A random linear-p table's inverse CDF in lanes is sample_direction's, to the root's accuracy") {
    PhotonRng rng(17, 0);
    double worst = 0;
    int vector_tables = 0;
    for (int table = 0; table < 200; ++table) {
        const bool narrow = table % 2 == 0;
        std::vector<double> angle;
        if (narrow) {
            for (double a = rng.uniform() < 0.5 ? 0.0 : 5.0 * rng.uniform(); a < 180.0; a += 0.01 + 11.0 * rng.uniform())
                angle.push_back(a);
            if (rng.uniform() < 0.5) angle.push_back(180.0);
        } else {
            for (int k = 0; k < 2 + static_cast<int>(rng.uniform() * 6); ++k) angle.push_back(180.0 * rng.uniform());
            std::sort(angle.begin(), angle.end());
            angle.erase(std::unique(angle.begin(), angle.end()), angle.end());
            if (angle.size() < 2) continue;
        }
        std::vector<double> value;
        for (std::size_t k = 0; k < angle.size(); ++k) value.push_back(std::pow(10.0, 6.0 * rng.uniform() - 3.0));
        const TabulatedPhase phase(angle, value, TabulatedConvention::linear_p);
        std::vector<double> u;
        for (int k = 0; k < 256; ++k) u.push_back(rng.uniform());
        for (double node : phase.breakpoints()) u.push_back(std::min(phase.cumulative(node), std::nextafter(1.0, 0.0)));
        while (u.size() % lane_width) u.push_back(0.5);
        for (std::size_t i = 0; i < u.size(); i += lane_width) {
            const Reals mu = phase.cos_psi(lanes_of([&](int l) { return u[i + l]; }));
            for (int l = 0; l < lane_width; ++l) {
                const double reference = phase.sample_direction(u[i + l], 0.5).cos_psi;
                const double sin_psi = std::sqrt(std::max(0.0, 1.0 - reference * reference));
                const double f = two_pi * phase.eval(reference) * sin_psi;
                const double eps = std::numeric_limits<double>::epsilon();
                const double bound = 4.5e-16 + sin_psi * (2e-12 * 0.2 + (f > 0.0 ? 16.0 * eps / f : 1.0));
                worst = std::max(worst, std::abs(mu[l] - reference) / bound);
            }
        }
        vector_tables += narrow ? 1 : 0;
    }
    INFO("worst difference / its bound " << worst);
    CHECK(vector_tables == 100);
    CHECK(worst <= 1.0);
}

namespace {
/// The largest |cos psi in float lanes - sample_direction's cos psi at the same u| over the
/// uniforms u (padded to whole vectors).
double worst_float_inverse(const TabulatedPhase& phase, std::vector<float> u) {
    while (u.size() % float_width) u.push_back(0.5f);
    double worst = 0;
    for (std::size_t i = 0; i < u.size(); i += float_width) {
        const Floats mu = phase.cos_psi(Floats(u.data() + i, lanes::stdx::element_aligned));
        for (int l = 0; l < float_width; ++l)
            worst = std::max(worst, std::abs(double(mu[l]) - phase.sample_direction(double(u[i + l]), 0.5).cos_psi));
    }
    return worst;
}
}  // namespace

// Float lanes sample a table from its FloatInverseTable (optics/phase/float_inverse_table.hpp):
// within 2^-23 of the exact inverse at the same u, from its build check (the cubic within 2^-24
// at every cell's middle) and the float evaluation's roundings. Checked at every one of the
// 2^24 uniforms a float lane draws (uniform_float_from_bits) for the canonical Petzold table,
// and for the other readings and a Fournier-Forand table at 2^18 of them; for all, at u = 0
// and 1 and at both ends of every cell (s = u and s = 1 - u on the cells' boundaries).
TEST_CASE("A tabulated phase function's inverse CDF in float lanes is within 2^-23 of sample_direction's") {
    const FournierForandPhase ff = FournierForandPhase::from_backscatter_fraction(0.0183);
    const TabulatedPhase tables[] = {petzold_m93(), petzold_m93(PetzoldReading::trapezoid),
                                     petzold_m93(PetzoldReading::linear), ff.table()};
    for (const TabulatedPhase& phase : tables) {
        const bool exhaustive = &phase == &tables[0];
        INFO(phase.name() << ", the table's error at the cells' middles " << phase.float_inverse().max_error());
        REQUIRE(phase.float_inverse().usable());
        CHECK(phase.float_inverse().max_error() <= FloatInverseTable::error_limit);
        std::vector<float> u = phase.float_inverse().cell_boundaries();
        u.insert(u.end(), {0.0f, 1.0f, 0.5f, std::nextafter(0.5f, 1.0f), std::nextafter(0.5f, 0.0f)});
        PhotonRng rng(23, 0);
        for (std::uint64_t k = 0; k < (exhaustive ? std::uint64_t{1} << 24 : std::uint64_t{1} << 18); ++k)
            u.push_back(uniform_float_from_bits(exhaustive ? static_cast<std::uint32_t>(k << 8) : rng.bits()));
        const double worst = worst_float_inverse(phase, std::move(u));
        INFO("worst " << worst);
        CHECK(worst <= 0x1p-23);
    }
}

// A table whose nodes are too coarse, or too spiky, for the cells (a kink's jump in curvature, a
// density varying by 1e4 between nodes) is refused when built, and its float lanes take the
// double lanes' inverse, rounded to float: within half a float ulp of it (2^-25 at |mu| <= 1;
// the double lanes' own value may differ in its last bits where the compiler contracts
// multiply-adds differently in the two places it is inlined).
TEST_CASE("A table the float lanes' inverse cannot follow is refused, and sampled in double lanes") {
    std::vector<double> spiky_angle, spiky_value;
    for (int i = 0; i <= 200; ++i) {
        spiky_angle.push_back(0.9 * i);
        spiky_value.push_back(i % 2 ? 1e4 : 1.0);
    }
    const TabulatedPhase tables[] = {
        TabulatedPhase({0, 10, 30, 60, 90, 120, 150, 180}, {50, 20, 5, 1, 0.5, 0.4, 0.45, 0.5}, TabulatedConvention::linear_p),
        TabulatedPhase(spiky_angle, spiky_value, TabulatedConvention::trapezoid)};
    for (const TabulatedPhase& phase : tables) {
        INFO("the table's error at the cells' middles " << phase.float_inverse().max_error());
        CHECK(phase.float_inverse().max_error() > FloatInverseTable::error_limit);
        CHECK_FALSE(phase.float_inverse().usable());
        CHECK(phase.float_inverse().memory_bytes() == 0);
        // The uniforms as floats in memory, as the lanes draw them: built in the registers from
        // doubles, GCC 12 (-O2 and above) may carry a lane's double value past its rounding to
        // float into the double lanes' reference.
        std::vector<float> u;
        for (double x : uniforms(4096, 29)) u.push_back(static_cast<float>(x));
        for (std::size_t i = 0; i < u.size(); i += float_width) {
            const Floats mu = phase.cos_psi(Floats(u.data() + i, lanes::stdx::element_aligned));
            for (int g = 0; g < float_width; g += lane_width) {
                const Reals reference = phase.cos_psi(Reals([&](int l) { return double(u[i + g + l]); }));
                for (int l = 0; l < lane_width; ++l) REQUIRE(std::abs(double(mu[g + l]) - reference[l]) <= 0x1p-25 + 1e-15);
            }
        }
    }
}

namespace {
/// The largest |f(x) - reference(x)| of a function in lanes (of V) over x = i / 2^20 in [0, 1].
template <class V = Reals, class F, class Reference>
double worst_on_unit_interval(F f, Reference reference) {
    constexpr int width = static_cast<int>(V::size());
    double worst = 0;
    for (int i = 0; i <= 1 << 20; i += width) {
        const V x = lanes_of<V>([&](int l) { return std::min(1.0, (i + l) / double(1 << 20)); });
        const V y = f(x);
        for (int l = 0; l < width; ++l) worst = std::max(worst, std::abs(double(y[l]) - reference(double(x[l]))));
    }
    return worst;
}
}  // namespace

// encode_theta in lanes trusts its guess 1e-4 bin (1.2e-6 rad) from a boundary: require a
// tenth of that. (A&S give 2e-8 rad for 4.4.46; with its 10-digit coefficients this grid
// measured 2.2e-8.)
TEST_CASE("acos_unit is within 1.2e-7 rad of acos (Abramowitz and Stegun 4.4.46)") {
    CHECK(worst_on_unit_interval([](const Reals& x) { return detail::acos_unit(x); },
                                 [](double x) { return std::acos(x); }) < 1.2e-7);
}

// encode_phi in lanes trusts its guess 1e-6 bin (2.45e-8 rad) from a boundary: require a
// tenth of that of atan_unit (its fit's error is 2.8e-9 in atan(sqrt t)/sqrt t, at most that
// in atan r; this grid measured 1.5e-9).
TEST_CASE("atan_unit is within 2.4e-9 rad of atan on [0, 1]") {
    CHECK(worst_on_unit_interval([](const Reals& r) { return detail::atan_unit(r); },
                                 [](double r) { return std::atan(r); }) < 2.4e-9);
}

// In float lanes the guesses are trusted 1e-3 bin from a boundary (1.2e-5 rad for theta,
// 2.45e-5 rad for phi): require a tenth of that, float rounding included.
TEST_CASE("acos_unit and atan_unit in float lanes are within a tenth of their margins") {
    CHECK(worst_on_unit_interval<Floats>([](const Floats& x) { return detail::acos_unit(x); },
                                         [](double x) { return std::acos(x); }) < 1.2e-6);
    CHECK(worst_on_unit_interval<Floats>([](const Floats& r) { return detail::atan_unit(r); },
                                         [](double r) { return std::atan(r); }) < 2.4e-6);
}

TEMPLATE_TEST_CASE("CompactRecords made in lanes equal CompactRecord::make byte for byte, the kept lanes in order",
                   "", double, float) {
    using V = lanes::LanesOf<TestType>;
    constexpr int lane_width = lanes::width_of<TestType>;
    const auto u = uniforms(3 * 8192, 3);
    std::vector<vec3> dirs;
    for (std::size_t i = 0; i + 1 < u.size(); i += 2) dirs.push_back(direction_of(u[i], u[i + 1]));
    // Poles (atan2's choices at dx = +-0), axes, and polar directions on the theta boundaries.
    for (double z : {1.0, -1.0})
        for (double x : {0.0, -0.0}) dirs.push_back({x, 0.0, z});
    for (const vec3& d : {vec3(1, 0, 0), vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, -1, 0)}) dirs.push_back(d);
    const auto& edges = detail::direction_encode_tables().theta_edge;
    // And polar directions just either side of them (dz offsets of 1e-12 to 3e-5: angles from
    // below the guess's error to beyond the 1e-4 bin (doubles) or 1e-3 bin (floats) where the
    // lanes stop correcting it).
    for (int k = 1; k < 256; ++k)
        for (double offset : {0.0, 1e-12, -1e-12, 1e-8, -1e-8, 1e-6, -1e-6, 3e-6, -3e-6, 3e-5, -3e-5}) {
            const double z = std::clamp(edges[k] + offset, -1.0, 1.0);
            dirs.push_back({std::sqrt(1.0 - z * z), 0.0, z});
        }
    while (dirs.size() % lane_width) dirs.push_back({0.0, 0.0, 1.0});

    std::size_t differing = 0;
    for (std::size_t i = 0; i < dirs.size(); i += lane_width) {
        auto component = [&](auto member) { return lanes_of<V>([&](int l) { return dirs[i + l].*member; }); };
        const Vec3Of<V> d{component(&vec3::x), component(&vec3::y), component(&vec3::z)};
        const Vec3Of<V> p{lanes_of<V>([&](int l) { return u[i + l]; }), lanes_of<V>([&](int l) { return 0.5 * u[i + l]; }),
                          lanes_of<V>([&](int l) { return 30.0 * u[i + l]; })};
        std::uint8_t batch[lane_width];
        for (int l = 0; l < lane_width; ++l) batch[l] = static_cast<std::uint8_t>((i + l) % 64);
        // Every keep pattern in turn (all lanes kept every 2^width groups), band 3.
        const unsigned keep = static_cast<unsigned>(i / lane_width) % (1u << lane_width);
        CompactRecord made[lane_width];
        const std::size_t kept = LaneRecords<CompactRecord>::make_kept(p, d, band_index{3}, batch, keep, made);
        std::size_t n = 0;
        for (int l = 0; l < lane_width; ++l) {
            if (!((keep >> l) & 1u)) continue;
            const CompactRecord ref = CompactRecord::make({p.x[l], p.y[l], p.z[l]}, {d.x[l], d.y[l], d.z[l]},
                                                          band_index{3}, batch[l]);
            differing += n >= kept || std::memcmp(&ref, &made[n], sizeof ref) != 0;
            ++n;
        }
        differing += n != kept;
    }
    CHECK(differing == 0);
}

namespace {
/// record_lanes against record() lane by lane, without absorption along the flights (a = 0:
/// NoAbsorption) or with LaneAbsorption's decay (a > 0). Detectors at the surface, in the water
/// and on a bottom plane; flights up, down, level, and parked lanes that must not count.
/// Doubles without absorption: the same operations on the same numbers, so the same sums; with
/// it, lanes::exp (exp_table's arithmetic, within 2 ulp of the exact value) against std::exp
/// (within 1): each score within 8 units of roundoff u = 2^-53. Floats: record() of the same
/// (float) flights in doubles; a crossing is counted alike unless a flight ends within rounding
/// of a plane (none among these flights); the scores w and w / |mu| differ by the float
/// division's rounding (u = 2^-24 relative each), and with absorption the transmittance by
/// (3 a s + 8) u (s = (d - z0) / uz and a s round once each, lanes::exp within 4 float ulp)
/// and by a |d_float - d| / |uz| where the float lanes' plane lies elsewhere: on the bottom, the
/// next float shallower than the floor.
/// `water`: record()'s absorber, `decay` the lanes' (LaneAbsorption or LaneMediumAbsorption);
/// a: the water's largest absorption coefficient (0: none, the flights' weights do not decay).
template <class T, class Water, class LaneDecay>
double worst_record_lanes_excess(const Water& water, double a, const LaneDecay& decay) {
    using V = lanes::LanesOf<T>;
    constexpr int lane_width = lanes::width_of<T>;
    constexpr bool floats = std::is_same_v<T, float>;
    constexpr double floor = 6.0;
    const IrradiancePlanes layers({0.0, 1.0, 2.5, floor}, 0.05, floor);
    const auto u = uniforms(5 * 2048, 5);
    double worst = 0;
    for (std::size_t i = 0; i + 5 * lane_width <= u.size(); i += 5 * lane_width) {
        auto at = [&](int k, int l) { return u[i + k * lane_width + l]; };
        const V z0 = lanes_of<V>([&](int l) { return 7.0 * at(0, l) - 0.5 * (l == 0); });
        const V uz = lanes_of<V>([&](int l) { return l == 1 ? 0.0 : 2.0 * at(1, l) - 1.0; });
        const V s = lanes_of<V>([&](int l) { return 3.0 * at(2, l); });
        const V w = lanes_of<V>([&](int l) { return at(3, l); });
        const V z1 = z0 + uz * s;
        const auto active = lanes_of<V>([&](int l) { return at(4, l); }) < T(0.9);
        std::vector<std::array<V, 4>> lane_tally(layers.size(), {V(T(0)), V(T(0)), V(T(0)), V(T(0))});
        if (a == 0.0) layers.record_lanes(z0, z1, uz, s, w, active, lane_tally.data());
        else layers.record_lanes(z0, z1, uz, s, w, active, lane_tally.data(), decay);
        for (int l = 0; l < lane_width; ++l) {
            std::vector<IrradianceTally> ref(layers.size(), IrradianceTally{});
            if (active[l]) layers.record(Flight{z0[l], z1[l], uz[l], s[l], w[l]}, water, ref.data());
            for (std::size_t d = 0; d < layers.size(); ++d) {
                const double depth = layers.depths()[d], mu = std::abs(uz[l]);
                const double to_plane = mu == 0.0 ? 0.0 : std::abs(depth - z0[l]) / mu;
                const double shift = floats && depth == floor ? depth - std::nextafter(float(depth), 0.0f) : 0.0;
                const double unit = floats ? float_unit : 0x1p-53;
                const double units = floats ? 3 + (a > 0.0 ? 3 * a * to_plane + 8 + a * shift / mu / unit : 0.0)
                                            : (a > 0.0 ? 8 : 0.0);
                for (int k = 0; k < 4; ++k)
                    worst = std::max(worst, std::abs(lane_tally[d][k][l] - ref[d][k]) - units * unit * std::abs(ref[d][k]));
            }
        }
    }
    return worst;
}

/// The same in homogeneous water of absorption a.
template <class T>
double worst_record_lanes_excess(double a) {
    const HomogeneousWater<HenyeyGreensteinPhase> water(a, 1.0, HenyeyGreensteinPhase(0.9));
    return worst_record_lanes_excess<T>(water, a, LaneAbsorption<T>{T(a)});
}

/// Water whose absorption changes with depth (linear between nodes, a jump at 2 m, constant
/// below 3 m), up to 2 /m: the flights' decay through the medium's optical path.
StratifiedWater<HenyeyGreensteinPhase> absorbing_layers() {
    DepthProfile p;
    p.depth = {0.0, 1.0, 2.0, 2.0, 3.0};
    p.absorption = {0.1, 2.0, 0.5, 1.5, 0.3};
    p.scattering = {{1.0, 1.0, 1.0, 1.0, 1.0}};
    return {p, {HenyeyGreensteinPhase(0.9)}};
}
}  // namespace

TEMPLATE_TEST_CASE("record_lanes tallies what record() tallies, lane by lane", "", double, float) {
    CHECK(worst_record_lanes_excess<TestType>(0.0) <= 0.0);
    CHECK(worst_record_lanes_excess<TestType>(0.3) <= 0.0);
    CHECK(worst_record_lanes_excess<TestType>(2.0) <= 0.0);
    const auto layers = absorbing_layers();
    CHECK(worst_record_lanes_excess<TestType>(layers, 2.0, LaneMediumAbsorption<decltype(layers), TestType>{layers}) <= 0.0);
}

namespace {
template <template <class...> class Tracer, class Phase>
TransportResult<CompactRecord> trace(const Phase& phase, TransportSettings s, Bottom bottom) {
    const auto medium = HomogeneousWater<Phase>::from_albedo(1.0, 0.8, phase);
    const Slab slab(1.0, bottom, 30.0);
    return Tracer<HomogeneousWater<Phase>, CompactRecord>(medium, slab, FlatSurface(1.34), CollimatedSun(30.0), s).run();
}

/// Stored events per map photon, per batch (CompactRecord labels each record's batch).
Estimate events_per_photon(const TransportResult<CompactRecord>& r) {
    std::vector<double> per_batch(r.batches, 0.0);
    for (const auto& rec : r.records) per_batch[rec.batch()] += 1.0;
    for (unsigned b = 0; b < r.batches; ++b) {
        const double lo = static_cast<double>(r.map_photons * b / r.batches);
        const double hi = static_cast<double>(r.map_photons * (b + 1) / r.batches);
        per_batch[b] /= hi - lo;
    }
    return batch_estimate(per_batch);
}

}  // namespace

namespace {
/// How closely a lane tracer's ledger (ledger.hpp) must close with weighted photons: every
/// change of the total weight is booked where it is made (absorption, roulette, backscatter
/// bias; a split by depth importance keeps it), so to rounding: 1e-9 of the incident weight
/// in double lanes, as PhotonTracer's; in float lanes the weights are floats and each lane's
/// absorbed weight is summed in float over at most 64 steps before it joins a double (a
/// relative 64 x 2^-24 = 3.8e-6 at most): 1e-5.
template <template <class...> class Tracer>
constexpr double ledger_bound() {
    using T = Tracer<HomogeneousWater<HenyeyGreensteinPhase>, CompactRecord>;
    return std::same_as<typename T::real_type, float> ? 1e-5 : 1e-9;
}

/// `Tracer` against PhotonTracer: every absorption mode, a Lambertian bottom, Fresnel surface,
/// roulette, a truncation by scattering order, and tabulated phase functions (Petzold, and
/// Fournier-Forand through its table).
template <template <class...> class Tracer>
void check_agrees_with_photon_tracer() {
    struct Case {
        AbsorptionMode mode;
        unsigned max_order;
    };
    for (const Case c : {Case{AbsorptionMode::analog, 0}, Case{AbsorptionMode::implicit_capture, 0},
                         Case{AbsorptionMode::continuous, 0}, Case{AbsorptionMode::analog, 3}}) {
        TransportSettings s;
        s.photons = s.map_photons = 60000;
        s.depths = {0.0, 1.0, 3.0, 6.0};
        s.absorption = c.mode;
        s.max_order = c.max_order;
        const Bottom bottom = Bottom::lambertian_at(6.0, 0.5);
        const auto a = trace<PhotonTracer>(HenyeyGreensteinPhase(0.85), s, bottom);
        const auto b = trace<Tracer>(HenyeyGreensteinPhase(0.85), s, bottom);
        INFO("absorption mode " << static_cast<int>(c.mode) << ", max order " << c.max_order);
        for (std::size_t i = 0; i < s.depths.size(); ++i)
            for (int k = 0; k < 4; ++k) testing::check_agree(a.irradiance[i][k], b.irradiance[i][k], "irradiance");
        testing::check_agree(a.bottom_ed, b.bottom_ed, "Ed at the bottom");
        testing::check_agree(events_per_photon(a), events_per_photon(b), "stored events per photon");
        CHECK(b.ledger.incident == 1.0);
        CHECK(std::abs(b.ledger.imbalance()) < (c.mode == AbsorptionMode::analog ? 1e-12 : ledger_bound<Tracer>()));
        if (c.max_order) CHECK(b.ledger.truncated > 0.01);
    }
    TransportSettings s;
    s.photons = s.map_photons = 40000;
    s.depths = {1.0, 4.0};
    s.absorption = AbsorptionMode::implicit_capture;
    const auto a = trace<PhotonTracer>(petzold_m93(), s, Bottom{});
    const auto b = trace<Tracer>(petzold_m93(), s, Bottom{});
    for (std::size_t i = 0; i < s.depths.size(); ++i)
        for (int k = 0; k < 4; ++k) testing::check_agree(a.irradiance[i][k], b.irradiance[i][k], "Petzold irradiance");
    testing::check_agree(events_per_photon(a), events_per_photon(b), "Petzold stored events per photon");
    const auto ff = FournierForandPhase::from_backscatter_fraction(0.01);
    static_assert(LaneSampled<FournierForandPhase, lanes::Reals> && LaneSampled<FournierForandPhase, lanes::Floats>);
    const auto c = trace<PhotonTracer>(ff, s, Bottom{});
    const auto d = trace<Tracer>(ff, s, Bottom{});
    for (std::size_t i = 0; i < s.depths.size(); ++i)
        for (int k = 0; k < 4; ++k) testing::check_agree(c.irradiance[i][k], d.irradiance[i][k], "Fournier-Forand irradiance");
    testing::check_agree(events_per_photon(c), events_per_photon(d), "Fournier-Forand stored events per photon");
}

/// `Tracer` against PhotonTracer under a wind-blown surface with a grazing sun and a uniform sky
/// (the surface's hits and the launches go through PhotonTracer's per-photon functions lane by
/// lane).
template <template <class...> class Tracer>
void check_agrees_under_a_wind_blown_surface() {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto medium = Water::from_albedo(1.0, 0.8, HenyeyGreensteinPhase(0.85));
    const Slab slab(1.0, Bottom::lambertian_at(6.0, 0.5), 30.0);
    TransportSettings s;
    s.photons = s.map_photons = 60000;
    s.depths = {0.0, 1.0, 3.0};
    const WindBlownSurface surface(0.04);
    const CollimatedSun sun(80.0);
    const UniformSky sky(0.1);
    const auto a = PhotonTracer<Water, CompactRecord, WindBlownSurface>(medium, slab, surface, sun, s, sky).run();
    const auto b = Tracer<Water, CompactRecord, WindBlownSurface>(medium, slab, surface, sun, s, sky).run();
    for (std::size_t i = 0; i < s.depths.size(); ++i)
        for (int k = 0; k < 4; ++k) testing::check_agree(a.irradiance[i][k], b.irradiance[i][k], "irradiance");
    testing::check_agree(events_per_photon(a), events_per_photon(b), "stored events per photon");
}

template <template <class...> class Tracer>
void check_same_for_1_and_2_threads() {
    testing::require_same_for_1_and_2_threads(AbsorptionMode::implicit_capture, [](const TransportSettings& s) {
        return trace<Tracer>(HenyeyGreensteinPhase(0.9), s, Bottom::lambertian_at(8.0, 0.3));
    });
}
}  // namespace

TEST_CASE("LaneTracer and PhotonTracer agree within their standard errors") {
    check_agrees_with_photon_tracer<LaneTracer>();
}

TEST_CASE("LaneTracer in float lanes and PhotonTracer agree within their standard errors") {
    check_agrees_with_photon_tracer<FloatLaneTracer>();
}

/// LaneTracer in double lanes with PhotonTracer's three parameters (medium, record, surface).
template <class M, class Record, class Surface>
using DoubleLaneTracer = LaneTracer<M, Record, double, Surface>;

TEST_CASE("LaneTracer and PhotonTracer agree under a wind-blown surface and a sky, in double and float lanes") {
    check_agrees_under_a_wind_blown_surface<DoubleLaneTracer>();
    check_agrees_under_a_wind_blown_surface<FloatLaneTracer>();
}

TEST_CASE("LaneTracer's surface detector counts every photon that reaches the surface from below") {
    testing::check_surface_plane_counts_every_crossing<DoubleLaneTracer>(1e-12);
}

// In float lanes the weights are rounded to float between events (u relative each time) and
// the tallies summed in float over at most flush_steps = 64 steps per lane: each of Ed(0),
// Eu(0) and the ledger's flux is then within 65 u of its exact sum.
TEST_CASE("LaneTracer's surface detector in float lanes counts every photon that reaches the surface from below") {
    testing::check_surface_plane_counts_every_crossing<FloatLaneTracer>(65 * float_unit);
}

TEST_CASE("LaneTracer's bottom detector counts every photon that reaches the bottom") {
    testing::check_bottom_plane_counts_every_arrival<LaneTracer>(1e-10);
}

TEST_CASE("LaneTracer's bottom detector in float lanes counts every photon that reaches the bottom") {
    testing::check_bottom_plane_counts_every_arrival<FloatLaneTracer>(65 * float_unit);
}

TEST_CASE("LaneTracer is bit-identical for 1 and 2 threads", "[threads]") {
    check_same_for_1_and_2_threads<LaneTracer>();
}

TEST_CASE("LaneTracer in float lanes is bit-identical for 1 and 2 threads", "[threads]") {
    check_same_for_1_and_2_threads<FloatLaneTracer>();
}

namespace {
/// The irradiances of run `b` against those of run `a` (PhotonTracer's, or the same tracer
/// without a variance reduction) at every detector, within their combined standard errors.
void check_irradiances_agree(const TransportResult<CompactRecord>& a, const TransportResult<CompactRecord>& b,
                             const std::vector<double>& depths, const std::string& what) {
    for (std::size_t i = 0; i < depths.size(); ++i)
        for (int k = 0; k < 4; ++k) {
            INFO("depth " << depths[i] << ", quantity " << k);
            testing::check_agree(a.irradiance[i][k], b.irradiance[i][k], "irradiance, against " + what);
        }
}

/// Stored flux per map photon, per batch: each record carries Phi / I(z) at its stored depth
/// (record_importance, transport/record_flux.hpp), so that with depth importance the sum is
/// the events per photon without it.
Estimate stored_flux_per_photon(const TransportResult<CompactRecord>& r, const ImportanceLevels& levels) {
    std::vector<double> per_batch(r.batches, 0.0);
    for (const auto& rec : r.records) per_batch[rec.batch()] += 1.0 / levels.factor(rec.position().z);
    for (unsigned b = 0; b < r.batches; ++b)
        per_batch[b] /= static_cast<double>(r.map_photons * (b + 1) / r.batches - r.map_photons * b / r.batches);
    return batch_estimate(per_batch);
}

/// `Tracer` with depth importance against PhotonTracer with the same, and against itself
/// without: the irradiances (above, at and below z_max, where photons are rouletted again),
/// Ed at the bottom, the records per photon (I(z) times more at depth) and their flux, the
/// ledger; with implicit capture and continuous absorption, HG and Petzold (sampled in the
/// vectors and lane by lane).
template <template <class...> class Tracer, class Phase>
void check_depth_importance_agrees(const Phase& phase, AbsorptionMode mode) {
    TransportSettings s;
    s.photons = s.map_photons = 40000;
    s.depths = {0.0, 2.0, 5.0, 8.0, 12.0};
    s.absorption = mode;
    s.importance = {0.7, 8.0};  // levels every 0.7 ln 2 / a = 2.4 m down to 8 m, then falling
    const Bottom bottom = Bottom::lambertian_at(14.0, 0.3);
    const auto a = trace<PhotonTracer>(phase, s, bottom);
    const auto b = trace<Tracer>(phase, s, bottom);
    TransportSettings plain = s;
    plain.importance = {};
    const auto c = trace<Tracer>(phase, plain, bottom);
    const auto medium = HomogeneousWater<Phase>::from_albedo(1.0, 0.8, phase);
    const ImportanceLevels levels(s.importance, medium);
    REQUIRE(levels.level(8.0) == 3);
    check_irradiances_agree(a, b, s.depths, "PhotonTracer");
    check_irradiances_agree(c, b, s.depths, "no importance");
    testing::check_agree(a.bottom_ed, b.bottom_ed, "Ed at the bottom");
    testing::check_agree(events_per_photon(a), events_per_photon(b), "stored events per photon");
    testing::check_agree(events_per_photon(c), stored_flux_per_photon(b, levels), "stored flux per photon");
    // Depth importance stores more records at depth: between 5 and 8 m, I = 4 and 8.
    const auto deep = [](const TransportResult<CompactRecord>& r) {
        return std::count_if(r.records.begin(), r.records.end(), [](const CompactRecord& q) { return q.z > 5.0 && q.z < 8.0; });
    };
    CHECK(deep(b) > 3 * deep(c));
    CHECK(b.ledger.incident == 1.0);
    CHECK(std::abs(b.ledger.imbalance()) < ledger_bound<Tracer>());
    // Photons rising through the levels meet roulette (PhotonTracer's change_level, lane by
    // lane): far more weight ends there than the low-weight roulette alone takes (about 6 times
    // in these cases; the same without the level changes).
    CHECK(b.ledger.roulette_killed > 3.0 * c.ledger.roulette_killed);
}
}  // namespace

TEST_CASE("LaneTracer with depth importance agrees with PhotonTracer's and with none") {
    check_depth_importance_agrees<LaneTracer>(HenyeyGreensteinPhase(0.85), AbsorptionMode::implicit_capture);
    check_depth_importance_agrees<LaneTracer>(HenyeyGreensteinPhase(0.85), AbsorptionMode::continuous);
    check_depth_importance_agrees<LaneTracer>(petzold_m93(), AbsorptionMode::continuous);
}

TEST_CASE("LaneTracer in float lanes with depth importance agrees with PhotonTracer's and with none") {
    check_depth_importance_agrees<FloatLaneTracer>(HenyeyGreensteinPhase(0.85), AbsorptionMode::implicit_capture);
    check_depth_importance_agrees<FloatLaneTracer>(HenyeyGreensteinPhase(0.85), AbsorptionMode::continuous);
    check_depth_importance_agrees<FloatLaneTracer>(petzold_m93(), AbsorptionMode::continuous);
}

TEST_CASE("LaneTracer with depth importance is bit-identical for 1 and 2 threads, in double and float lanes", "[threads]") {
    testing::require_same_for_1_and_2_threads(AbsorptionMode::implicit_capture, [](const TransportSettings& given) {
        TransportSettings s = given;
        s.importance = {0.5, 6.0};
        return trace<LaneTracer>(HenyeyGreensteinPhase(0.9), s, Bottom::lambertian_at(8.0, 0.3));
    });
    testing::require_same_for_1_and_2_threads(AbsorptionMode::implicit_capture, [](const TransportSettings& given) {
        TransportSettings s = given;
        s.importance = {0.5, 6.0};
        return trace<FloatLaneTracer>(HenyeyGreensteinPhase(0.9), s, Bottom::lambertian_at(8.0, 0.3));
    });
}

namespace {
/// `Tracer` with backscatter bias (importance.hpp) against PhotonTracer with the same, and
/// against itself without: the irradiances (Eu and Eou at depth are what the bias is for),
/// Ed at the bottom, the records per photon (a record per unit of weight: the forward draws'
/// weights above 1 store further copies), the ledger (the weights' changes booked); with and
/// without depth importance.
template <template <class...> class Tracer>
void check_backscatter_bias_agrees(bool with_importance) {
    TransportSettings s;
    s.photons = s.map_photons = 40000;
    s.depths = {0.0, 2.0, 5.0, 8.0};
    s.backscatter_bias = 0.3;
    if (with_importance) s.importance = {0.7, 8.0};
    const Bottom bottom = Bottom::lambertian_at(10.0, 0.3);
    const TabulatedPhase petzold = petzold_m93();
    const auto a = trace<PhotonTracer>(petzold, s, bottom);
    const auto b = trace<Tracer>(petzold, s, bottom);
    TransportSettings plain = s;
    plain.backscatter_bias = 0.0;
    const auto c = trace<Tracer>(petzold, plain, bottom);
    INFO("depth importance " << with_importance);
    check_irradiances_agree(a, b, s.depths, "PhotonTracer");
    check_irradiances_agree(c, b, s.depths, "no bias");
    testing::check_agree(a.bottom_ed, b.bottom_ed, "Ed at the bottom");
    testing::check_agree(events_per_photon(a), events_per_photon(b), "stored events per photon, against PhotonTracer");
    testing::check_agree(events_per_photon(c), events_per_photon(b), "stored events per photon, against no bias");
    CHECK(b.ledger.incident == 1.0);
    CHECK(std::abs(b.ledger.imbalance()) < ledger_bound<Tracer>());
    // The forward draws' factor 1 / (1 - eps) adds weight at most events (booked as gained).
    CHECK(b.ledger.roulette_gained > 10.0 * c.ledger.roulette_gained + 0.1);
}
}  // namespace

TEST_CASE("LaneTracer with backscatter bias agrees with PhotonTracer's and with none, in double and float lanes") {
    for (bool with_importance : {false, true}) {
        check_backscatter_bias_agrees<LaneTracer>(with_importance);
        check_backscatter_bias_agrees<FloatLaneTracer>(with_importance);
    }
}

TEMPLATE_TEST_CASE("Backscatter bias draws in lanes what it draws for one value", "", double, float) {
    using V = lanes::LanesOf<TestType>;
    const TabulatedPhase petzold = petzold_m93();
    const auto [begin, end] = petzold.backward_uniforms();
    const BackscatterBiasOf<TestType> bias(0.2, begin, end);
    const auto u = uniforms(4096, 13);
    for (std::size_t i = 0; i + V::size() <= u.size(); i += V::size()) {
        const V v = lanes_of<V>([&](int l) { return u[i + l]; });
        const auto d = bias.draw(v);
        for (std::size_t l = 0; l < V::size(); ++l) {
            const auto one = bias.draw(static_cast<TestType>(v[l]));
            REQUIRE(d.u[l] == one.u);
            REQUIRE(d.weight[l] == one.weight);
        }
    }
}

TEST_CASE("LaneTracer with backscatter bias is bit-identical for 1 and 2 threads, in double and float lanes", "[threads]") {
    const auto with_bias = [](const TransportSettings& given) {
        TransportSettings s = given;
        s.backscatter_bias = 0.2;
        return s;
    };
    testing::require_same_for_1_and_2_threads(AbsorptionMode::implicit_capture, [&](const TransportSettings& s) {
        return trace<LaneTracer>(petzold_m93(), with_bias(s), Bottom::lambertian_at(8.0, 0.3));
    });
    testing::require_same_for_1_and_2_threads(AbsorptionMode::implicit_capture, [&](const TransportSettings& s) {
        return trace<FloatLaneTracer>(petzold_m93(), with_bias(s), Bottom::lambertian_at(8.0, 0.3));
    });
}

namespace {
/// Problem 3's kind of water (canonical_problems.md): a Rayleigh component (the water's) and a
/// particle component whose scattering, with the absorption, peaks at depth, and a jump at 6 m
/// (two layers of different water).
using LayeredWater = StratifiedWater<RayleighPhase, HenyeyGreensteinPhase>;
LayeredWater layered_water() {
    DepthProfile p;
    p.depth = {0.0, 2.0, 4.0, 6.0, 6.0, 10.0};
    p.absorption = {0.1, 0.4, 0.2, 0.2, 0.6, 0.3};
    p.scattering = {{0.3, 0.3, 0.3, 0.3, 0.3, 0.3}, {0.5, 2.0, 1.0, 1.0, 0.2, 0.8}};
    return {p, {RayleighPhase{}, HenyeyGreensteinPhase(0.85)}};
}

/// `Tracer` against PhotonTracer in depth-varying water (free paths through the medium's optical
/// depth, the albedo at each event's depth, the two phase functions mixed by depth, and with
/// continuous absorption the decay along flights and to the detectors' planes), in every
/// absorption mode and with depth importance, over a Lambertian bottom below the jump.
template <template <class...> class Tracer>
void check_agrees_in_stratified_water() {
    const LayeredWater water = layered_water();
    const Slab slab(1.0, Bottom::lambertian_at(12.0, 0.3), 30.0);
    struct Case {
        AbsorptionMode mode;
        bool importance;
    };
    for (const Case c : {Case{AbsorptionMode::analog, false}, Case{AbsorptionMode::implicit_capture, false},
                         Case{AbsorptionMode::continuous, false}, Case{AbsorptionMode::continuous, true}}) {
        TransportSettings s;
        s.photons = s.map_photons = 40000;
        s.depths = {0.0, 1.0, 3.0, 6.0, 9.0, 12.0};
        s.absorption = c.mode;
        if (c.importance) s.importance = {0.7, 9.0};
        INFO("absorption mode " << static_cast<int>(c.mode) << (c.importance ? ", depth importance" : ""));
        const auto a = PhotonTracer<LayeredWater, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s).run();
        const auto b = Tracer<LayeredWater, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s).run();
        check_irradiances_agree(a, b, s.depths, "PhotonTracer");
        testing::check_agree(a.bottom_ed, b.bottom_ed, "Ed at the bottom");
        testing::check_agree(events_per_photon(a), events_per_photon(b), "stored events per photon");
        CHECK(b.ledger.incident == 1.0);
        CHECK(std::abs(b.ledger.imbalance()) < (c.mode == AbsorptionMode::analog ? 1e-12 : ledger_bound<Tracer>()));
    }
}
}  // namespace

TEST_CASE("LaneTracer and PhotonTracer agree in stratified water, in double and float lanes") {
    check_agrees_in_stratified_water<LaneTracer>();
    check_agrees_in_stratified_water<FloatLaneTracer>();
}

TEST_CASE("LaneTracer rejects depth importance with analog photons by name") {
    TransportSettings s;
    s.photons = 100;
    s.importance.cosine = 0.5;
    s.importance.max_depth = 5.0;
    s.absorption = AbsorptionMode::analog;
    const auto medium = HomogeneousWater<HenyeyGreensteinPhase>::from_albedo(1.0, 0.8, HenyeyGreensteinPhase(0.8));
    const auto make = [&] {
        return LaneTracer<HomogeneousWater<HenyeyGreensteinPhase>, CompactRecord>(
            medium, Slab(1.0, Bottom{}, 10.0), FlatSurface(1.34), CollimatedSun(0.0), s);
    };
    CHECK_THROWS_WITH(make(), Catch::Contains("depth importance") && Catch::Contains("analog"));
}
#endif
