#include <catch2/catch.hpp>
#include "secchi/core/stats.hpp"
#include "secchi/scene/any_surface.hpp"
#include "secchi/scene/flat_surface.hpp"
#include "secchi/scene/sky.hpp"
#include "secchi/scene/wind_blown_surface.hpp"
#include "secchi/scene/slab.hpp"
#include "secchi/scene/sun.hpp"
#include "random_draws.hpp"
#include <vector>

using namespace secchi;

TEST_CASE("Fresnel reflectance at normal incidence, n = 1.34") {
    const double expected = std::pow((1.34 - 1.0) / (1.34 + 1.0), 2);  // ((n-1)/(n+1))^2 = 0.021112
    REQUIRE(fresnel_reflectance(1.0, 1.0, 1.34) == Approx(expected).epsilon(1e-12));
    REQUIRE(fresnel_reflectance(1.0, 1.34, 1.0) == Approx(expected).epsilon(1e-12));
    REQUIRE(expected == Approx(0.021112).epsilon(1e-4));
}

TEST_CASE("Fresnel at the Brewster angle: only the s-polarised half reflects") {
    const double n = 1.34, theta_b = std::atan(n);
    const double rs = (1.0 - n * n) / (1.0 + n * n);
    REQUIRE(fresnel_reflectance(std::cos(theta_b), 1.0, n) == Approx(0.5 * rs * rs).epsilon(1e-12));
}

TEST_CASE("Total internal reflection beyond the critical angle from below") {
    const double tc = critical_angle(1.34, 1.0);
    REQUIRE(tc / deg == Approx(48.27).epsilon(1e-3));
    REQUIRE(fresnel_reflectance(std::cos(tc + 1e-6), 1.34, 1.0) == 1.0);
    REQUIRE(fresnel_reflectance(std::cos(tc - 1e-3), 1.34, 1.0) < 1.0);
    const FlatSurface s(1.34);
    const double th = 60 * deg;
    REQUIRE(s.reflectance_from_water({std::sin(th), 0, -std::cos(th)}) == 1.0);
}

TEST_CASE("Reflectance is reciprocal: R(air, theta_i) = R(water, theta_t)") {
    for (double th_deg : {10.0, 30.0, 60.0, 85.0}) {
        const double ci = std::cos(th_deg * deg);
        const double st = std::sin(th_deg * deg) / 1.34, ct = std::sqrt(1 - st * st);
        REQUIRE(fresnel_reflectance(ci, 1.0, 1.34) == Approx(fresnel_reflectance(ct, 1.34, 1.0)).epsilon(1e-12));
    }
}

TEST_CASE("The sun at 60 deg travels at 40.3 deg in water (n = 1.34)") {
    const CollimatedSun sun(60.0);
    REQUIRE(sun.plane_irradiance() == Approx(0.5));
    const vec3 d = FlatSurface(1.34).transmit_into_water(sun.direction());
    REQUIRE(std::acos(d.z) / deg == Approx(40.26).epsilon(1e-3));
    REQUIRE(glm::length(d) == Approx(1.0));
}

TEST_CASE("Water index 1.0 means no interface") {
    const FlatSurface s(1.0);
    const vec3 d = CollimatedSun(60.0).direction();
    REQUIRE(s.reflectance_from_air(d) == 0.0);
    REQUIRE(s.reflectance_from_water({d.x, d.y, -d.z}) == 0.0);
    REQUIRE(s.transmit_into_water(d).z == Approx(d.z));
}

TEST_CASE("Invalid scene input is rejected with the parameter's name") {
    REQUIRE_THROWS_WITH(FlatSurface(0.9), Catch::Contains("water index"));
    REQUIRE_THROWS_WITH(CollimatedSun(95.0), Catch::Contains("sun zenith"));
    REQUIRE_THROWS_WITH(Bottom::lambertian_at(5.0, 1.5), Catch::Contains("bottom albedo"));
    REQUIRE_THROWS_WITH(Slab(-1.0, Bottom{}, 10.0), Catch::Contains("section width"));
}

TEST_CASE("Periodic wrap lands in [0, W)") {
    const Slab slab(2.0, Bottom{}, 10.0);
    for (double x : {-5.0, -2.0, -1e-17, 0.0, 1.999, 2.0, 7.3}) {
        const double w = slab.wrap(x);
        REQUIRE(w >= 0.0);
        REQUIRE(w < 2.0);
    }
    REQUIRE(slab.wrap(7.5) == Approx(1.5));
}

