// Triangle meshes through Embree 3 (scene/triangle_mesh.hpp, scene/embree_mesh.hpp): the mesh
// contract refused by name; closest hits over random rays against a brute-force search of every
// triangle in double precision, and a box given as a mesh against AxisBox; the first pass over a
// mesh box against the same box as a shape, and the same for 1 and 2 threads.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/scene/embree_mesh.hpp"
#include "secchi/scene/shapes.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <cmath>

using namespace secchi;
using testing::Rand;

namespace {
/// The closest hit of o + t d, t in [0, t_max), on the outer side of any triangle of the
/// meshes, by testing every triangle in double (Moller & Trumbore 1997); `edge_margin`
/// receives the smallest barycentric coordinate of the hit times the triangle's shortest
/// edge (m): how near the hit is to an edge, where single precision may decide otherwise.
std::optional<ObjectHit> brute_force_hit(const std::vector<TriangleMesh>& meshes, const vec3& o, const vec3& d, double t_max,
                                         double& edge_margin) {
    std::optional<ObjectHit> best;
    for (std::size_t m = 0; m < meshes.size(); ++m)
        for (std::size_t i = 0; i < meshes[m].triangles.size(); ++i) {
            const auto& tri = meshes[m].triangles[i];
            const vec3 a = meshes[m].vertices[tri[0]], e1 = meshes[m].vertices[tri[1]] - a, e2 = meshes[m].vertices[tri[2]] - a;
            const vec3 n = meshes[m].normal(i);
            if (glm::dot(n, d) >= 0.0) continue;  // the inner side
            const vec3 p = glm::cross(d, e2);
            const double det = glm::dot(e1, p);
            const vec3 s = o - a;
            const double u = glm::dot(s, p) / det;
            const vec3 q = glm::cross(s, e1);
            const double v = glm::dot(d, q) / det, t = glm::dot(e2, q) / det;
            if (u < 0.0 || v < 0.0 || u + v > 1.0 || t < 0.0 || t >= t_max) continue;
            if (best && best->t <= t) continue;
            best = ObjectHit{t, o + d * t, n, static_cast<std::uint32_t>(m)};
            const double shortest = std::min({glm::length(e1), glm::length(e2), glm::length(e2 - e1)});
            edge_margin = std::min({u, v, 1.0 - u - v}) * shortest;
        }
    return best;
}
}  // namespace

TEST_CASE("Meshes that are not closed solids wound outward are refused, by name") {
    const TriangleMesh box = box_mesh(vec3(0.0), vec3(1.0), ObjectMaterial::absorbing());
    CHECK(box.volume() == Approx(1.0).epsilon(1e-14));
    CHECK(box.triangles.size() == 12);
    TriangleMesh open = box;
    open.triangles.pop_back();
    CHECK_THROWS_WITH(validated(open), Catch::Contains("reverse uses") && Catch::Contains("closed"));
    TriangleMesh inward = box;
    for (auto& t : inward.triangles) std::swap(t[1], t[2]);
    CHECK_THROWS_WITH(validated(inward), Catch::Contains("enclosed volume") && Catch::Contains("-1"));
    TriangleMesh twisted = box;
    std::swap(twisted.triangles[0][1], twisted.triangles[0][2]);
    CHECK_THROWS_WITH(validated(twisted), Catch::Contains("edge") && Catch::Contains("consistent winding"));
    TriangleMesh bad_index = box;
    bad_index.triangles[3][2] = 8;
    CHECK_THROWS_WITH(validated(bad_index), Catch::Contains("triangle[3] vertex index = 8"));
    TriangleMesh nan = box;
    nan.vertices[5].y = NAN;
    CHECK_THROWS_WITH(validated(nan), Catch::Contains("vertex[5] coordinate"));
    TriangleMesh flat = box;
    flat.vertices[1] = flat.vertices[0];
    CHECK_THROWS_WITH(validated(flat), Catch::Contains("area"));
    TriangleMesh grey = box;
    grey.material.albedo = 1.5;
    CHECK_THROWS_WITH(validated(grey), Catch::Contains("object albedo"));
    CHECK_THROWS_WITH(validated(TriangleMesh{}), Catch::Contains("triangle count"));
    CHECK_THROWS_WITH(EmbreeMesh({}), Catch::Contains("mesh count"));
    CHECK_THROWS_WITH(EmbreeMesh({open}), Catch::Contains("mesh[0] edge"));
    CHECK_THROWS_WITH(sphere_mesh(vec3(0.0), 1.0, 1, 8, {}), Catch::Contains("sphere mesh rings"));
    // The sphere's mesh is inscribed: its volume approaches 4/3 pi r^3 from below.
    const double r = 0.7, v = 4.0 / 3.0 * pi * r * r * r;
    const double coarse = sphere_mesh(vec3(1.0), r, 8, 16, {}).volume(), fine = sphere_mesh(vec3(1.0), r, 64, 128, {}).volume();
    CHECK(coarse < fine);
    CHECK(fine < v);
    CHECK(fine > 0.99 * v);
}

