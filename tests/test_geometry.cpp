// Objects in the water (scene/geometry.hpp, scene/shapes.hpp) and the first pass over them
// (transport/tracer.hpp): the shapes' intersections against exact answers over random rays
// (from outside, from inside, from the surface, grazing, cut by t_max), the periodic copies
// against a brute-force search, and the shadow of an opaque box on the bottom: in
// non-scattering water exactly 0 in the umbra and exactly Beer-Lambert outside it (photon by
// photon), with scattering filled in, the energy ledger closing with what the box absorbed.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/shapes.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <cmath>
#include <random>

using namespace secchi;

static_assert(SceneGeometry<NoGeometry> && SceneGeometry<Shapes>);

namespace {
using testing::Rand;

AxisBox random_box(Rand& r) {
    const vec3 lo{r.in(-1.0, 1.0), r.in(-1.0, 1.0), r.in(-1.0, 1.0)};  // braces: drawn left to right
    return {lo, lo + vec3{r.in(0.1, 2.0), r.in(0.1, 2.0), r.in(0.1, 2.0)}};
}

/// A point on a face of the box (away from its edges) and the face's outward normal.
std::pair<vec3, vec3> point_on_box(const AxisBox& b, Rand& r) {
    const int k = static_cast<int>(3.0 * r()) % 3;
    const bool high = r() < 0.5;
    vec3 p, n(0.0);
    for (int j = 0; j < 3; ++j) p[j] = b.lo()[j] + (b.hi()[j] - b.lo()[j]) * r.in(0.01, 0.99);
    p[k] = high ? b.hi()[k] : b.lo()[k];
    n[k] = high ? 1.0 : -1.0;
    return {p, n};
}
}  // namespace

TEST_CASE("AxisBox: rays from outside hit where they were aimed, within t_max; from inside they leave") {
    Rand r(21);
    for (int trial = 0; trial < 2000; ++trial) {
        const AxisBox box = random_box(r);
        const auto [p, n_out] = point_on_box(box, r);
        const double t0 = r.in(0.01, 3.0);
        INFO("trial " << trial);
        {  // aimed from outside at p, entering: hits p at t0, normal = the face's outward normal
            const vec3 d = r.direction_against(n_out, -1.0);
            const vec3 o = p - t0 * d;
            const auto h = box.intersect(o, d, INFINITY);
            REQUIRE(h);
            CHECK(h->t == Approx(t0).margin(1e-13));
            CHECK((h->normal == n_out));
            CHECK(box.intersect(o, d, t0 * (1.0 + 1e-9)));     // t_max just beyond: hit
            CHECK_FALSE(box.intersect(o, d, t0 * (1.0 - 1e-9)));  // just before: cut
            // From the surface point itself: moving in hits at 0, moving out does not.
            const auto on = box.intersect(p, d, 1.0);
            REQUIRE(on);
            CHECK(on->t == 0.0);
            CHECK_FALSE(box.intersect(p, -d, 1.0));
            // Leaving the box from p, the ray never comes back (convex): a miss from further out.
            CHECK_FALSE(box.intersect(p - t0 * d, -d, INFINITY));
        }
        {  // from inside: leaves at a face, through a point on the surface, normal facing the ray
            vec3 o;
            for (int k = 0; k < 3; ++k) o[k] = r.in(box.lo()[k], box.hi()[k]);
            const vec3 d = r.direction();
            const auto h = box.intersect(o, d, INFINITY);
            REQUIRE(h);
            CHECK(h->t > 0.0);
            const vec3 q = o + h->t * d;
            CHECK(box.contains(o + (h->t - 1e-9) * d));
            CHECK_FALSE(box.contains(o + (h->t + 1e-9) * d));
            CHECK(glm::dot(h->normal, d) < 0.0);
            CHECK(glm::length(h->normal) == 1.0);
            int k = 0;
            while (h->normal[k] == 0.0) ++k;
            CHECK(q[k] == Approx(h->normal[k] < 0.0 ? box.hi()[k] : box.lo()[k]).margin(1e-13));
            CHECK_FALSE(box.intersect(o, d, h->t));  // [0, t_max): the exit itself is cut
        }
    }
}