// ---- The wind-blown surface (scene/wind_blown_surface.hpp) ----------------------------------

namespace {

/// What a photon of direction d (moving down from the air or up from the water onto the
/// surface; or, hidden on its way out, up in the air or down in the water) meets on average,
/// by quadrature over the slope plane instead of by sampling: the slopes (z_u along the
/// wind, z_c across it) have density p ~ exp(-z_u^2 / (2 s_u^2) - z_c^2 / (2 s_c^2)), each facet
/// weighted by the area it shows the photon, |d_z| + d_h . z (projected_area), or by 1 where
/// that is positive (redraw). Midpoint rule on 3000 x 3000 cells over +-6 standard deviations
/// (the redraw weight jumps where facets turn away, a first-order error there, and hidden light
/// meets facets near that edge: 600 x 600 cells misplace its reflectance by 0.5 %).
/// Returns the mean reflectance and the mean |z| of the transmitted direction (its cosine in
/// the other medium) over the transmitted part.
struct FacetAverages {
    double reflectance, transmitted_cosine;
};
FacetAverages facet_quadrature(const vec3& d, Side from, const FacetSlopes& slopes, FacetSampling sampling) {
    const double n1 = from == Side::air ? 1.0 : 1.34, n2 = from == Side::air ? 1.34 : 1.0;
    const vec3 down{d.x, d.y, from == Side::air ? d.z : -d.z};  // the surface seen from the photon's side (mirrored in z from below)
    const double wx = std::cos(slopes.wind_azimuth_deg * deg), wy = std::sin(slopes.wind_azimuth_deg * deg);
    const double su = std::sqrt(slopes.upwind), sc = std::sqrt(slopes.crosswind);
    const int cells = 3000;
    double mass = 0, reflected = 0, transmitted = 0, cosine = 0;
    for (int i = 0; i < cells; ++i)
        for (int j = 0; j < cells; ++j) {
            const double zu = su * (-6.0 + 12.0 * (i + 0.5) / cells), zc = sc * (-6.0 + 12.0 * (j + 0.5) / cells);
            const double sx = zu * wx - zc * wy, sy = zu * wy + zc * wx;  // the slopes along x and y
            const double seen = down.z + down.x * sx + down.y * sy;     // cos(omega) sec(theta_n)
            if (seen <= 0) continue;
            const double density = std::exp(-0.5 * (zu * zu / slopes.upwind + zc * zc / slopes.crosswind));
            const double w = density * (sampling == FacetSampling::projected_area ? seen : 1.0);
            const double norm = std::sqrt(1 + sx * sx + sy * sy), cos_i = seen / norm;
            const double r = fresnel_reflectance(cos_i, n1, n2);
            const vec3 m{-sx / norm, -sy / norm, -1.0 / norm};
            mass += w;
            reflected += w * r;
            if (r < 1) {
                transmitted += w * (1 - r);
                cosine += w * (1 - r) * std::abs(refract_through(down, m, cos_i, n1, n2).z);
            }
        }
    return {reflected / mass, cosine / transmitted};
}

/// The same averages from `n` sampled hits, each with its standard error (the transmitted
/// cosine is a ratio of means, sum (1 - R) |z| / sum (1 - R): its SE by the delta method).
struct SampledAverages {
    Estimate reflectance, transmitted_cosine;
};
SampledAverages sampled_hits(const WindBlownSurface& surface, const vec3& d, Side from, int n) {
    std::vector<double> r(n), z(n);
    PhotonRng rng(5, 0);
    for (int i = 0; i < n; ++i) {
        const SurfaceHit hit = surface.hit(d, from, rng);
        r[i] = hit.reflectance;
        z[i] = std::abs(hit.transmitted.z);
    }
    const auto mean_and_se = [n](auto&& value) {
        double sum = 0, sum2 = 0;
        for (int i = 0; i < n; ++i) sum += value(i), sum2 += value(i) * value(i);
        const double mean = sum / n;
        return Estimate{mean, std::sqrt((sum2 / n - mean * mean) / (n - 1))};
    };
    const Estimate refl = mean_and_se([&](int i) { return r[i]; });
    const Estimate tw = mean_and_se([&](int i) { return 1 - r[i]; });
    const Estimate twz = mean_and_se([&](int i) { return (1 - r[i]) * z[i]; });
    const double cosine = twz.value / tw.value;
    const Estimate residual = mean_and_se([&](int i) { return (1 - r[i]) * (z[i] - cosine) / tw.value; });
    return {refl, {cosine, residual.se}};
}

}  // namespace

