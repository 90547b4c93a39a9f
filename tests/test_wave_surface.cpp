// The sinusoidal surface with geometry (scene/wave_surface.hpp), sums of sinusoids
// (scene/wave_sum.hpp) and the first pass through them (transport/tracer.hpp): their ray
// crossings against a brute-force search over random rays,
// reflection and refraction at the local normal against Snell's and Fresnel's laws, the caustic
// pattern on a flat bottom under a vertical sun against the analytic refraction geometry (the
// manual's validation case, 7.4: amplitude 0.4 m, wavelength 5 m), the flat limit (amplitude
// 0) against the flat surface, and the energy ledger; a sum of two equal collinear terms is the
// single sinusoid photon by photon, and crossed waves' caustics match their refraction geometry.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/scene/shapes.hpp"
#include "secchi/scene/wave_surface.hpp"
#include "secchi/scene/wave_sum.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

using namespace secchi;

static_assert(GeometricSurface<SinusoidalWave> && !AirWaterSurface<SinusoidalWave>);
static_assert(SurfacePolicy<SinusoidalWave> && SurfacePolicy<FlatSurface>);
static_assert(GeometricSurface<WaveSum> && !AirWaterSurface<WaveSum>);

namespace {
using testing::Rand;

/// The first t in (0, t_max] where the ray reaches the surface, by sampling g every `step`
/// and bisecting the first sign change: the brute-force answer.
template <class Wave>
std::optional<double> brute_crossing(const Wave& w, const vec3& o, const vec3& d, Side side, double t_max,
                                     double step) {
    const double sign = side == Side::water ? 1.0 : -1.0;
    const auto g = [&](double t) {
        const vec3 p = o + d * t;
        return sign * (p.z - w.surface_depth(p.x, p.y));
    };
    for (double t0 = 0.0; t0 < t_max; t0 += step) {
        const double t1 = std::min(t_max, t0 + step);
        if (g(t1) > 0.0) continue;
        double lo = t0, hi = t1;
        for (int i = 0; i < 100; ++i) (g(0.5 * (lo + hi)) > 0.0 ? lo : hi) = 0.5 * (lo + hi);
        return hi;
    }
    return std::nullopt;
}

/// A random ray (origin, direction) starting up to max_off m off the surface on `side` (never
/// on it), from a point in [-10, 10]^2; nearly horizontal (grazing) when `grazing`.
template <class Wave>
std::pair<vec3, vec3> ray_beside(const Wave& w, Rand& r, Side side, double max_off, bool grazing) {
    const double x = r.in(-10.0, 10.0), y = r.in(-10.0, 10.0), zs = w.surface_depth(x, y);
    const double off = r.in(1e-6, max_off);
    const vec3 o{x, y, side == Side::water ? zs + off : zs - off};
    vec3 d = r.direction();
    if (grazing) d = glm::normalize(vec3{d.x, d.y, 1e-4 * d.z});
    return {o, d};
}
}  // namespace

TEST_CASE("SinusoidalWave: its crossings are the brute-force search's, from the water and from the air") {
    Rand r(11);
    int crossings = 0, misses = 0;
    for (int i = 0; i < 3000; ++i) {
        const SinusoidalWave w(r.in(0.0, 0.6), r.in(1.0, 8.0), r.in(-3.0, 3.0), r.in(-3.0, 3.0));
        const Side side = i % 2 ? Side::water : Side::air;
        const auto [o, d] = ray_beside(w, r, side, 1.0, i % 7 == 0);
        const double t_max = r.in(0.1, 30.0);
        const auto got = w.first_crossing(o, d, side, t_max);
        const auto want = brute_crossing(w, o, d, side, t_max, 1e-3);
        INFO("ray " << i << ": amplitude " << w.amplitude() << ", wavelength " << w.wavelength());
        REQUIRE(got.has_value() == want.has_value());
        if (got) {
            ++crossings;
            CHECK(*got == Approx(*want).margin(1e-9));
            const vec3 p = o + d * *got;
            CHECK(std::abs(p.z - w.surface_depth(p.x, p.y)) < 1e-9);
        } else {
            ++misses;
        }
    }
    CHECK(crossings > 1000);
    CHECK(misses > 300);  // both outcomes are exercised
}