TEST_CASE("AxisBox: grazing rays, along a face and just inside it") {
    const AxisBox box(vec3(0.0, 0.0, 1.0), vec3(1.0, 2.0, 3.0));
    // Sliding along the face x = 1 (in its plane) does not enter the solid; 1e-9 inside does.
    CHECK_FALSE(box.intersect(vec3(1.0, -1.0, 2.0), vec3(0.0, 1.0, 0.0), INFINITY));
    const auto h = box.intersect(vec3(1.0 - 1e-9, -1.0, 2.0), vec3(0.0, 1.0, 0.0), INFINITY);
    REQUIRE(h);
    CHECK(h->t == 1.0);
    CHECK((h->normal == vec3(0.0, -1.0, 0.0)));
    CHECK_FALSE(box.intersect(vec3(1.0 + 1e-9, -1.0, 2.0), vec3(0.0, 1.0, 0.0), INFINITY));
    // Through an edge (a segment of length 0 inside): no entry.
    const vec3 d = glm::normalize(vec3(1.0, 1.0, 0.0));
    CHECK_FALSE(box.intersect(vec3(0.0, -1.0, 2.0), d, INFINITY));  // touches only the edge (1, 0)
    CHECK(box.intersect(vec3(-1e-9, -1.0, 2.0), d, INFINITY));
}

TEST_CASE("Sphere: rays from outside hit where they were aimed; from inside they leave; grazing") {
    Rand r(22);
    for (int trial = 0; trial < 2000; ++trial) {
        const vec3 c{r.in(-1.0, 1.0), r.in(-1.0, 1.0), r.in(-1.0, 1.0)};
        const double radius = r.in(0.1, 2.0);
        const Sphere s(c, radius);
        const vec3 n_out = r.direction(), p = c + radius * n_out;
        const double t0 = r.in(0.01, 3.0);
        INFO("trial " << trial);
        {
            const vec3 d = r.direction_against(n_out, -1.0);
            const vec3 o = p - t0 * d;
            const auto h = s.intersect(o, d, INFINITY);
            REQUIRE(h);
            CHECK(h->t == Approx(t0).margin(1e-12));
            // The normal is (hit point - c) / r: a rounding error of the point, a few eps
            // (|o| + t0) along the ray, moves it by that over r and the ray's cosine with n.
            const double cosine = -glm::dot(d, n_out);
            INFO("normal error " << glm::length(h->normal - n_out) << ", cosine " << cosine << ", r " << radius);
            CHECK(glm::length(h->normal - n_out) < 1e-14 * (2.0 + t0) / (radius * cosine));
            CHECK(s.intersect(o, d, t0 * (1.0 + 1e-9)));
            CHECK_FALSE(s.intersect(o, d, t0 * (1.0 - 1e-9)));
            CHECK_FALSE(s.intersect(p + t0 * (-d), -d, INFINITY));  // leaving: never comes back
        }
        {
            const vec3 o = c + r.direction() * (radius * std::cbrt(r()));  // uniform inside
            const vec3 d = r.direction();
            const auto h = s.intersect(o, d, INFINITY);
            REQUIRE(h);
            const vec3 q = o + h->t * d;
            CHECK(glm::length(q - c) == Approx(radius).margin(1e-13));
            CHECK(glm::length(h->normal + (q - c) / radius) < 1e-12);  // inward: facing the ray
            CHECK_FALSE(s.intersect(o, d, h->t));
        }
        {  // impact parameter rho r: a hit at t = L - sqrt(r^2 - rho^2 r^2) below 1, none above
            const vec3 d = r.direction();
            vec3 e = glm::normalize(glm::cross(d, r.direction()));
            const double len = 5.0;
            for (const double rho : {1.0 - 1e-6, 0.5, 1.0 + 1e-6}) {
                const vec3 o = c + rho * radius * e - len * d;
                const auto h = s.intersect(o, d, INFINITY);
                if (rho > 1.0) {
                    CHECK_FALSE(h);
                } else {
                    REQUIRE(h);
                    CHECK(h->t == Approx(len - radius * std::sqrt(1.0 - rho * rho)).margin(1e-9));
                }
            }
        }
    }
}

