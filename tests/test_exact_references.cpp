// The whole solver against an independent, exact solution: plane-parallel, homogeneous,
// infinitely deep water under an index-matched top (no Fresnel interface), sun at nadir,
// black sky, solved by the discrete-ordinate method (DISORT, 256 streams; the values in
// disort_reference.hpp come from scripts/disort_reference.py, an independent solver that
// shares no code with secchi). Each case checks what a defect once got wrong:
//  - weakly absorbing, forward-scattering water (w0 = 0.99, HG g = 0.9): diffuse light returns
//    from far below the deepest detector, attenuated by the diffuse attenuation (~0.06 /m
//    here), not by c; a cut-off counted in attenuation lengths of c lost 1-4 % of Eu, Eou and
//    Lu at tau 0-10;
//  - scalar irradiance at the top boundary of strongly scattering water (w0 = 0.9, 0.99;
//    isotropic, Rayleigh, HG 0.5): averaged over a layer below the boundary, where the
//    diffuse radiance rises steeply, Eod read 2-5 % high at tau 0;
//  - the nadir radiance in forward-peaked, absorbing water (HG g = 0.9, w0 = 0.2), and with
//    upward importance at every depth, where without it the estimate is heavy-tailed.
// Tolerance: 4 standard errors of ours plus the reference's accuracy (2e-4 relative: the
// change between 192 and 256 streams is below that), fixed before the runs.
#include <catch2/catch.hpp>

#include "disort_reference.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/solver/phase_choice.hpp"
#include "secchi/solver/plane_parallel.hpp"

#include <array>
#include <cmath>
#include <string>
#include <vector>

using namespace secchi;

namespace {

constexpr double reference_accuracy = 2e-4;

const test::DisortCase& disort_case(std::string_view phase, double albedo) {
    for (const auto& c : test::disort_cases)
        if (c.phase == phase && c.albedo == albedo) return c;
    FAIL("no DISORT case " << phase << " w0 = " << albedo);
    return test::disort_cases.front();
}

struct Budget {
    std::uint64_t photons, map_photons;
};

PlaneParallelResult run_case(const test::DisortCase& c, Budget budget, DepthImportance importance = {},
                             double backscatter_bias = 0.0, double upward_importance = 0.0) {
    PlaneParallelConfig cfg;
    cfg.attenuation = 1.0;
    cfg.albedo = c.albedo;
    cfg.sun_zenith_deg = c.sun_zenith_deg;
    cfg.water_index = 1.0;  // index-matched: no interface
    cfg.transport.depths.assign(c.tau.begin(), c.tau.end());
    cfg.transport.photons = budget.photons;
    cfg.transport.map_photons = budget.map_photons;
    cfg.transport.threads = 2;
    cfg.transport.seed = 11;
    cfg.transport.importance = importance;
    cfg.transport.backscatter_bias = backscatter_bias;
    cfg.transport.upward_importance = upward_importance;  // lobe: the default g = 0.9
    cfg.store = StoreKind::voi_grid;
    // The DISORT cases' phase functions only (each type instantiates the whole simulation).
    return std::visit([&](const auto& p) { return solve_plane_parallel(p, cfg); },
                      parse_phase_among<IsotropicPhase, RayleighPhase, HenyeyGreensteinPhase>(
                          "phase", std::string(c.phase), "isotropic, rayleigh or hg:G"));
}

/// |ours - exact| <= 4 SE + the reference's accuracy.
void check_against(const Estimate& ours, double exact, const std::string& what) {
    INFO(what << ": ours " << ours.value << " +- " << ours.se << ", exact " << exact << " ("
              << 100.0 * (ours.value / exact - 1.0) << " %)");
    CHECK(ours.se > 0.0);
    CHECK(std::abs(ours.value - exact) <= 4.0 * ours.se + reference_accuracy * exact);
}

void check_irradiances(const test::DisortCase& c, const PlaneParallelResult& r) {
    for (std::size_t i = 0; i < c.tau.size(); ++i) {
        const std::string at = std::string(c.phase) + " w0 " + std::to_string(c.albedo) + " tau " + std::to_string(c.tau[i]);
        const auto& e = r.depths[i].irradiance;
        if (c.tau[i] > 0.0) check_against(e[Ed], c.ed[i], "Ed " + at);  // Ed(0) = 1 exactly, SE 0
        check_against(e[Eu], c.eu[i], "Eu " + at);
        if (c.tau[i] > 0.0) check_against(e[Eod], c.eod[i], "Eod " + at);
        else CHECK(e[Eod].value == Approx(c.eod[i]).epsilon(1e-12));  // only the sun crosses the top going down
        check_against(e[Eou], c.eou[i], "Eou " + at);
    }
}

}  // namespace