TEST_CASE("EmbreeMesh: the closest hit of random rays is the brute-force search's over every triangle") {
    // Two spheres (1,984 and 480 triangles, one overlapping the other's bounds) and a box; rays
    // from random points outside them, in random directions or aimed at them, cut at random t_max. Single
    // precision may decide otherwise within about 1e-5 m of an edge: such rays are counted, not
    // compared (a handful of 20,000).
    const std::vector<TriangleMesh> meshes{sphere_mesh(vec3(0.0, 0.0, 2.0), 0.8, 32, 32, ObjectMaterial::lambertian(0.3)),
                                           sphere_mesh(vec3(1.0, 0.4, 2.5), 0.5, 16, 16, ObjectMaterial::absorbing()),
                                           box_mesh(vec3(-2.0, -1.0, 0.5), vec3(-1.2, 1.0, 1.0), ObjectMaterial::lambertian(0.9))};
    const EmbreeMesh g(meshes);
    CHECK(g.triangle_count() == 2 * 32 * 31 + 2 * 16 * 15 + 12);
    CHECK(g.material(2).albedo == 0.9);
    CHECK(g.bounds().lo.x == -2.0);
    auto inside_any = [](const vec3& p) {
        return glm::length(p - vec3(0.0, 0.0, 2.0)) < 0.8 || glm::length(p - vec3(1.0, 0.4, 2.5)) < 0.5 ||
               AxisBox(vec3(-2.0, -1.0, 0.5), vec3(-1.2, 1.0, 1.0)).contains(p);
    };
    Rand r(31);
    int hits = 0, near_edges = 0, compared = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        vec3 o;
        do o = vec3(r.in(-3.0, 3.0), r.in(-3.0, 3.0), r.in(-1.0, 5.0));
        while (inside_any(o));
        // Half the rays aimed at a point in a random mesh's bounds (so that many hit), half anywhere.
        const Bounds aim = meshes[trial % 3].bounds();
        const vec3 target{r.in(aim.lo.x, aim.hi.x), r.in(aim.lo.y, aim.hi.y), r.in(aim.lo.z, aim.hi.z)};
        const vec3 d = trial % 2 ? glm::normalize(target - o) : r.direction();
        const double t_max = trial % 4 == 0 ? INFINITY : r.in(0.0, 6.0);
        double margin = INFINITY;
        const auto want = brute_force_hit(meshes, o, d, t_max, margin);
        const auto got = g.closest_hit(o, d, t_max);
        if (margin < 1e-5 || (want && std::abs(want->t - t_max) < 1e-5)) {
            ++near_edges;
            continue;
        }
        ++compared;
        INFO("trial " << trial);
        REQUIRE(bool(got) == bool(want));
        if (!got) continue;
        ++hits;
        CHECK(got->t == Approx(want->t).epsilon(1e-12).margin(1e-12));
        CHECK(got->material == want->material);
        CHECK(glm::length(got->normal - want->normal) < 1e-14);
        CHECK(glm::length(got->point - want->point) < 1e-12);
        CHECK(glm::dot(got->normal, d) < 0.0);
    }
    INFO("near edges " << near_edges << ", compared " << compared << ", hits " << hits);
    CHECK(near_edges < 20);
    CHECK(hits > 5000);
}