TEST_CASE("Shapes: the closest of several, its material; bad shapes and materials refused by name") {
    Shapes g;
    g.add(AxisBox(vec3(0.0, 0.0, 2.0), vec3(1.0, 1.0, 3.0)), ObjectMaterial::absorbing());
    g.add(Sphere(vec3(0.5, 0.5, 1.0), 0.25), ObjectMaterial::lambertian(0.4));
    const vec3 down(0.0, 0.0, 1.0);
    const auto h = g.closest_hit(vec3(0.5, 0.5, 0.0), down, INFINITY);
    REQUIRE(h);
    CHECK(h->t == 0.75);
    CHECK(h->material == 1);
    CHECK(g.material(h->material).albedo == 0.4);
    CHECK((h->point == vec3(0.5, 0.5, 0.75)));
    const auto past = g.closest_hit(vec3(0.9, 0.9, 0.0), down, INFINITY);  // beside the sphere
    REQUIRE(past);
    CHECK(past->t == 2.0);
    CHECK(past->material == 0);
    CHECK_FALSE(g.closest_hit(vec3(0.9, 0.9, 0.0), down, 2.0));
    CHECK(g.bounds().lo.z == 0.75);
    CHECK(g.bounds().hi.z == 3.0);
    CHECK_THROWS_WITH(ObjectMaterial::lambertian(1.2), Catch::Contains("object albedo") && Catch::Contains("1.2"));
    CHECK_THROWS_WITH(AxisBox(vec3(0.0), vec3(1.0, 0.0, 1.0)), Catch::Contains("box extent"));
    CHECK_THROWS_WITH(Sphere(vec3(0.0), -1.0), Catch::Contains("sphere radius"));
    CHECK_THROWS_WITH(Shapes().add(Sphere(vec3(0.0), 1.0), ObjectMaterial{-0.5}), Catch::Contains("object albedo"));
}

TEST_CASE("Lambertian reflection: cosine about the normal is sqrt(u1), in the normal's hemisphere") {
    Rand r(23);
    for (int i = 0; i < 1000; ++i) {
        const vec3 n = r.direction();
        const double u1 = r(), u2 = r();
        const vec3 d = lambertian_direction(n, u1, u2);
        CHECK(glm::length(d) == Approx(1.0).margin(1e-14));
        CHECK(glm::dot(d, n) == Approx(std::sqrt(u1)).margin(1e-12));
    }
}

TEST_CASE("Periodic copies: the closest hit across the seams is the brute-force search's") {
    Rand r(24);
    const double w = 1.5;
    Shapes g;
    g.add(AxisBox(vec3(0.0, 0.2, 1.0), vec3(0.3, 0.7, 2.0)), ObjectMaterial::absorbing());  // on the seam x = 0
    g.add(Sphere(vec3(1.0, 1.1, 1.5), 0.4), ObjectMaterial::lambertian(0.5));
    int hits = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const vec3 o{r.in(-5.0, 5.0), r.in(-5.0, 5.0), r.in(0.0, 3.0)};
        const vec3 d = r.direction();
        const double t_max = r.in(0.0, 6.0);
        // Brute force: every copy whose cell the flight's horizontal extent reaches, and one more.
        std::optional<ObjectHit> best;
        auto cell = [w](double x) { return static_cast<int>(std::floor(x / w)); };
        for (int i = cell(o.x - t_max) - 1; i <= cell(o.x + t_max) + 1; ++i)
            for (int j = cell(o.y - t_max) - 1; j <= cell(o.y + t_max) + 1; ++j) {
                const vec3 shift(i * w, j * w, 0.0);
                const auto h = g.closest_hit(o - shift, d, best ? best->t : t_max);
                if (h) best = ObjectHit{h->t, h->point + shift, h->normal, h->material};
            }
        const auto got = periodic_closest_hit(g, w, o, d, t_max);
        INFO("trial " << trial << " o " << o.x << " " << o.y << " " << o.z << " t_max " << t_max);
        REQUIRE(bool(got) == bool(best));
        if (!got) continue;
        ++hits;
        CHECK(got->t == Approx(best->t).margin(1e-12));
        CHECK(got->material == best->material);
        CHECK(glm::length(got->point - best->point) < 1e-12);
        CHECK(glm::length(got->normal - best->normal) < 1e-9);
    }
    CHECK(hits > 400);  // the test sees hits, not only misses
}

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <class Water, SceneGeometry G>
using ObjectTracer = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, G>;

