// First-pass transport: Beer-Lambert (manual 7.3.3), energy balance, unbiasedness of implicit
// capture against analog transport, determinism across thread counts. Statistical checks
// compare against the exact answer within 4 measured standard errors (fixed in advance).
#include <catch2/catch.hpp>
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/any_surface.hpp"
#include "secchi/scene/sky.hpp"
#include "secchi/scene/wind_blown_surface.hpp"
#include "secchi/transport/tracer.hpp"
#include "transport_checks.hpp"
#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

using namespace secchi;

namespace {
template <class Phase>
TransportResult<CompactRecord> run(const Phase& phase, double w0, TransportSettings s, Bottom bottom = {},
                                   double n_water = 1.34, double zenith = 60.0) {
    const auto medium = HomogeneousWater<Phase>::from_albedo(1.0, w0, phase);
    const Slab slab(1.0, bottom, 30.0);
    return PhotonTracer<HomogeneousWater<Phase>, CompactRecord>(medium, slab, FlatSurface(n_water),
                                                                CollimatedSun(zenith), s)
        .run();
}
/// HG water of albedo w0 over a Lambertian bottom under a wind-blown surface (problem 5's
/// sigma^2 = 0.04) and a sun at 80 deg, whose photons meet tilted facets and re-cross the surface.
/// Surface: the tracer's surface type, WindBlownSurface or AnySurface holding it.
template <class Surface = WindBlownSurface>
TransportResult<CompactRecord> run_wind_blown(TransportSettings s, Shadowing shadowing = Shadowing::none) {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto medium = Water::from_albedo(1.0, 0.5, HenyeyGreensteinPhase(0.7));
    const Slab slab(1.0, Bottom::lambertian_at(6.0, 0.4), 30.0);
    const Surface surface = WindBlownSurface(FacetSlopes::isotropic(0.04), 1.34, FacetSampling::projected_area, 1.0, shadowing);
    return PhotonTracer<Water, CompactRecord, Surface>(medium, slab, surface, CollimatedSun(80.0), s).run();
}
/// HG water over a Lambertian bottom under a flat surface, lit by a sun at 30 deg and a uniform
/// sky (whose photons meet the surface at their own angles). Surface: FlatSurface or AnySurface.
template <class Surface>
TransportResult<CompactRecord> run_flat_sun_and_sky(TransportSettings s) {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto medium = Water::from_albedo(1.0, 0.8, HenyeyGreensteinPhase(0.9));
    const Slab slab(1.0, Bottom::lambertian_at(4.0, 0.3), 30.0);
    const Surface surface = FlatSurface(1.34);
    return PhotonTracer<Water, CompactRecord, Surface>(medium, slab, surface, CollimatedSun(30.0), s, UniformSky(0.4)).run();
}
TransportResult<CompactRecord> run_wind_blown_hiding(TransportSettings s) { return run_wind_blown(s, Shadowing::smith); }
bool within_se(const Estimate& e, double exact, double k = 4.0) {
    INFO("estimate " << e.value << " +- " << e.se << " vs exact " << exact);
    return std::abs(e.value - exact) <= k * e.se && e.se > 0;
}
}  // namespace

TEST_CASE("Beer-Lambert for w0 = 0: Ed(z) = T Ed(0+) exp(-c z / mu_w)") {
    TransportSettings s;
    s.photons = 400000;
    s.depths = {0.0, 1.0, 3.0};
    s.absorption = AbsorptionMode::analog;
    const auto r = run(IsotropicPhase{}, 0.0, s);
    const double t = 1.0 - fresnel_reflectance(0.5, 1.0, 1.34);
    const double mu_w = FlatSurface(1.34).transmit_into_water(CollimatedSun(60).direction()).z;
    for (std::size_t i = 0; i < s.depths.size(); ++i) {
        const double exact = 0.5 * t * std::exp(-s.depths[i] / mu_w);
        CHECK(within_se(r.irradiance[i][Ed], exact));
        CHECK(r.irradiance[i][Eu].value == 0.0);
        // The direct beam's scalar irradiance is Ed / mu_w, on the surface too: the detector
        // scores each crossing at the plane itself (irradiance_planes.hpp).
        CHECK(within_se(r.irradiance[i][Eod], exact / mu_w, 5.0));
    }
    CHECK(r.records.empty());
}

