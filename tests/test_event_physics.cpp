// The first pass's per-event rules (transport/event_physics.hpp) are written once for one
// photon and for photons in lanes: over random inputs, every lane of the vector form equals
// the scalar form of the same precision bit for bit, and both obey the rules' exact
// properties (flights end on the boundary they meet, absorption conserves weight, storage
// and absorption choices follow their uniforms).
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include "secchi/optics/stratified_water.hpp"
#include "secchi/transport/event_physics.hpp"
#include <catch2/catch.hpp>
#include <cstring>
#include <random>

using namespace secchi;

namespace {

TransportSettings settings_for(AbsorptionMode mode, double map_depth, unsigned max_order, double roulette_weight) {
    TransportSettings s;
    s.absorption = mode;
    s.map_depth = map_depth;
    s.max_order = max_order;
    s.roulette_weight = roulette_weight;
    return s;
}

template <class T>
bool same_bits(T a, T b) {
    return std::memcmp(&a, &b, sizeof(T)) == 0;
}

/// Random photon values: depths in [0, floor], unit direction cosines of either sign (some
/// nearly horizontal), free paths up to several floor depths, weights and uniforms in (0, 1).
template <class T>
struct Inputs {
    T z, uz, s, w, u, order;
};

template <class T>
Inputs<T> draw(std::mt19937_64& gen, double floor_depth) {
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    const double uz = unit(gen) < 0.1 ? (unit(gen) - 0.5) * 1e-3 : 2.0 * unit(gen) - 1.0;
    return {static_cast<T>(floor_depth * unit(gen)), static_cast<T>(uz == 0.0 ? 1e-9 : uz),
            static_cast<T>(-std::log(unit(gen)) * floor_depth), static_cast<T>(unit(gen)),
            static_cast<T>(unit(gen)), static_cast<T>(std::floor(8.0 * unit(gen)))};
}

}  // namespace

TEST_CASE("free flights end where the photon meets the surface or the floor, else after s", "[event_physics]") {
    std::mt19937_64 gen(7);
    for (double floor_depth : {1.0, 5.0, 30.0}) {
        const EventPhysics physics(TransportSettings{}, floor_depth);
        for (int i = 0; i < 20000; ++i) {
            const auto in = draw<double>(gen, floor_depth);
            const FreeFlight<double> f = physics.free_flight(in.z, in.uz, in.s);
            const double z_free = in.z + in.uz * in.s;
            REQUIRE(f.to_surface == (z_free < 0.0));
            REQUIRE(f.to_floor == (z_free >= floor_depth));
            if (f.to_surface) {
                REQUIRE(f.z1 == 0.0);  // on the surface exactly
                REQUIRE(f.t <= in.s);
                REQUIRE(f.t * -in.uz == Approx(in.z).margin(1e-12));
            } else if (f.to_floor) {
                REQUIRE(f.z1 == Approx(floor_depth).epsilon(1e-12));
                REQUIRE(f.t <= in.s);
            } else {
                REQUIRE(f.t == in.s);
                REQUIRE(f.z1 == z_free);
            }
        }
    }
}

TEST_CASE("absorption conserves weight and follows the analog uniform", "[event_physics]") {
    std::mt19937_64 gen(11);
    for (AbsorptionMode mode : {AbsorptionMode::analog, AbsorptionMode::implicit_capture, AbsorptionMode::continuous}) {
        const EventPhysics physics(settings_for(mode, INFINITY, 0, 0.01), 10.0);
        for (int i = 0; i < 5000; ++i) {
            const auto in = draw<double>(gen, 10.0);
            const double w0 = std::uniform_real_distribution<double>(0.0, 1.0)(gen);
            const Absorption<double> a = physics.absorb(in.w, in.u, w0);
            switch (mode) {
                case AbsorptionMode::analog:
                    REQUIRE(a.ends == (in.u >= w0));
                    REQUIRE(a.absorbed == (a.ends ? in.w : 0.0));
                    REQUIRE(a.w == in.w);
                    break;
                case AbsorptionMode::implicit_capture:
                    REQUIRE(!a.ends);
                    REQUIRE(a.w + a.absorbed == Approx(in.w).epsilon(1e-15));
                    REQUIRE(a.w == in.w * w0);
                    break;
                case AbsorptionMode::continuous:
                    REQUIRE(!a.ends);
                    REQUIRE(a.absorbed == 0.0);
                    REQUIRE(a.w == in.w);
                    break;
            }
        }
    }
}