constexpr double width = 1.0, depth = 4.0;
constexpr unsigned bins = 10;  // 0.1 m bins

/// An opaque box of albedo `albedo` above the bottom (at 4 m): [0.25, 0.75]^2 x [2, 2.5] m.
/// (Its shadow under a vertical sun is its footprint on the bottom, 1.5 m below; a box resting
/// on the bottom would cover its own shadow, which no light could then reach.)
Shapes box_above_bottom(double albedo) {
    Shapes g;
    g.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::lambertian(albedo));
    return g;
}

template <class Water, SceneGeometry G>
TransportResult<CompactRecord> trace(const Water& water, const G& g, const TransportSettings& s) {
    return ObjectTracer<Water, G>(water, Slab(width, Bottom::lambertian_at(depth, 0.0)), FlatSurface(1.34),
                                  SunAndSky(CollimatedSun(0.0)), s, g)
        .run();
}

TransportSettings shadow_settings(AbsorptionMode mode) {
    TransportSettings s;
    s.photons = 40000;
    s.map_photons = 4000;
    s.depths = {0.0, 1.0};
    s.bottom_bins = bins;
    s.absorption = mode;
    s.roulette_weight = 0.0;  // the ledger closes per photon (no roulette)
    s.block_size = 1000;
    return s;
}

bool umbra(unsigned ix, unsigned iy) { return ix >= 3 && ix <= 6 && iy >= 3 && iy <= 6; }      // inside [0.3, 0.7]^2
bool lit(unsigned ix, unsigned iy) { return ix <= 1 || ix >= 8 || iy <= 1 || iy >= 8; }     // outside [0.2, 0.8]^2
}  // namespace

TEST_CASE("Without objects the tracer's output is unchanged: an empty Shapes is NoGeometry, bit for bit") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    for (const AbsorptionMode mode : {AbsorptionMode::continuous, AbsorptionMode::analog}) {
        const auto s = shadow_settings(mode);
        const auto a = trace(water, NoGeometry{}, s);
        const auto b = trace(water, Shapes{}, s);
        testing::require_identical(a, b);
        REQUIRE(a.ledger.absorbed_bottom == b.ledger.absorbed_bottom);
        REQUIRE(b.ledger.absorbed_objects == 0.0);
        for (std::size_t k = 0; k < a.bottom_ed_bins.size(); ++k)
            REQUIRE(a.bottom_ed_bins[k].value == b.bottom_ed_bins[k].value);
    }
}