TEST_CASE("SinusoidalWave: reflection and refraction at the local normal follow Snell and Fresnel") {
    Rand r(12);
    const SinusoidalWave w(0.4, 5.0, 0.7, 0.3, 1.34);
    for (int i = 0; i < 2000; ++i) {
        const double x = r.in(-5.0, 5.0), y = r.in(-5.0, 5.0);
        const vec3 p{x, y, w.surface_depth(x, y)};
        const vec3 n = w.normal_into_water(x, y);
        // The normal is the gradient of z + eta: perpendicular to the surface's tangents.
        const double h = 1e-6;
        const vec3 tx{2 * h, 0.0, w.surface_depth(x + h, y) - w.surface_depth(x - h, y)};
        const vec3 ty{0.0, 2 * h, w.surface_depth(x, y + h) - w.surface_depth(x, y - h)};
        CHECK(std::abs(glm::dot(n, glm::normalize(tx))) < 1e-8);
        CHECK(std::abs(glm::dot(n, glm::normalize(ty))) < 1e-8);
        CHECK(n.z > 0.0);
        const Side from = i % 2 ? Side::water : Side::air;
        const double into = from == Side::air ? 1.0 : -1.0;  // sign of d . n for a ray crossing from `from`
        vec3 d = r.direction();
        if (glm::dot(d, n) * into < 1e-3) d = glm::reflect(d, n);
        if (glm::dot(d, n) * into < 1e-3) continue;
        const SurfaceHit hit = w.hit_at(p, d, from);
        const double n1 = from == Side::air ? 1.0 : 1.34, n2 = from == Side::air ? 1.34 : 1.0;
        const double cos_i = std::abs(glm::dot(d, n));
        CHECK(hit.reflectance == Approx(fresnel_reflectance(cos_i, n1, n2)).margin(1e-12));
        CHECK(glm::length(hit.reflected - glm::reflect(d, n)) < 1e-12);
        if (hit.reflectance < 1.0) {
            const vec3& t = hit.transmitted;
            CHECK(glm::length(t) == Approx(1.0).margin(1e-12));
            CHECK(glm::dot(t, n) * into > 0.0);  // on the far side
            // Snell: n1 sin(theta_i) = n2 sin(theta_t), in the plane of incidence.
            CHECK(n1 * glm::length(glm::cross(d, n)) == Approx(n2 * glm::length(glm::cross(t, n))).margin(1e-12));
            CHECK(std::abs(glm::dot(t, glm::cross(d, n))) < 1e-12);
        }
    }
}

TEST_CASE("SinusoidalWave: bad parameters and sections that do not hold whole wavelengths are refused") {
    CHECK_THROWS_WITH(SinusoidalWave(-0.1, 5.0), Catch::Contains("wave amplitude"));
    CHECK_THROWS_WITH(SinusoidalWave(0.4, 0.0), Catch::Contains("wavelength of the wave"));
    CHECK_THROWS_WITH(SinusoidalWave(0.4, 5.0, NAN), Catch::Contains("wave direction"));
    CHECK_THROWS_WITH(SinusoidalWave(0.4, 5.0, 0.0, 0.0, 0.9), Catch::Contains("water index"));
    CHECK(SinusoidalWave(0.4, 5.0).periodic_in(10.0));
    CHECK_FALSE(SinusoidalWave(0.4, 5.0).periodic_in(7.5));
    CHECK(SinusoidalWave(0.4, 5.0, std::numbers::pi / 2).periodic_in(5.0));
    CHECK(SinusoidalWave(0.4, 5.0 / std::sqrt(2.0), std::numbers::pi / 4).periodic_in(5.0));  // k = 2 pi (1, 1) / W
    CHECK_FALSE(SinusoidalWave(0.4, 5.0, 0.3).periodic_in(5.0));
    CHECK(SinusoidalWave(0.0, 5.0, 0.3).periodic_in(3.0));  // flat: any section
}

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <class Water, SurfacePolicy Surface>
using WaveTracer = PhotonTracer<Water, CompactRecord, Surface>;

/// The manual's validation wave (7.4): amplitude 0.4 m, wavelength 5 m, along x, its crest at
/// x = 2.5 m (phase pi), in a section of one wavelength.
constexpr double amplitude = 0.4, wavelength = 5.0, n_water = 1.34;
SinusoidalWave manual_wave() { return SinusoidalWave(amplitude, wavelength, 0.0, std::numbers::pi, n_water); }

/// The analytic bottom irradiance per x-bin under a vertical sun of unit irradiance, in water
/// of attenuation c without scattering: a ray entering at x meets the surface at depth
/// z_s = -A cos(k x + phi) with slope angle theta_i = atan|eta'(x)|, is refracted by
/// theta_i - theta_t (sin theta_t = sin theta_i / n) towards the side where eta rises (the
/// normal into the water leans that way), and reaches the bottom at depth D at
/// X = x + tan(theta_i - theta_t) sgn(eta') (D - z_s), with weight (1 - R(theta_i))
/// exp(-c (D - z_s) / cos(theta_i - theta_t)). Bin j of n over the section W reads n times the
/// weight landing in it per unit incident photon: midpoint rule over M entry points.
std::vector<double> analytic_profile(double bottom, double c, unsigned n, double width, std::size_t m) {
    const double k = 2.0 * std::numbers::pi / wavelength, phase = std::numbers::pi;
    std::vector<double> e(n, 0.0);
    for (std::size_t i = 0; i < m; ++i) {
        const double x = width * (static_cast<double>(i) + 0.5) / static_cast<double>(m);
        const double zs = -amplitude * std::cos(k * x + phase);
        const double slope = -amplitude * k * std::sin(k * x + phase);  // eta'(x)
        const double ti = std::atan(std::abs(slope)), tt = std::asin(std::sin(ti) / n_water), dev = ti - tt;
        const double path = (bottom - zs) / std::cos(dev);
        const double X = x + std::copysign(std::tan(dev), slope) * (bottom - zs);
        const double wrapped = X - width * std::floor(X / width);
        const auto j = std::min<std::size_t>(n - 1, static_cast<std::size_t>(wrapped / width * n));
        e[j] += (1.0 - fresnel_reflectance(std::cos(ti), 1.0, n_water)) * std::exp(-c * path);
    }
    for (double& v : e) v *= static_cast<double>(n) / static_cast<double>(m);
    return e;
}