TEST_CASE("infinitely deep, weakly absorbing, forward-scattering water: irradiances and Lu at tau 0-10 (DISORT)") {
    const auto& c = disort_case("hg:0.9", 0.99);
    const auto r = run_case(c, {200'000, 20'000});
    check_irradiances(c, r);
    for (std::size_t i = 0; i < c.tau.size(); ++i) check_against(r.depths[i].lu, c.lu[i], "Lu tau " + std::to_string(c.tau[i]));
}

TEST_CASE("scalar irradiance at the top boundary of strongly scattering water (DISORT)") {
    for (const auto& [phase, albedo] : {std::pair{"isotropic", 0.9}, {"isotropic", 0.99}, {"rayleigh", 0.99}, {"hg:0.5", 0.9}}) {
        const auto& c = disort_case(phase, albedo);
        check_irradiances(c, run_case(c, {200'000, 0}));
    }
}

TEST_CASE("canonical problem 2a's nadir radiance against an independent Monte Carlo") {
    // scripts/independent_lu_check.py (numpy, no secchi code): plane-parallel photons with
    // their direction cosine only, the canonical Petzold function, a flat Fresnel surface,
    // and the collision estimate of Lu from every scattering event (no map, no collection
    // volume). 4e6 photons, seed 7, with the peak within 2.29 deg transmitted as secchi does
    // (with 5 deg: the same to 0.1-0.3 %, so the truncation is not what either measures):
    // Lu = 6.8541e-3 (0.3 %), 3.1428e-3 (0.4 %), 1.1405e-3 (0.4 %) at tau 1, 5, 10. With the
    // peak averaged over the cone instead, the map's estimate rests on the few photons within
    // 2.3 deg of straight up and reads low (that run of the script, psi_t = 0: 2-4 % low).
    constexpr std::array<double, 3> tau{1.0, 5.0, 10.0}, lu{6.8541e-3, 3.1428e-3, 1.1405e-3}, rel_se{0.003, 0.004, 0.004};
    PlaneParallelConfig cfg;  // sun at 60 deg, n = 1.34
    cfg.albedo = 0.9;
    cfg.water_index = 1.34;
    cfg.transport.depths.assign(tau.begin(), tau.end());
    cfg.transport.photons = cfg.transport.map_photons = 1'000'000;
    cfg.transport.threads = 2;
    cfg.transport.seed = 11;
    cfg.store = StoreKind::voi_grid;
    const auto r = solve_plane_parallel(petzold_m93(), cfg);
    for (std::size_t i = 0; i < tau.size(); ++i) {
        const Estimate& ours = r.depths[i].lu;
        const double se = std::hypot(ours.se, rel_se[i] * lu[i]);
        INFO("tau " << tau[i] << ": ours " << ours.value << " +- " << ours.se << ", independent " << lu[i]);
        CHECK(std::abs(ours.value - lu[i]) <= 4.0 * se);
    }
}

TEST_CASE("nadir radiance in forward-peaked, absorbing water, HG g = 0.9, w0 = 0.2 (DISORT)") {
    const auto& c = disort_case("hg:0.9", 0.2);
    const auto r = run_case(c, {4'000'000, 4'000'000});
    check_irradiances(c, r);
    for (std::size_t i = 0; i < c.tau.size(); ++i)
        if (c.tau[i] <= 2.0) check_against(r.depths[i].lu, c.lu[i], "Lu tau " + std::to_string(c.tau[i]));
}

TEST_CASE("depth importance in homogeneous water: the map carries 1/I(z), Lu stays exact (DISORT)") {
    // Photons split by depth (I(z) = 2^L(z), transport/importance.hpp) store I(z) times as many
    // records at depth, each carrying Phi / I(z): the map's own normalisation (RecordFlux), which
    // every estimator applies. (Applied by the optics instead, homogeneous water once forgot
    // it and read Lu 240 times too high.)
    const auto& c = disort_case("hg:0.9", 0.2);
    const auto r = run_case(c, {1'000'000, 1'000'000}, DepthImportance{1.0, 5.0});
    check_irradiances(c, r);
    for (std::size_t i = 0; i < c.tau.size(); ++i)
        if (c.tau[i] <= 2.0) check_against(r.depths[i].lu, c.lu[i], "Lu tau " + std::to_string(c.tau[i]));
}

TEST_CASE("backscatter bias with depth importance: irradiances and Lu stay exact (DISORT)") {
    // With depth importance down to tau 10, a fifth of the scattering events draws its angle
    // from the phase function's backward part,
    // the weights corrected (transport/importance.hpp, BackscatterBias): every irradiance and Lu
    // against the exact solution, and, at equal photons, Eu and Eou at tau 5 and 10 carried by
    // more photons than without the bias (their SE below the unbiased run's).
    const auto& c = disort_case("hg:0.9", 0.2);
    const auto biased = run_case(c, {1'000'000, 1'000'000}, DepthImportance{1.0, 10.0}, 0.2);
    check_irradiances(c, biased);
    for (std::size_t i = 0; i < c.tau.size(); ++i)
        if (c.tau[i] <= 2.0) check_against(biased.depths[i].lu, c.lu[i], "Lu tau " + std::to_string(c.tau[i]));
    const auto plain = run_case(c, {1'000'000, 1'000'000}, DepthImportance{1.0, 10.0});
    for (std::size_t i = 0; i < c.tau.size(); ++i) {
        if (c.tau[i] < 5.0) continue;
        INFO("tau " << c.tau[i]);
        CHECK(biased.depths[i].irradiance[Eou].se < plain.depths[i].irradiance[Eou].se);
        CHECK(biased.depths[i].irradiance[Eu].se < plain.depths[i].irradiance[Eu].se);
    }
}

TEST_CASE("upward importance with depth importance: Lu at every depth and the irradiances stay exact (DISORT)") {
    // Without it the nadir radiance of this water is heavy-tailed below tau 2 (photons within
    // HG's broad peak about straight up carry it: Lu at tau 5 reads 3-7 % low with an SE that
    // understates its scatter; docs/limitations.md). With 35 % of the scattering directions
    // drawn from a lobe about straight up and the records stored by their direction
    // (transport/importance.hpp, UpwardImportance; the share chosen on seeds 1-4, not this
    // one), every Lu down to tau 10 against the exact solution, with every irradiance.
    const auto& c = disort_case("hg:0.9", 0.2);
    const auto r = run_case(c, {1'000'000, 1'000'000}, DepthImportance{1.0, 10.0}, 0.0, 0.35);
    check_irradiances(c, r);
    for (std::size_t i = 0; i < c.tau.size(); ++i) check_against(r.depths[i].lu, c.lu[i], "Lu tau " + std::to_string(c.tau[i]));
}

TEST_CASE("upward importance in weakly absorbing water: weights stay bounded, irradiances and Lu exact (DISORT)") {
    // At w0 = 0.99 a photon scatters about 100 times. The mixture's weight factors (up to
    // 1 / (1 - eps) each) compound unless the mixture is drawn only for photons of relative
    // weight at most 1 (transport/tracer.hpp): without that rule this run read Lu and Eu 20-40 %
    // low at 5-7 SE. Every irradiance and Lu at tau 0-10 against the exact solution.
    const auto& c = disort_case("hg:0.9", 0.99);
    const auto r = run_case(c, {200'000, 200'000}, {}, 0.0, 0.35);
    check_irradiances(c, r);
    for (std::size_t i = 0; i < c.tau.size(); ++i) check_against(r.depths[i].lu, c.lu[i], "Lu tau " + std::to_string(c.tau[i]));
}
