// The bottom as a policy (scene/bottom.hpp, scene/minnaert_bottom.hpp): the models' own
// contracts against exact answers (reflectance = the BRDF's hemispherical integral, the
// sampled directions' inverse CDF, k = 1 = Lambertian), and the first pass over a model that
// is not the default: bit-identical to the default for the same BRDF, and, over an index-
// matched surface in non-scattering water, Eu/Ed on the bottom = rho(mu_sun) exactly.
#include <catch2/catch.hpp>

#include "secchi/map/photon_map.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/minnaert_bottom.hpp"
#include "secchi/transport/lane_tracer.hpp"
#include "secchi/transport/tracer.hpp"
#include "transport_checks.hpp"
#include <cmath>
#include <random>
#include <type_traits>

using namespace secchi;

static_assert(IrradianceBottom<Bottom>);
static_assert(BottomModel<MinnaertBottom> && !IrradianceBottom<MinnaertBottom>);
// The second pass reads the bottom's radiance from Ed: a slab of another model makes no map.
static_assert(!std::is_convertible_v<BasicSlab<MinnaertBottom>, Slab>);
static_assert(FirstPassTracer<PhotonTracer<HomogeneousWater<IsotropicPhase>, CompactRecord, FlatSurface, SunAndSky,
                                           IrradiancePlanes, MinnaertBottom>>);

TEST_CASE("Bottom: no bottom, transparent, Lambertian; bad parameters are refused by name") {
    const Bottom none;
    CHECK(std::isinf(none.depth()));
    CHECK(none.transmits());
    const Bottom clear = Bottom::transparent_at(3.0);
    CHECK(clear.depth() == 3.0);
    CHECK(clear.transmits());
    CHECK(clear.radiance_per_irradiance() == 0.0);
    const Bottom sand = Bottom::lambertian_at(4.0, 0.3);
    CHECK_FALSE(sand.transmits());
    CHECK(sand.reflectance(vec3(0.6, 0.0, 0.8)) == 0.3);
    CHECK(sand.radiance_per_irradiance() == Approx(0.3 / std::numbers::pi).epsilon(1e-15));
    CHECK_THROWS_WITH(Bottom::lambertian_at(4.0, 1.2), Catch::Contains("bottom albedo") && Catch::Contains("1.2"));
    CHECK_THROWS_WITH(Bottom::lambertian_at(4.0, NAN), Catch::Contains("bottom albedo"));
    CHECK_THROWS_WITH(Bottom::transparent_at(0.0), Catch::Contains("bottom depth"));
    CHECK_THROWS_WITH(Bottom::transparent_at(INFINITY), Catch::Contains("bottom depth"));
    CHECK_THROWS_WITH(MinnaertBottom(5.0, 0.5, 0.7), Catch::Contains("Minnaert exponent k") && Catch::Contains("0.7"));
    CHECK_THROWS_WITH(MinnaertBottom(5.0, -0.1, 2.0), Catch::Contains("Minnaert normal reflectance"));
    CHECK_THROWS_WITH(MinnaertBottom(-5.0, 0.5, 2.0), Catch::Contains("bottom depth"));
    CHECK_THROWS_WITH(Slab(1.0, Bottom{}, 0.0), Catch::Contains("escape depth"));
}