/// The caustic runs' first pass: 1e6 photons, none stored, the bottom's Ed in n x n bins,
/// continuous absorption without roulette (every photon reaches the bottom: no scattering).
TransportSettings caustic_settings(unsigned n) {
    TransportSettings s;
    s.photons = 1'000'000;
    s.map_photons = 0;
    s.depths = {1.0};
    s.bottom_bins = n;
    s.absorption = AbsorptionMode::continuous;
    s.roulette_weight = 0.0;
    return s;
}

/// Bins that are the largest within +-2 bins (cyclically) and above `above` x the mean.
std::vector<unsigned> peaks(const std::vector<double>& v, double above) {
    double mean = 0.0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    std::vector<unsigned> out;
    const int n = static_cast<int>(v.size());
    for (int j = 0; j < n; ++j) {
        bool top = v[j] > above * mean;
        for (int dj = -2; dj <= 2 && top; ++dj) top = dj == 0 || v[j] >= v[((j + dj) % n + n) % n];
        if (top) out.push_back(static_cast<unsigned>(j));
    }
    return out;
}
}  // namespace

TEST_CASE("Caustics on a flat bottom under the manual's wave match the analytic refraction geometry") {
    // No scattering (w0 = 0, continuous absorption: free paths from b = 0), c = 0.05 1/m, a
    // vertical sun: every photon entering the water goes straight to the bottom along its
    // refracted ray. The bottom's Ed in 64 x 64 bins, averaged over y, is compared bin by bin
    // with the analytic profile (each of the 64 within 4 SE; SE of the y-average from the
    // bins' batch SEs, sqrt(sum se^2) / 64), and its maxima (larger than their +-2 neighbours
    // and 1.5 x the mean) are the analytic maxima within one bin (7.8 cm). Depths: the manual
    // does not state its depth; its shifts (0.3 m at x = 2 m, about 1 m at x = 4 m) imply
    // about 4.4 m and 8.3 m respectively, and the crest's paraxial focus is at
    // n R / (n - 1) = 6.2 m (R = 1 / (A k^2) = 1.58 m): all three are checked.
    const double c = 0.05;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    constexpr unsigned n = 64;
    for (const double bottom : {4.4, 6.2, 8.3}) {
        const TransportSettings s = caustic_settings(n);
        const auto r = WaveTracer<IsoWater, SinusoidalWave>(water, Slab(wavelength, Bottom::transparent_at(bottom)),
                                                           manual_wave(), SunAndSky(CollimatedSun(0.0)), s)
                           .run();
        std::vector<double> got(n, 0.0), se2(n, 0.0);
        for (unsigned iy = 0; iy < n; ++iy)
            for (unsigned ix = 0; ix < n; ++ix) {
                got[ix] += r.bottom_ed_bins[iy * n + ix].value / n;
                se2[ix] += std::pow(r.bottom_ed_bins[iy * n + ix].se / n, 2);
            }
        const std::vector<double> want = analytic_profile(bottom, c, n, wavelength, 2'000'000);
        int outside = 0;
        for (unsigned j = 0; j < n; ++j) {
            INFO("depth " << bottom << " m, bin " << j << ": " << got[j] << " +- " << std::sqrt(se2[j]) << ", analytic "
                          << want[j]);
            if (std::abs(got[j] - want[j]) > 4.0 * std::sqrt(se2[j])) ++outside;
            CHECK(std::abs(got[j] - want[j]) <= 4.0 * std::sqrt(se2[j]));
        }
        const auto pg = peaks(got, 1.5), pw = peaks(want, 1.5);
        INFO("depth " << bottom << " m: " << pg.size() << " maxima, analytic " << pw.size());
        REQUIRE(pg.size() == pw.size());
        REQUIRE(!pw.empty());
        for (std::size_t i = 0; i < pw.size(); ++i) {
            INFO("maximum at bin " << pg[i] << ", analytic " << pw[i]);
            CHECK(std::abs(static_cast<int>(pg[i]) - static_cast<int>(pw[i])) <= 1);
        }
        CHECK(std::abs(r.ledger.imbalance()) <= 1e-9 * r.ledger.incident);
    }
}