TEST_CASE("Wind-blown facets are met in proportion to the area they show the photon (M93's weighting, eq. 7.13)") {
    // Grazing sun (problem 5's 80 deg) from two azimuths, the sun overhead, and light from below
    // at 30 and 60 deg; M93's isotropic slopes and Cox and Munk's anisotropic ones at 10 m/s
    // (the wind towards 30 deg), both facet choices.
    struct Case {
        vec3 d;
        Side from;
    };
    const double s80 = std::sin(80 * deg), c80 = std::cos(80 * deg);
    const std::vector<Case> cases = {
        {{s80, 0.0, c80}, Side::air},
        {{0.5 * s80, std::sqrt(0.75) * s80, c80}, Side::air},
        {{0.0, 0.0, 1.0}, Side::air},
        {{0.3 * std::sin(30 * deg), std::sqrt(0.91) * std::sin(30 * deg), -std::cos(30 * deg)}, Side::water},
        {{std::sin(60 * deg), 0.0, -std::cos(60 * deg)}, Side::water},
        // Hidden light (Shadowing::smith) meeting the waves on its way out: up in the air at 80
        // and 86 deg, down in the water at 84 deg.
        {{s80, 0.0, -c80}, Side::air},
        {{0.6 * std::sin(86 * deg), 0.8 * std::sin(86 * deg), -std::cos(86 * deg)}, Side::air},
        {{std::sin(84 * deg), 0.0, std::cos(84 * deg)}, Side::water},
    };
    for (const FacetSlopes& slopes : {FacetSlopes::isotropic(0.04), FacetSlopes::cox_munk(10.0, 30.0)})
        for (const FacetSampling sampling : {FacetSampling::projected_area, FacetSampling::redraw}) {
            const WindBlownSurface surface(slopes, 1.34, sampling);
            for (const auto& c : cases) {
                const FacetAverages exact = facet_quadrature(c.d, c.from, slopes, sampling);
                const SampledAverages mc = sampled_hits(surface, c.d, c.from, 200000);
                INFO("slopes " << slopes.upwind << ", " << slopes.crosswind << "; sampling " << static_cast<int>(sampling)
                               << ", direction (" << c.d.x << ", " << c.d.y << ", " << c.d.z << "): reflectance "
                               << mc.reflectance.value << " +- " << mc.reflectance.se << " vs " << exact.reflectance
                               << "; transmitted cosine " << mc.transmitted_cosine.value << " +- "
                               << mc.transmitted_cosine.se << " vs " << exact.transmitted_cosine);
                CHECK(std::abs(mc.reflectance.value - exact.reflectance) <= 4 * mc.reflectance.se + 1e-6);
                // (Light hidden in the water is grazing: nearly all of it is totally reflected, and
                // with a transmitted share below 1e-4 the sample has too few transmissions to compare.)
                if (1.0 - exact.reflectance > 1e-4)
                    CHECK(std::abs(mc.transmitted_cosine.value - exact.transmitted_cosine) <=
                          4 * mc.transmitted_cosine.se + 1e-6);
            }
        }
}