TEST_CASE("Energy balances exactly for a non-absorbing finite slab (analog)") {
    TransportSettings s;
    s.photons = 50000;
    s.map_photons = 50000;
    s.depths = {0.5};
    s.absorption = AbsorptionMode::analog;
    const auto r = run(HenyeyGreensteinPhase(0.8), 1.0, s, Bottom::transparent_at(2.0));
    CHECK(r.ledger.incident == Approx(1.0));
    CHECK(r.ledger.absorbed == 0.0);
    CHECK(std::abs(r.ledger.imbalance()) < 1e-12);
    CHECK(r.ledger.surface_reflected + r.ledger.escaped_up + r.ledger.transmitted == Approx(1.0).epsilon(1e-12));
    CHECK(r.ledger.transmitted > 0.3);
    CHECK(r.ledger.escaped_up > 0.01);
    for (const auto& rec : r.records) {
        REQUIRE(rec.x >= 0.0f);
        REQUIRE(rec.x < 1.0f);
        REQUIRE(rec.z >= 0.0f);
        REQUIRE(rec.z <= 2.0f);
    }
}

TEST_CASE("Energy balances with implicit capture and Russian roulette") {
    TransportSettings s;
    s.photons = 100000;
    s.depths = {1.0};
    s.absorption = AbsorptionMode::implicit_capture;
    s.roulette_weight = 0.01;
    const auto r = run(HenyeyGreensteinPhase(0.8), 0.7, s, Bottom::lambertian_at(3.0, 0.5));
    // Each roulette is booked as it is made (a survivor's gain w / p - w, a loser's w), so the
    // ledger closes to rounding, not only in expectation.
    CHECK(std::abs(r.ledger.imbalance()) <= 1e-9 * r.ledger.incident);
    CHECK(r.ledger.roulette_killed > 0.0);
    CHECK(r.ledger.absorbed_bottom > 0.0);
}

namespace {
/// `trace(settings)` in analog mode, then with implicit capture and continuous absorption: every
/// irradiance at every depth agrees within 4 combined SE, and the ledger balances.
template <class Trace>
void check_absorption_modes_agree(TransportSettings s, Trace&& trace) {
    s.absorption = AbsorptionMode::analog;
    const auto a = trace(s);
    for (AbsorptionMode mode : {AbsorptionMode::implicit_capture, AbsorptionMode::continuous}) {
        s.absorption = mode;
        const auto b = trace(s);
        for (std::size_t i = 0; i < s.depths.size(); ++i)
            for (int k = 0; k < 4; ++k)
                testing::check_agree(a.irradiance[i][k], b.irradiance[i][k],
                                     "mode " + std::to_string(static_cast<int>(mode)) + " depth " +
                                         std::to_string(s.depths[i]) + " quantity " + std::to_string(k));
        CHECK(std::abs(b.ledger.imbalance()) <= 1e-9 * b.ledger.incident);
        CHECK(b.ledger.truncated == 0.0);
    }
}
}  // namespace

TEST_CASE("Implicit capture, continuous absorption and analog transport agree within their standard errors") {
    TransportSettings s;
    s.photons = 200000;
    s.depths = {1.0, 4.0};
    check_absorption_modes_agree(s, [](const TransportSettings& settings) {
        return run(HenyeyGreensteinPhase(0.7), 0.5, settings, Bottom::lambertian_at(6.0, 0.4));
    });
}

TEST_CASE("Under a wind-blown surface the absorption modes agree within their standard errors") {
    // Analog photons choose reflection at the sun's facet with the Fresnel probability; the
    // others carry the transmittance in their weight where the reflected light leaves.
    TransportSettings s;
    s.photons = 200000;
    s.depths = {0.0, 1.0, 4.0};
    check_absorption_modes_agree(s, [](const TransportSettings& settings) { return run_wind_blown(settings); });
}

TEST_CASE("Under a wind-blown surface results are bit-identical for 1 and 2 threads", "[threads]") {
    testing::require_same_for_1_and_2_threads(AbsorptionMode::continuous, [](TransportSettings s) { return run_wind_blown(s); });
    testing::require_same_for_1_and_2_threads(AbsorptionMode::continuous, run_wind_blown_hiding);
}

