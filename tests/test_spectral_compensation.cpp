// Spectral bias compensation (manual 3.5.2; estimate/spectral_compensation.hpp): the core search
// over all bands sets the brightness, the expanded search per band the shares. Checked: the
// jackknife of a mean is the batch SE; r_spectral = r_core is the per-band estimate; on maps
// whose bands share one light field the compensated estimate agrees with the per-band one and
// its SE is smaller; on uniform maps of known radiance its SE is honest (the scatter of
// independent maps' estimates about the truth); where the shape varies slowly (horizontal rays
// in three waters) it agrees with a 4 times larger per-band run; where the shape varies fast
// (a 0.45 m cylinder across a steep gradient of one band) it carries the documented bias; bad
// radii and one-band maps are refused; the cylinder's one search for every band and both radii
// (manual 3.5.2.3), and the step spheres' one search per band for both, give the per-band
// searches' sums on random rays. Tolerances fixed before the runs.
#include <catch2/catch.hpp>
#include "secchi/estimate/spectral_compensation.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/solver/spectral.hpp"
#include <cmath>
#include <string>
#include <vector>

using namespace secchi;
using Catch::Matchers::Contains;

namespace {
using Water = HomogeneousWater<HenyeyGreensteinPhase>;
using Store = VoiGridStore<CompactRecord>;
constexpr double r_core = 0.05;

HomogeneousRayOptics optics_of(const Water& w) {
    return HomogeneousRayOptics(ConeAveragedPhase(w.phase(), 0.005), w.attenuation(), w.scattering());
}
std::vector<HomogeneousRayOptics> optics_of(const std::vector<Water>& waters) {
    std::vector<HomogeneousRayOptics> out;
    for (const auto& w : waters) out.push_back(optics_of(w));
    return out;
}

/// Three waters of other IOPs and phase functions (as three wavelengths would have).
std::vector<Water> three_waters() {
    return {Water::from_albedo(1.0, 0.9, HenyeyGreensteinPhase(0.8)), Water::from_albedo(0.5, 0.6, HenyeyGreensteinPhase(0.5)),
            Water::from_albedo(1.5, 0.5, HenyeyGreensteinPhase(0.7))};
}

PlaneParallelConfig config(std::uint64_t seed, std::uint64_t photons) {
    PlaneParallelConfig cfg;
    cfg.sun_zenith_deg = 30.0;
    cfg.sky_irradiance = 0.3;
    cfg.transport.depths = {1.0, 2.0};
    cfg.transport.photons = cfg.transport.map_photons = photons;
    cfg.transport.batches = 16;
    cfg.transport.threads = 2;
    cfg.transport.seed = seed;
    cfg.transport.map_depth = 40.0;
    return cfg;
}

/// A k x k grid of nadir rays at depth z over the unit section.
std::vector<Ray> nadir(double z, unsigned k) { return nadir_ray_grid(z, INFINITY, k, 1.0); }

/// Horizontal rays (along x) at depth z, at y = 0.1, 0.3, ..., 0.9.
std::vector<Ray> horizontal(double z) {
    std::vector<Ray> rays;
    for (double y : {0.1, 0.3, 0.5, 0.7, 0.9}) rays.push_back({{0.0, y, z}, {1.0, 0.0, 0.0}, INFINITY});
    return rays;
}

double combined(const Estimate& a, const Estimate& b) { return std::hypot(a.se, b.se); }
}  // namespace

TEST_CASE("The jackknife of a mean of batches is the batch standard error") {
    const std::vector<double> batches{1.0, 3.0, 2.5, 0.5, 4.0, 2.0};
    const Estimate mean = batch_estimate(batches);
    std::vector<double> left_out;
    for (std::size_t b = 0; b < batches.size(); ++b) {
        double s = 0.0;
        for (std::size_t i = 0; i < batches.size(); ++i)
            if (i != b) s += batches[i];
        left_out.push_back(s / static_cast<double>(batches.size() - 1));
    }
    const Estimate jack = jackknife_estimate(mean.value, left_out);
    CHECK(jack.value == mean.value);
    CHECK(jack.se == Approx(mean.se).epsilon(1e-12));
    CHECK(std::isinf(jackknife_estimate(1.0, std::vector<double>{1.0}).se));
}