TEST_CASE("Smith's Lambda is the facet area facing a direction, less 1; light is hidden with probability 1 - G1") {
    // 1 + Lambda(d) = E[max(0, |d_z| + d_h . z)] / |d_z| over the slope density, two ways:
    // over the slope plane (800 x 800 midpoint cells of 0.02 s: the kink of max(0, .) across
    // the cells, oblique for anisotropic slopes, leaves errors of order 1e-5 of 1 + Lambda, so
    // Lambda within 2e-4 relative), and along the slope t = d_h . z / |d_h| alone, a Gaussian of
    // variance s_u^2 cos^2 + s_c^2 sin^2 of d's angle to the wind (Simpson's rule on 20,000
    // intervals over the part t > -|d_z| / |d_h| up to 12 s: 1e-9 relative).
    for (const FacetSlopes& slopes : {FacetSlopes::isotropic(0.04), FacetSlopes::cox_munk(10.0, 30.0)}) {
        const WindBlownSurface surface(slopes, 1.34, FacetSampling::projected_area, 1.0, Shadowing::smith);
        for (const double theta : {30.0, 70.0, 80.0, 85.0, 88.0})
            for (const double phi : {0.0, 50.0, 120.0}) {
                const vec3 d{std::sin(theta * deg) * std::cos(phi * deg), std::sin(theta * deg) * std::sin(phi * deg),
                             std::cos(theta * deg)};
                const double su = std::sqrt(slopes.upwind), sc = std::sqrt(slopes.crosswind);
                const double wx = std::cos(slopes.wind_azimuth_deg * deg), wy = std::sin(slopes.wind_azimuth_deg * deg);
                double mass = 0, seen = 0;
                const int cells = 800;
                for (int i = 0; i < cells; ++i)
                    for (int j = 0; j < cells; ++j) {
                        const double zu = su * (-8.0 + 16.0 * (i + 0.5) / cells), zc = sc * (-8.0 + 16.0 * (j + 0.5) / cells);
                        const double p = std::exp(-0.5 * (zu * zu / slopes.upwind + zc * zc / slopes.crosswind));
                        mass += p;
                        seen += p * std::max(0.0, d.z + d.x * (zu * wx - zc * wy) + d.y * (zu * wy + zc * wx));
                    }
                // Along the slope: E[max(0, mu + h t)] for t ~ N(0, s_t^2).
                const double h = std::hypot(d.x, d.y), ca = (d.x * wx + d.y * wy) / h, cb = (d.y * wx - d.x * wy) / h;
                const double st = std::sqrt(slopes.upwind * ca * ca + slopes.crosswind * cb * cb);
                const double t0 = -d.z / h, t1 = 12.0 * st;
                const int n = 20000;
                double simpson = 0.0;
                for (int k = 0; k <= n; ++k) {
                    const double t = t0 + (t1 - t0) * k / n;
                    const double f = (d.z + h * t) * std::exp(-0.5 * t * t / (st * st)) / (st * std::sqrt(2.0 * pi));
                    simpson += (k == 0 || k == n ? 1.0 : (k % 2 ? 4.0 : 2.0)) * f;
                }
                simpson *= (t1 - t0) / (3.0 * n);
                INFO("theta " << theta << ", phi " << phi);
                CHECK(surface.smith_lambda(d) == Approx(seen / mass / d.z - 1.0).epsilon(2e-4).margin(1e-9));
                CHECK(surface.smith_lambda(d) == Approx(simpson / d.z - 1.0).epsilon(1e-9).margin(1e-12));
                CHECK(surface.smith_lambda(vec3(d.x, d.y, -d.z)) == surface.smith_lambda(d));  // either side
            }
        // Hidden with probability 1 - G1: 200,000 draws at 85 deg, within 4 SE.
        const vec3 d{std::sin(85 * deg), 0.0, -std::cos(85 * deg)};
        const double p = 1.0 - surface.clearing_probability(d);
        PhotonRng rng(6, 0);
        int hidden = 0;
        for (int i = 0; i < 200000; ++i) hidden += surface.hidden(d, rng);
        CHECK(std::abs(hidden / 200000.0 - p) <= 4.0 * std::sqrt(p * (1 - p) / 200000.0));
        CHECK(p > 0.05);
    }
    const WindBlownSurface none(0.04);
    PhotonRng a(7, 0), b(7, 0);
    CHECK_FALSE(none.hidden({1.0, 0.0, 0.0}, a));
    CHECK(a.uniform() == b.uniform());  // nothing drawn
    CHECK(WindBlownSurface(FacetSlopes::isotropic(0.04), 1.34, FacetSampling::projected_area, 1.0, Shadowing::smith).smith_lambda({0.0, 0.0, 1.0}) == 0.0);
}

TEST_CASE("A grazing sun's light meets the wind-blown surface with reflectance near 0.25, not the flat 0.35") {
    // Preisendorfer and Mobley (1986), as M93 quote them for problem 5: a capillary-wave surface
    // at U = 7.23 m/s reflects more than 0.22 of a sun at 80 deg; a flat one 0.350.
    const double s80 = std::sin(80 * deg), c80 = std::cos(80 * deg);
    const FacetAverages wind =
        facet_quadrature({s80, 0.0, c80}, Side::air, FacetSlopes::isotropic(0.04), FacetSampling::projected_area);
    CHECK(fresnel_reflectance(c80, 1.0, 1.34) == Approx(0.3502).margin(1e-4));
    CHECK(wind.reflectance > 0.22);
    CHECK(wind.reflectance < 0.30);
}