TEST_CASE("A surface chosen at run time (AnySurface, as the plane-parallel solver holds it) traces bit for bit as the surface it holds") {
    const auto require_same = [](const TransportResult<CompactRecord>& a, const TransportResult<CompactRecord>& b) {
        testing::require_identical(a, b);
        REQUIRE(a.above.ed_direct.value == b.above.ed_direct.value);
        REQUIRE(a.above.ed_diffuse.value == b.above.ed_diffuse.value);
        REQUIRE(a.above.eu.value == b.above.eu.value);
        REQUIRE(a.ledger.surface_reflected == b.ledger.surface_reflected);
        REQUIRE(a.ledger.escaped_up == b.ledger.escaped_up);
    };
    for (const AbsorptionMode mode : {AbsorptionMode::analog, AbsorptionMode::implicit_capture, AbsorptionMode::continuous}) {
        TransportSettings s;
        s.photons = s.map_photons = 20000;
        s.depths = {0.0, 0.5, 3.0};
        s.absorption = mode;
        require_same(run_flat_sun_and_sky<FlatSurface>(s), run_flat_sun_and_sky<AnySurface>(s));
        for (const Shadowing shadowing : {Shadowing::none, Shadowing::smith})
            require_same(run_wind_blown<WindBlownSurface>(s, shadowing), run_wind_blown<AnySurface>(s, shadowing));
    }
}

TEST_CASE("Waves hiding the light leaving a wind-blown surface: the ledger closes, modes agree, less of a grazing sun is reflected") {
    // Smith's hiding (Shadowing::smith): light leaving a facet meets the surface again with
    // probability 1 - G1. For a sun at 80 deg, about a quarter of whose light is reflected at
    // grazing angles (Lambda of order 0.05-0.5 there), part of that light is sent back into the
    // surface and partly enters: Eu(0+) must fall below the run without hiding by more than 4
    // combined SE, and the energy ledger must still close.
    TransportSettings s;
    s.photons = 200000;
    s.depths = {0.0, 1.0, 4.0};
    check_absorption_modes_agree(s, run_wind_blown_hiding);
    s.absorption = AbsorptionMode::analog;
    const auto off = run_wind_blown(s), on = run_wind_blown(s, Shadowing::smith);
    INFO("Eu(0+) " << on.above.eu.value << " +- " << on.above.eu.se << " with hiding, " << off.above.eu.value << " +- "
                   << off.above.eu.se << " without");
    CHECK(off.above.eu.value - on.above.eu.value > 4.0 * std::hypot(off.above.eu.se, on.above.eu.se));
    CHECK(std::abs(on.ledger.imbalance()) <= 1e-9 * on.ledger.incident);
    CHECK(on.ledger.truncated == 0.0);
}

TEST_CASE("An index-matched wind-blown surface with hiding is no surface at all: its light goes straight on") {
    // n_water = 1: every facet transmits without reflection or refraction, so however often the
    // waves hide it, light keeps its direction and weight: the irradiances are those of a flat
    // surface of index 1 (within 4 combined SE; different seeds, the walks draw differently).
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto medium = Water::from_albedo(1.0, 0.5, HenyeyGreensteinPhase(0.7));
    const Slab slab(1.0, Bottom::lambertian_at(6.0, 0.4), 30.0);
    TransportSettings s;
    s.photons = 200000;
    s.depths = {0.0, 1.0, 4.0};
    const auto flat = PhotonTracer<Water, CompactRecord>(medium, slab, FlatSurface(1.0), CollimatedSun(80.0), s).run();
    s.seed = 2;
    const WindBlownSurface waves(FacetSlopes::isotropic(0.04), 1.0, FacetSampling::projected_area, 1.0, Shadowing::smith);
    const auto hiding = PhotonTracer<Water, CompactRecord, WindBlownSurface>(medium, slab, waves, CollimatedSun(80.0), s).run();
    for (std::size_t i = 0; i < s.depths.size(); ++i)
        for (const IrradianceKind q : {Ed, Eu, Eod, Eou})
            testing::check_agree(flat.irradiance[i][q], hiding.irradiance[i][q], "depth " + std::to_string(s.depths[i]));
    testing::check_agree(flat.above.eu, hiding.above.eu, "Eu(0+)");
    CHECK(std::abs(hiding.ledger.imbalance()) <= 1e-9 * hiding.ledger.incident);
}

