// The surface photon map (map/surface_record.hpp, TransportSettings::surface_map) and the
// irradiance estimated from it (estimate/surface_irradiance.hpp): the gather against a
// brute-force sum over every arrival (across the section's seams), the irradiance on a box's
// top and on the bottom around its shadow against Beer-Lambert in non-scattering water, and
// with scattering the bottom's irradiance against the first pass's own bottom Ed; the map off
// changes nothing, and the arrivals are the same for 1 and 2 threads.
#include <catch2/catch.hpp>

#include "secchi/estimate/surface_irradiance.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/shapes.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <cmath>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <class Water, SceneGeometry G>
using ObjectTracer = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, G>;

constexpr double width = 1.0, depth = 4.0, radius = 0.05;

/// A black box (footprint [0.25, 0.75]^2, top at 2 m) above a black bottom at 4 m, 1 m section.
Shapes box_above_bottom(double albedo) {
    Shapes g;
    g.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::lambertian(albedo));
    return g;
}

template <class Water, SceneGeometry G>
TransportResult<CompactRecord> trace(const Water& water, const G& g, const TransportSettings& s, double bottom_albedo) {
    return ObjectTracer<Water, G>(water, Slab(width, Bottom::lambertian_at(depth, bottom_albedo)), FlatSurface(1.34),
                                  SunAndSky(CollimatedSun(0.0)), s, g)
        .run();
}

TransportSettings map_settings(std::uint64_t photons) {
    TransportSettings s;
    s.photons = photons;
    s.map_photons = photons;
    s.depths = {1.0};
    s.surface_map = true;
    s.roulette_weight = 0.0;
    s.block_size = 1000;
    return s;
}

SurfaceIrradiance irradiance_of(const TransportResult<CompactRecord>& r) {
    return SurfaceIrradiance(r.surface_photons, r.map_flux.per_record, r.batches, width, Radius(radius));
}
}  // namespace

TEST_CASE("Surface irradiance: the gather is the brute-force sum over every arrival, across the seams") {
    // Random arrivals on two faces (normals -z and +x), random queries anywhere (near the seams
    // too): E per batch is B Phi sum w / (pi r^2) over the arrivals whose nearest periodic image
    // lies within r and whose normal is within 60 degrees of the query's.
    testing::Rand r(41);
    std::vector<SurfacePhoton> arrivals;
    for (int i = 0; i < 20000; ++i) {
        const vec3 n = i % 4 ? vec3(0.0, 0.0, -1.0) : vec3(1.0, 0.0, 0.0);
        arrivals.push_back({{r.in(0.0, width), r.in(0.0, width), r.in(2.0, 2.1)}, n, r.in(0.1, 1.0), 0,
                            static_cast<std::uint8_t>(i % 8)});
    }
    const double phi = 2e-5;
    const SurfaceIrradiance e(arrivals, phi, 8, width, Radius(radius));
    CHECK(e.size() == arrivals.size());
    for (int q = 0; q < 300; ++q) {
        const vec3 x{q % 3 ? r.in(-0.04, 0.04) : r.in(-2.0, 3.0), r.in(-2.0, 3.0), r.in(2.0, 2.1)};
        const vec3 n = q % 5 ? vec3(0.0, 0.0, -1.0) : glm::normalize(vec3(1.0, 0.0, -0.5));
        std::vector<double> batch(8, 0.0);
        for (const SurfacePhoton& p : arrivals)
            for (int i = -3; i <= 3; ++i)
                for (int j = -3; j <= 3; ++j) {
                    const vec3 image = p.point + vec3(i * width, j * width, 0.0);
                    if (glm::length(image - x) < radius && glm::dot(p.normal, n) >= 0.5) batch[p.batch] += p.weight;
                }
        for (double& v : batch) v *= 8.0 * phi / (pi * radius * radius);
        const Estimate want = batch_estimate(batch), got = e.irradiance(x, n);
        INFO("query " << q << " at " << x.x << ", " << x.y);
        CHECK(got.value == Approx(want.value).epsilon(1e-12).margin(1e-300));
        CHECK(got.se == Approx(want.se).epsilon(1e-9).margin(1e-300));
    }
    CHECK_THROWS_WITH(SurfaceIrradiance(arrivals, phi, 8, width, Radius(0.3)), Contains("surface gather radius (m) = 0.3"));
    CHECK_THROWS_WITH(SurfaceIrradiance(arrivals, phi, 4, width, Radius(radius)), Contains("surface photon batch"));
    CHECK_THROWS_WITH(SurfaceIrradiance(arrivals, -1.0, 8, width, Radius(radius)), Contains("flux per record"));
}