TEST_CASE("Spectral compensation with r_spectral = r_core is the per-band estimate") {
    const auto waters = three_waters();
    const auto run = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, config(5, 20000), Radius(r_core));
    const SpectralCompensationEstimator est(run.map, VoiCylinder(0.0, INFINITY), optics_of(waters),
                                            SpectralCompensation{r_core, r_core});
    // A nadir grid in the water, and a view from the air (Fresnel-weighted photons and the sky).
    for (const auto& rays : {nadir(1.0, 4), nadir(-0.01, 4)}) {
        const std::vector<Estimate> compensated = est.average(rays, 2);
        REQUIRE(compensated.size() == 3);
        for (unsigned k = 0; k < 3; ++k) {
            const Estimate band = est.core().average(rays, k, 2);
            INFO("band " << k << " z " << rays[0].origin.z);
            CHECK(compensated[k].value == Approx(band.value).epsilon(1e-12));
            CHECK(compensated[k].se == Approx(band.se).epsilon(1e-9));
        }
    }
    // One ray: radiance() is average() of that ray.
    const Ray ray{{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, INFINITY};
    const std::vector<Estimate> one = est.radiance(ray);
    for (unsigned k = 0; k < 3; ++k) CHECK(one[k].value == Approx(est.core().radiance(ray, k).value).epsilon(1e-12));
}

namespace {
/// Property test of SpectralCompensationEstimator's shared searches (manual 3.5.2.3) with
/// `volume`: five edge rays and 60 random ones (in the water and from the air, any direction,
/// finite or unbounded, across the periodic section's seams, up to the surface with its
/// internal reflection and down to a Lambertian bottom at 3 m), r_spectral = r_core and 0.12,
/// on a map of three waters whose segments end at different lengths, against the definition
/// made here from the per-band estimators at each radius (2 x 3 searches per segment): the
/// same compensated values, SEs and photon counts; the sums may differ only in their order
/// (images across a seam), so within 1e-12.
template <class Volume>
void check_shared_searches(const Volume& volume) {
    const auto waters = three_waters();
    PlaneParallelConfig cfg = config(51, 20000);
    cfg.bottom = Bottom::lambertian_at(3.0, 0.3);
    const auto run = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, cfg, Radius(r_core));
    for (const double spectral_radius : {r_core, 0.12}) {
        const SpectralCompensationEstimator est(run.map, volume, optics_of(waters), SpectralCompensation{r_core, spectral_radius});
        // The edges first: a ray of length 0, one from the air stopped above the surface, one
        // straight up (the surface's reflection at normal incidence), one straight down to the
        // bottom, one along a seam of the section; then random rays.
        const std::vector<Ray> edges{{{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, 0.0},
                                     {{0.5, 0.5, -0.5}, {0.0, 0.0, 1.0}, 0.2},
                                     {{0.3, 0.7, 1.5}, {0.0, 0.0, -1.0}, INFINITY},
                                     {{0.3, 0.7, 1.5}, {0.0, 0.0, 1.0}, INFINITY},
                                     {{0.0, 0.4, 1.0}, {0.0, 1.0, 0.0}, 2.5}};
        PhotonRng rng(61, 0);
        for (int i = 0; i < 60 + static_cast<int>(edges.size()); ++i) {
            const double cos_theta = 2.0 * rng.uniform() - 1.0, phi = 2.0 * pi * rng.uniform();
            const vec3 d(sin_from_cos(cos_theta) * std::cos(phi), sin_from_cos(cos_theta) * std::sin(phi), cos_theta);
            const double z = i % 5 == 0 ? -0.05 : 0.02 + 2.9 * rng.uniform();
            const Ray ray = i < static_cast<int>(edges.size())
                                ? edges[static_cast<std::size_t>(i)]
                                : Ray{{rng.uniform(), rng.uniform(), z}, d, i % 3 == 0 ? INFINITY : 0.1 + 4.0 * rng.uniform()};
            CompensatedSum one_search = est.empty_sum(), per_band = est.empty_sum();
            est.add(ray, 1.0, one_search);
            std::vector<RadianceSum> at_core(3, RadianceSum(run.map.batches())), at_spectral(3, RadianceSum(run.map.batches()));
            for (unsigned k = 0; k < 3; ++k) {
                est.core().add(ray, k, 1.0, at_core[k]);
                est.spectral().add(ray, k, 1.0, at_spectral[k]);
            }
            per_band.add_ray(at_core, at_spectral, 1.0);
            INFO(volume.name() << ", ray " << i << " from (" << ray.origin.x << ", " << ray.origin.y << ", " << ray.origin.z
                               << ") along (" << ray.direction.x << ", " << ray.direction.y << ", " << ray.direction.z
                               << "), t_max " << ray.t_max << ", r_spectral " << spectral_radius);
            CHECK(one_search.photons_touched() == per_band.photons_touched());
            for (unsigned k = 0; k < 3; ++k) {
                const Estimate a = one_search.estimate(k), b = per_band.estimate(k);
                CHECK(a.value == Approx(b.value).epsilon(1e-12).margin(1e-300));
                CHECK(a.se == Approx(b.se).epsilon(1e-9).margin(1e-300));
            }
        }
    }
}
}  // namespace