namespace {
/// Photons from the sun and a uniform sky through non-scattering water (w0 = 0, c = 1 /m), in
/// continuous absorption (each plane crossing carries exp(-c z / mu)).
TransportResult<CompactRecord> run_sun_and_sky(double e_perp, double sky, double n_water, std::vector<double> depths) {
    TransportSettings s;
    s.photons = 200000;
    s.depths = std::move(depths);
    s.absorption = AbsorptionMode::continuous;
    const auto medium = HomogeneousWater<IsotropicPhase>::from_albedo(1.0, 0.0, IsotropicPhase{});
    return PhotonTracer<HomogeneousWater<IsotropicPhase>, CompactRecord>(
               medium, Slab(1.0, Bottom{}, 30.0), FlatSurface(n_water), CollimatedSun(60.0, 0.0, e_perp), s,
               UniformSky(sky))
        .run();
}
/// integral_0^1 f(mu) dmu by Simpson's rule on 2000 intervals.
template <class F>
double integrate_unit(F&& f) {
    const int n = 2000;
    double sum = f(0.0) + f(1.0);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * f(static_cast<double>(i) / n);
    return sum / (3.0 * n);
}
}  // namespace

TEST_CASE("A uniform sky through no interface: Ed(z) = 2 E_sky E_3(c z)") {
    // Radiance L = E_sky / pi from every downward direction: Ed(z) = 2 pi L int_0^1 mu e^(-cz/mu) dmu
    // = 2 E_sky E_3(cz), E_3 the exponential integral (E_3(0) = 1/2).
    const double e_sky = 0.7;
    const std::vector<double> depths = {0.0, 0.5, 2.0};
    const auto r = run_sun_and_sky(0.0, e_sky, 1.0, depths);
    // Depth 0: every photon crosses with weight 1, exactly E_sky (no spread, no SE).
    CHECK(r.irradiance[0][Ed].value == Approx(e_sky).epsilon(1e-12));
    for (std::size_t i = 1; i < depths.size(); ++i) {
        const double z = depths[i];
        const double e3 = integrate_unit([z](double mu) { return mu > 0 ? mu * std::exp(-z / mu) : 0.0; });
        CHECK(within_se(r.irradiance[i][Ed], 2.0 * e_sky * e3));
    }
}

TEST_CASE("Sun and uniform sky through a flat surface: Ed(0-) = E_sun (1 - R(60 deg)) + E_sky (1 - r_diffuse)") {
    // The sky's light is reflected with r_diffuse = int_0^1 R(mu) 2 mu dmu (its cosine-weighted
    // directions), about 0.066 for n = 1.34 (Mobley 1994, sec. 4.3).
    const double r_diffuse = integrate_unit([](double mu) { return fresnel_reflectance(mu, 1.0, 1.34) * 2.0 * mu; });
    CHECK(r_diffuse > 0.06);
    CHECK(r_diffuse < 0.07);
    const double e_perp = 1.0, e_sky = 0.3;
    const auto r = run_sun_and_sky(e_perp, e_sky, 1.34, {0.0});
    const double sun = 0.5 * e_perp * (1.0 - fresnel_reflectance(0.5, 1.0, 1.34));
    CHECK(within_se(r.irradiance[0][Ed], sun + e_sky * (1.0 - r_diffuse)));
    CHECK(std::abs(r.ledger.imbalance()) < 1e-12);
}

TEST_CASE("Beer-Lambert with continuous absorption is exact per photon") {
    // w0 = 0: b = 0, so no photon ever interacts and each crossing carries exp(-c z / mu_w).
    TransportSettings s;
    s.photons = 64;
    s.depths = {2.0};
    s.absorption = AbsorptionMode::continuous;
    const auto r = run(IsotropicPhase{}, 0.0, s);
    const double t = 1.0 - fresnel_reflectance(0.5, 1.0, 1.34);
    const double mu_w = FlatSurface(1.34).transmit_into_water(CollimatedSun(60).direction()).z;
    CHECK(r.irradiance[0][Ed].value == Approx(0.5 * t * std::exp(-2.0 / mu_w)).epsilon(1e-12));
    CHECK(r.irradiance[0][Ed].se < 1e-15);
}

TEST_CASE("The surface's detector counts every photon that reaches the surface from below") {
    testing::check_surface_plane_counts_every_crossing<PhotonTracer>(1e-12);
}