TEST_CASE("Flat limits: problems 2a and 6 through a wave of amplitude 0 and over a box as the bottom") {
    // Problem 2a (Petzold, c = 1 1/m, w0 = 0.9, sun at 60 deg, infinitely deep water) and
    // problem 6 (w0 = 0.2 over a Lambertian bottom of reflectance 0.5 at tau 5), each under the
    // flat surface and under a SinusoidalWave of amplitude 0; problem 6 also with its bottom
    // built as geometry: a transparent floor at 6 m and an opaque Lambertian box of albedo 0.5
    // filling the section from 5 m to it. The wave's Fresnel choices are random where the flat
    // surface's sun photons carry the expected value, and the box's reflection draws its own
    // numbers: the runs agree in distribution, not in bits (4 combined SE, different seeds).
    using PetzoldWater = HomogeneousWater<TabulatedPhase>;
    const SunAndSky sun(CollimatedSun(60.0));
    const SinusoidalWave flat_wave(0.0, 1.0, 0.0, 0.0, n_water);
    TransportSettings s;
    s.photons = 200'000;
    s.map_photons = 0;
    s.depths = {1.0, 5.0};
    const auto check_same = [](const auto& a, const auto& b, const std::string& what) {
        for (std::size_t i = 0; i < 2; ++i)
            for (const IrradianceKind q : {Ed, Eu, Eod, Eou})
                testing::check_agree(a.irradiance[i][q], b.irradiance[i][q], what + ", depth " + std::to_string(i));
        testing::check_agree(a.above.eu, b.above.eu, what + ", Eu(0+)");
        CHECK(std::abs(b.ledger.imbalance()) <= 1e-9 * b.ledger.incident);
    };
    {
        const PetzoldWater water = PetzoldWater::from_albedo(1.0, 0.9, petzold_m93());
        const Slab slab(1.0, Bottom::infinitely_deep());
        const auto flat = WaveTracer<PetzoldWater, FlatSurface>(water, slab, FlatSurface(n_water), sun, s).run();
        s.seed = 2;
        const auto wave = WaveTracer<PetzoldWater, SinusoidalWave>(water, slab, flat_wave, sun, s).run();
        check_same(flat, wave, "problem 2a, wave of amplitude 0");
    }
    {
        const PetzoldWater water = PetzoldWater::from_albedo(1.0, 0.2, petzold_m93());
        const Slab slab(1.0, Bottom::lambertian_at(5.0, 0.5));
        s.seed = 3;
        s.depths = {1.0, 4.999};  // just above the bottom (the box's top face in the third scene)
        const auto flat = WaveTracer<PetzoldWater, FlatSurface>(water, slab, FlatSurface(n_water), sun, s).run();
        s.seed = 4;
        const auto wave = WaveTracer<PetzoldWater, SinusoidalWave>(water, slab, flat_wave, sun, s).run();
        check_same(flat, wave, "problem 6, wave of amplitude 0");
        testing::check_agree(flat.bottom_ed, wave.bottom_ed, "problem 6, wave of amplitude 0, bottom Ed");
        Shapes box_bottom;
        box_bottom.add(AxisBox(vec3(0.0, 0.0, 5.0), vec3(1.0, 1.0, 6.0)), ObjectMaterial::lambertian(0.5));
        s.seed = 5;
        const auto boxed = PhotonTracer<PetzoldWater, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, Shapes>(
                               water, Slab(1.0, Bottom::transparent_at(6.0)), FlatSurface(n_water), sun, s, box_bottom)
                               .run();
        check_same(flat, boxed, "problem 6, box as the bottom");
        INFO("absorbed by the box " << boxed.ledger.absorbed_objects << ", by the bottom " << flat.ledger.absorbed_bottom);
        CHECK(boxed.ledger.transmitted == 0.0);
    }
}