TEST_CASE("One search for every band and both radii gives the sums of the per-band searches (manual 3.5.2.3)") {
    // VoiCylinder's gather_nested: one search per segment for all three bands.
    check_shared_searches(VoiCylinder(0.0, 3.0));
}

TEST_CASE("Step spheres: one search per band for both radii gives the sums of the per-band searches") {
    // StepSpheres' gather_nested: its spheres follow each band's segment, so one search per
    // band's segment, at the spectral radius, serves both radii.
    check_shared_searches(StepSpheres(16, 0.0, 3.0));
}

TEST_CASE("The nested sums refuse a band's segment longer than the searched ray, and step spheres a shorter one") {
    const auto waters = three_waters();
    const auto run = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, config(81, 2000), Radius(r_core));
    const PathRadianceEstimator path(run.map, VoiCylinder(0.0, INFINITY), optics_of(waters), Radius(0.1));
    std::vector<double> outer(3 * run.map.batches()), inner(3 * run.map.batches());
    const Ray ray{{0.5, 0.5, 1.0}, {0.0, 0.0, 1.0}, 1.0};
    CHECK_NOTHROW(path.accumulate_nested(ray, std::vector<double>{1.0, 0.5, -INFINITY}, Radius(r_core), outer, inner));
    CHECK_THROWS_WITH(path.accumulate_nested(ray, std::vector<double>{1.0, 1.5, 0.5}, Radius(r_core), outer, inner),
                      Contains("band segment length (m) = 1.5") && Contains("searched ray's length"));
    CHECK_THROWS_WITH(path.accumulate_nested(ray, std::vector<double>{1.0, 0.5, 0.5}, Radius(0.2), outer, inner),
                      Contains("inner radius (m) = 0.2"));
    // Step spheres follow the segment's length: a shorter segment's spheres are not the searched ray's.
    const PathRadianceEstimator spheres(run.map, StepSpheres(8), optics_of(waters), Radius(0.1));
    CHECK_NOTHROW(spheres.accumulate_nested(ray, std::vector<double>{-INFINITY, 1.0, -INFINITY}, Radius(r_core), outer, inner));
    CHECK_THROWS_WITH(spheres.accumulate_nested(ray, std::vector<double>{1.0, 0.5, -INFINITY}, Radius(r_core), outer, inner),
                      Contains("band segment length (m) = 0.5") && Contains("spheres(8) follows the segment's length"));
}