TEST_CASE("Results are bit-identical for 1 and 2 threads", "[threads]") {
    testing::require_same_for_1_and_2_threads(
        AbsorptionMode::continuous, [](const TransportSettings& s) { return run(HenyeyGreensteinPhase(0.9), 0.9, s); });
}

TEST_CASE("A run given an earlier map's records writes into their memory and gives the same result", "[threads]") {
    TransportSettings s;
    s.photons = s.map_photons = 20000;
    s.depths = {1.0, 5.0};
    s.block_size = 1000;
    s.threads = 2;
    const auto water = HomogeneousWater<HenyeyGreensteinPhase>::from_albedo(1.0, 0.9, HenyeyGreensteinPhase(0.9));
    const PhotonTracer<HomogeneousWater<HenyeyGreensteinPhase>, CompactRecord> tracer(
        water, Slab(1.0, Bottom{}, 30.0), FlatSurface(1.34), CollimatedSun(60.0), s);
    const auto fresh = tracer.run();
    auto first = tracer.run();
    const CompactRecord* memory = first.records.data();
    const std::size_t capacity = first.records.capacity();
    CHECK(capacity < fresh.records.size() * 5 / 4);  // the map's spare capacity stays under 1/4
    const auto second = tracer.run(std::move(first.records));
    CHECK(second.records.data() == memory);
    CHECK(second.records.capacity() == capacity);
    testing::require_identical(fresh, second);
}

namespace {
/// What parallel_for reports to the installed progress sink: loop_started and loop_finished
/// from the loop's own thread, advanced() from any worker.
class CountingSink final : public ProgressSink {
public:
    void loop_started(std::size_t total) override {
        ++started;
        this->total += total;
    }
    void advanced() override { advanced_count.fetch_add(1, std::memory_order_relaxed); }
    void loop_finished() override { ++finished; }

    std::atomic<std::size_t> advanced_count{0};
    std::size_t started = 0, finished = 0, total = 0;
};
}  // namespace

TEST_CASE("parallel_for runs every index once, reports only the outermost loop, and rethrows a body's exception",
          "[threads]") {
    for (unsigned threads : {1u, 2u, 4u}) {
        INFO(threads << " threads");
        CountingSink sink;
        const ProgressScope scope(&sink);
        std::vector<int> runs(1000, 0);  // each slot written by the one worker that took its index
        std::atomic<int> taken{0}, inner{0};
        parallel_for(runs.size(), threads, [&](std::size_t i) {
            // Index 0 waits for a second index to be taken: on 2 or more threads the workers overlap.
            taken.fetch_add(1);
            if (threads > 1 && i == 0)
                while (taken.load() < 2) std::this_thread::yield();
            ++runs[i];
            if (i % 100 == 0) parallel_for(10, 2, [&](std::size_t) { inner.fetch_add(1); });  // nested: not reported
        });
        CHECK(std::count(runs.begin(), runs.end(), 1) == 1000);
        CHECK(inner == 100);
        CHECK(sink.started == 1);
        CHECK(sink.total == 1000);
        CHECK(sink.advanced_count == 1000);
        CHECK(sink.finished == 1);

        // Every index throws: one exception reaches the caller, after every worker has stopped.
        std::atomic<int> ran{0};
        CHECK_THROWS_WITH(parallel_for(1000, threads,
                                       [&](std::size_t i) {
                                           ran.fetch_add(1);
                                           throw std::runtime_error("index " + std::to_string(i));
                                       }),
                          Catch::StartsWith("index "));
        CHECK(ran >= 1);
        CHECK(ran <= static_cast<int>(threads));  // a worker takes no index after an exception
        CHECK(sink.started == 2);
        CHECK(sink.finished == 2);
    }
}

namespace {
/// The detectors' tally written out plainly: every plane tested, every crossing scored.
void reference_record(const std::vector<double>& planes, double grazing, const Flight& f, IrradianceTally* tally) {
    const double score = std::abs(f.uz) >= grazing ? 1.0 / std::abs(f.uz) : 2.0 / grazing;
    for (std::size_t i = 0; i < planes.size(); ++i) {
        const double d = planes[i];
        if (f.uz > 0.0 && f.z0 <= d && d < f.z1) {
            tally[i][Ed] += f.w;
            tally[i][Eod] += f.w * score;
        }
        if (f.uz < 0.0 && f.z1 <= d && d < f.z0) {
            tally[i][Eu] += f.w;
            tally[i][Eou] += f.w * score;
        }
    }
}
}  // namespace