TEST_CASE("EmbreeMesh: a box as 12 triangles meets rays as AxisBox does; on its surface, in at 0, out never") {
    const vec3 lo(0.2, 0.3, 1.0), hi(0.9, 0.7, 1.6);
    const AxisBox box(lo, hi);
    const EmbreeMesh g({box_mesh(lo, hi, ObjectMaterial::absorbing())});
    Rand r(32);
    for (int trial = 0; trial < 4000; ++trial) {
        // A point on a face, at least 1 mm from its edges, and the face's outward normal.
        const int k = trial % 3;
        const bool high = r() < 0.5;
        vec3 p, n_out(0.0);
        for (int j = 0; j < 3; ++j) p[j] = r.in(lo[j] + 1e-3, hi[j] - 1e-3);
        p[k] = high ? hi[k] : lo[k];
        n_out[k] = high ? 1.0 : -1.0;
        const vec3 d = r.direction_against(n_out, -1.0);
        const double t0 = r.in(0.01, 3.0);
        const vec3 o = p - t0 * d;
        INFO("trial " << trial);
        const auto want = box.intersect(o, d, INFINITY);
        const auto got = g.closest_hit(o, d, INFINITY);
        REQUIRE(want);
        REQUIRE(got);
        CHECK(got->t == Approx(want->t).epsilon(1e-15));
        CHECK(glm::length(got->normal - want->normal) < 1e-15);
        // Starting on the face: moving in meets it at t = 0 (not too grazing: embree_mesh.hpp);
        // moving out (the reflected photon, 1e-9 m off the surface as the tracer leaves it, or
        // on it) meets nothing.
        if (-glm::dot(d, n_out) > 0.02) {
            const auto on = g.closest_hit(p, d, 1.0);
            REQUIRE(on);
            CHECK(on->t == 0.0);
        }
        const vec3 out = lambertian_direction(n_out, r(), r());
        CHECK_FALSE(g.closest_hit(p + 1e-9 * n_out, out, INFINITY));
        CHECK_FALSE(g.closest_hit(p, out, INFINITY));
        // t_max cuts the hit: just before it none, just after it the hit.
        CHECK_FALSE(g.closest_hit(o, d, want->t * (1.0 - 1e-9)));
        CHECK(g.closest_hit(o, d, want->t * (1.0 + 1e-9)));
    }
}

namespace {
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <SceneGeometry G>
TransportResult<CompactRecord> trace_over(const G& g, const TransportSettings& s) {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    return PhotonTracer<HgWater, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, G>(
               water, Slab(1.0, Bottom::lambertian_at(4.0, 0.2)), FlatSurface(1.34), SunAndSky(CollimatedSun(0.5)), s, g)
        .run();
}
}  // namespace

TEST_CASE("The first pass over a box given as a mesh is the first pass over the box as a shape") {
    // A Lambertian box (A 0.5) across the seam x = 0 of a 1 m section is not possible as one
    // AxisBox in [0, W]^2, so the box sits inside; the photons, seeds and physics are the same,
    // and the two geometries give the same distances and normals (previous test): the runs agree
    // photon by photon except where single precision decides a hit within ~1e-5 m of an edge
    // otherwise, after which that photon's path differs. So: every figure within 4 combined SE,
    // and what the box absorbed within 1 %.
    const vec3 lo(0.25, 0.25, 2.0), hi(0.75, 0.75, 2.5);
    Shapes shape;
    shape.add(AxisBox(lo, hi), ObjectMaterial::lambertian(0.5));
    const EmbreeMesh mesh({box_mesh(lo, hi, ObjectMaterial::lambertian(0.5))});
    TransportSettings s;
    s.photons = 40000;
    s.map_photons = 4000;
    s.depths = {0.0, 1.0, 3.0};
    s.bottom_bins = 4;
    s.block_size = 1000;
    s.roulette_weight = 0.0;
    const auto a = trace_over(shape, s), b = trace_over(mesh, s);
    INFO("absorbed by the box: shape " << a.ledger.absorbed_objects << ", mesh " << b.ledger.absorbed_objects);
    CHECK(b.ledger.absorbed_objects == Approx(a.ledger.absorbed_objects).epsilon(0.01));
    CHECK(std::abs(b.ledger.imbalance()) <= 1e-9 * b.ledger.incident);
    for (std::size_t k = 0; k < a.bottom_ed_bins.size(); ++k)
        testing::check_agree(a.bottom_ed_bins[k], b.bottom_ed_bins[k], "bottom bin " + std::to_string(k));
    for (std::size_t z = 0; z < s.depths.size(); ++z)
        for (const auto q : {Ed, Eu, Eod, Eou})
            testing::check_agree(a.irradiance[z][q], b.irradiance[z][q], "irradiance at depth index " + std::to_string(z));
}

TEST_CASE("The first pass over meshes is the same for 1 and 2 threads; meshes outside the section are refused") {
    const EmbreeMesh g({box_mesh(vec3(0.25, 0.25, 2.0), vec3(0.75, 0.75, 2.5), ObjectMaterial::lambertian(0.5)),
                        sphere_mesh(vec3(0.8, 0.2, 1.0), 0.15, 12, 24, ObjectMaterial::lambertian(0.9))});
    testing::require_same_for_1_and_2_threads(AbsorptionMode::continuous, [&](TransportSettings s) {
        s.bottom_bins = 4;
        return trace_over(g, s);
    });
    TransportSettings s;
    s.photons = 1000;
    const EmbreeMesh outside({sphere_mesh(vec3(0.95, 0.5, 1.0), 0.1, 8, 8, ObjectMaterial::absorbing())});
    CHECK_THROWS_WITH(trace_over(outside, s), Catch::Contains("object bounds' highest x, y"));
}
