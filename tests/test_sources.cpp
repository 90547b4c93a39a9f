// Light sources (scene/source.hpp): the parametric sky's sampler against its own pdf
// (chi-square over the quads and within one), its radiance against Harrison and Coombes and
// its irradiance split; the traced atmosphere's direct beam against Beer-Lambert, its height
// profile, zero optical thickness against the sun alone (M93 problem 2a), and the coupled
// system's energy ledger. Statistical checks use 4 measured standard errors, or chi-square
// bounds of dof +- 4 sqrt(2 dof), fixed in advance.
#include <catch2/catch.hpp>
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/scene/any_source.hpp"
#include "secchi/scene/atmosphere.hpp"
#include "secchi/scene/parametric_sky.hpp"
#include "secchi/transport/lane_tracer.hpp"
#include "secchi/transport/tracer.hpp"
#include "transport_checks.hpp"
#include <cmath>
#include <vector>

using namespace secchi;

namespace {

bool within_se(const Estimate& e, double exact, double k = 4.0) {
    INFO("estimate " << e.value << " +- " << e.se << " vs exact " << exact);
    return std::abs(e.value - exact) <= k * e.se && e.se > 0;
}

/// Pearson's chi-square of `counts` against `expected` (same length), pooling the bins whose
/// expected count is below 5 into one; returns {chi2, degrees of freedom}.
std::pair<double, double> chi_square(const std::vector<double>& counts, const std::vector<double>& expected) {
    double chi2 = 0.0, pooled_n = 0.0, pooled_e = 0.0;
    int bins = 0;
    for (std::size_t i = 0; i < counts.size(); ++i) {
        if (expected[i] < 5.0) {
            pooled_n += counts[i];
            pooled_e += expected[i];
            continue;
        }
        chi2 += (counts[i] - expected[i]) * (counts[i] - expected[i]) / expected[i];
        ++bins;
    }
    if (pooled_e > 0.0) {
        chi2 += (pooled_n - pooled_e) * (pooled_n - pooled_e) / pooled_e;
        ++bins;
    }
    return {chi2, bins - 1.0};
}

void check_chi_square(const std::vector<double>& counts, const std::vector<double>& expected) {
    const auto [chi2, dof] = chi_square(counts, expected);
    INFO("chi2 " << chi2 << " with " << dof << " degrees of freedom");
    CHECK(dof > 10);
    CHECK(std::abs(chi2 - dof) <= 4.0 * std::sqrt(2.0 * dof));
}

using Water = HomogeneousWater<HenyeyGreensteinPhase>;

/// HG water (g = 0.8, albedo w0, c = 1 /m) over a Lambertian bottom at 4 m (or infinitely deep).
template <template <class...> class Tracer = PhotonTracer, class Source>
TransportResult<CompactRecord> trace(const Source& source, TransportSettings s, double w0 = 0.9,
                                     Bottom bottom = Bottom::lambertian_at(4.0, 0.5)) {
    const auto water = Water::from_albedo(1.0, w0, HenyeyGreensteinPhase(0.8));
    return Tracer<Water, CompactRecord, FlatSurface, Source>(water, Slab(1.0, bottom, 30.0), FlatSurface(1.34), source,
                                                              s)
        .run();
}

#if SECCHI_HAS_LANES
template <class M, class Record, class Surface, class Source>
using DoubleLanes = LaneTracer<M, Record, double, Surface, Source>;
#endif

}  // namespace

TEST_CASE("Harrison and Coombes' clear sky, evaluated by hand at one point") {
    // Zenith sky point, sun at 60 deg (psi = 60 deg): (1.63 + 53.7 e^(-5.49 pi/3) + 2.04 (1/4)(1/2))
    // (1 - e^-0.19)(1 - e^-1.06), evaluated independently (Python) as 0.2325202836002042.
    CHECK(ParametricSky::harrison_coombes(1.0, pi / 3.0, 0.5) == Approx(0.2325202836002042).epsilon(1e-13));
    const ParametricSky sky;
    CHECK(sky.harrison_coombes(vec3{0.0, 0.0, 1.0}) == Approx(0.2325202836002042).epsilon(1e-13));
}