TEST_CASE("Minnaert: reflectance is the BRDF's hemispherical integral; directions follow mu^k") {
    std::mt19937_64 gen(11);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    for (int trial = 0; trial < 200; ++trial) {
        const double a0 = uni(gen), k = 1.0 + 4.0 * uni(gen), mu_in = 0.02 + 0.98 * uni(gen);
        const MinnaertBottom b(2.0, a0, k);
        const vec3 in(std::sqrt(1.0 - mu_in * mu_in), 0.0, mu_in);
        // rho = 2 pi int_0^1 f_r(mu_in, mu) mu dmu (the BRDF does not depend on azimuth),
        // Simpson's rule on 2000 intervals of mu.
        const int n = 2000;
        auto f = [&](double mu) { return b.brdf(in, vec3(std::sqrt(1.0 - mu * mu), 0.0, -mu)) * mu; };
        double sum = f(0.0) + f(1.0);
        for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(static_cast<double>(i) / n);
        INFO("A0 " << a0 << " k " << k << " mu_in " << mu_in);
        CHECK(b.reflectance(in) == Approx(two_pi * sum / (3.0 * n)).epsilon(1e-6));
        CHECK(b.reflectance(in) <= a0);
        // Reciprocity: f_r(in, out) = f_r(out reversed, in reversed).
        const vec3 out = b.reflected_direction(in, uni(gen), uni(gen));
        CHECK(b.brdf(in, out) == Approx(b.brdf(-out, -in)).epsilon(1e-14));
        // The inverse CDF: P(mu_out < mu) = mu^(k + 1), so mu_out(u)^(k + 1) = u.
        const double u1 = uni(gen), u2 = uni(gen);
        const vec3 d = b.reflected_direction(in, u1, u2);
        CHECK(d.z <= 0.0);
        CHECK(glm::length(d) == Approx(1.0).epsilon(1e-14));
        CHECK(std::pow(-d.z, k + 1.0) == Approx(u1).margin(1e-13));
        CHECK(std::atan2(d.y, d.x) == Approx(std::remainder(two_pi * u2, two_pi)).margin(1e-9));
    }
}

TEST_CASE("Minnaert with k = 1 is the Lambertian bottom, draw for draw") {
    std::mt19937_64 gen(12);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    const MinnaertBottom m(2.0, 0.4, 1.0);
    const Bottom l = Bottom::lambertian_at(2.0, 0.4);
    for (int i = 0; i < 1000; ++i) {
        const double mu = uni(gen), u1 = uni(gen), u2 = uni(gen);
        const vec3 in(std::sqrt(1.0 - mu * mu), 0.0, mu);
        REQUIRE(m.reflectance(in) == l.reflectance(in));
        const vec3 a = m.reflected_direction(in, u1, u2), b = l.reflected_direction(in, u1, u2);
        REQUIRE((a.x == b.x && a.y == b.y && a.z == b.z));
    }
}

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <class Water, BottomModel B>
using TracerOn = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, B>;

template <class Water, BottomModel B>
TransportResult<CompactRecord> trace_scattering(const Water& water, const B& bottom, TransportSettings s) {
    return TracerOn<Water, B>(water, BasicSlab<B>(1.0, bottom), FlatSurface(1.34), CollimatedSun(30.0), s).run();
}

TransportSettings scattering_settings(AbsorptionMode mode) {
    TransportSettings s;
    s.photons = 40000;
    s.map_photons = 5000;
    s.depths = {0.0, 2.0, 4.0};
    s.absorption = mode;
    return s;
}
}  // namespace

TEST_CASE("The first pass over Minnaert k = 1 is the one over the Lambertian bottom, bit for bit") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    for (const AbsorptionMode mode : {AbsorptionMode::continuous, AbsorptionMode::analog}) {
        const auto s = scattering_settings(mode);
        const auto a = trace_scattering(water, MinnaertBottom(4.0, 0.6, 1.0), s);
        const auto b = trace_scattering(water, Bottom::lambertian_at(4.0, 0.6), s);
        testing::require_identical(a, b);
        REQUIRE(a.ledger.absorbed_bottom == b.ledger.absorbed_bottom);
    }
}