TEST_CASE("Irradiance planes: every crossing scores w (plane) and w / |mu| (scalar), 2 / mu_c when grazing") {
    const std::vector<double> depths{0.0, 0.5, 1.0, 5.0, 29.99};
    const double grazing = 0.05, floor_depth = 30.0;
    const IrradiancePlanes planes(depths, grazing, floor_depth);
    std::vector<double> at;  // the planes as the constructor places them (a bottom plane just above the floor)
    for (double z : depths) at.push_back(std::min(z, floor_depth * (1.0 - 1e-12) - 1e-12));
    // Random flights, grazing ones, and flights ending within a few ulps of a plane (from
    // either side, either direction), where the half-open crossing rule decides.
    std::vector<Flight> flights;
    PhotonRng rng(8, 0);
    for (int k = 0; k < 200000; ++k) {
        const double z0 = 6.0 * rng.uniform(), uz = (2.0 * rng.uniform() - 1.0) * (k % 4 ? 1.0 : 0.1);
        const double s = -std::log(rng.uniform());
        flights.push_back({z0, z0 + uz * s, uz, s, 1.0});
    }
    for (double edge : at)
        for (int k = 0; k < 2000; ++k) {
            const double uz = (rng.uniform() < 0.5 ? -1.0 : 1.0) * std::pow(rng.uniform(), 4);
            double s = std::abs(0.3 * rng.uniform() / uz);
            double end = std::nextafter(edge, k % 2 ? 1e9 : -1e9);
            for (int j = 0; j < k % 5; ++j) end = std::nextafter(end, k % 2 ? 1e9 : -1e9);
            if (k % 7 == 0) end = edge;
            const double z0 = std::max(0.0, end - uz * s);
            s = (end - z0) / uz;
            if (!(s > 0.0)) continue;
            flights.push_back({z0, z0 + uz * s, uz, s, 1.0});
        }
    flights.push_back({1.0, 1.0, 0.0, 2.0, 1.0});  // level, on a plane: crosses nothing
    long grazing_hits = 0, hits = 0;
    for (const Flight& f : flights) {
        std::vector<IrradianceTally> a(depths.size()), b(depths.size());
        planes.record(f, NoAbsorption{}, a.data());
        reference_record(at, grazing, f, b.data());
        for (std::size_t i = 0; i < depths.size(); ++i) {
            hits += b[i][Ed] + b[i][Eu] > 0.0;
            grazing_hits += (b[i][Ed] + b[i][Eu] > 0.0) && std::abs(f.uz) < grazing;
            for (int k = 0; k < 4; ++k)
                if (a[i][k] != b[i][k]) FAIL("z0 " << f.z0 << " uz " << f.uz << " s " << f.s << ": plane " << i);
        }
    }
    CHECK(hits > 10000);
    CHECK(grazing_hits > 100);
}

TEST_CASE("Irradiance planes: the grazing score is the mean of 1/|mu| over the band for a constant radiance") {
    // Crossings of a plane under a radiance constant over the band |mu| < mu_c come with
    // density proportional to mu: the mean of 1/mu is int_0^mu_c (1/mu) mu dmu / int_0^mu_c mu dmu.
    const IrradiancePlanes planes({1.0}, 0.05, INFINITY);
    const double mu_c = planes.grazing_cosine();
    const double mean = mu_c / (0.5 * mu_c * mu_c);  // = 2 / mu_c
    CHECK(planes.inverse_cosine(0.01) == Approx(mean).epsilon(1e-15));
    CHECK(planes.inverse_cosine(-0.049) == Approx(mean).epsilon(1e-15));
    CHECK(planes.inverse_cosine(0.05) == Approx(20.0).epsilon(1e-15));
    CHECK(planes.inverse_cosine(-0.5) == Approx(2.0).epsilon(1e-15));
    CHECK_THROWS_WITH(IrradiancePlanes({1.0}, 0.0, INFINITY), Catch::Contains("grazing cosine"));
}

