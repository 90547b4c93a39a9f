// Ward's glossy reflection (scene/ward.hpp) and glossy objects in the first pass: the BRDF is
// reciprocal and its directional albedo at most rho_s (by quadrature); the sampler's weights
// average to that albedo and distribute the light over the directions as f cos does; a glossy
// floor under a vertical beam sends up exactly the Eu and Eou the BRDF gives (quadrature);
// the ledger closes, threads agree, rho_s = 0 is the Lambertian material bit for bit, and
// what cannot be modelled is refused by name.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/shapes.hpp"
#include "secchi/scene/ward.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <cmath>
#include <vector>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
const vec3 up{0.0, 0.0, -1.0};  // the normal of a horizontal surface facing the water above it

vec3 direction_at(double theta, double phi, const vec3& n) { return rotate_direction(n, std::cos(theta), phi); }

/// integral over the hemisphere of n of g(o) d omega: midpoint rule on 1500 x 720 cells in
/// (theta, phi) (cells 0.06 x 0.5 degrees: the narrowest lobe tested, alpha = 0.05, is 3 degrees wide).
template <class G>
double hemisphere(const vec3& n, G&& g) {
    const int nt = 1500, np = 720;
    double sum = 0.0;
    for (int a = 0; a < nt; ++a) {
        const double theta = 0.5 * pi * (a + 0.5) / nt;
        double ring = 0.0;
        for (int b = 0; b < np; ++b) ring += g(direction_at(theta, two_pi * (b + 0.5) / np, n));
        sum += ring * std::sin(theta);
    }
    return sum * (0.5 * pi / nt) * (two_pi / np);
}
}  // namespace

TEST_CASE("Ward: reciprocal, and its directional albedo is at most rho_s at every incidence") {
    testing::Rand r(51);
    for (const double alpha : {0.05, 0.2, 0.5}) {
        const WardLobe lobe(alpha);
        for (int k = 0; k < 200; ++k) {
            const vec3 i = r.direction_against(up, 1.0), o = r.direction_against(up, 1.0);
            CHECK(lobe.brdf_per_albedo(i, o, up) == Approx(lobe.brdf_per_albedo(o, i, up)).epsilon(1e-12));
            CHECK(lobe.brdf_per_albedo(i, -o, up) == 0.0);
        }
        for (const double theta_i : {0.0, 30.0, 60.0, 80.0, 88.0}) {
            const vec3 i = direction_at(theta_i * deg, 0.3, up);
            const double albedo =
                hemisphere(up, [&](const vec3& o) { return lobe.brdf_per_albedo(i, o, up) * glm::dot(o, up); });
            INFO("alpha " << alpha << ", incidence " << theta_i << " deg: albedo / rho_s " << albedo);
            CHECK(albedo <= 1.0 + 1e-3);  // the quadrature's own error is below 1e-3
            CHECK(albedo > 0.5);
        }
    }
}