TEST_CASE("A hit's directions are unit vectors on the right sides of its facet, and a flat surface's are Snell's") {
    const WindBlownSurface surface(0.04);
    PhotonRng rng(3, 1);
    const vec3 sun = CollimatedSun(70.0).direction();
    for (int i = 0; i < 1000; ++i) {
        const SurfaceHit h = surface.hit(sun, Side::air, rng);
        CHECK(glm::length(h.reflected) == Approx(1.0).margin(1e-12));
        CHECK(glm::length(h.transmitted) == Approx(1.0).margin(1e-12));
        // Reflection keeps the angle to the facet's normal; refraction obeys Snell's law about it:
        // the normal is along reflected - sun, and sin(theta_t) = sin(theta_i) / 1.34.
        const vec3 m = glm::normalize(h.reflected - sun);
        const double cos_i = std::abs(glm::dot(sun, m)), cos_t = std::abs(glm::dot(h.transmitted, m));
        CHECK(std::sqrt(1 - cos_t * cos_t) == Approx(std::sqrt(1 - cos_i * cos_i) / 1.34).margin(1e-9));
        CHECK(h.reflectance == Approx(fresnel_reflectance(cos_i, 1.0, 1.34)).margin(1e-12));
    }
    PhotonRng unused(0, 0);
    const FlatSurface flat(1.34);
    const SurfaceHit h = flat.hit(sun, Side::air, unused);
    CHECK(h.reflectance == flat.reflectance_from_air(sun));
    CHECK(h.transmitted == flat.transmit_into_water(sun));
    CHECK(h.reflected == FlatSurface::reflect(sun));
}

TEST_CASE("A uniform sky's photons come with density cos(theta) / pi, and a bad sky is rejected by name") {
    // Mean cos(theta) = 2/3 and mean cos^2(theta) = 1/2 for the density cos(theta)/pi on the hemisphere.
    PhotonRng rng(4, 0);
    const int n = 100000;
    double m1 = 0, m2 = 0;
    for (int i = 0; i < n; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const vec3 d = UniformSky::direction(u1, u2);
        REQUIRE(glm::length(d) == Approx(1.0).margin(1e-12));
        REQUIRE(d.z > 0.0);
        m1 += d.z, m2 += d.z * d.z;
    }
    m1 /= n, m2 /= n;
    // SE of the mean of mu: sqrt((1/2 - 4/9) / n) = 7.5e-4 at n = 1e5.
    CHECK(std::abs(m1 - 2.0 / 3.0) < 4 * std::sqrt((0.5 - 4.0 / 9.0) / n));
    CHECK(UniformSky(0.5).radiance() == Approx(0.5 / pi));
    REQUIRE_THROWS_WITH(UniformSky(-0.1), Catch::Contains("sky irradiance"));
    REQUIRE_THROWS_WITH(UniformSky(NAN), Catch::Contains("sky irradiance"));
    REQUIRE_THROWS_WITH(CollimatedSun(60.0, 0.0, -1.0), Catch::Contains("E_perp"));
}

TEST_CASE("Invalid wind-blown surfaces are rejected with the parameter's name") {
    REQUIRE_THROWS_WITH(WindBlownSurface(0.0), Catch::Contains("slope variance"));
    REQUIRE_THROWS_WITH(WindBlownSurface(NAN), Catch::Contains("slope variance"));
    REQUIRE_THROWS_WITH(WindBlownSurface(0.04, 0.5), Catch::Contains("water index"));
    REQUIRE_THROWS_WITH(WindBlownSurface(FacetSlopes{-0.01, 0.02, 0.0}), Catch::Contains("upwind slope variance"));
    REQUIRE_THROWS_WITH(WindBlownSurface(FacetSlopes{0.01, NAN, 0.0}), Catch::Contains("crosswind slope variance"));
    REQUIRE_THROWS_WITH(WindBlownSurface(FacetSlopes{0.0, 0.0, 0.0}), Catch::Contains("mean square slope"));
    REQUIRE_THROWS_WITH(WindBlownSurface(FacetSlopes{0.01, 0.01, INFINITY}), Catch::Contains("wind azimuth"));
    REQUIRE_THROWS_WITH(FacetSlopes::isotropic_at_wind(-1.0), Catch::Contains("wind speed"));
    REQUIRE_THROWS_WITH(FacetSlopes::cox_munk(NAN, 0.0), Catch::Contains("wind speed"));
    REQUIRE_THROWS_WITH(parse_facets("weighted"), Catch::Contains("facets"));
    CHECK(FacetSlopes::isotropic_at_wind(7.23).mean_square_slope() == Approx(0.04).margin(2e-5));
    // Cox and Munk's fits: s_u^2 + s_c^2 = 0.003 + 0.00508 U, near their isotropic 0.003 + 0.00512 U.
    CHECK(FacetSlopes::cox_munk(10.0, 0.0).mean_square_slope() == Approx(0.0538));
}