TEST_CASE("Record chunks keep every record, in order") {
    detail::RecordChunks<FullRecord> chunks;
    std::vector<FullRecord> expected;
    for (int i = 0; i < 5000; ++i) {  // 3.05 chunks of 1638 records
        const FullRecord r = FullRecord::make({i, 0.5 * i, 1.0}, {0.0, 0.0, 1.0}, 0, static_cast<std::uint8_t>(i));
        chunks.push_back(r);
        expected.push_back(r);
    }
    CHECK(chunks.size() == 5000);
    detail::RecordChunks<FullRecord> moved(std::move(chunks));
    CHECK(chunks.size() == 0);  // NOLINT(bugprone-use-after-move): the source is left empty
    // Room for a group of records, of which the first two are kept: they follow in order.
    FullRecord* room = moved.room(4);
    for (int k = 0; k < 4; ++k) {
        room[k] = FullRecord::make({5000.0 + k, 0.0, 1.0}, {0.0, 0.0, 1.0}, 0, 0);
        if (k < 2) expected.push_back(room[k]);
    }
    moved.commit(2);
    CHECK(moved.size() == 5002);
    std::vector<FullRecord> out{expected[7]};
    moved.move_to(out);
    REQUIRE(out.size() == 5003);
    for (int i = 0; i < 5002; ++i) REQUIRE(out[i + 1].position() == expected[i].position());
    CHECK(moved.size() == 0);
}

TEST_CASE("Room for a group at a chunk's end starts the next chunk, keeping the records before it") {
    const std::size_t per_chunk = detail::ChunkPool<FullRecord>::per_chunk;
    detail::RecordChunks<FullRecord> chunks;
    auto record = [](std::size_t i) { return FullRecord::make({double(i), 0.0, 0.0}, {0.0, 0.0, 1.0}, 0, 0); };
    for (std::size_t i = 0; i + 2 < per_chunk; ++i) chunks.push_back(record(i));
    FullRecord* room = chunks.room(4);  // two slots left: a new chunk
    for (std::size_t k = 0; k < 4; ++k) room[k] = record(per_chunk - 2 + k);
    chunks.commit(3);
    REQUIRE(chunks.size() == per_chunk + 1);
    std::vector<FullRecord> out;
    chunks.move_to(out);
    REQUIRE(out.size() == per_chunk + 1);
    for (std::size_t i = 0; i < out.size(); ++i) REQUIRE(out[i].position().x == double(i));
}

TEST_CASE("The map is built in block order whatever order the blocks finish in, in reused chunks") {
    const auto blocks = detail::make_blocks(1000, 2, 100);  // 10 blocks; photons 0-599 are map photons
    REQUIRE(blocks.size() == 10);
    detail::ChunkPool<FullRecord> pool;
    const std::size_t per_chunk = detail::ChunkPool<FullRecord>::per_chunk;
    std::vector<detail::BlockResult<FullRecord>> results;
    for (std::size_t i = 0; i < blocks.size(); ++i) results.emplace_back(3, &pool);
    std::vector<double> expected;  // block i stores 300 (i + 1) records if its photons are map photons
    for (std::size_t i = 0; i < blocks.size(); ++i)
        for (std::size_t j = 0; blocks[i].end <= 600 && j < 300 * (i + 1); ++j) expected.push_back(1000.0 * i + j);
    detail::OrderedRecords<FullRecord> map(blocks, 600);
    for (std::size_t i : {3, 1, 0, 2, 9, 5, 4, 8, 6, 7}) {
        for (std::size_t j = 0; blocks[i].end <= 600 && j < 300 * (i + 1); ++j)
            results[i].records.push_back(FullRecord::make({1000.0 * i + j, 0.0, 0.0}, {0.0, 0.0, 1.0}, 0, 0));
        map.finished(i, results);
        if (i == 1) CHECK(results[3].records.size() == 1200);  // waits for blocks 0-2
        if (i == 2) CHECK(results[3].records.size() == 0);    // appended with them
    }
    const std::vector<FullRecord> records = map.take();
    REQUIRE(records.size() == expected.size());
    for (std::size_t k = 0; k < records.size(); ++k) REQUIRE(records[k].position().x == expected[k]);
    CHECK(records.size() > 2 * per_chunk);  // the blocks' chunks ...
    CHECK(pool.idle() >= 2);                // ... went back to the pool
    CHECK(pool.take().capacity() == per_chunk);
}