TEST_CASE("Ward: the sampler's weights average to the albedo and spread the light as f cos does") {
    // 400,000 draws per case; their mean weight against the quadrature's albedo, and the weight
    // landing in 8 bands of cos(theta_o) against the quadrature of f cos over each band, each
    // within 4 SE (SE from the draws' spread).
    for (const double alpha : {0.05, 0.3})
        for (const double theta_i : {10.0, 55.0, 80.0}) {
            const WardLobe lobe(alpha);
            const vec3 i = direction_at(theta_i * deg, 1.1, up);
            const int n = 400000, bands = 8;
            std::vector<double> sum(bands + 1, 0.0), sum2(bands + 1, 0.0);
            PhotonRng rng(52, static_cast<std::uint64_t>(theta_i));
            for (int k = 0; k < n; ++k) {
                const double u1 = rng.uniform(), u2 = rng.uniform();
                const GlossyDraw g = lobe.sample(i, up, u1, u2);
                REQUIRE(g.weight >= 0.0);
                REQUIRE(g.weight < 2.0);
                if (g.weight == 0.0) continue;
                REQUIRE(glm::length(g.direction) == Approx(1.0).epsilon(1e-12));
                REQUIRE(glm::dot(g.direction, up) > 0.0);
                const int band = std::min(bands - 1, static_cast<int>(glm::dot(g.direction, up) * bands));
                sum[band] += g.weight, sum2[band] += g.weight * g.weight;
                sum[bands] += g.weight, sum2[bands] += g.weight * g.weight;
            }
            for (int b = 0; b <= bands; ++b) {
                const double want = hemisphere(up, [&](const vec3& o) {
                    const double mu = glm::dot(o, up);
                    const bool in = b == bands || std::min(bands - 1, static_cast<int>(mu * bands)) == b;
                    return in ? lobe.brdf_per_albedo(i, o, up) * mu : 0.0;
                });
                const double mean = sum[b] / n, se = std::sqrt((sum2[b] / n - mean * mean) / (n - 1));
                INFO("alpha " << alpha << ", incidence " << theta_i << ", band " << b << ": " << mean << " +- " << se
                              << " vs " << want);
                CHECK(std::abs(mean - want) <= 4.0 * se + 1e-4);  // 1e-4: the quadrature's error
            }
        }
}

namespace {
template <class Water>
using ObjectTracer = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, Shapes>;
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;

/// A floor of material m filling a 1 m section from 2 m down to the bottom at 2.5 m.
Shapes floor_of(ObjectMaterial m) {
    Shapes g;
    g.add(AxisBox(vec3(0.0, 0.0, 2.0), vec3(1.0, 1.0, 2.5)), std::move(m));
    return g;
}
}  // namespace

TEST_CASE("A glossy floor under a vertical beam sends up the Eu and Eou of its BRDF") {
    // No scattering (w0 = 0, continuous absorption), c = 0.4 1/m, an index-matched surface (the
    // light sent up leaves), a vertical beam of unit irradiance: the floor at 2 m receives
    // E = exp(-2 c) and leaves the radiance L(o) = f(i, o) E in each direction o, attenuated by
    // exp(-c (2 - z) / cos(theta_o)) on the way to depth z. So
    //     Eu(z) = exp(-2 c) rho_s integral f_s/rho_s exp(-c (2 - z) / cos theta_o) cos theta_o d omega,
    // and Eou(z) the same without the cos(theta_o): quadrature, against the first pass
    // within 4 SE at 1 m and 1.8 m. rho_s 0.6 (no diffuse part), alpha 0.2, incidence normal.
    const double c = 0.4, rho_s = 0.6, alpha = 0.2;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    TransportSettings s;
    s.photons = 400'000;
    s.map_photons = 0;
    s.depths = {1.0, 1.8};
    s.absorption = AbsorptionMode::continuous;
    s.roulette_weight = 0.0;
    const auto r = ObjectTracer<IsoWater>(water, Slab(1.0, Bottom::lambertian_at(2.5, 0.0)), FlatSurface(1.0),
                                          SunAndSky(CollimatedSun(0.0)), s, floor_of(ObjectMaterial::ward(0.0, rho_s, alpha)))
                       .run();
    const WardLobe lobe(alpha);
    for (std::size_t k = 0; k < s.depths.size(); ++k) {
        const double path = 2.0 - s.depths[k];
        const auto up_light = [&](bool plane) {
            return std::exp(-2.0 * c) * rho_s * hemisphere(up, [&](const vec3& o) {
                       const double mu = glm::dot(o, up);
                       return lobe.brdf_per_albedo(up, o, up) * std::exp(-c * path / mu) * (plane ? mu : 1.0);
                   });
        };
        const Estimate& eu = r.irradiance[k][Eu];
        const Estimate& eou = r.irradiance[k][Eou];
        INFO("depth " << s.depths[k] << ": Eu " << eu.value << " +- " << eu.se << " vs " << up_light(true) << "; Eou "
                      << eou.value << " +- " << eou.se << " vs " << up_light(false));
        CHECK(std::abs(eu.value - up_light(true)) <= 4.0 * eu.se);
        CHECK(std::abs(eou.value - up_light(false)) <= 4.0 * eou.se);
    }
    CHECK(std::abs(r.ledger.imbalance()) <= 1e-9 * r.ledger.incident);
}