TEST_CASE("storage keeps an event with probability equal to the weight, above the map's depth", "[event_physics]") {
    const EventPhysics weighted(settings_for(AbsorptionMode::implicit_capture, 2.0, 0, 0.01), 10.0);
    const EventPhysics analog(settings_for(AbsorptionMode::analog, 2.0, 0, 0.01), 10.0);
    CHECK(weighted.keeps(0.3, 0.29, 1.0));
    CHECK_FALSE(weighted.keeps(0.3, 0.3, 1.0));
    CHECK_FALSE(weighted.keeps(0.3, 0.1, 2.5));  // below the map's depth
    CHECK(weighted.keeps(0.3, 0.1, 2.0));
    CHECK(analog.keeps(1.0, 0.999, 1.0));       // every analog event (its uniform is not read)
    CHECK_FALSE(analog.keeps(1.0, 0.5, 2.01));
    CHECK(weighted.storage_draws());
    CHECK_FALSE(analog.storage_draws());
    CHECK(EventPhysics::copies(0.5, 4.0, 0.0) == 2.0);
    CHECK(EventPhysics::copies(0.5, 3.0, 0.49) == 1.0);
    CHECK(EventPhysics::copies(0.5, 3.0, 0.5) == 2.0);
    const EventPhysics limited(settings_for(AbsorptionMode::continuous, INFINITY, 3, 0.0), 10.0);
    CHECK_FALSE(limited.beyond_order(2u));
    CHECK(limited.beyond_order(3u));
    CHECK_FALSE(limited.roulette_due(1e-30));  // roulette off
    CHECK(weighted.roulette_due(0.009));
    CHECK_FALSE(weighted.roulette_due(0.01));
}

#if SECCHI_HAS_LANES
namespace {

/// Every rule in the lanes against the same rule per lane in scalars of the lanes' precision.
template <class T>
void check_lanes_against_scalar(AbsorptionMode mode, double floor_depth, double map_depth) {
    using Reals = lanes::LanesOf<T>;
    constexpr int width = lanes::width_of<T>;
    const EventPhysics physics(settings_for(mode, map_depth, 5, 0.02), floor_depth);
    const HomogeneousWater<HenyeyGreensteinPhase> hg(0.1, 0.9, HenyeyGreensteinPhase(0.85));
    std::mt19937_64 gen(2024);
    for (int round = 0; round < 4000; ++round) {
        Inputs<T> in[width];
        for (auto& x : in) x = draw<T>(gen, floor_depth);
        auto gather = [&](T Inputs<T>::*field) { return Reals([&](int l) { return in[l].*field; }); };
        const Reals z = gather(&Inputs<T>::z), uz = gather(&Inputs<T>::uz), s = gather(&Inputs<T>::s),
                    w = gather(&Inputs<T>::w), u = gather(&Inputs<T>::u), order = gather(&Inputs<T>::order);
        const double w0 = 0.9;
        const FreeFlight<Reals> f = physics.free_flight(z, uz, s);
        const Absorption<Reals> a = physics.absorb(w, u, w0);
        const Reals albedo = T(0.5) + T(0.5) * s / (s + T(1));  // each lane's own w0 (depth-varying water)
        const Absorption<Reals> a_own = physics.absorb(w, u, albedo);
        const auto keep = physics.keeps(w, u, z);
        const auto beyond = physics.beyond_order(order);
        const auto due = physics.roulette_due(w);
        const ScatteringAngles<Reals> angles = EventPhysics::angles(hg, z, u, w);
        for (int l = 0; l < width; ++l) {
            const FreeFlight<T> fs = physics.free_flight(in[l].z, in[l].uz, in[l].s);
            REQUIRE(same_bits(fs.t, T(f.t[l])));
            REQUIRE(same_bits(fs.z1, T(f.z1[l])));
            REQUIRE(fs.to_surface == bool(f.to_surface[l]));
            REQUIRE(fs.to_floor == bool(f.to_floor[l]));
            const Absorption<T> as = physics.absorb(in[l].w, in[l].u, w0);
            REQUIRE(same_bits(as.w, T(a.w[l])));
            REQUIRE(same_bits(as.absorbed, T(a.absorbed[l])));
            REQUIRE(as.ends == bool(a.ends[l]));
            const Absorption<T> own = physics.absorb(in[l].w, in[l].u, T(albedo[l]));
            REQUIRE(same_bits(own.w, T(a_own.w[l])));
            REQUIRE(same_bits(own.absorbed, T(a_own.absorbed[l])));
            REQUIRE(own.ends == bool(a_own.ends[l]));
            REQUIRE(physics.keeps(in[l].w, in[l].u, in[l].z) == bool(keep[l]));
            REQUIRE(physics.beyond_order(in[l].order) == bool(beyond[l]));
            REQUIRE(physics.roulette_due(in[l].w) == bool(due[l]));
            const ScatteringAngles<double> as_scalar = EventPhysics::angles(hg, double(in[l].z), double(in[l].u), double(in[l].w));
            // The lanes' inverse CDF and 2 pi u in their precision, against the scalar sampler.
            REQUIRE(double(angles.cos_psi[l]) == Approx(as_scalar.cos_psi).margin(std::is_same_v<T, float> ? 2e-5 : 1e-12));
            REQUIRE(double(angles.phi[l]) == Approx(as_scalar.phi).margin(std::is_same_v<T, float> ? 1e-5 : 1e-14));
        }
    }
}

}  // namespace