TEST_CASE("Bands of one light field: the compensated estimate agrees with the per-band one, with a smaller SE") {
    // Three bands of the same water (independent photons): the same light field in each. A 5 x 5
    // nadir grid (rays 0.2 m apart) with r_spectral = 0.1: the rays' spectral cylinders are
    // disjoint. Expected SE ratio ~ sqrt(1/3 + (2/3) (r_core / r_spectral)^2) = 0.71 (the core
    // total from 3 bands' photons, the shares from 4 times the area).
    const Water water = three_waters()[0];
    const std::vector<Water> waters(3, water);
    const auto run = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, config(11, 60000), Radius(r_core));
    const SpectralCompensationEstimator est(run.map, VoiCylinder(0.0, INFINITY), optics_of(waters),
                                            SpectralCompensation{r_core, 0.1});
    double se2_compensated = 0.0, se2_band = 0.0;
    for (double z : {1.0, 2.0}) {
        const std::vector<Estimate> compensated = est.average(nadir(z, 5), 2);
        for (unsigned k = 0; k < 3; ++k) {
            const Estimate band = est.core().average(nadir(z, 5), k, 2);
            INFO("z " << z << " band " << k << ": compensated " << compensated[k].value << " +- " << compensated[k].se
                      << ", per band " << band.value << " +- " << band.se << ", SE ratio " << compensated[k].se / band.se);
            CHECK(std::isfinite(compensated[k].se));
            CHECK(compensated[k].se > 0.0);
            CHECK(std::abs(compensated[k].value - band.value) <= 3.0 * combined(compensated[k], band));
            se2_compensated += compensated[k].se * compensated[k].se;
            se2_band += band.se * band.se;
        }
    }
    const double ratio = std::sqrt(se2_compensated / se2_band);
    WARN("SE ratio compensated / per band (rms over 2 depths x 3 bands): " << ratio);
    CHECK(ratio < 0.85);
}

TEST_CASE("Uniform maps of known radiance: the compensated estimate is unbiased and its SE honest") {
    // Records uniform over the unit cube, band 0, 1, 2 in proportions 3 : 2 : 1, flux 1 each,
    // isotropic phase, attenuation c_k along the ray: a vertical ray of length L has the path
    // radiance n_k (1 - exp(-c_k L)) / (4 pi c_k), n_k the band's records per m^3; the bands'
    // ratios are the same everywhere, so the compensation is unbiased. 10 independent maps,
    // 4 rays each (spectral cylinders disjoint), 3 bands: the z-scores (estimate - truth) / SE
    // must have mean square ~ 1 (a t distribution of 15 degrees of freedom: 15/13), here within
    // [0.6, 1.8], and mean within +-0.5.
    constexpr unsigned batches = 16;
    constexpr std::size_t records_per_map = 60000;
    const std::vector<double> c{0.5, 2.0, 1.0};
    const std::vector<double> share{3.0 / 6.0, 2.0 / 6.0, 1.0 / 6.0};
    const double length = 0.6;
    std::vector<HomogeneousRayOptics> per_band;
    for (double ck : c) per_band.emplace_back(ConeAveragedPhase(IsotropicPhase{}, 0.005), ck, 0.0);
    std::vector<Ray> rays;
    for (double x : {0.25, 0.75})
        for (double y : {0.25, 0.75}) rays.push_back({{x, y, 0.2}, {0.0, 0.0, 1.0}, length});

    double z2_compensated = 0.0, z_compensated = 0.0, z2_band = 0.0, ratio2 = 0.0;
    int n = 0;
    for (std::uint64_t map_seed = 1; map_seed <= 10; ++map_seed) {
        PhotonRng rng(map_seed, 7);
        std::vector<CompactRecord> records;
        for (std::size_t i = 0; i < records_per_map; ++i) {
            const std::size_t six = i % 6;
            const auto band = static_cast<band_index>(six < 3 ? 0 : six < 5 ? 1 : 2);
            const vec3 p(rng.uniform(), rng.uniform(), rng.uniform());
            const auto batch = static_cast<std::uint8_t>(std::min<double>(batches - 1, std::floor(rng.uniform() * batches)));
            records.push_back(CompactRecord::make(p, vec3(0.0, 0.0, 1.0), band, batch));
        }
        const PhotonMap map(Store(std::move(records), Radius(r_core)), RecordFlux::uniform(1.0), batches,
                            MapScene::open_water(1.0), Estimate{}, std::vector<double>{450.0, 550.0, 650.0});
        const SpectralCompensationEstimator est(map, VoiCylinder(0.0, INFINITY), per_band, SpectralCompensation{r_core, 0.2});
        for (const Ray& ray : rays) {
            const std::vector<Estimate> compensated = est.radiance(ray);
            for (unsigned k = 0; k < 3; ++k) {
                const double density = share[k] * static_cast<double>(records_per_map);  // per m^3
                const double truth = density * (1.0 - std::exp(-c[k] * length)) / (4.0 * pi * c[k]);
                const Estimate band = est.core().radiance(ray, k);
                const double z = (compensated[k].value - truth) / compensated[k].se;
                z2_compensated += z * z;
                z_compensated += z;
                z2_band += (band.value - truth) * (band.value - truth) / (band.se * band.se);
                ratio2 += compensated[k].se * compensated[k].se / (band.se * band.se);
                ++n;
            }
        }
    }
    const double mean_z2 = z2_compensated / n, mean_z = z_compensated / n;
    WARN("uniform maps, " << n << " estimates: compensated mean z^2 " << mean_z2 << ", mean z " << mean_z
                          << "; per band mean z^2 " << z2_band / n << "; rms SE ratio " << std::sqrt(ratio2 / n));
    CHECK(mean_z2 >= 0.6);
    CHECK(mean_z2 <= 1.8);
    CHECK(std::abs(mean_z) <= 0.5);
}