TEST_CASE("The parametric sky's sampler matches its own pdf over the quads and the disk (chi-square)") {
    const ParametricSky sky;  // the manual's problem 4: 0.4158 direct, 0.2729 diffuse, 64 x 128 quads
    const std::size_t n = sky.quad_count();
    REQUIRE(n == 64 * 128);
    const std::uint64_t samples = 1'000'000;
    std::vector<double> counts(n + 1, 0.0), expected(n + 1, 0.0);
    expected[0] = samples * sky.disk_probability();
    for (std::size_t i = 0; i < n; ++i) expected[i + 1] = samples * sky.quad_probability(i);
    double total_p = sky.disk_probability();
    for (std::size_t i = 0; i < n; ++i) total_p += sky.quad_probability(i);
    CHECK(total_p == Approx(1.0).epsilon(1e-12));
    CHECK(sky.disk_probability() == Approx(0.4158 / (0.4158 + 0.2729)).epsilon(1e-12));
    for (std::uint64_t k = 0; k < samples; ++k) {
        PhotonRng rng(7, k);
        const SourcePhoton p = sky.emit(rng);
        REQUIRE(p.fate == SourceFate::arrives);
        REQUIRE(p.dir.z > 0.0);
        REQUIRE(std::abs(glm::length(p.dir) - 1.0) < 1e-12);
        if (p.direct) {
            // Within the disk: at most its angular radius from the sun's beam.
            REQUIRE(glm::dot(p.dir, sky.beam_direction()) >= std::cos(sky.disk_half_angle()) - 1e-12);
            counts[0] += 1;
        } else {
            counts[sky.quad_of(p.dir) + 1] += 1;
        }
    }
    check_chi_square(counts, expected);
}

TEST_CASE("Within one quad the sky's directions have density cos(theta) per solid angle (chi-square)") {
    const ParametricSky sky;
    // The most probable quad (near the sun), and one on the horizon (band 0, cos(theta) in
    // [0, 1/64], where the cos(theta) density is the most uneven).
    std::size_t brightest = 0;
    for (std::size_t i = 0; i < sky.quad_count(); ++i)
        if (sky.quad_probability(i) > sky.quad_probability(brightest)) brightest = i;
    for (const std::size_t quad : {brightest, std::size_t{5}}) {
        const auto q = sky.quad_bounds(quad);
        const int m = 8;  // 8 x 8 sub-cells, equal in cos(theta) and azimuth
        std::vector<double> counts(m * m, 0.0), expected(m * m, 0.0);
        const std::uint64_t samples = 200'000;
        for (int a = 0; a < m; ++a) {
            const double mu_a = q.mu0 + (q.mu1 - q.mu0) * a / m, mu_b = q.mu0 + (q.mu1 - q.mu0) * (a + 1) / m;
            // The measure cos(theta) dOmega = mu dmu dphi over the sub-cell, over the quad's.
            const double share = (mu_b * mu_b - mu_a * mu_a) / (q.mu1 * q.mu1 - q.mu0 * q.mu0);
            for (int b = 0; b < m; ++b) expected[a * m + b] = samples * share / m;
        }
        for (std::uint64_t k = 0; k < samples; ++k) {
            PhotonRng rng(11, k);
            const double u1 = rng.uniform(), u2 = rng.uniform();
            const vec3 d = sky.sample_in_quad(quad, u1, u2);
            REQUIRE(sky.quad_of(d) == quad);
            double phi = std::atan2(-d.y, -d.x);
            if (phi < 0.0) phi += two_pi;
            const int a = std::min(m - 1, static_cast<int>((d.z - q.mu0) / (q.mu1 - q.mu0) * m));
            const int b = std::min(m - 1, static_cast<int>((phi - q.phi0) / (q.phi1 - q.phi0) * m));
            counts[a * m + b] += 1;
        }
        INFO("quad " << quad);
        check_chi_square(counts, expected);
    }
}