TEST_CASE("Through the wave with scattering the ledger closes, for 1 and 2 threads alike; bad scenes refused") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const Slab slab(wavelength, Bottom::lambertian_at(6.0, 0.5));
    const SunAndSky sky(CollimatedSun(60.0), UniformSky(0.5));  // low sun and a sky: light meets crests sideways
    for (const AbsorptionMode mode : {AbsorptionMode::analog, AbsorptionMode::continuous}) {
        TransportSettings s;
        s.photons = 40'000;
        s.map_photons = 4'000;
        s.depths = {0.5, 3.0};
        s.absorption = mode;
        s.roulette_weight = 0.0;
        s.block_size = 1000;
        const auto one = WaveTracer<HgWater, SinusoidalWave>(water, slab, manual_wave(), sky, s).run();
        INFO("imbalance " << one.ledger.imbalance() << ", escaped up " << one.ledger.escaped_up);
        CHECK(std::abs(one.ledger.imbalance()) <= 1e-9 * one.ledger.incident);
        CHECK(one.ledger.truncated == 0.0);
        // Stored events reach above the mean plane, into the crests, and none above them.
        bool in_crests = false;
        for (const auto& rec : one.records) {
            in_crests = in_crests || rec.position().z < 0.0f;
            REQUIRE(rec.position().z >= -amplitude - 1e-6);
        }
        CHECK(in_crests);
        s.threads = 2;
        const auto two = WaveTracer<HgWater, SinusoidalWave>(water, slab, manual_wave(), sky, s).run();
        testing::require_identical(one, two);
    }
    TransportSettings s;
    s.photons = 1000;
    s.depths = {0.2};
    using T = WaveTracer<HgWater, SinusoidalWave>;
    const SunAndSky sun(CollimatedSun(0.0));
    CHECK_THROWS_WITH(T(water, slab, manual_wave(), sun, s), Catch::Contains("detector depth"));
    s.depths = {1.0};
    CHECK_THROWS_WITH(T(water, Slab(7.5, Bottom::lambertian_at(6.0, 0.5)), manual_wave(), sun, s),
                      Catch::Contains("section width"));
    CHECK_THROWS_WITH(T(water, Slab(wavelength, Bottom::lambertian_at(0.3, 0.5)), manual_wave(), sun, s),
                      Catch::Contains("bottom or escape depth"));
    CHECK_NOTHROW(T(water, slab, manual_wave(), sun, s));
    // Objects reaching above the troughs (0.4 m) are refused; one just below them is taken.
    using WithObjects = PhotonTracer<HgWater, CompactRecord, SinusoidalWave, SunAndSky, IrradiancePlanes, Bottom, Shapes>;
    Shapes high, low;
    high.add(AxisBox(vec3(1.0, 1.0, 0.3), vec3(2.0, 2.0, 1.0)), ObjectMaterial::absorbing());
    low.add(AxisBox(vec3(1.0, 1.0, 0.4), vec3(2.0, 2.0, 1.0)), ObjectMaterial::absorbing());
    CHECK_THROWS_WITH(WithObjects(water, slab, manual_wave(), sun, s, high),
                      Catch::Contains("object bounds' top depth (m) = 0.3") && Catch::Contains("troughs"));
    CHECK_NOTHROW(WithObjects(water, slab, manual_wave(), sun, s, low));
}

namespace {
/// A random sum of 1-4 terms (amplitudes up to 0.3 m, wavelengths 0.5-8 m, any direction).
WaveSum random_sum(Rand& r) {
    std::vector<Sinusoid> terms;
    const int n = 1 + static_cast<int>(4.0 * r()) % 4;
    for (int i = 0; i < n; ++i) terms.emplace_back(r.in(0.0, 0.3), r.in(0.5, 8.0), r.in(-3.0, 3.0), r.in(-3.0, 3.0));
    return WaveSum(std::move(terms));
}
}  // namespace

TEST_CASE("WaveSum: its crossings are the brute-force search's; one term crosses where SinusoidalWave does") {
    // The brute force samples g every 2e-4 m and bisects the first sign change; it misses a
    // crossing pair closer than its step (a grazing pass through a crest), which the bounded
    // search finds: such a crossing is accepted if it is on the surface and before the brute
    // force's. Otherwise the two agree to 1e-9 m (the brute force's bisection from its samples).
    Rand r(31);
    int crossings = 0, misses = 0, finer = 0;
    for (int i = 0; i < 3000; ++i) {
        const WaveSum w = random_sum(r);
        const Side side = i % 2 ? Side::water : Side::air;
        const auto [o, d] = ray_beside(w, r, side, 0.5, i % 7 == 0);
        const double t_max = r.in(0.1, 8.0);
        const auto got = w.first_crossing(o, d, side, t_max);
        const auto want = brute_crossing(w, o, d, side, t_max, 2e-4);
        INFO("ray " << i << ": " << w.terms().size() << " terms");
        if (want) {
            REQUIRE(got);
            CHECK(*got <= *want + 1e-9);
        }
        if (got) {
            ++crossings;
            const vec3 p = o + d * *got;
            CHECK(std::abs(p.z - w.surface_depth(p.x, p.y)) < 1e-9);
            CHECK(*got <= t_max);
            if (!want || *got < *want - 1e-9) ++finer;
            else CHECK(*got == Approx(*want).margin(1e-9));
        } else {
            ++misses;
        }
    }
    INFO("crossings " << crossings << ", misses " << misses << ", found between the brute force's samples " << finer);
    CHECK(crossings > 1000);
    CHECK(misses > 300);
    CHECK(finer <= 30);  // 1 %: grazing passes only

    // One term: SinusoidalWave's surface, crossed at the same points (both bisect to the last bit).
    for (int i = 0; i < 3000; ++i) {
        const double a = r.in(0.0, 0.6), l = r.in(1.0, 8.0), dir = r.in(-3.0, 3.0), ph = r.in(-3.0, 3.0);
        const SinusoidalWave one(a, l, dir, ph);
        const WaveSum sum({Sinusoid(a, l, dir, ph)});
        const double x = r.in(-10.0, 10.0), y = r.in(-10.0, 10.0);
        const Side side = i % 2 ? Side::water : Side::air;
        const double off = r.in(1e-6, 1.0);
        const vec3 o{x, y, one.surface_depth(x, y) + (side == Side::water ? off : -off)};
        const vec3 d = r.direction();
        const double t_max = r.in(0.1, 30.0);
        const auto a1 = one.first_crossing(o, d, side, t_max), a2 = sum.first_crossing(o, d, side, t_max);
        INFO("ray " << i);
        REQUIRE(a1.has_value() == a2.has_value());
        if (a1) CHECK(*a2 == Approx(*a1).margin(1e-12));
        CHECK(glm::length(one.normal_into_water(x, y) - sum.normal_into_water(x, y)) < 1e-15);
    }
}