TEST_CASE("A box's shadow in non-scattering water: 0 in the umbra, Beer-Lambert outside, photon by photon") {
    // w0 = 0, continuous absorption: free paths are drawn from b = 0 (none ends in the water),
    // so every photon of the vertical sun goes straight down from its launch point (x, y) with
    // weight T exp(-c z), T = 1 - R(normal incidence) its share through the flat surface: onto
    // the box's top (absorbed there, at z = 2 m) or onto the bottom (z = 4 m, black: absorbed).
    // The tracer's launch points are the first two draws of each photon's stream, so the
    // photons arriving in each bin are known: bin k of batch b reads E0 n^2 N_kb w / N_b
    // exactly, N_kb the photons launched over it (outside the box's footprint), w = T exp(-c H).
    // "Exactly" to rounding: sums of at most a few hundred equal terms per bin and batch, a
    // relative error below 1e-13; 1e-12 allows for the batch mean. Umbra bins read 0 (+- 0).
    const double c = 0.2;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    const auto s = shadow_settings(AbsorptionMode::continuous);
    const auto r = trace(water, box_above_bottom(0.0), s);

    const double n_w = 1.34, r_normal = std::pow((n_w - 1.0) / (n_w + 1.0), 2);
    CHECK(FlatSurface(n_w).reflectance_from_air(vec3(0.0, 0.0, 1.0)) == Approx(r_normal).epsilon(1e-14));
    const double w_bottom = (1.0 - r_normal) * std::exp(-c * depth), w_box = (1.0 - r_normal) * std::exp(-c * 2.0);

    // The launch points, photon by photon, into bins per batch; and those on the box's top.
    const BottomGrid grid(bins, width);
    std::vector<std::vector<double>> launched(s.batches, std::vector<double>(grid.size(), 0.0));
    std::vector<double> batch_photons(s.batches, 0.0);
    double on_box = 0.0;
    for (const auto& blk : detail::make_blocks(s.photons, s.batches, s.block_size))
        for (std::uint64_t i = blk.begin; i < blk.end; ++i) {
            PhotonRng rng(s.seed, i);
            const double x = width * rng.uniform();
            const double y = width * rng.uniform();
            batch_photons[blk.batch] += 1.0;
            if (x > 0.25 && x < 0.75 && y > 0.25 && y < 0.75) on_box += 1.0;  // the box's interior footprint
            else launched[blk.batch][grid.bin(x, y)] += 1.0;
        }

    REQUIRE(r.bottom_ed_bins.size() == bins * bins);
    int umbra_bins = 0, lit_bins = 0;
    for (unsigned iy = 0; iy < bins; ++iy)
        for (unsigned ix = 0; ix < bins; ++ix) {
            const Estimate& e = r.bottom_ed_bins[iy * bins + ix];
            INFO("bin " << ix << ", " << iy << ": " << e.value << " +- " << e.se);
            if (umbra(ix, iy)) {
                ++umbra_bins;
                CHECK(e.value == 0.0);
                CHECK(e.se == 0.0);
            } else if (lit(ix, iy)) {
                ++lit_bins;
                double expected = 0.0;
                for (unsigned b = 0; b < s.batches; ++b)
                    expected += grid.area_ratio() * launched[b][iy * bins + ix] * w_bottom / batch_photons[b];
                expected /= s.batches;
                CHECK(e.value == Approx(expected).epsilon(1e-12));
                // And Beer-Lambert in expectation: within 4 of its own standard errors.
                CHECK(std::abs(e.value - w_bottom) <= 4.0 * e.se);
            }
        }
    CHECK(umbra_bins == 16);
    CHECK(lit_bins == 64);
    const double n = static_cast<double>(s.photons);
    CHECK(r.ledger.absorbed_objects == Approx(on_box * w_box / n).epsilon(1e-12));
    CHECK(r.ledger.absorbed_bottom == Approx((n - on_box) * w_bottom / n).epsilon(1e-12));
    CHECK(std::abs(r.ledger.imbalance()) < 1e-12);
    // The bins together are the section's bottom Ed.
    double mean = 0.0;
    for (const Estimate& e : r.bottom_ed_bins) mean += e.value;
    CHECK(mean / (bins * bins) == Approx(r.bottom_ed.value).epsilon(1e-12));
}