TEST_CASE("The parametric sky's radiance is Harrison and Coombes' and gives the diffuse irradiance") {
    const ParametricSky sky;
    // The plane irradiance of the sky's radiance, by a midpoint rule on a grid that does not
    // follow the quads (1000 x 2000 cells): the diffuse irradiance, to the grid's resolution.
    const int nm = 1000, np = 2000;
    double e = 0.0;
    for (int i = 0; i < nm; ++i) {
        const double mu = (i + 0.5) / nm, sin_t = std::sqrt(1.0 - mu * mu);
        for (int j = 0; j < np; ++j) {
            const double phi = two_pi * (j + 0.5) / np;
            e += sky.sky_radiance({-sin_t * std::cos(phi), -sin_t * std::sin(phi), mu}) * mu;
        }
    }
    e *= (1.0 / nm) * (two_pi / np);
    CHECK(e == Approx(0.2729).epsilon(2e-3));
    // The disk's: its radiance times the integral of cos(theta) over the cone, by a midpoint
    // rule in the cone's own polar coordinates.
    const double alpha = sky.disk_half_angle();
    double disk = 0.0;
    const int ng = 200, nb = 400;
    for (int i = 0; i < ng; ++i) {
        const double gamma = alpha * (i + 0.5) / ng;
        for (int j = 0; j < nb; ++j) {
            const vec3 d = rotate_direction(sky.beam_direction(), std::cos(gamma), two_pi * (j + 0.5) / nb);
            disk += d.z * std::sin(gamma);
        }
    }
    disk *= sky.disk_radiance() * (alpha / ng) * (two_pi / nb);
    CHECK(disk == Approx(0.4158).epsilon(1e-4));
    // Shape: a quad's radiance is Harrison and Coombes' at its centre, to the curvature of N
    // over the quad (1/64 in cos(theta), 2.8 deg in azimuth; within 1 % away from the sun and
    // the zenith), up to the one scale factor: compare the ratios to a reference quad.
    const auto centre = [&](const vec3& d) {
        const auto q = sky.quad_bounds(sky.quad_of(d));
        const double mu = 0.5 * (q.mu0 + q.mu1), sin_t = std::sqrt(1.0 - mu * mu), phi = 0.5 * (q.phi0 + q.phi1);
        return vec3{-sin_t * std::cos(phi), -sin_t * std::sin(phi), mu};
    };
    const vec3 reference = centre({0.0, 0.8, 0.6});  // 90 deg in azimuth from the sun, 53 deg from the zenith
    const double scale = sky.sky_radiance(reference) / sky.harrison_coombes(reference);
    for (const vec3& d : {vec3{0.6, 0.0, 0.8}, vec3{0.0, -0.9, std::sqrt(0.19)}, vec3{-0.6, 0.6, std::sqrt(0.28)},
                          vec3{0.8, 0.5, std::sqrt(0.11)}}) {
        const vec3 c = centre(d);
        INFO("quad centre " << c.x << ", " << c.y << ", " << c.z);
        CHECK(sky.sky_radiance(c) / sky.harrison_coombes(c) == Approx(scale).epsilon(0.01));
    }
    // The circumsolar sky is far brighter than the anti-solar sky at the same height.
    const vec3 to_sun = sky.beam_direction(), away{-to_sun.x, -to_sun.y, to_sun.z};
    CHECK(sky.sky_radiance(rotate_direction(to_sun, std::cos(0.1), 0.3)) > 5.0 * sky.sky_radiance(away));
}

TEST_CASE("Downward irradiance just above the surface is direct + diffuse") {
    TransportSettings s;
    s.photons = 100'000;
    s.depths = {0.0, 1.0};
    SECTION("parametric sky: every photon arrives once, the split is the sky's") {
        const ParametricSky sky;
        const auto r = trace(sky, s);
        CHECK(r.above.ed_direct.value + r.above.ed_diffuse.value == Approx(0.4158 + 0.2729).epsilon(1e-12));
        CHECK(within_se(r.above.ed_direct, 0.4158));
        CHECK(within_se(r.above.ed_diffuse, 0.2729));
        CHECK(r.ledger.to_space == 0.0);
    }
    SECTION("traced atmosphere: the direct part is Beer-Lambert along the slant path") {
        const TracedAtmosphere atmosphere;
        const auto r = trace(atmosphere, s);
        const double direct = 0.5 * std::exp(-(0.145 + 0.264) / 0.5);
        CHECK(atmosphere.direct_irradiance_at_surface() == Approx(direct).epsilon(1e-14));
        CHECK(within_se(r.above.ed_direct, direct));
        CHECK(r.above.ed_diffuse.value > 0.1);
        // The net flux into the water is the same counted above the surface and below it
        // (the detector at depth 0): an identity per photon, to the rounding of the sums.
        const double above = r.above.ed_direct.value + r.above.ed_diffuse.value - r.above.eu.value;
        const double below = r.irradiance[0][Ed].value - r.irradiance[0][Eu].value;
        CHECK(std::abs(above - below) <= 1e-12 * (r.irradiance[0][Ed].value + r.irradiance[0][Eu].value));
    }
}