TEST_CASE("WaveSum: flat when every amplitude is 0; level rays; bad terms and sections refused") {
    const WaveSum flat({Sinusoid(0.0, 3.0), Sinusoid(0.0, 1.0, 1.0)});
    Rand r(32);
    for (int i = 0; i < 1000; ++i) {
        const vec3 d = r.direction();
        const vec3 o{r.in(-5.0, 5.0), r.in(-5.0, 5.0), d.z > 0.0 ? -r.in(0.01, 2.0) : r.in(0.01, 2.0)};
        const Side side = o.z > 0.0 ? Side::water : Side::air;
        const auto t = flat.first_crossing(o, d, side, INFINITY);
        REQUIRE(t);
        CHECK(*t == Approx(-o.z / d.z).margin(1e-12));
        CHECK_FALSE(flat.first_crossing(o, d, side, 0.99 * -o.z / d.z));
        CHECK(flat.normal_into_water(o.x, o.y) == vec3(0.0, 0.0, 1.0));
    }
    // A level ray in the water between the troughs of two crossed waves meets a crest rising
    // through its depth; one below every trough (the sum of the amplitudes) meets nothing.
    const WaveSum crossed({Sinusoid(0.3, 5.0), Sinusoid(0.2, 2.5, std::numbers::pi / 2)});
    CHECK(crossed.trough_depth() == Approx(0.5));
    CHECK(crossed.first_crossing({0.0, 0.3, 0.1}, glm::normalize(vec3{1.0, 0.3, 0.0}), Side::water, INFINITY));
    CHECK_FALSE(crossed.first_crossing({0.0, 0.3, 0.51}, glm::normalize(vec3{1.0, 0.3, 0.0}), Side::water, INFINITY));
    CHECK(crossed.periodic_in(5.0));
    CHECK_FALSE(crossed.periodic_in(2.5));  // the first term needs 5 m
    CHECK_THROWS_WITH(WaveSum({}), Catch::Contains("wave sum terms"));
    CHECK_THROWS_WITH(WaveSum({Sinusoid(0.1, 1.0)}, 0.5), Catch::Contains("water index"));
    CHECK_THROWS_WITH(Sinusoid(-0.1, 1.0), Catch::Contains("wave amplitude"));
    TransportSettings s;
    s.photons = 1000;
    s.depths = {0.45};  // above the sum's lowest possible trough
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    using T = WaveTracer<HgWater, WaveSum>;
    const SunAndSky sun(CollimatedSun(0.0));
    CHECK_THROWS_WITH(T(water, Slab(5.0, Bottom::lambertian_at(6.0, 0.5)), crossed, sun, s), Catch::Contains("detector depth"));
    s.depths = {1.0};
    CHECK_THROWS_WITH(T(water, Slab(2.5, Bottom::lambertian_at(6.0, 0.5)), crossed, sun, s), Catch::Contains("section width"));
    CHECK_NOTHROW(T(water, Slab(5.0, Bottom::lambertian_at(6.0, 0.5)), crossed, sun, s));
}