TEST_CASE("With scattering the umbra fills in, the ledger closes with the box's absorption, modes agree") {
    // w0 = 0.8, c = 0.5 1/m (b H = 1.6 scattering lengths to the bottom), forward-peaked HG:
    // light scattered sideways reaches the bottom in the box's shadow. The box reflects half the
    // light it receives (Lambertian, A = 0.5) and absorbs the rest. No roulette: the ledger
    // closes photon by photon, exactly in analog mode and to rounding with weights; 1e-9
    // relative bounds rounding of 40,000-term sums (about 1e-12) with a wide margin.
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const Shapes box = box_above_bottom(0.5);
    const auto analog = trace(water, box, shadow_settings(AbsorptionMode::analog));
    const auto weighted = trace(water, box, shadow_settings(AbsorptionMode::continuous));
    for (const auto* r : {&analog, &weighted}) {
        const EnergyLedger& l = r->ledger;
        INFO("absorbed by the box " << l.absorbed_objects << ", imbalance " << l.imbalance());
        CHECK(l.absorbed_objects > 0.01);
        CHECK(std::abs(l.imbalance()) <= 1e-9 * l.incident);
        for (unsigned iy = 3; iy <= 6; ++iy)
            for (unsigned ix = 3; ix <= 6; ++ix) CHECK(r->bottom_ed_bins[iy * bins + ix].value > 0.0);
    }
    // The two modes estimate the same irradiances (4 combined SE, fixed in advance).
    testing::check_agree(analog.bottom_ed, weighted.bottom_ed, "bottom Ed");
    testing::check_agree(analog.bottom_ed_bins[4 * bins + 4], weighted.bottom_ed_bins[4 * bins + 4], "umbra bin (4, 4)");
    testing::check_agree(analog.irradiance[1][Eu], weighted.irradiance[1][Eu], "Eu at 1 m");
    // The umbra is darker than the open bottom (it lacks the direct beam).
    double umbra_mean = 0.0, lit_mean = 0.0;
    for (unsigned iy = 0; iy < bins; ++iy)
        for (unsigned ix = 0; ix < bins; ++ix) {
            if (umbra(ix, iy)) umbra_mean += weighted.bottom_ed_bins[iy * bins + ix].value / 16.0;
            if (lit(ix, iy)) lit_mean += weighted.bottom_ed_bins[iy * bins + ix].value / 64.0;
        }
    INFO("umbra " << umbra_mean << ", open " << lit_mean);
    CHECK(umbra_mean < lit_mean);
}

TEST_CASE("With objects the output is the same for 1 and 2 threads; objects outside the section are refused") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    Shapes g = box_above_bottom(0.5);
    g.add(Sphere(vec3(0.1, 0.9, 1.0), 0.1), ObjectMaterial::lambertian(0.9));  // touching the seams
    testing::require_same_for_1_and_2_threads(AbsorptionMode::continuous, [&](TransportSettings s) {
        s.bottom_bins = 4;
        return trace(water, g, s);
    });
    const auto s = shadow_settings(AbsorptionMode::continuous);
    Shapes outside;
    outside.add(Sphere(vec3(0.95, 0.5, 1.0), 0.1), ObjectMaterial::absorbing());
    CHECK_THROWS_WITH(trace(water, outside, s), Catch::Contains("object bounds' highest x, y"));
    Shapes below;
    below.add(AxisBox(vec3(0.1, 0.1, 3.5), vec3(0.2, 0.2, 4.5)), ObjectMaterial::absorbing());
    CHECK_THROWS_WITH(trace(water, below, s), Catch::Contains("object bounds' bottom depth"));
    auto many = s;
    many.bottom_bins = 5000;
    CHECK_THROWS_WITH(trace(water, NoGeometry{}, many), Catch::Contains("bottom bins"));
}