TEST_CASE("The atmosphere's height profile: exponential Rayleigh and aerosol, inverted exactly") {
    const TracedAtmosphere a;
    CHECK(a.optical_thickness() == Approx(0.409).epsilon(1e-15));
    CHECK(a.depth_of_height(0.0) == Approx(0.409).epsilon(1e-15));
    CHECK(a.height_at(a.optical_thickness()) == 0.0);
    CHECK(a.height_at(0.409) < 1e-12);
    for (const double t : {1e-9, 1e-4, 0.01, 0.1, 0.2, 0.3, 0.4, 0.40899}) {
        const double z = a.height_at(t);
        INFO("t = " << t << ", z = " << z << " km");
        CHECK(a.depth_of_height(z) == Approx(t).epsilon(1e-12));
    }
    // At the surface the aerosol's share of the extinction is (0.264/2) / (0.145/8 + 0.264/2).
    CHECK(a.aerosol_share(0.0) == Approx((0.264 / 2.0) / (0.145 / 8.0 + 0.264 / 2.0)).epsilon(1e-14));
    CHECK(a.aerosol_share(20.0) < 0.1);
}

TEST_CASE("An atmosphere of zero optical thickness is the sun alone at the surface (M93 problem 2a), bit for bit") {
    AtmosphereSpec none;
    none.rayleigh_tau = none.aerosol_tau = 0.0;
    const TracedAtmosphere atmosphere(none);
    CHECK_FALSE(atmosphere.returns_light());
    const auto water = HomogeneousWater<TabulatedPhase>::from_albedo(1.0, 0.9, petzold_m93());
    const Slab slab(1.0, Bottom{}, 40.0);
    for (const AbsorptionMode mode : {AbsorptionMode::continuous, AbsorptionMode::implicit_capture, AbsorptionMode::analog}) {
        TransportSettings s;
        s.photons = 20'000;
        s.map_photons = 10'000;
        s.depths = {0.0, 1.0, 5.0, 10.0};
        s.absorption = mode;
        using W = HomogeneousWater<TabulatedPhase>;
        const auto a = PhotonTracer<W, CompactRecord, FlatSurface, TracedAtmosphere>(water, slab, FlatSurface(1.34),
                                                                                      atmosphere, s)
                           .run();
        const auto b = PhotonTracer<W, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(60.0), s).run();
        testing::require_identical(a, b);
        CHECK(a.ledger.surface_reflected == b.ledger.surface_reflected);
        CHECK(a.ledger.escaped_up == b.ledger.escaped_up);
        CHECK(a.ledger.to_space == 0.0);
        const AnySource any(atmosphere);
        testing::require_identical(
            PhotonTracer<W, CompactRecord, FlatSurface, AnySource>(water, slab, FlatSurface(1.34), any, s).run(), b);
#if SECCHI_HAS_LANES
        if (mode == AbsorptionMode::continuous)
            testing::require_identical(
                LaneTracer<W, CompactRecord, double, FlatSurface, TracedAtmosphere>(water, slab, FlatSurface(1.34),
                                                                                     atmosphere, s)
                    .run(),
                LaneTracer<W, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(60.0), s).run());
#endif
    }
}

TEST_CASE("The coupled atmosphere-water system's energy ledger closes") {
    // Every photon's weight ends in one account: to space, absorbed in the air (aerosol albedo
    // 0.8), absorbed in the water or by the bottom. Exact per photon without roulette; light
    // going up from the surface is the atmosphere's, so nothing is booked as reflected or
    // escaped at the surface.
    AtmosphereSpec spec;
    spec.aerosol_albedo = 0.8;
    const TracedAtmosphere atmosphere(spec);
    for (const AbsorptionMode mode : {AbsorptionMode::analog, AbsorptionMode::implicit_capture, AbsorptionMode::continuous}) {
        TransportSettings s;
        s.photons = 40'000;
        s.depths = {0.0, 1.0};
        s.absorption = mode;
        s.roulette_weight = 0.0;
        const auto check = [&](const TransportResult<CompactRecord>& r, const std::string& tracer) {
            const EnergyLedger& l = r.ledger;
            INFO(tracer << ", absorption mode " << static_cast<int>(mode) << ": to space " << l.to_space
                        << ", absorbed in air " << l.absorbed_air << ", in water " << l.absorbed << ", bottom "
                        << l.absorbed_bottom);
            CHECK(l.incident == 1.0);
            CHECK(std::abs(l.imbalance()) < 1e-12);
            CHECK(l.to_space > 0.05);
            CHECK(l.absorbed_air > 0.01);
            CHECK(l.absorbed > 0.05);
            CHECK(l.absorbed_bottom > 0.01);
            CHECK(l.surface_reflected == 0.0);
            CHECK(l.escaped_up == 0.0);
            CHECK(l.truncated == 0.0);
        };
        check(trace(atmosphere, s), "PhotonTracer");
#if SECCHI_HAS_LANES
        check(trace<DoubleLanes>(atmosphere, s), "LaneTracer");
#endif
    }
}