TEST_CASE("WaveSum: two equal collinear terms are SinusoidalWave of their summed amplitude, photon by photon") {
    // A(cos u) + A'(cos u) = (A + A') cos u: the same surface, so the first pass draws the same
    // numbers for every photon and takes the same paths; the crossings differ only in the
    // last bits of their bisections, so every output agrees to 1e-9 relative (a Fresnel choice
    // or a bin flipped by such a difference would show as a far larger one).
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const Slab slab(wavelength, Bottom::lambertian_at(6.0, 0.5));
    const SunAndSky sky(CollimatedSun(40.0), UniformSky(0.5));
    TransportSettings s;
    s.photons = 40'000;
    s.map_photons = 0;
    s.depths = {0.5, 3.0};
    s.bottom_bins = 8;
    const auto one = WaveTracer<HgWater, SinusoidalWave>(water, slab, manual_wave(), sky, s).run();
    const WaveSum halves({Sinusoid(0.5 * amplitude, wavelength, 0.0, std::numbers::pi),
                          Sinusoid(0.5 * amplitude, wavelength, 0.0, std::numbers::pi)},
                         n_water);
    const auto two = WaveTracer<HgWater, WaveSum>(water, slab, halves, sky, s).run();
    for (std::size_t i = 0; i < 2; ++i)
        for (const IrradianceKind q : {Ed, Eu, Eod, Eou}) {
            INFO("depth " << i << ", quantity " << static_cast<int>(q));
            CHECK(two.irradiance[i][q].value == Approx(one.irradiance[i][q].value).epsilon(1e-9));
        }
    for (std::size_t k = 0; k < one.bottom_ed_bins.size(); ++k)
        CHECK(two.bottom_ed_bins[k].value == Approx(one.bottom_ed_bins[k].value).epsilon(1e-9));
    CHECK(two.ledger.surface_reflected == Approx(one.ledger.surface_reflected).epsilon(1e-9));
    CHECK(two.ledger.absorbed == Approx(one.ledger.absorbed).epsilon(1e-9));
}

namespace {
/// Crossed waves: 0.25 m, 5 m along x (crest at x = 2.5 m) and 0.1 m, 2.5 m along y, in a 5 m
/// section. The steepest facet tilts 21.9 deg (|grad eta| <= 0.314 + 0.251): below 30 deg, so
/// light reflected up from a vertical sun (2 theta from the zenith) climbs faster than any
/// facet rises and never meets the surface again, and refracted light never leaves the water.
WaveSum crossed_waves() {
    return WaveSum({Sinusoid(0.25, 5.0, 0.0, std::numbers::pi), Sinusoid(0.1, 2.5, std::numbers::pi / 2, 0.0)}, n_water);
}

/// The analytic bottom irradiance under a vertical sun of unit irradiance, water of attenuation
/// c without scattering, in n bins along x (along_x) or y, averaged over the other axis: the ray
/// entering at (x, y) meets the surface at depth -eta(x, y), is refracted at the normal there
/// (Snell, facet_hit) and goes straight to the bottom at depth D with weight
/// (1 - R) exp(-c (D + eta) / t_z). Midpoint rule over `fine` entry points along the profile's
/// axis (a caustic squeezes many into few bins: the fine axis keeps each bin's count exact to
/// about 0.5 %) and `coarse` along the other; each bin reads n times the weight landing in it
/// per incident photon.
std::vector<double> analytic_profile(const WaveSum& wave, double bottom, double c, unsigned n, double width, bool along_x,
                                     unsigned fine, unsigned coarse) {
    std::vector<double> e(n, 0.0);
    for (unsigned i = 0; i < fine; ++i)
        for (unsigned j = 0; j < coarse; ++j) {
            const double u = width * (i + 0.5) / fine, v = width * (j + 0.5) / coarse;
            const double x = along_x ? u : v, y = along_x ? v : u;
            const vec3 p{x, y, wave.surface_depth(x, y)};
            const SurfaceHit h = wave.hit_at(p, vec3(0.0, 0.0, 1.0), Side::air);
            const vec3& t = h.transmitted;
            const double path = (bottom - p.z) / t.z;
            const double landing = along_x ? x + path * t.x : y + path * t.y;
            e[std::min(n - 1, static_cast<unsigned>(periodic_wrap(landing, width) / width * n))] +=
                (1.0 - h.reflectance) * std::exp(-c * path);
        }
    for (double& v : e) v *= static_cast<double>(n) / (static_cast<double>(fine) * coarse);
    return e;
}

/// Whether every maximum of `a` has one of `b` within one bin (cyclically).
bool each_near(const std::vector<unsigned>& a, const std::vector<unsigned>& b, unsigned n) {
    return std::all_of(a.begin(), a.end(), [&](unsigned i) {
        return std::any_of(b.begin(), b.end(), [&](unsigned j) {
            const unsigned d = i > j ? i - j : j - i;
            return std::min(d, n - d) <= 1;
        });
    });
}
}  // namespace