TEST_CASE("Slowly varying spectral shape: compensation unbiased against a larger per-band run") {
    // Horizontal rays at 1.5 m in three waters whose radiances fall with depth at different
    // rates: the bands' ratios vary across the r_spectral = 0.1 m cylinder by about
    // exp(+-dK r), with the share's bias ~ dK^2 r^2 / 8 < 1e-3 (dK < 1 /m): far below the SE.
    // Compensated from 40000 photons per band; per band (r_core) from an independent map of
    // 160000 per band. Within 3 combined SE, every band.
    const auto waters = three_waters();
    const std::vector<double> wavelengths{450.0, 550.0, 650.0};
    const auto small = trace_spectral_map<Store>(waters, wavelengths, config(21, 40000), Radius(r_core));
    const auto large = trace_spectral_map<Store>(waters, wavelengths, config(22, 160000), Radius(r_core));
    const SpectralCompensationEstimator est(small.map, VoiCylinder(0.0, INFINITY), optics_of(waters),
                                            SpectralCompensation{r_core, 0.1});
    const RadianceEstimator reference(large.map, VoiCylinder(0.0, INFINITY), optics_of(waters), Radius(r_core));
    const std::vector<Estimate> compensated = est.average(horizontal(1.5), 2);
    for (unsigned k = 0; k < 3; ++k) {
        const Estimate ref = reference.average(horizontal(1.5), k, 2);
        const Estimate band = est.core().average(horizontal(1.5), k, 2);
        INFO("band " << k << ": compensated " << compensated[k].value << " +- " << compensated[k].se << ", reference "
                     << ref.value << " +- " << ref.se << ", same map per band " << band.value << " +- " << band.se);
        CHECK(std::abs(compensated[k].value - ref.value) <= 3.0 * combined(compensated[k], ref));
        CHECK(compensated[k].se < band.se);
    }
}