TEST_CASE("Under a traced atmosphere results are bit-identical for 1 and 2 threads") {
    const TracedAtmosphere atmosphere;
    testing::require_same_for_1_and_2_threads(AbsorptionMode::continuous,
                                              [&](const TransportSettings& s) { return trace(atmosphere, s); });
    const ParametricSky sky;
    testing::require_same_for_1_and_2_threads(AbsorptionMode::implicit_capture,
                                              [&](const TransportSettings& s) { return trace(sky, s); });
}

#if SECCHI_HAS_LANES
TEST_CASE("LaneTracer and PhotonTracer agree under a traced atmosphere and under a parametric sky") {
    TransportSettings s;
    s.photons = 60'000;
    s.depths = {0.0, 1.0, 3.0};
    const auto check = [&](const auto& source, const std::string& what) {
        const auto a = trace(source, s);
        const auto b = trace<DoubleLanes>(source, s);
        for (std::size_t i = 0; i < s.depths.size(); ++i)
            for (const int k : {int(Ed), int(Eu), int(Eod), int(Eou)})
                testing::check_agree(a.irradiance[i][k], b.irradiance[i][k],
                                     what + ", depth " + std::to_string(s.depths[i]) + ", kind " + std::to_string(k));
        testing::check_agree(a.above.ed_diffuse, b.above.ed_diffuse, what + ", Ed(0+) diffuse");
        testing::check_agree(a.above.eu, b.above.eu, what + ", Eu(0+)");
    };
    check(TracedAtmosphere{}, "traced atmosphere");
    check(ParametricSky{}, "parametric sky");
}
#endif

TEST_CASE("Invalid sources are rejected by name") {
    const auto atmosphere = [](auto&& set) {
        AtmosphereSpec s;
        set(s);
        return TracedAtmosphere(s);
    };
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.rayleigh_tau = -0.1; }),
                        Catch::Contains("Rayleigh optical thickness = -0.1"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.aerosol_tau = NAN; }),
                        Catch::Contains("aerosol optical thickness"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.aerosol_g = 1.0; }), Catch::Contains("aerosol g = 1"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.aerosol_albedo = 1.5; }),
                        Catch::Contains("aerosol single-scattering albedo = 1.5"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.aerosol_scale_height_km = 0.0; }),
                        Catch::Contains("aerosol scale height"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.rayleigh_scale_height_km = -8.0; }),
                        Catch::Contains("Rayleigh scale height"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.sun_zenith_deg = 90.0; }), Catch::Contains("sun zenith"));
    REQUIRE_THROWS_WITH(atmosphere([](AtmosphereSpec& s) { s.e_perp = 0.0; }), Catch::Contains("E_perp = 0"));
    const auto sky = [](auto&& set) {
        ParametricSkySpec s;
        set(s);
        return ParametricSky(s);
    };
    REQUIRE_THROWS_WITH(sky([](ParametricSkySpec& s) { s.direct = -1.0; }), Catch::Contains("direct irradiance = -1"));
    REQUIRE_THROWS_WITH(sky([](ParametricSkySpec& s) { s.diffuse = NAN; }), Catch::Contains("diffuse irradiance"));
    REQUIRE_THROWS_WITH(sky([](ParametricSkySpec& s) { s.direct = s.diffuse = 0.0; }),
                        Catch::Contains("direct + diffuse irradiance = 0"));
    REQUIRE_THROWS_WITH(sky([](ParametricSkySpec& s) { s.sun_diameter_deg = 0.0; }),
                        Catch::Contains("sun diameter"));
    REQUIRE_THROWS_WITH(sky([](ParametricSkySpec& s) { s.zenith_bands = 0; }), Catch::Contains("zenith bands = 0"));
    REQUIRE_THROWS_WITH(sky([](ParametricSkySpec& s) { s.azimuth_sectors = 0; }),
                        Catch::Contains("azimuth sectors = 0"));
}