TEST_CASE("Homogeneous water samples the phase function's direction without its density") {
    const auto water = HomogeneousWater<HenyeyGreensteinPhase>::from_albedo(1.0, 0.9, HenyeyGreensteinPhase(0.8));
    static_assert(depth_independent<HomogeneousWater<HenyeyGreensteinPhase>>);
    for (double u : {1e-9, 0.2, 0.5, 0.999}) {
        const PhaseSample s = water.sample_phase(3.0, u, 0.7);
        const PhaseDirection d = scattering_direction(water, 3.0, u, 0.7);
        CHECK(d.cos_psi == s.cos_psi);
        CHECK(d.phi == s.phi);
    }
}

TEST_CASE("Invalid transport settings are rejected by name") {
    TransportSettings s;
    s.photons = 10;
    s.batches = 1;
    REQUIRE_THROWS_WITH(s.validate(), Catch::Contains("batches"));
    s.batches = 4;
    s.map_photons = 11;
    REQUIRE_THROWS_WITH(s.validate(), Catch::Contains("map photons"));
    // The compact record labels 64 batches (its batch byte also holds a store tag).
    s.map_photons = s.photons = 1000;
    s.batches = 65;
    const auto water = HomogeneousWater<IsotropicPhase>::from_albedo(1.0, 0.5, IsotropicPhase{});
    const auto tracer = [&] {
        return PhotonTracer<HomogeneousWater<IsotropicPhase>, CompactRecord>(water, Slab(1.0, Bottom{}, 10.0),
                                                                             FlatSurface(1.34), CollimatedSun(0.0), s);
    };
    REQUIRE_THROWS_WITH(tracer(), Catch::Contains("batches = 65"));
    s.batches = 64;
    REQUIRE_NOTHROW(tracer());
    // No sun (E_perp = 0) and a black sky: nothing shines.
    REQUIRE_THROWS_WITH((PhotonTracer<HomogeneousWater<IsotropicPhase>, CompactRecord>(
                            water, Slab(1.0, Bottom{}, 10.0), FlatSurface(1.34), CollimatedSun(0.0, 0.0, 0.0), s)),
                        Catch::Contains("incident irradiance"));
}

TEST_CASE("A detector on a Lambertian bottom sees Eu = A Ed (exact with weighted photons)") {
    // The plane sits 1e-12 of the depth above the bottom: with continuous absorption a weight
    // there differs from the bottom's by a t < 1e-10 relative.
    testing::check_bottom_plane_counts_every_arrival<PhotonTracer>(1e-10);
}

namespace {
/// A detector policy of its own (IrradianceDetector): IrradiancePlanes whose scalar
/// irradiances score every crossing 1/|mu| down to mu = 0.3 (2/0.3 below it), whatever the
/// settings' grazing cosine.
class CoarseGrazingPlanes : public IrradiancePlanes {
public:
    CoarseGrazingPlanes(std::vector<double> depths, double /*grazing_cosine*/, double floor_depth)
        : IrradiancePlanes(std::move(depths), 0.3, floor_depth) {}
};
static_assert(IrradianceDetector<CoarseGrazingPlanes>);
}  // namespace

TEST_CASE("The detectors are a policy: the tracer tallies through the one it is given") {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto medium = Water::from_albedo(1.0, 0.8, HenyeyGreensteinPhase(0.8));
    const Slab slab(1.0, Bottom{}, 30.0);
    TransportSettings s;
    s.photons = 20000;
    s.depths = {1.0, 4.0};
    const auto plain = PhotonTracer<Water, CompactRecord>(medium, slab, FlatSurface(1.34), CollimatedSun(30.0), s).run();
    const auto coarse = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, CoarseGrazingPlanes>(
                            medium, slab, FlatSurface(1.34), CollimatedSun(30.0), s)
                            .run();
    for (std::size_t i = 0; i < s.depths.size(); ++i) {
        // The same photons: the plane irradiances are the same sums, the scalar ones differ
        // only in the grazing crossings' scores (the coarse rule scores fewer of them 1/|mu|).
        CHECK(coarse.irradiance[i][Ed].value == plain.irradiance[i][Ed].value);
        CHECK(coarse.irradiance[i][Eu].value == plain.irradiance[i][Eu].value);
        CHECK(coarse.irradiance[i][Eod].value != plain.irradiance[i][Eod].value);
        CHECK(std::abs(coarse.irradiance[i][Eod].value / plain.irradiance[i][Eod].value - 1.0) < 0.1);
    }
}