TEST_CASE("Over a Minnaert bottom the ledger closes and the absorption modes agree") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const MinnaertBottom rock(4.0, 0.7, 3.0);
    const auto analog = trace_scattering(water, rock, scattering_settings(AbsorptionMode::analog));
    const auto weighted = trace_scattering(water, rock, scattering_settings(AbsorptionMode::continuous));
    CHECK(std::abs(analog.ledger.imbalance()) < 1e-12);  // analog: exact per photon
    CHECK(analog.ledger.absorbed_bottom > 0.0);
    for (std::size_t i = 0; i < analog.depths.size(); ++i)
        for (const IrradianceKind k : {Ed, Eu})
            testing::check_agree(analog.irradiance[i][k], weighted.irradiance[i][k],
                                 "depth " + std::to_string(analog.depths[i]) + " kind " + std::to_string(int(k)));
}

TEST_CASE("Index-matched surface, no scattering: on a Minnaert bottom Eu / Ed = A0 mu^(k-1) exactly") {
    // Every photon arrives on the bottom in the refracted sun's direction (no interface: mu =
    // cos 60 deg = 0.5) with the same weight exp(-c H / mu), and leaves it with that weight
    // times rho(0.5) = A0 0.5^(k - 1) (continuous absorption, no roulette): the plane on the
    // bottom counts Ed and Eu, whose ratio is rho to rounding. Light leaving upwards reaches
    // the surface and leaves (no Fresnel reflection): Eu(0) = Ed(H) rho(0.5) (k + 1)
    // int_0^1 mu^k exp(-c H / mu) dmu in expectation (the directions' pdf (k + 1) mu^k).
    // "To rounding": sums of 50,000 equal terms in doubles (blocks of 4096, then batches),
    // whose relative error is bounded by about 1e-11 (n eps for the longest sum).
    const double c = 0.1, depth = 5.0, a0 = 0.8, k = 3.0, mu_sun = 0.5;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    const MinnaertBottom rock(depth, a0, k);
    TransportSettings s;
    s.photons = 50000;
    s.depths = {0.0, depth};
    s.absorption = AbsorptionMode::continuous;
    s.roulette_weight = 0.0;
    const double rho = a0 * std::pow(mu_sun, k - 1.0);  // 0.2 (a Lambertian A0 = 0.8 gives 0.8)

    auto check = [&](const TransportResult<CompactRecord>& r) {
        const auto& on_bottom = r.irradiance[1];
        CHECK(on_bottom[Ed].value == Approx(std::exp(-c * depth / mu_sun) * mu_sun).epsilon(1e-11));
        CHECK(on_bottom[Eu].value == Approx(rho * on_bottom[Ed].value).epsilon(1e-11));
        CHECK(r.bottom_ed.value == Approx(on_bottom[Ed].value).epsilon(1e-11));
        CHECK(r.ledger.absorbed_bottom == Approx(r.ledger.incident * std::exp(-c * depth / mu_sun) * (1.0 - rho)).epsilon(1e-11));
        CHECK(std::abs(r.ledger.imbalance()) < 1e-12);
        const int n = 4000;
        auto f = [&](double mu) { return mu > 0.0 ? std::pow(mu, k) * std::exp(-c * depth / mu) : 0.0; };
        double sum = f(0.0) + f(1.0);
        for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(static_cast<double>(i) / n);
        const double eu0 = on_bottom[Ed].value * rho * (k + 1.0) * sum / (3.0 * n);
        const Estimate& got = r.irradiance[0][Eu];
        INFO("Eu(0) " << got.value << " +- " << got.se << ", expected " << eu0);
        CHECK(std::abs(got.value - eu0) <= 4.0 * got.se);
    };
    const BasicSlab<MinnaertBottom> slab(1.0, rock);
    const CollimatedSun sun(60.0);
    check(TracerOn<IsoWater, MinnaertBottom>(water, slab, FlatSurface(1.0), sun, s).run());
#if SECCHI_HAS_LANES
    check(LaneTracer<IsoWater, CompactRecord, double, FlatSurface, SunAndSky, IrradiancePlanes, MinnaertBottom>(
              water, slab, FlatSurface(1.0), sun, s)
              .run());
#endif
}
