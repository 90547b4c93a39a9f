// Spectral runs (solver/spectral.hpp): several bands in one photon map, each band's photons
// traced through its own water and estimated with its own optics. A 3-band run must equal three
// 1-band runs (independent photons) within 3 combined standard errors for every irradiance and
// for Lu; band 0 of a spectral run is the plain run of the same seed; the map refuses bands it
// lacks. Tolerances fixed before the runs.
#include <catch2/catch.hpp>
#include "secchi/estimate/radiance.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/solver/spectral.hpp"
#include <cmath>
#include <string>
#include <vector>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
using Water = HomogeneousWater<HenyeyGreensteinPhase>;
using Store = VoiGridStore<CompactRecord>;
constexpr double radius = 0.05;
const std::vector<double> depths{1.0, 2.0};

/// Three waters of other IOPs and phase functions (as three wavelengths would have).
std::vector<Water> three_waters() {
    return {Water::from_albedo(1.0, 0.9, HenyeyGreensteinPhase(0.8)), Water::from_albedo(0.5, 0.6, HenyeyGreensteinPhase(0.5)),
            Water::from_albedo(1.5, 0.5, HenyeyGreensteinPhase(0.7))};
}

HomogeneousRayOptics optics_of(const Water& w) {
    return HomogeneousRayOptics(ConeAveragedPhase(w.phase(), 0.005), w.attenuation(), w.scattering());
}

PlaneParallelConfig config(std::uint64_t seed) {
    PlaneParallelConfig cfg;
    cfg.sun_zenith_deg = 30.0;
    cfg.sky_irradiance = 0.3;
    cfg.transport.depths = depths;
    cfg.transport.photons = cfg.transport.map_photons = 60000;
    cfg.transport.batches = 16;
    cfg.transport.threads = 2;
    cfg.transport.seed = seed;
    cfg.transport.map_depth = 40.0;
    return cfg;
}

/// Lu at depth z in band k: the whole radiance of a 10 x 10 grid of nadir rays.
template <class Estimator>
Estimate lu(const Estimator& est, double z, unsigned band) {
    return est.average(nadir_ray_grid(z, INFINITY, 10, 1.0), band, 2);
}

void check_agree(const Estimate& a, const Estimate& b, const std::string& what) {
    INFO(what << ": " << a.value << " +- " << a.se << " vs " << b.value << " +- " << b.se);
    CHECK(a.se < 0.05 * a.value);
    CHECK(std::abs(a.value - b.value) <= 3.0 * std::hypot(a.se, b.se));
}
}  // namespace

TEST_CASE("A 3-band run equals three 1-band runs within their combined SE (every irradiance, Lu)") {
    const auto waters = three_waters();
    const auto spectral = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, config(5), Radius(radius));
    REQUIRE(spectral.map.bands() == 3);
    std::vector<HomogeneousRayOptics> per_band;
    for (const auto& w : waters) per_band.push_back(optics_of(w));
    const RadianceEstimator est(spectral.map, VoiCylinder(0.0, INFINITY), per_band, Radius(radius));
    for (unsigned k = 0; k < 3; ++k) {
        const auto single = trace_photon_map<Store>(waters[k], config(100 + k), Radius(radius));
        const RadianceEstimator one(single.map, VoiCylinder(0.0, INFINITY), optics_of(waters[k]), Radius(radius));
        for (std::size_t i = 0; i < depths.size(); ++i) {
            const std::string at = "band " + std::to_string(k) + " z " + std::to_string(depths[i]);
            for (int q = 0; q < 4; ++q)
                check_agree(spectral.first_pass[k].depths[i].irradiance[q], single.first_pass.depths[i].irradiance[q],
                            at + " irradiance " + std::to_string(q));
            check_agree(lu(est, depths[i], k), lu(one, depths[i], 0), at + " Lu");
        }
    }
}

TEST_CASE("Band 0 of a spectral run is the plain run of the same seed; bands the map lacks are refused") {
    const auto waters = three_waters();
    const auto spectral = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, config(7), Radius(radius));
    const auto plain = trace_photon_map<Store>(waters[0], config(7), Radius(radius));
    std::vector<HomogeneousRayOptics> per_band;
    for (const auto& w : waters) per_band.push_back(optics_of(w));
    const RadianceEstimator est(spectral.map, VoiCylinder(0.0, INFINITY), per_band, Radius(radius));
    const RadianceEstimator one(plain.map, VoiCylinder(0.0, INFINITY), optics_of(waters[0]), Radius(radius));
    for (std::size_t i = 0; i < depths.size(); ++i)
        for (int q = 0; q < 4; ++q)
            CHECK(spectral.first_pass[0].depths[i].irradiance[q].value == plain.first_pass.depths[i].irradiance[q].value);
    // The same photons, summed in the store's order among the other bands' photons.
    const Estimate a = lu(est, 2.0, 0), b = lu(one, 2.0, 0);
    CHECK(a.value == Approx(b.value).epsilon(1e-12));
    CHECK(a.se == Approx(b.se).epsilon(1e-9));
    // The direct sun in band 2 is attenuated by band 2's water (c' of its optics) along the beam.
    const DirectBeam top = est.direct_sun({0.5, 0.5, 0.0}, 2), at2 = est.direct_sun({0.5, 0.5, 2.0}, 2);
    CHECK(at2.e_perp == Approx(top.e_perp * std::exp(-per_band[2].attenuation * 2.0 / at2.direction.z)).epsilon(1e-9));

    CHECK_THROWS_WITH(est.radiance({{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, INFINITY}, 3), Contains("band") && Contains("3"));
    CHECK_THROWS_WITH(RadianceEstimator(spectral.map, VoiCylinder(0.0, INFINITY), std::vector{optics_of(waters[0])}, Radius(radius)),
                      Contains("optics per band"));
    CHECK_THROWS_WITH(trace_spectral_map<Store>(waters, {450.0, 550.0}, config(7), Radius(radius)), Contains("wavelengths"));
}