TEST_CASE("The surface map of a box's shadow without scattering: Beer-Lambert on the box's top and the lit bottom, 0 in the umbra") {
    // w0 = 0, continuous absorption, vertical sun through the flat surface: light arrives
    // straight down with irradiance T exp(-c z) (T = 1 - R at normal incidence): on the box's
    // top (z = 2 m) and on the bottom outside the box's footprint (4 m); none in the umbra.
    // Queries at least r inside the top and the umbra, and r outside the footprint: the disc
    // lies on one face. Each estimate within 4 of its SE of the exact value (8 queries per
    // face); the umbra's exactly 0.
    const double c = 0.2;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    const auto r = trace(water, box_above_bottom(0.0), map_settings(200'000), 0.0);
    const SurfaceIrradiance e = irradiance_of(r);
    const double t = 1.0 - std::pow(0.34 / 2.34, 2);
    REQUIRE(e.size() > 100'000);
    testing::Rand q(42);
    for (int i = 0; i < 8; ++i) {
        const vec3 top{q.in(0.3, 0.7), q.in(0.3, 0.7), 2.0};
        const Estimate on_top = e.irradiance(top, vec3(0.0, 0.0, -1.0));
        INFO("top " << on_top.value << " +- " << on_top.se << ", exact " << t * std::exp(-2.0 * c));
        CHECK(std::abs(on_top.value - t * std::exp(-2.0 * c)) <= 4.0 * on_top.se);
        const Estimate umbra = e.irradiance({q.in(0.3, 0.7), q.in(0.3, 0.7), depth}, vec3(0.0, 0.0, -1.0));
        CHECK(umbra.value == 0.0);
        CHECK(umbra.se == 0.0);
        // Lit: a point in the frame [-0.2, 0.2] around the section's seam (outside [0.2, 0.8]^2).
        const vec3 lit{q.in(-0.2, 0.2), q.in(0.0, 1.0), depth};
        const Estimate bottom = e.irradiance(lit, vec3(0.0, 0.0, -1.0));
        INFO("bottom " << bottom.value << " +- " << bottom.se << ", exact " << t * std::exp(-depth * c));
        CHECK(std::abs(bottom.value - t * std::exp(-depth * c)) <= 4.0 * bottom.se);
    }
    // The box's sides receive nothing from a vertical sun without scattering.
    CHECK(e.irradiance({0.25, 0.5, 2.25}, vec3(-1.0, 0.0, 0.0)).value == 0.0);
}

TEST_CASE("With scattering the surface map's bottom irradiance is the first pass's bottom Ed; the map changes nothing else") {
    // No objects, w0 = 0.8 forward-peaked water over a reflecting bottom: Ed on the bottom is
    // the same everywhere, so the gather's estimate at any point estimates the first pass's
    // bottom_ed (both from the same photons: the difference's SE is at most the combined SE,
    // used as the bar, 4 of it, at 6 points).
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    auto s = map_settings(100'000);
    const auto r = trace(water, NoGeometry{}, s, 0.3);
    const SurfaceIrradiance e = irradiance_of(r);
    testing::Rand q(43);
    for (int i = 0; i < 6; ++i) {
        const Estimate got = e.irradiance({q.in(0.0, 1.0), q.in(0.0, 1.0), depth}, vec3(0.0, 0.0, -1.0));
        testing::check_agree(got, r.bottom_ed, "bottom Ed, point " + std::to_string(i));
    }
    // Each arrival is on the bottom, wrapped into the section, facing the water.
    for (const SurfacePhoton& p : r.surface_photons) {
        REQUIRE(p.surface == SurfacePhoton::bottom);
        REQUIRE(p.point.z == depth);
        REQUIRE((p.point.x >= 0.0 && p.point.x < width && p.point.y >= 0.0 && p.point.y < width));
    }
    // Off: no arrivals, and the rest of the result bit for bit the same (the map draws no numbers).
    s.surface_map = false;
    const auto off = trace(water, NoGeometry{}, s, 0.3);
    CHECK(off.surface_photons.empty());
    testing::require_identical(r, off);
    // 1 and 2 threads: the same arrivals in the same order.
    s.surface_map = true;
    s.threads = 2;
    const auto two = trace(water, box_above_bottom(0.5), s, 0.3);
    s.threads = 1;
    const auto one = trace(water, box_above_bottom(0.5), s, 0.3);
    REQUIRE(one.surface_photons.size() == two.surface_photons.size());
    CHECK(one.surface_photons.size() > 1000);
    for (std::size_t i = 0; i < one.surface_photons.size(); ++i) {
        const SurfacePhoton &a = one.surface_photons[i], &b = two.surface_photons[i];
        REQUIRE((a.point == b.point && a.normal == b.normal && a.weight == b.weight && a.surface == b.surface &&
                 a.batch == b.batch));
    }
}