TEST_CASE("A calm axis (Cox and Munk at U = 0: no upwind slope) gives level facets along it, with either facet choice") {
    for (const FacetSampling sampling : {FacetSampling::projected_area, FacetSampling::redraw}) {
        const WindBlownSurface calm(FacetSlopes::cox_munk(0.0, 0.0), 1.34, sampling);
        PhotonRng rng(9, 2);
        for (const vec3 d : {vec3{1.0, 0.0, 0.0}, vec3{std::sin(80 * deg), 0.0, std::cos(80 * deg)}}) {
            // Travel along the wind: every facet is level along x, so the reflection keeps d.x.
            const SurfaceHit h = calm.hit(d, Side::air, rng);
            CHECK(h.reflected.x == Approx(d.x).margin(1e-12));
        }
    }
}

namespace {
bool same_hit(const SurfaceHit& a, const SurfaceHit& b) {
    return a.reflectance == b.reflectance && a.reflected == b.reflected && a.transmitted == b.transmitted;
}
}  // namespace

TEST_CASE("A surface chosen at run time (AnySurface) hits, hides and draws as the surface it holds, bit for bit") {
    const FlatSurface flat(1.34);
    const WindBlownSurface waves(FacetSlopes::cox_munk(7.0, 30.0), 1.33, FacetSampling::projected_area, 1.0,
                                 Shadowing::smith);
    const AnySurface any_flat = flat, any_waves = waves;
    CHECK(any_flat.water_index() == 1.34);
    CHECK(any_waves.water_index() == 1.33);
    CHECK(any_flat.get_if<FlatSurface>() != nullptr);
    CHECK(any_waves.get_if<FlatSurface>() == nullptr);
    CHECK_FALSE(any_flat.hides());
    CHECK(any_waves.hides());
    CHECK_FALSE(AnySurface(WindBlownSurface(0.04)).hides());

    // Random directions from either side: the same hit, the same hiding, and the same draws
    // taken from the photon's stream (the next uniform after them agrees too).
    testing::Rand rand(11);
    PhotonRng direct_rng(5, 9), any_rng(5, 9), flat_rng(5, 9), any_flat_rng(5, 9);
    for (int i = 0; i < 2000; ++i) {
        const Side side = i % 2 == 0 ? Side::air : Side::water;
        const vec3 d = rand.direction_against({0.0, 0.0, 1.0}, side == Side::air ? 1.0 : -1.0);
        REQUIRE(same_hit(waves.hit(d, side, direct_rng), any_waves.hit(d, side, any_rng)));
        REQUIRE(waves.hidden(-d, direct_rng) == any_waves.hidden(-d, any_rng));
        REQUIRE(same_hit(flat.hit(d, side, flat_rng), any_flat.hit(d, side, any_flat_rng)));
        REQUIRE_FALSE(any_flat.hidden(-d, any_flat_rng));
    }
    CHECK(direct_rng.uniform() == any_rng.uniform());
    CHECK(flat_rng.uniform() == any_flat_rng.uniform());

    // The sun's hit is fixed (computed once by the tracer) where the surface held draws nothing.
    const vec3 sun = CollimatedSun(40.0).direction();
    PhotonRng unused(0, 0);
    REQUIRE(any_flat.fixed_hit(sun).has_value());
    CHECK(same_hit(*any_flat.fixed_hit(sun), flat.hit(sun, Side::air, unused)));
    CHECK_FALSE(any_waves.fixed_hit(sun).has_value());
}