TEST_CASE("Fast-varying spectral shape: the documented bias of a wide spectral search") {
    // Two bands: clear scattering water (c = 1, albedo 0.9, g = 0.8: K ~ 0.2 /m) and turbid
    // absorbing water (c = 6, albedo 0.5, K ~ 3-4 /m). Horizontal rays at 0.5 m with r_spectral = 0.45: the cylinder spans
    // 0.05-0.95 m, over which the turbid band's radiance changes ~20-fold. Its disk average is
    // 2 I_1(K r) / (K r) ~ 1.3-1.5 times the axis' value (more where the radiance steepens
    // towards the surface), the clear band's ~1: the turbid band's share comes out high by 30 %
    // or more, the clear band's low by its small share of that. The compensated turbid band must
    // exceed the per-band estimate by more than 3 combined SE.
    const std::vector<Water> waters{Water::from_albedo(1.0, 0.9, HenyeyGreensteinPhase(0.8)),
                                    Water::from_albedo(6.0, 0.5, HenyeyGreensteinPhase(0.8))};
    PlaneParallelConfig cfg = config(31, 80000);
    cfg.transport.depths = {0.5};
    const auto run = trace_spectral_map<Store>(waters, {450.0, 650.0}, cfg, Radius(r_core));
    const SpectralCompensationEstimator est(run.map, VoiCylinder(0.0, INFINITY), optics_of(waters),
                                            SpectralCompensation{r_core, 0.45});
    const std::vector<Estimate> compensated = est.average(horizontal(0.5), 2);
    const Estimate turbid = est.core().average(horizontal(0.5), 1, 2);
    const Estimate clear = est.core().average(horizontal(0.5), 0, 2);
    WARN("fast-varying shape: turbid band compensated " << compensated[1].value << " +- " << compensated[1].se
                                                         << ", per band " << turbid.value << " +- " << turbid.se
                                                         << "; clear band compensated " << compensated[0].value << " +- "
                                                         << compensated[0].se << ", per band " << clear.value << " +- "
                                                         << clear.se);
    CHECK(compensated[1].value - turbid.value > 3.0 * combined(compensated[1], turbid));
}

TEST_CASE("Spectral compensation refuses bad radii and maps of one band") {
    const auto waters = three_waters();
    const auto run = trace_spectral_map<Store>(waters, {450.0, 550.0, 650.0}, config(41, 2000), Radius(r_core));
    const auto per_band = optics_of(waters);
    const auto build = [&](double core, double spectral) {
        return SpectralCompensationEstimator(run.map, VoiCylinder(0.0, INFINITY), per_band, SpectralCompensation{core, spectral});
    };
    CHECK_THROWS_AS(build(0.1, 0.05), input_error);
    CHECK_THROWS_WITH(build(0.1, 0.05), Contains("spectral radius (m) = 0.05") && Contains("core radius"));
    CHECK_THROWS_WITH(build(0.0, 0.1), Contains("core radius (m) = 0"));
    CHECK_THROWS_WITH(build(-0.05, 0.1), Contains("core radius (m) = -0.05"));
    CHECK_THROWS_WITH(build(NAN, 0.1), Contains("core radius (m) = nan"));
    CHECK_THROWS_WITH(build(0.05, 0.0), Contains("spectral radius (m) = 0"));
    CHECK_THROWS_WITH(build(0.05, INFINITY), Contains("spectral radius (m) = inf"));
    CHECK_THROWS_WITH(build(0.05, 0.5), Contains("spectral radius (m) = 0.5") && Contains("half the section width"));
    CHECK_THROWS_WITH(SpectralCompensationEstimator(run.map, VoiCylinder(0.0, INFINITY), std::vector{per_band[0]},
                                                    SpectralCompensation{0.05, 0.1}),
                      Contains("optics per band"));

    const auto one = trace_spectral_map<Store>(std::vector{waters[0]}, {450.0}, config(41, 2000), Radius(r_core));
    CHECK_THROWS_AS(SpectralCompensationEstimator(one.map, VoiCylinder(0.0, INFINITY), per_band[0], SpectralCompensation{0.05, 0.1}),
                    input_error);
    CHECK_THROWS_WITH(SpectralCompensationEstimator(one.map, VoiCylinder(0.0, INFINITY), per_band[0], SpectralCompensation{0.05, 0.1}),
                      Contains("bands = 1"));
}