TEST_CASE("Glossy objects in the first pass: the ledger closes, threads agree, rho_s = 0 is Lambertian; refusals") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const Slab slab(1.0, Bottom::lambertian_at(4.0, 0.3));
    const SunAndSky sun(CollimatedSun(30.0));
    Shapes glossy;
    glossy.add(AxisBox(vec3(0.25, 0.25, 1.5), vec3(0.75, 0.75, 2.0)), ObjectMaterial::ward(0.2, 0.5, 0.1));
    glossy.add(Sphere(vec3(0.5, 0.5, 3.0), 0.3), ObjectMaterial::ward(0.0, 0.9, 0.3));
    TransportSettings s;
    s.photons = 40'000;
    s.map_photons = 20'000;
    s.depths = {1.0, 2.5};
    s.block_size = 1000;
    for (const AbsorptionMode mode : {AbsorptionMode::continuous, AbsorptionMode::implicit_capture}) {
        s.absorption = mode;
        s.threads = 1;
        const auto one = ObjectTracer<HgWater>(water, slab, FlatSurface(1.34), sun, s, glossy).run();
        INFO("imbalance " << one.ledger.imbalance() << ", absorbed by objects " << one.ledger.absorbed_objects);
        CHECK(std::abs(one.ledger.imbalance()) <= 1e-9 * one.ledger.incident);
        CHECK(one.ledger.absorbed_objects > 0.0);
        s.threads = 2;
        const auto two = ObjectTracer<HgWater>(water, slab, FlatSurface(1.34), sun, s, glossy).run();
        testing::require_identical(one, two);
    }
    // rho_s = 0: no lobe drawn, the Lambertian material's bits.
    s.threads = 1;
    s.absorption = AbsorptionMode::continuous;
    Shapes matte, ward0;
    matte.add(AxisBox(vec3(0.25, 0.25, 1.5), vec3(0.75, 0.75, 2.0)), ObjectMaterial::lambertian(0.4));
    ward0.add(AxisBox(vec3(0.25, 0.25, 1.5), vec3(0.75, 0.75, 2.0)), ObjectMaterial::ward(0.4, 0.0, 0.2));
    testing::require_identical(ObjectTracer<HgWater>(water, slab, FlatSurface(1.34), sun, s, matte).run(),
                               ObjectTracer<HgWater>(water, slab, FlatSurface(1.34), sun, s, ward0).run());
    // Analog photons cannot carry a glossy reflection's weight.
    s.absorption = AbsorptionMode::analog;
    CHECK_THROWS_WITH(ObjectTracer<HgWater>(water, slab, FlatSurface(1.34), sun, s, glossy).run(),
                      Contains("object glossy albedo = 0.5") && Contains("weighted photons"));
    CHECK_THROWS_WITH(ObjectMaterial::ward(0.6, 0.5, 0.1), Contains("object glossy albedo = 0.5") && Contains("1 - the diffuse"));
    CHECK_THROWS_WITH(ObjectMaterial::ward(0.2, 0.5, 0.0), Contains("Ward roughness = 0"));
    CHECK_THROWS_WITH(ObjectMaterial::ward(0.2, -0.1, 0.1), Contains("object glossy albedo = -0.1"));
    AlbedoMap bright(2, 1, 1.0, {0.3, 0.8});
    ObjectMaterial mapped = ObjectMaterial::mapped(bright);
    mapped.specular = 0.3;
    CHECK_THROWS_WITH(ObjectMaterial::checked(mapped), Contains("1 - the diffuse albedo (0.8"));
}