TEST_CASE("the rules in lanes equal the rules per photon, bit for bit", "[event_physics][lanes]") {
    for (AbsorptionMode mode : {AbsorptionMode::analog, AbsorptionMode::implicit_capture, AbsorptionMode::continuous})
        for (double map_depth : {double(INFINITY), 3.0}) {
            check_lanes_against_scalar<double>(mode, 5.0, map_depth);
            check_lanes_against_scalar<float>(mode, 5.0, map_depth);
        }
}

namespace {
/// Water of two scattering components whose shares change with depth: Rayleigh (no lane
/// sampler: lane by lane) and `particles` (sampled in the vectors).
template <class Particles>
StratifiedWater<RayleighPhase, Particles> two_components(const Particles& particles) {
    DepthProfile p;
    p.depth = {0.0, 2.0, 5.0};
    p.absorption = {0.1, 0.1, 0.1};
    p.scattering = {{0.5, 0.5, 0.5}, {0.1, 3.0, 0.5}};
    return {p, {RayleighPhase{}, particles}};
}

/// The mixture's angles in lanes of T against the scalar sampler at each lane's depth and
/// uniforms: the same component (lane by lane in double), cos psi and phi to the lanes'
/// precision (float lanes round the rescaled uniform to float: 6e-8 relative, times the
/// inverse CDF's slope, at most 1 / (2 pi min p) ~ 80 for Petzold).
template <class T, class Water>
void check_mixture_angles(const Water& water) {
    using Reals = lanes::LanesOf<T>;
    constexpr int width = lanes::width_of<T>;
    std::mt19937_64 gen(7);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::size_t chose[2] = {0, 0};
    for (int round = 0; round < 3000; ++round) {
        const Reals z([&](int) { return static_cast<T>(6.0 * unit(gen)); });
        const Reals u([&](int) { return static_cast<T>(unit(gen)); }), v([&](int) { return static_cast<T>(unit(gen)); });
        const ScatteringAngles<Reals> lanes = EventPhysics::angles(water, z, u, v);
        for (int l = 0; l < width; ++l) {
            const ScatteringAngles<double> one = EventPhysics::angles(water, double(z[l]), double(u[l]), double(v[l]));
            ++chose[water.choose(double(z[l]), double(u[l])).index];
            REQUIRE(double(lanes.cos_psi[l]) == Approx(one.cos_psi).margin(std::is_same_v<T, float> ? 2e-5 : 1e-10));
            REQUIRE(double(lanes.phi[l]) == Approx(one.phi).margin(std::is_same_v<T, float> ? 1e-5 : 1e-14));
        }
    }
    CHECK(chose[0] > 1000);  // both components drawn often
    CHECK(chose[1] > 1000);
}
}  // namespace

TEMPLATE_TEST_CASE("A mixture's angles in lanes are its components' samples lane by lane", "[event_physics][lanes]",
                   double, float) {
    check_mixture_angles<TestType>(two_components(HenyeyGreensteinPhase(0.85)));
    check_mixture_angles<TestType>(two_components(petzold_m93()));
}

TEST_CASE("float flights to the floor end on float(floor depth) exactly", "[event_physics][lanes]") {
    const EventPhysics physics(TransportSettings{}, 0.1);  // not a float
    const FreeFlight<float> f = physics.free_flight(0.05f, 0.5f, 1.0f);
    REQUIRE(f.to_floor);
    CHECK(f.z1 == static_cast<float>(0.1));
}
#endif