TEST_CASE("Caustics of crossed waves on a flat bottom match their refraction geometry") {
    // As the manual's case above, now in two dimensions: no scattering, c = 0.05 1/m, vertical
    // sun, the bottom at 6.2 m (the second term's paraxial focus, n R / (n - 1), R = 1 / (A k^2)
    // = 1.58 m). The bottom's Ed in 64 x 64 bins, averaged over y and over x: each of the 2 x 64
    // profile bins within 4 SE of the analytic profile (SE as above), and every maximum of a
    // profile (larger than its +-2 neighbours and 1.3 x the mean) within one bin of one of the
    // other's (a caustic on a bin edge may show as a maximum on either side of it).
    const double c = 0.05, bottom = 6.2, width = 5.0;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    constexpr unsigned n = 64;
    const TransportSettings s = caustic_settings(n);
    const auto r = WaveTracer<IsoWater, WaveSum>(water, Slab(width, Bottom::transparent_at(bottom)), crossed_waves(),
                                                 SunAndSky(CollimatedSun(0.0)), s)
                       .run();
    for (const bool along_x : {true, false}) {
        std::vector<double> got(n, 0.0), se2(n, 0.0);
        for (unsigned iy = 0; iy < n; ++iy)
            for (unsigned ix = 0; ix < n; ++ix) {
                const unsigned j = along_x ? ix : iy, k = iy * n + ix;
                got[j] += r.bottom_ed_bins[k].value / n;
                se2[j] += std::pow(r.bottom_ed_bins[k].se / n, 2);
            }
        const std::vector<double> want = analytic_profile(crossed_waves(), bottom, c, n, width, along_x, 20'000, 200);
        for (unsigned j = 0; j < n; ++j) {
            INFO((along_x ? "x" : "y") << " bin " << j << ": " << got[j] << " +- " << std::sqrt(se2[j]) << ", analytic "
                                       << want[j]);
            CHECK(std::abs(got[j] - want[j]) <= 4.0 * std::sqrt(se2[j]));
        }
        const auto pg = peaks(got, 1.3), pw = peaks(want, 1.3);
        INFO((along_x ? "x" : "y") << ": " << pg.size() << " maxima, analytic " << pw.size());
        REQUIRE(!pw.empty());
        CHECK(each_near(pw, pg, n));
        CHECK(each_near(pg, pw, n));
    }
    CHECK(std::abs(r.ledger.imbalance()) <= 1e-9 * r.ledger.incident);
    CHECK(r.ledger.truncated == 0.0);
}

TEST_CASE("Through crossed waves with scattering the ledger closes, for 1 and 2 threads alike") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const Slab slab(5.0, Bottom::lambertian_at(6.0, 0.5));
    const SunAndSky sky(CollimatedSun(60.0), UniformSky(0.5));
    TransportSettings s;
    s.photons = 40'000;
    s.map_photons = 4'000;
    s.depths = {0.5, 3.0};
    s.roulette_weight = 0.0;
    s.block_size = 1000;
    const auto one = WaveTracer<HgWater, WaveSum>(water, slab, crossed_waves(), sky, s).run();
    INFO("imbalance " << one.ledger.imbalance());
    CHECK(std::abs(one.ledger.imbalance()) <= 1e-9 * one.ledger.incident);
    CHECK(one.ledger.truncated == 0.0);
    s.threads = 2;
    const auto two = WaveTracer<HgWater, WaveSum>(water, slab, crossed_waves(), sky, s).run();
    testing::require_identical(one, two);
}

namespace {
/// A broken surface policy: the manual's wave, whose meetings send light back where it came
/// from: light from the air "enters" the water moving up, and light from the water is
/// "reflected" on along its way up. Such a photon meets the surface again at once, for ever:
/// the tracer must stop it (truncated) rather than follow it.
struct ReturningWave {
    SinusoidalWave wave = manual_wave();
    [[nodiscard]] std::optional<double> first_crossing(const vec3& o, const vec3& d, Side side, double t_max) const {
        return wave.first_crossing(o, d, side, t_max);
    }
    [[nodiscard]] vec3 normal_into_water(double x, double y) const { return wave.normal_into_water(x, y); }
    [[nodiscard]] SurfaceHit hit_at(const vec3&, const vec3& d, Side from) const {
        const vec3 up{d.x, d.y, -std::abs(d.z)};
        return from == Side::air ? SurfaceHit{0.0, up, up} : SurfaceHit{1.0, up, up};
    }
    [[nodiscard]] double crest_depth() const { return wave.crest_depth(); }
    [[nodiscard]] double trough_depth() const { return wave.trough_depth(); }
    [[nodiscard]] bool periodic_in(double w) const { return wave.periodic_in(w); }
    [[nodiscard]] double water_index() const { return wave.water_index(); }
};
static_assert(GeometricSurface<ReturningWave>);
}  // namespace

TEST_CASE("A surface policy that keeps returning light to itself stops photons (truncated) instead of looping") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    TransportSettings s;
    s.photons = 2000;
    s.map_photons = 0;
    s.depths = {1.0};
    const auto r = WaveTracer<HgWater, ReturningWave>(water, Slab(wavelength, Bottom::lambertian_at(6.0, 0.5)),
                                                      ReturningWave{}, SunAndSky(CollimatedSun(30.0)), s)
                       .run();
    INFO("truncated " << r.ledger.truncated);
    CHECK(r.ledger.truncated > 0.5);
    CHECK(std::abs(r.ledger.imbalance()) <= 1e-9 * r.ledger.incident);
}
