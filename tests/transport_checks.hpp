#pragma once
// Checks shared by the first-pass tests (test_transport.cpp, test_lane_tracer.cpp): two
// estimates agreeing within 4 combined standard errors (fixed in advance), and two runs with
// bit-identical output (records, every irradiance and its SE, ledger, bottom Ed), also for 1
// and 2 threads; the surface and bottom detectors against the energy ledger.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/scene/wind_blown_surface.hpp"
#include "secchi/transport/tracer.hpp"
#include <cmath>
#include <cstring>
#include <string>

namespace secchi::testing {

inline void check_agree(const Estimate& x, const Estimate& y, const std::string& what) {
    INFO(what << ": " << x.value << " +- " << x.se << " vs " << y.value << " +- " << y.se);
    CHECK(std::abs(x.value - y.value) <= 4.0 * std::hypot(x.se, y.se));
}

template <class Record>
void require_identical(const TransportResult<Record>& a, const TransportResult<Record>& b) {
    REQUIRE(a.records.size() == b.records.size());
    REQUIRE(std::memcmp(a.records.data(), b.records.data(), a.records.size() * sizeof(Record)) == 0);
    REQUIRE(a.irradiance.size() == b.irradiance.size());
    for (std::size_t i = 0; i < a.irradiance.size(); ++i)
        for (int k = 0; k < 4; ++k) {
            REQUIRE(a.irradiance[i][k].value == b.irradiance[i][k].value);
            REQUIRE(a.irradiance[i][k].se == b.irradiance[i][k].se);
        }
    REQUIRE(a.ledger.absorbed == b.ledger.absorbed);
    REQUIRE(a.bottom_ed.value == b.bottom_ed.value);
}

/// Traces `trace(settings)` on 1 and on 2 threads (30,000 photons, 20,000 of them into the
/// map, blocks of 1,000, detectors at 0, 1 and 5 m, absorption `mode`) and requires
/// bit-identical output.
template <class Trace>
void require_same_for_1_and_2_threads(AbsorptionMode mode, Trace&& trace) {
    TransportSettings s;
    s.photons = 30000;
    s.map_photons = 20000;
    s.depths = {0.0, 1.0, 5.0};
    s.block_size = 1000;
    s.absorption = mode;
    s.threads = 1;
    const auto a = trace(s);
    s.threads = 2;
    const auto b = trace(s);
    require_identical(a, b);
}

/// The plane detector at the surface (depth 0) counts every crossing of the surface once: a
/// photon reaching it from below in Eu(0), one leaving it downward (entering from the sun,
/// or reflected back) in Ed(0). Then Ed(0) - Eu(0), the net downward flux just below the
/// surface, is exactly the flux that entered less the flux that escaped upward, per photon
/// history: Ed(0+) (incident - surface_reflected - escaped_up) (the ledger counts per photon,
/// the irradiances in the sun's units: Ed(0+) = E_perp cos(zenith) just above). An identity,
/// not an estimate: the check is to the rounding of the sums (`relative` of Ed(0) + Eu(0)), for
/// every absorption mode, with and without a refracting surface (n = 1: every photon that
/// reaches the surface escapes), for the tracer under test (PhotonTracer, LaneTracer) on water
/// with a reflecting bottom; under a flat surface, and under a wind-blown one with a grazing sun,
/// whose photons meet the surface again when a tilted facet sends them back across it (their
/// hits make no flights, so the plane must see only where each history finally crosses).
template <template <class...> class Tracer>
void check_surface_plane_counts_every_crossing(double relative) {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto water = Water::from_albedo(1.0, 0.9, HenyeyGreensteinPhase(0.5));
    const Slab slab(1.0, Bottom::lambertian_at(3.0, 0.5), 30.0);
    const auto check = [&](const auto& surface, const CollimatedSun& sun, const std::string& what) {
        using Surface = std::decay_t<decltype(surface)>;
        for (const AbsorptionMode mode :
             {AbsorptionMode::analog, AbsorptionMode::implicit_capture, AbsorptionMode::continuous}) {
            TransportSettings s;
            s.photons = s.map_photons = 20000;
            s.depths = {0.0, 1.0};
            s.absorption = mode;
            const auto r = Tracer<Water, CompactRecord, Surface>(water, slab, surface, sun, s).run();
            const double net = r.irradiance[0][Ed].value - r.irradiance[0][Eu].value;
            const auto& ledger = r.ledger;
            INFO(what << ", absorption mode " << static_cast<int>(mode) << ": Ed(0) " << r.irradiance[0][Ed].value
                      << ", Eu(0) " << r.irradiance[0][Eu].value << ", escaped " << ledger.escaped_up);
            CHECK(ledger.escaped_up > 0.05);
            CHECK(ledger.truncated == 0.0);
            const double entered =
                sun.plane_irradiance() * (ledger.incident - ledger.surface_reflected - ledger.escaped_up);
            CHECK(std::abs(net - entered) <= relative * (r.irradiance[0][Ed].value + r.irradiance[0][Eu].value));
        }
    };
    check(FlatSurface(1.34), CollimatedSun(40.0), "flat, n = 1.34");
    check(FlatSurface(1.0), CollimatedSun(40.0), "no interface");
    check(WindBlownSurface(0.04, 1.34), CollimatedSun(80.0), "wind-blown, sigma^2 = 0.04, sun at 80 deg");
}

/// The plane detector on a Lambertian bottom counts every photon that reaches the bottom and
/// every one it reflects: Ed(bottom) is the ledger's flux arriving at the bottom, and with
/// weighted photons (implicit capture, continuous absorption: the reflected weight is A w,
/// no roulette) Eu(bottom) = A Ed(bottom). Identities, to the rounding of the sums
/// (`relative`); the bottom at 3.3 m, a depth no float holds (float lanes keep the floor at
/// the float nearest it).
template <template <class...> class Tracer>
void check_bottom_plane_counts_every_arrival(double relative) {
    using Water = HomogeneousWater<HenyeyGreensteinPhase>;
    const auto water = Water::from_albedo(1.0, 0.5, HenyeyGreensteinPhase(0.9));
    const double albedo = 0.5, depth = 3.3;
    REQUIRE(static_cast<double>(static_cast<float>(depth)) != depth);
    const Slab slab(1.0, Bottom::lambertian_at(depth, albedo), 30.0);
    for (const AbsorptionMode mode :
         {AbsorptionMode::analog, AbsorptionMode::implicit_capture, AbsorptionMode::continuous}) {
        TransportSettings s;
        s.photons = s.map_photons = 20000;
        s.depths = {1.0, depth};
        s.absorption = mode;
        s.roulette_weight = 0.0;  // roulette after a reflection would change weights at random
        const auto r = Tracer<Water, CompactRecord>(water, slab, FlatSurface(1.34), CollimatedSun(30.0), s).run();
        const auto& bottom = r.irradiance[1];
        INFO("absorption mode " << static_cast<int>(mode) << ": Ed " << bottom[Ed].value << ", Eu " << bottom[Eu].value
                                << ", arriving " << r.bottom_ed.value);
        CHECK(bottom[Ed].value > 0.05);
        CHECK(std::abs(bottom[Ed].value - r.bottom_ed.value) <= relative * bottom[Ed].value);
        if (mode != AbsorptionMode::analog)
            CHECK(std::abs(bottom[Eu].value - albedo * bottom[Ed].value) <= relative * bottom[Ed].value);
    }
}

}  // namespace secchi::testing