TEST_CASE("Albedo maps: refused by name, read by the point's cell through the periodic copies") {
    CHECK_THROWS_WITH(AlbedoMap(2, 2, 1.0, {0.1, 0.2, 0.3}), Catch::Contains("albedo map values = 3"));
    CHECK_THROWS_WITH(AlbedoMap(2, 1, 1.0, {0.1, 1.5}), Catch::Contains("albedo map[1] = 1.5"));
    CHECK_THROWS_WITH(AlbedoMap(0, 1, 1.0, {}), Catch::Contains("albedo map cells per side"));
    CHECK_THROWS_WITH(AlbedoMap(1, 1, 0.0, {0.5}), Catch::Contains("albedo map width"));
    const AlbedoMap m(2, 2, 4.0, {0.1, 0.2, 0.3, 0.4});  // cells of 2 m: (0, 0) 0.1, (1, 0) 0.2, (0, 1) 0.3, (1, 1) 0.4
    CHECK(m.at(1.0, 1.0) == 0.1);
    CHECK(m.at(3.0, 1.0) == 0.2);
    CHECK(m.at(1.0, 3.0) == 0.3);
    CHECK(m.at(3.9, 3.9) == 0.4);
    CHECK(m.at(-1.0, 1.0) == 0.2);   // x = -1 is x = 3 of the copy to the left
    CHECK(m.at(9.0, 7.0) == 0.3);    // (1, 3) of a copy two periods over
    CHECK(m.at(4.0, 0.0) == 0.1);    // on the seam: the next copy's first cell
    const ObjectMaterial mapped = ObjectMaterial::mapped(m);
    CHECK(mapped.albedo_at(vec3(3.0, 3.0, 2.0)) == 0.4);
    CHECK(ObjectMaterial::lambertian(0.7).albedo_at(vec3(3.0, 3.0, 2.0)) == 0.7);
}

TEST_CASE("A box whose albedo map blackens one strip of its top: the strip absorbs what lands on it, exactly") {
    // Non-scattering water (w0 = 0, continuous), vertical sun, index-matched surface (nothing
    // reflected back down at it): every photon goes straight down from its launch point. The
    // map has 8 strips across x; on the box's top (z = 2 m, x from 0.25 to 0.75) the strip
    // x in [0.25, 0.375) is black and the rest white (A = 1): photons landing on the black strip
    // are absorbed there with weight exp(-2 c); the others are reflected upward and leave
    // through the surface (they cannot meet the box or its copies again). So the box absorbs
    // N_black exp(-2 c) / N, photon by photon (a map read mirrored or shifted would not).
    const double c = 0.2;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    Shapes box;
    box.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)),
            ObjectMaterial::mapped(AlbedoMap(8, 1, width, {1.0, 1.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0})));
    const auto s = shadow_settings(AbsorptionMode::continuous);
    const auto r = ObjectTracer<IsoWater, Shapes>(water, Slab(width, Bottom::lambertian_at(depth, 0.0)), FlatSurface(1.0),
                                                  SunAndSky(CollimatedSun(0.0)), s, box)
                       .run();
    double black = 0.0, white = 0.0;
    for (const auto& blk : detail::make_blocks(s.photons, s.batches, s.block_size))
        for (std::uint64_t i = blk.begin; i < blk.end; ++i) {
            PhotonRng rng(s.seed, i);
            const double x = width * rng.uniform(), y = width * rng.uniform();
            if (x > 0.25 && x < 0.75 && y > 0.25 && y < 0.75) (x < 0.375 ? black : white) += 1.0;
        }
    const double n = static_cast<double>(s.photons);
    INFO("on the black strip " << black << ", on the white part " << white);
    CHECK(black > 2000.0);
    CHECK(white > 2.5 * black);
    CHECK(r.ledger.absorbed_objects == Approx(black * std::exp(-c * 2.0) / n).epsilon(1e-12));
    CHECK(std::abs(r.ledger.imbalance()) < 1e-12);
    // A uniform map of the same albedo is the constant material, bit for bit.
    Shapes grey_map, grey;
    grey_map.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::mapped(AlbedoMap(1, 1, width, {0.5})));
    grey.add(AxisBox(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5)), ObjectMaterial::lambertian(0.5));
    const HgWater hg = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    testing::require_identical(trace(hg, grey_map, s), trace(hg, grey, s));
}
