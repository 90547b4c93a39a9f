// A bounded water body (scene/tank.hpp): the walls along the section's edges make each periodic
// copy a closed tank. Under a low sun in non-scattering water the band of the floor in the
// shadow of the sun-side wall is exactly dark (light from the neighbouring copy, which would
// light it without walls, is stopped) and the rest of the floor is Beer-Lambert; with
// scattering the energy ledger closes with what the walls absorb; bad tanks are refused.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/fresnel.hpp"
#include "secchi/scene/tank.hpp"
#include "secchi/transport/tracer.hpp"
#include "transport_checks.hpp"
#include <cmath>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <class Water, SceneGeometry G>
using ObjectTracer = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, G>;

/// A tank 2 m wide and 1 m deep, walls 0.1 m thick (a 2.2 m section), black floor.
const Tank tank{2.0, 0.1, 1.0, ObjectMaterial::absorbing()};
constexpr unsigned bins = 22;  // 0.1 m: the walls fill bins 0 and 21

template <class Water, SceneGeometry G>
TransportResult<CompactRecord> trace(const Water& water, const G& g, TransportSettings s, double zenith_deg) {
    return ObjectTracer<Water, G>(water, Slab(tank.section_width(), Bottom::lambertian_at(tank.depth, 0.0)),
                                  FlatSurface(1.34), SunAndSky(CollimatedSun(zenith_deg)), s, g)
        .run();
}
}  // namespace

TEST_CASE("A tank's walls keep its neighbours' light out: the shadow of a low sun's wall is exactly dark") {
    // Sun at 40 deg from the +x side (its light travels towards -x), c = 0.2 1/m, w0 = 0,
    // continuous absorption: light crosses the surface at x_s and reaches the floor at
    // x_s - D tan(theta_w), sin(theta_w) = sin(40 deg) / 1.34. Floor points within D tan(theta_w)
    // = 0.547 m of the +x wall (x in (1.553, 2.1)) would be lit through the wall's place from
    // the next copy: with walls they are dark, bins 16-20 exactly 0; bins 1-14 (x in [0.1, 1.5])
    // are lit, their mean Ed(0+) (1 - R(40 deg)) exp(-c D / cos(theta_w)), Ed(0+) = E_perp cos(40 deg)
    // with E_perp = 1 (the results' unit), within 4 SE (SE of the mean
    // from the bins' own, sqrt(sum se^2) / n); the floor under the walls reads 0.
    const double c = 0.2, zenith = 40.0;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    TransportSettings s;
    s.photons = 400'000;
    s.map_photons = 0;
    s.depths = {0.5};
    s.bottom_bins = bins;
    s.absorption = AbsorptionMode::continuous;
    s.roulette_weight = 0.0;
    const auto r = trace(water, tank.walls(), s, zenith);
    const double sin_w = std::sin(zenith * deg) / 1.34, cos_w = std::sqrt(1.0 - sin_w * sin_w);
    const double lit = std::cos(zenith * deg) * (1.0 - fresnel_reflectance(std::cos(zenith * deg), 1.0, 1.34)) *
                       std::exp(-c * tank.depth / cos_w);
    double sum = 0.0, se2 = 0.0;
    int n_lit = 0;
    for (unsigned iy = 0; iy < bins; ++iy)
        for (unsigned ix = 0; ix < bins; ++ix) {
            const Estimate& e = r.bottom_ed_bins[iy * bins + ix];
            INFO("bin " << ix << ", " << iy << ": " << e.value);
            const bool wall = ix == 0 || ix == bins - 1 || iy == 0 || iy == bins - 1;
            if (wall || (ix >= 16 && ix <= 20)) {
                CHECK(e.value == 0.0);
            } else if (ix <= 14) {
                sum += e.value;
                se2 += e.se * e.se;
                ++n_lit;
            }
        }
    const double mean = sum / n_lit, se = std::sqrt(se2) / n_lit;
    INFO("lit floor " << mean << " +- " << se << ", Beer-Lambert " << lit);
    CHECK(std::abs(mean - lit) <= 4.0 * se);
    CHECK(r.ledger.absorbed_objects > 0.0);
    CHECK(std::abs(r.ledger.imbalance()) <= 1e-12);
    // Without the walls the same band is lit (the copies' light crosses the seam).
    const auto open = trace(water, NoGeometry{}, s, zenith);
    for (unsigned ix = 16; ix <= 20; ++ix) CHECK(open.bottom_ed_bins[10 * bins + ix].value > 0.5 * lit);
}

TEST_CASE("A tank with scattering: the ledger closes with what the walls absorb, threads agree; bad tanks refused") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const Tank grey{2.0, 0.1, 1.0, ObjectMaterial::lambertian(0.4)};
    TransportSettings s;
    s.photons = 40'000;
    s.map_photons = 10'000;
    s.depths = {0.5};
    s.block_size = 1000;
    const auto one = trace(water, grey.walls(), s, 30.0);
    CHECK(std::abs(one.ledger.imbalance()) <= 1e-9 * one.ledger.incident);
    CHECK(one.ledger.absorbed_objects > 0.0);
    s.threads = 2;
    testing::require_identical(one, trace(water, grey.walls(), s, 30.0));
    CHECK_THROWS_WITH((Tank{0.0, 0.1, 1.0}.walls()), Contains("tank inner width (m) = 0"));
    CHECK_THROWS_WITH((Tank{2.0, 0.0, 1.0}.walls()), Contains("tank wall thickness (m) = 0"));
    CHECK_THROWS_WITH((Tank{2.0, 0.1, -1.0}.walls()), Contains("tank depth (m) = -1"));
    // The walls reach the floor: a slab whose floor is above them is refused by the tracer.
    CHECK_THROWS_WITH((ObjectTracer<HgWater, Shapes>(water, Slab(2.2, Bottom::lambertian_at(0.5, 0.0)), FlatSurface(1.34),
                                                     SunAndSky(CollimatedSun(30.0)), s, grey.walls())),
                      Contains("object bounds' bottom depth"));
}
