// A height-field bottom (scene/height_field.hpp): bad terrains refused by name; the closest hits
// of random rays against a brute-force search over every triangle in double precision, in one
// column and through the periodic copies; rays through the grid's vertices and edges (none
// slips between triangles); the flat limit against a plane's closed form; the
// first pass over a terrain: in non-scattering water photon by photon and against the exact
// integral of Beer-Lambert over the terrain, with scattering the ledger closing with what the
// terrain absorbs, nothing passing through it, and the same output for 1 and 2 threads.
#include <catch2/catch.hpp>

#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/scene/height_field.hpp"
#include "secchi/transport/tracer.hpp"
#include "random_draws.hpp"
#include "transport_checks.hpp"
#include <array>
#include <iomanip>
#include <cmath>
#include <vector>

using namespace secchi;
using testing::Rand;

static_assert(SceneGeometry<HeightField>);

namespace {

/// A triangle of the terrain and its unit normal out of the solid (up: n.z < 0).
struct Tri {
    vec3 a, b, c, n;
};

/// The 2 nx ny triangles of the terrain of node depths `h` (index j nx + i), built as the header
/// documents them (each cell split along the diagonal from node (i, j) to node (i + 1, j + 1);
/// node nx is node 0), with vertices at (W i / nx, W j / ny, h): independent of the class.
std::vector<Tri> triangles_of(const std::vector<double>& h, unsigned nx, unsigned ny, double w) {
    const auto node = [&](unsigned i, unsigned j) {
        return vec3(w * i / nx, w * j / ny, h[static_cast<std::size_t>(j % ny) * nx + i % nx]);
    };
    std::vector<Tri> tris;
    for (unsigned j = 0; j < ny; ++j)
        for (unsigned i = 0; i < nx; ++i) {
            const vec3 p00 = node(i, j), p10 = node(i + 1, j), p11 = node(i + 1, j + 1), p01 = node(i, j + 1);
            for (const auto& v : {std::array<vec3, 3>{p00, p10, p11}, std::array<vec3, 3>{p00, p11, p01}}) {
                vec3 n = glm::normalize(glm::cross(v[1] - v[0], v[2] - v[0]));
                if (n.z > 0.0) n = -n;
                tris.push_back({v[0], v[1], v[2], n});
            }
        }
    return tris;
}

/// The brute-force search's answer: the closest hit, and whether the ray crosses the plane of
/// some triangle within `band` of one of its edges before it (where the two searches may
/// legitimately differ: the ray then passes, to rounding, through an edge or a vertex).
struct Search {
    std::optional<ObjectHit> hit;
    std::vector<double> near_edge;  ///< distances where the ray crosses a plane near an edge
    double band = 0.0;              ///< the largest band used (m)
    [[nodiscard]] bool near(double t_max) const {
        const double until = (hit ? hit->t : t_max) + 1e-9;
        for (const double t : near_edge)
            if (t <= until) return true;
        return false;
    }
};

/// How far from an edge (m) the two searches may disagree: 1e-9 m, plus the rounding of a
/// crossing's position on a plane, a few eps (1e-14 here) of the scene's scale L (m) over the
/// cosine between the ray and the plane (how much a rounding of the plane moves the crossing).
double edge_band(double scale, double cosine) { return 1e-9 + 1e-14 * scale / std::abs(cosine); }

/// Every triangle of `tris` shifted by `shift`, front side only (n . d < 0), by Moller &
/// Trumbore's test in double, barycentric coordinates in [0, 1] exactly, t in [0, t_max).
void brute_force(const std::vector<Tri>& tris, const vec3& shift, const vec3& o, const vec3& d, double t_max, double scale,
                 Search& s) {
    for (const Tri& tri : tris) {
        const double cosine = glm::dot(tri.n, d);
        if (cosine >= 0.0) continue;
        const vec3 a = tri.a + shift, e1 = tri.b - tri.a, e2 = tri.c - tri.a;
        const vec3 p = glm::cross(d, e2);
        const double det = glm::dot(e1, p);
        const vec3 q0 = o - a, q = glm::cross(q0, e1);
        const double u = glm::dot(q0, p) / det, v = glm::dot(d, q) / det, t = glm::dot(e2, q) / det;
        // The crossing's distances from the lines of the three edges: barycentric x height.
        const double area2 = glm::length(glm::cross(e1, e2));
        const double margin = std::min({(1.0 - u - v) * area2 / glm::length(e2 - e1), u * area2 / glm::length(e2),
                                        v * area2 / glm::length(e1)});
        const double band = edge_band(scale, cosine);
        s.band = std::max(s.band, band);
        if (t > -band && t < t_max + band && (std::abs(margin) < band || (margin >= 0.0 && std::abs(t - t_max) < band)))
            s.near_edge.push_back(t);
        if (u < 0.0 || v < 0.0 || u + v > 1.0 || t < 0.0 || !(t < t_max)) continue;
        if (s.hit && s.hit->t <= t) continue;
        s.hit = ObjectHit{t, o + d * t, tri.n, 0};
    }
}

/// How closely the distances must agree: both are a plane crossing computed from coordinates
/// of size L (scale, m), each op rounding by eps (2.2e-16), about ten of them: 1e-14 L over
/// the cosine with the plane; and 1e-12 of t for the rest.
double t_tolerance(double t, double scale, double cosine) { return 1e-12 * t + 1e-14 * scale / std::abs(cosine); }

/// A terrain of random node depths, and one sampled from a smooth function with flat parts
/// (plateaus where sin(2 pi x) <= 0: exactly horizontal triangles).
struct Terrain {
    std::vector<double> h;
    unsigned nx, ny;
    double w, floor;
    [[nodiscard]] HeightField field(ObjectMaterial m = ObjectMaterial::absorbing()) const {
        return HeightField(nx, ny, w, floor, h, std::move(m));
    }
};

Terrain random_terrain(Rand& r, unsigned nx, unsigned ny, double w, double lo, double hi, double floor) {
    Terrain t{{}, nx, ny, w, floor};
    for (unsigned k = 0; k < nx * ny; ++k) t.h.push_back(r.in(lo, hi));
    return t;
}

Terrain plateau_terrain() {
    const auto f = [](double x, double y) { return 1.5 + 0.4 * std::max(0.0, std::sin(two_pi * x)) * std::cos(two_pi * y); };
    Terrain t{{}, 12, 12, 1.0, 3.0};
    for (unsigned j = 0; j < t.ny; ++j)
        for (unsigned i = 0; i < t.nx; ++i) t.h.push_back(f(t.w * i / t.nx, t.w * j / t.ny));
    return t;
}

/// A point above the terrain: (x, y) in [x_lo, x_hi]^2, z in [z_lo, z_hi], at least 1e-6 m
/// above it (photons are in the water).
vec3 point_above(const HeightField& hf, Rand& r, double x_lo, double x_hi, double z_lo, double z_hi) {
    while (true) {
        const vec3 o{r.in(x_lo, x_hi), r.in(x_lo, x_hi), r.in(z_lo, z_hi)};
        if (o.z < hf.depth_at(o.x, o.y) - 1e-6) return o;
    }
}

vec3 level_direction(Rand& r, double dz) {
    const double phi = two_pi * r();
    return glm::normalize(vec3(std::cos(phi), std::sin(phi), dz));
}
}  // namespace

TEST_CASE("Height field: bad terrains are refused by name and value") {
    const auto grey = ObjectMaterial::lambertian(0.3);
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, -0.1, 0.5, 0.5}, grey),
                      Catch::Contains("height field depth[1] = -0.1") && Catch::Contains(">= 0"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, 0.5, 0.5, 3.0}, grey),
                      Catch::Contains("height field depth[3] = 3") && Catch::Contains("floor"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, 0.5, 0.5, 3.5}, grey), Catch::Contains("height field depth[3] = 3.5"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, 0.5, NAN}, grey),
                      Catch::Contains("height field depths = 3") && Catch::Contains("nx x ny = 4"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, 0.5, NAN, 0.5}, grey),
                      Catch::Contains("height field depth[2] = nan") && Catch::Contains("finite"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, 0.5, INFINITY, 0.5}, grey),
                      Catch::Contains("height field depth[2] = inf"));
    CHECK_THROWS_WITH(HeightField(2, 2, 0.0, 3.0, {0.5, 0.5, 0.5, 0.5}, grey), Catch::Contains("height field width (m) = 0"));
    CHECK_THROWS_WITH(HeightField(2, 2, -1.0, 3.0, {0.5, 0.5, 0.5, 0.5}, grey), Catch::Contains("height field width (m) = -1"));
    CHECK_THROWS_WITH(HeightField(2, 2, INFINITY, 3.0, {0.5, 0.5, 0.5, 0.5}, grey), Catch::Contains("height field width"));
    CHECK_THROWS_WITH(HeightField(2, 2, NAN, 3.0, {0.5, 0.5, 0.5, 0.5}, grey), Catch::Contains("height field width"));
    CHECK_THROWS_WITH(HeightField(0, 2, 1.0, 3.0, {}, grey), Catch::Contains("height field nodes per side = 0"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, NAN, {0.5, 0.5, 0.5, 0.5}, grey), Catch::Contains("height field floor depth"));
    CHECK_THROWS_WITH(HeightField(2, 2, 1.0, 3.0, {0.5, 0.5, 0.5, 0.5}, ObjectMaterial{1.5}),
                      Catch::Contains("object albedo = 1.5"));
    // A 1 x 1 grid is a flat terrain (its one node repeating); a terrain can reach the surface.
    const HeightField flat(1, 1, 2.0, 3.0, {0.0}, grey);
    CHECK(flat.depth_at(0.7, 1.9) == 0.0);
    // from_function samples f at the nodes (W i / nx, W j / ny); node nx is node 0.
    const auto f = [](double x, double y) { return 1.0 + x + 0.1 * y; };
    const HeightField g = HeightField::from_function(4, 3, 2.0, 5.0, f, grey);
    for (unsigned j = 0; j <= 3; ++j)
        for (unsigned i = 0; i <= 4; ++i) CHECK(g.node_depth(i, j) == f(2.0 * (i % 4) / 4, 2.0 * (j % 3) / 3));
    CHECK(g.min_depth() == 1.0);
    CHECK(g.max_depth() == f(1.5, 2.0 * 2 / 3));
    const Bounds b = g.bounds();
    CHECK((b.lo == vec3(0.0, 0.0, 1.0)));
    CHECK((b.hi == vec3(2.0, 2.0, 5.0)));
    CHECK(g.material(0).albedo == 0.3);
}

TEST_CASE("Height field: the closest hit of random rays is the brute-force search's over every triangle") {
    // Rays from points above the terrain (over the column and around it): aimed at random points
    // of the terrain, in uniform directions, near-level (|d_z| from 1e-1 down to 1e-8), exactly
    // level, vertical (down and up), and grazing rays aimed at the terrain from close by; t_max
    // unbounded or random. The brute force tests every triangle (exactly inside, front side).
    // Rays crossing a plane within edge_band of an edge are counted apart (they pass, to
    // rounding, through an edge or vertex, where either may answer): the band is 1e-9 m at
    // normal incidence, so a handful at most; the rest are compared: hit or miss, distance
    // (t_tolerance), normal (1e-12: both are the plane's normal to a few eps), point.
    Rand r(41);
    const Terrain terrains[] = {random_terrain(r, 7, 5, 2.0, 1.0, 2.0, 2.5), plateau_terrain()};
    int compared = 0, hits = 0, near_edges = 0, level_hits = 0, vertical_hits = 0, grazing_hits = 0;
    for (const Terrain& terrain : terrains) {
        const HeightField hf = terrain.field();
        const std::vector<Tri> tris = triangles_of(terrain.h, terrain.nx, terrain.ny, terrain.w);
        REQUIRE(tris.size() == 2 * terrain.nx * terrain.ny);
        const double w = terrain.w, lo = hf.min_depth(), hi = hf.max_depth(), scale = w + hi;
        for (int trial = 0; trial < 6000; ++trial) {
            const int kind = trial % 6;
            vec3 o, d;
            if (kind == 0 || kind == 1) {  // aimed at the terrain, or anywhere
                o = point_above(hf, r, -0.5 * w, 1.5 * w, lo - 1.0, hi);
                const double x = r.in(0.0, w), y = r.in(0.0, w);
                d = kind == 0 ? glm::normalize(vec3(x, y, hf.depth_at(x, y)) - o) : r.direction();
            } else if (kind == 2) {  // near-level, up or down
                o = point_above(hf, r, -0.5 * w, 1.5 * w, lo - 0.2, hi);
                d = level_direction(r, (r() < 0.5 ? -1.0 : 1.0) * std::pow(10.0, -r.in(1.0, 8.0)));
            } else if (kind == 3) {  // level, at the terrain's depths
                o = point_above(hf, r, -0.5 * w, 1.5 * w, lo, hi);
                d = level_direction(r, 0.0);
            } else if (kind == 4) {  // vertical, from over the column
                o = point_above(hf, r, 0.0, w, lo - 1.0, hi);
                d = vec3(0.0, 0.0, trial % 4 == 0 ? -1.0 : 1.0);
            } else {  // grazing, aimed at a terrain point from up to 1 m before it (in the water)
                do {
                    d = level_direction(r, r.in(1e-3, 0.1));
                    const double x = r.in(0.0, w), y = r.in(0.0, w);
                    o = vec3(x, y, hf.depth_at(x, y)) - r.in(0.01, 1.0) * d;
                } while (!(o.z < hf.depth_at(o.x, o.y) - 1e-6));
            }
            const double t_max = trial % 3 == 0 ? INFINITY : r.in(0.0, 4.0);
            Search want;
            brute_force(tris, vec3(0.0), o, d, t_max, scale, want);
            const auto got = hf.closest_hit(o, d, t_max);
            if (want.near(t_max)) {
                ++near_edges;
                continue;
            }
            ++compared;
            INFO("trial " << trial << " kind " << kind << ": o " << o.x << " " << o.y << " " << o.z << ", d " << d.x << " "
                          << d.y << " " << d.z << ", t_max " << t_max);
            REQUIRE(bool(got) == bool(want.hit));
            if (!got) continue;
            ++hits;
            level_hits += kind == 3;
            vertical_hits += kind == 4;
            grazing_hits += kind == 2 || kind == 5;
            const double cosine = glm::dot(want.hit->normal, d);
            INFO("t " << got->t << " vs " << want.hit->t << ", cosine " << cosine);
            CHECK(std::abs(got->t - want.hit->t) <= t_tolerance(want.hit->t, scale, cosine));
            CHECK(glm::length(got->normal - want.hit->normal) < 1e-12);
            CHECK(glm::length(got->point - (o + d * got->t)) < 1e-15 * (1.0 + got->t));
            CHECK(glm::dot(got->normal, d) < 0.0);
            CHECK(std::abs(glm::length(got->normal) - 1.0) < 1e-15);
            CHECK(got->material == 0);
            // [0, t_max): the hit itself is cut; the next double above keeps it.
            CHECK_FALSE(hf.closest_hit(o, d, got->t));
            const auto again = hf.closest_hit(o, d, std::nextafter(got->t, INFINITY));
            REQUIRE(again);
            CHECK(again->t == got->t);
        }
    }
    INFO("compared " << compared << ", hits " << hits << " (level " << level_hits << ", vertical " << vertical_hits
                     << ", grazing " << grazing_hits << "), near edges " << near_edges);
    WARN("random rays: compared " << compared << ", hits " << hits << " (level " << level_hits << ", vertical "
                                  << vertical_hits << ", grazing " << grazing_hits << "), near edges set apart " << near_edges);
    // The test sees every kind of ray hit (floors at about half the counts of seed 41).
    CHECK(near_edges <= 12);  // 0.1 % of 12,000
    CHECK(hits > 2500);
    CHECK(level_hits > 150);
    CHECK(vertical_hits > 400);
    CHECK(grazing_hits > 1000);
}

TEST_CASE("Height field: a ray starting on the terrain meets it at t = 0 moving down into it, never moving out") {
    // Points on the terrain (x, y, depth_at(x, y)), at least 1e-6 m from every edge (edges are
    // where the normal is ambiguous). Into the solid (n . d < -1e-3): a hit at exactly 0, the
    // point itself, the triangle's normal. Out of it (n . d > 1e-3): no hit at 0 (the brute
    // force, which sees the triangle from behind, decides whether the ray meets another hill
    // later); straight up: never (a height field).
    Rand r(42);
    const Terrain terrains[] = {random_terrain(r, 7, 5, 2.0, 1.0, 2.0, 2.5), plateau_terrain()};
    int later_hits = 0, points = 0;
    for (const Terrain& terrain : terrains) {
        const HeightField hf = terrain.field();
        const std::vector<Tri> tris = triangles_of(terrain.h, terrain.nx, terrain.ny, terrain.w);
        const double scale = terrain.w + hf.max_depth();
        for (int trial = 0; trial < 2000; ++trial) {
            const double x = r.in(0.0, terrain.w), y = r.in(0.0, terrain.w);
            Search above;  // the triangle under (x, y), from straight above
            brute_force(tris, vec3(0.0), vec3(x, y, -1.0), vec3(0.0, 0.0, 1.0), INFINITY, 0.0, above);
            REQUIRE(above.hit);
            bool near = false;
            for (const Tri& tri : tris) {  // within 1e-6 m of an edge in x, y: skipped
                const vec3 corners[] = {tri.a, tri.b, tri.c};
                for (int k = 0; k < 3; ++k) {
                    const vec3 p = corners[k], q = corners[(k + 1) % 3];
                    const double ex = q.x - p.x, ey = q.y - p.y, len = std::hypot(ex, ey);
                    const double along = ((x - p.x) * ex + (y - p.y) * ey) / len;
                    const double off = std::abs((x - p.x) * ey - (y - p.y) * ex) / len;
                    if (off < 1e-6 && along > -1e-6 && along < len + 1e-6) near = true;
                }
            }
            if (near) continue;
            ++points;
            const vec3 p(x, y, hf.depth_at(x, y)), n = above.hit->normal;
            INFO("trial " << trial << " at " << x << " " << y);
            CHECK(p.z == Approx(above.hit->point.z).margin(1e-14));  // depth_at is the terrain
            for (const vec3& d : {vec3(0.0, 0.0, 1.0), r.direction_against(n, -1.0)}) {
                const auto in = hf.closest_hit(p, d, INFINITY);
                REQUIRE(in);
                CHECK(in->t == 0.0);
                CHECK((in->point == p));
                CHECK(glm::length(in->normal - n) < 1e-12);
            }
            CHECK_FALSE(hf.closest_hit(p, vec3(0.0, 0.0, -1.0), INFINITY));
            const vec3 out_dir = r.direction_against(n, 1.0);
            const double t_max = trial % 2 ? INFINITY : r.in(0.0, 2.0);
            Search want;
            brute_force(tris, vec3(0.0), p, out_dir, t_max, scale, want);
            const auto out = hf.closest_hit(p, out_dir, t_max);
            if (want.near(t_max)) continue;
            REQUIRE(bool(out) == bool(want.hit));
            if (!out) continue;
            ++later_hits;
            CHECK(out->t > 1e-6);
            CHECK(std::abs(out->t - want.hit->t) <= t_tolerance(want.hit->t, scale, glm::dot(want.hit->normal, out_dir)));
        }
    }
    INFO("points " << points << ", rays leaving that meet another slope later " << later_hits);
    CHECK(points > 3500);
    CHECK(later_hits > 100);
}

TEST_CASE("Height field: rays through the grid's vertices and edges, and along them, never slip between triangles") {
    // The rays the comparison above sets apart: aimed exactly at a node (x_i, y_j) = (W i / nx,
    // W j / ny) (the seam's nodes i = nx, j = ny included), at a point of a cell's side or of its
    // diagonal, from a point in the water up to 0.5 m before it, or straight down onto it; and
    // rays running along a grid line or a diagonal in x, y. Where the ray is inside the solid
    // just past the point aimed at (1e-7 m on, more than 1e-12 m below the terrain), it has
    // entered it there or before: it must meet the terrain no later than that point (1e-12 m
    // plus the rounding of the aim, 1e-14 L over the cosine), at a point on it (depth_at there,
    // 1e-12 m); through periodic_closest_hit too, from a copy over (for a point on the column's
    // side, only through the copies: the ray leaves this column there). A ray slipping through
    // an edge would pass the point unmet. Where it is in the water past the point, it only
    // grazed a ridge or a peak there (and may go on): any hit must still be on the terrain. One
    // column alone owes a hit only where the ray comes to the point from the water (1e-7 m
    // before it): a ray from a point beside the column may have entered the solid in a
    // neighbouring copy.
    Rand r(46);
    const Terrain terrains[] = {random_terrain(r, 7, 5, 2.0, 1.0, 2.0, 2.5), plateau_terrain()};
    int entering = 0, grazing = 0, undecided = 0, from_solid = 0;
    for (const Terrain& terrain : terrains) {
        const HeightField hf = terrain.field();
        const unsigned nx = terrain.nx, ny = terrain.ny;
        const double w = terrain.w, scale = w + hf.max_depth();
        const auto node = [&](unsigned i, unsigned j) {
            return vec3(w * i / nx, w * j / ny, terrain.h[static_cast<std::size_t>(j % ny) * nx + i % nx]);
        };
        const auto check_meets = [&](const vec3& o, const vec3& d, const vec3& target, bool periodic) {
            periodic = periodic || target.x == 0.0 || target.y == 0.0 || target.x == w || target.y == w;
            const double t_target = glm::length(target - o);
            const vec3 past = target + 1e-7 * d, before = target - 1e-7 * d;
            const double below = past.z - hf.depth_at(past.x, past.y);
            // One column answers for its own part of the ray: where the ray comes to the point
            // from inside the solid (having entered it in another copy), it enters nothing there.
            const bool from_water = before.z < hf.depth_at(before.x, before.y) - 1e-12;
            const auto hit = periodic ? periodic_closest_hit(hf, w, o + vec3(w, -w, 0.0), d, INFINITY)
                                      : hf.closest_hit(o, d, INFINITY);
            INFO(std::setprecision(17) << "aimed at " << target.x << " " << target.y << " " << target.z << " from " << o.x
                                       << " " << o.y << " " << o.z
                             << (periodic ? " (a copy over)" : "") << "; 1e-7 m past it, " << below << " m below the terrain");
            if (hit) {
                const vec3 p = o + d * hit->t;
                CHECK(std::abs(p.z - hf.depth_at(p.x, p.y)) < 1e-12);
            }
            if (std::abs(below) <= 1e-12) {
                ++undecided;
            } else if (below < 0.0) {
                ++grazing;
            } else if (!periodic && !from_water) {
                ++from_solid;
            } else {
                ++entering;
                REQUIRE(hit);
                const double cosine = std::max(1e-3, -glm::dot(hit->normal, d));
                CHECK(hit->t <= t_target + 1e-12 + 1e-14 * scale / cosine);
            }
        };
        for (unsigned j = 0; j <= ny; ++j)
            for (unsigned i = 0; i <= nx; ++i) {
                const vec3 p00 = node(i, j), p10 = node(i + 1, j), p11 = node(i + 1, j + 1), p01 = node(i, j + 1);
                const double s = r();
                const vec3 targets[] = {p00, p00 + s * (p10 - p00), p00 + s * (p01 - p00), p00 + s * (p11 - p00)};
                for (const vec3& target : targets) {
                    if (target.x > w || target.y > w) continue;  // beyond the column: the next copy's
                    // From a point in the water before the target along d (a ray from a pit's
                    // bottom can leave it only steeply: drawn again until in the water).
                    const auto in_water = [&](const vec3& o) { return o.z < hf.depth_at(o.x, o.y) - 1e-6; };
                    for (int k = 0; k < 6; ++k) {
                        vec3 d, o;
                        do {
                            d = k == 0 ? vec3(0.0, 0.0, 1.0) : r.direction_against(vec3(0.0, 0.0, 1.0), 1.0);
                            o = target - r.in(0.01, 0.5) * d;
                        } while (!in_water(o));
                        check_meets(o, d, target, k % 2 == 1);
                    }
                    // Along the grid lines and the diagonal through the point, descending at up
                    // to 87 degrees from the horizontal.
                    for (const vec3& along : {vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(w / nx, w / ny, 0.0)}) {
                        vec3 d, o;
                        do {
                            const vec3 flat = glm::normalize(along) * (r() < 0.5 ? -1.0 : 1.0);
                            d = glm::normalize(flat + vec3(0.0, 0.0, r.in(0.05, 20.0)));
                            o = target - r.in(0.01, 0.5) * d;
                        } while (!in_water(o));
                        check_meets(o, d, target, false);
                        check_meets(o, d, target, true);
                    }
                }
            }
    }
    WARN("rays through vertices and edges: " << entering << " entering the solid there (or before), " << grazing
                                              << " grazing it, " << from_solid << " coming from inside it (one column), "
                                              << undecided << " undecided");
    CHECK(entering > 2000);
    CHECK(undecided < 20);
}

TEST_CASE("Height field through the periodic copies: rays across many seams against a brute force over the copies") {
    // periodic_closest_hit (geometry.hpp) with the section's width: each copy answers for its own
    // column. The brute force searches every triangle of every copy whose column the flight's
    // horizontal extent reaches (and one more on each side, as in test_geometry.cpp). Half the
    // rays descend slowly (d_z from 0.005 to 0.1) over up to 20 m: they cross several seams at
    // the terrain's depths before they meet it; the other half go in uniform directions.
    // Tolerances as for one column (the scale now includes the origins' 3 m from the section).
    Rand r(43);
    const Terrain terrain = random_terrain(r, 5, 4, 1.5, 0.5, 1.5, 2.0);
    const HeightField hf = terrain.field(ObjectMaterial::lambertian(0.5));
    const std::vector<Tri> tris = triangles_of(terrain.h, terrain.nx, terrain.ny, terrain.w);
    const double w = terrain.w, scale = 3.0 + w + hf.max_depth();
    const auto cell = [w](double x) { return static_cast<int>(std::floor(x / w)); };
    int compared = 0, hits = 0, near_edges = 0, many_seams = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const vec3 o = point_above(hf, r, -3.0, 3.0, 0.0, hf.max_depth());
        const vec3 d = trial % 2 ? level_direction(r, r.in(0.005, 0.1)) : r.direction();
        const double t_max = trial % 2 ? r.in(0.0, 20.0) : r.in(0.0, 8.0);
        Search want;
        const vec3 end = o + d * t_max;
        for (int i = cell(std::min(o.x, end.x)) - 1; i <= cell(std::max(o.x, end.x)) + 1; ++i)
            for (int j = cell(std::min(o.y, end.y)) - 1; j <= cell(std::max(o.y, end.y)) + 1; ++j)
                brute_force(tris, vec3(i * w, j * w, 0.0), o, d, t_max, scale, want);
        const auto got = periodic_closest_hit(hf, w, o, d, t_max);
        if (want.near(t_max)) {
            ++near_edges;
            continue;
        }
        ++compared;
        INFO("trial " << trial << ": o " << o.x << " " << o.y << " " << o.z << ", d " << d.x << " " << d.y << " " << d.z
                      << ", t_max " << t_max);
        REQUIRE(bool(got) == bool(want.hit));
        if (!got) continue;
        ++hits;
        const vec3 at = o + d * got->t;
        if (std::abs(cell(at.x) - cell(o.x)) + std::abs(cell(at.y) - cell(o.y)) >= 3) ++many_seams;
        CHECK(std::abs(got->t - want.hit->t) <= t_tolerance(want.hit->t, scale, glm::dot(want.hit->normal, d)));
        CHECK(glm::length(got->normal - want.hit->normal) < 1e-12);
        CHECK(glm::length(got->point - want.hit->point) < 1e-12 * scale + std::abs(got->t - want.hit->t));
    }
    WARN("periodic: compared " << compared << ", hits " << hits << " (" << many_seams
                               << " after 3 or more seams), near edges set apart " << near_edges);
    CHECK(near_edges <= 4);  // 0.1 % of 4,000
    CHECK(hits > 1500);
    CHECK(many_seams > 300);  // about half the count of seed 43
}

TEST_CASE("Height field: depth_at is the interpolant, periodic and continuous across the seams") {
    Rand r(44);
    const Terrain terrain = random_terrain(r, 5, 4, 1.5, 0.5, 1.5, 2.0);
    const HeightField hf = terrain.field();
    const double w = terrain.w;
    // At the nodes: the node depths (u, v a rounding from 0: 1e-14 of the depths).
    for (unsigned j = 0; j <= terrain.ny; ++j)
        for (unsigned i = 0; i <= terrain.nx; ++i)
            CHECK(hf.depth_at(w * i / terrain.nx, w * j / terrain.ny) ==
                  Approx(terrain.h[(j % terrain.ny) * terrain.nx + i % terrain.nx]).margin(1e-14));
    // The steepest slope of any triangle bounds how much depth_at changes over a distance.
    double slope = 0.0;
    for (const Tri& t : triangles_of(terrain.h, terrain.nx, terrain.ny, w))
        slope = std::max(slope, std::hypot(t.n.x, t.n.y) / -t.n.z);
    for (int trial = 0; trial < 2000; ++trial) {
        const double x = r.in(0.0, w), y = r.in(0.0, w);
        const int k = static_cast<int>(r.in(-3.0, 4.0)), m = static_cast<int>(r.in(-3.0, 4.0));
        // Periodic: the same depth a whole number of periods over (to the rounding of x + k W:
        // a few eps of 6 m, times the slope).
        CHECK(std::abs(hf.depth_at(x + k * w, y + m * w) - hf.depth_at(x, y)) <= 1e-14 * slope + 1e-15);
        // Across the seams x = W (= 0) and y = W: within 2 delta of the seam on either side, the
        // depths differ by at most the slope times the distance (a terrain whose last cells
        // joined anything but node 0 would jump by the difference of two nodes, ~0.5 m).
        const double delta = 1e-7;
        CHECK(std::abs(hf.depth_at(w - delta, y) - hf.depth_at(delta, y)) <= 2.0 * delta * slope * (1.0 + 1e-6));
        CHECK(std::abs(hf.depth_at(x, w - delta) - hf.depth_at(x, delta)) <= 2.0 * delta * slope * (1.0 + 1e-6));
        // A vertical ray from the surface meets the terrain at depth_at, in any copy.
        const vec3 o(x + k * w, y + m * w, 0.0);
        const auto h = periodic_closest_hit(hf, w, o, vec3(0.0, 0.0, 1.0), INFINITY);
        REQUIRE(h);
        CHECK(h->t == Approx(hf.depth_at(x, y)).margin(1e-13));
    }
    CHECK(slope > 1.0);  // the terrain is rough: the continuity checks above bind
}

TEST_CASE("Height field, flat limit: a constant depth is met where the plane z = h is, normal straight up") {
    // A constant depth h: every triangle is the plane z = h, g0 = h - o_z and g1 = -d_z exactly,
    // so t = (h - o_z) / d_z to the ulp (an ulp more only where a hit at a cell's edge is clamped
    // to the part's end: 1e-15 relative), the normal exactly (0, 0, -1). Through the periodic
    // copies, from origins over several periods; upward and level rays above it never meet it,
    // nor a level ray sliding along it, nor one inside the solid.
    Rand r(45);
    const double h = 1.7, w = 1.3;
    for (const HeightField& flat : {HeightField(6, 4, w, 3.0, std::vector<double>(24, h), ObjectMaterial::absorbing()),
                                    HeightField(1, 1, w, 3.0, {h}, ObjectMaterial::absorbing())}) {
        for (int trial = 0; trial < 3000; ++trial) {
            const vec3 o{r.in(-5.0, 5.0), r.in(-5.0, 5.0), r.in(0.0, h)};
            const vec3 d = r.direction_against(vec3(0.0, 0.0, 1.0), 1.0);
            const double closed = (h - o.z) / d.z;
            const auto hit = periodic_closest_hit(flat, w, o, d, INFINITY);
            INFO("trial " << trial);
            REQUIRE(hit);
            CHECK(hit->t == Approx(closed).epsilon(1e-15).margin(0.0));
            CHECK((hit->normal == vec3(0.0, 0.0, -1.0)));
            CHECK(hit->point.z == Approx(h).epsilon(1e-15));
            CHECK_FALSE(periodic_closest_hit(flat, w, o, d, closed * (1.0 - 1e-12)));
            CHECK_FALSE(periodic_closest_hit(flat, w, o, -d, INFINITY));
            CHECK_FALSE(periodic_closest_hit(flat, w, o, level_direction(r, 0.0), 10.0));
            const vec3 on{o.x, o.y, h};
            CHECK_FALSE(periodic_closest_hit(flat, w, on, level_direction(r, 0.0), 10.0));
            CHECK_FALSE(periodic_closest_hit(flat, w, on + vec3(0.0, 0.0, 0.1), level_direction(r, 0.0), 10.0));
            const auto start = periodic_closest_hit(flat, w, on, d, INFINITY);
            REQUIRE(start);
            CHECK(start->t == 0.0);
        }
    }
}

namespace {
using IsoWater = HomogeneousWater<IsotropicPhase>;
using HgWater = HomogeneousWater<HenyeyGreensteinPhase>;
template <class Water>
using TerrainTracer = PhotonTracer<Water, CompactRecord, FlatSurface, SunAndSky, IrradiancePlanes, Bottom, HeightField>;

constexpr double section = 1.0, floor_depth = 4.0;

/// Hills and hollows between 0.8 and 3.2 m over a 1 m section, 8 x 8 nodes; the slab's black
/// bottom at 4 m under it.
HeightField hills(ObjectMaterial m) {
    return HeightField::from_function(
        8, 8, section, floor_depth,
        [](double x, double y) {
            return 2.0 + 0.8 * std::sin(two_pi * x) * std::cos(two_pi * y) + 0.4 * std::cos(2.0 * two_pi * y + 1.0);
        },
        std::move(m));
}

template <class Water>
TransportResult<CompactRecord> trace(const Water& water, const HeightField& g, const TransportSettings& s) {
    return TerrainTracer<Water>(water, Slab(section, Bottom::lambertian_at(floor_depth, 0.0)), FlatSurface(1.34),
                                SunAndSky(CollimatedSun(0.0)), s, g)
        .run();
}

TransportSettings terrain_settings(AbsorptionMode mode) {
    TransportSettings s;
    s.photons = 40000;
    s.map_photons = 4000;
    s.depths = {0.0, 0.5};
    s.absorption = mode;
    s.roulette_weight = 0.0;  // the ledger closes per photon (no roulette)
    s.block_size = 1000;
    return s;
}

/// The integral of exp(-c h) over the triangle (a, b, c) on which h is linear: the Duffy map
/// of the unit square onto it, (s, q) -> a + s (b - a) + s q (c - b), Jacobian 2 A s, and 8-point
/// Gauss-Legendre in s and q (exact to degree 15: -c h changes by at most about 1.3 over a
/// triangle here, so the Taylor terms of exp beyond degree 15 are below 1.3^16 / 16! ~ 1e-11 of
/// it, and the rule's error on them far smaller; the closed form on one triangle checks it).
double beer_lambert_over(const Tri& t, double c) {
    static constexpr double x8[] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267, 0.9602898564975363};
    static constexpr double w8[] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745, 0.1012285362903763};
    const double area2 = std::abs((t.b.x - t.a.x) * (t.c.y - t.a.y) - (t.c.x - t.a.x) * (t.b.y - t.a.y));
    double sum = 0.0;
    for (int i = 0; i < 8; ++i)
        for (int k = 0; k < 8; ++k) {
            const double s = 0.5 * (1.0 + (i < 4 ? -x8[i] : x8[i - 4])), q = 0.5 * (1.0 + (k < 4 ? -x8[k] : x8[k - 4]));
            const double ws = 0.5 * w8[i % 4], wq = 0.5 * w8[k % 4];
            const double h = t.a.z + s * (t.b.z - t.a.z) + s * q * (t.c.z - t.b.z);
            sum += ws * wq * area2 * s * std::exp(-c * h);
        }
    return sum;
}
}  // namespace

TEST_CASE("Height field in non-scattering water: every photon is absorbed where it lands, photon by photon") {
    // w0 = 0, continuous absorption: free paths are drawn from b = 0 (none ends in the water),
    // so every photon of the vertical sun goes straight down from its launch point (x, y) (the
    // first two draws of its stream, times W) onto the black terrain, with weight
    // T exp(-c h(x, y)) (T = 1 - R(normal incidence)): the terrain absorbs their sum over N,
    // exactly but for rounding (sums of 40,000 terms, each exp to an ulp: 1e-12 relative);
    // nothing reaches the slab's floor under it; the ledger closes (1e-12).
    // Its expectation is T / W^2 times the integral of exp(-c h) over the terrain (per triangle,
    // Gauss-Legendre, exact to rounding); the estimate lies within 4 SE of it, the SE from the
    // spread of the 32 batches' photon-by-photon means (batches of 1,250 photons, equal:
    // SE = sd(batch means) / sqrt(32)), fixed in advance.
    const double c = 0.5;
    const IsoWater water = IsoWater::from_albedo(c, 0.0, IsotropicPhase{});
    const HeightField terrain = hills(ObjectMaterial::absorbing());
    const auto s = terrain_settings(AbsorptionMode::continuous);
    const auto r = trace(water, terrain, s);

    const double n_w = 1.34, t_surface = 1.0 - std::pow((n_w - 1.0) / (n_w + 1.0), 2);
    std::vector<double> batch_sum(s.batches, 0.0), batch_photons(s.batches, 0.0);
    double sum = 0.0;
    for (const auto& blk : detail::make_blocks(s.photons, s.batches, s.block_size))
        for (std::uint64_t i = blk.begin; i < blk.end; ++i) {
            PhotonRng rng(s.seed, i);
            const double x = section * rng.uniform();
            const double y = section * rng.uniform();
            const double w = t_surface * std::exp(-c * terrain.depth_at(x, y));
            batch_sum[blk.batch] += w;
            batch_photons[blk.batch] += 1.0;
            sum += w;
        }
    const double n = static_cast<double>(s.photons);
    INFO("absorbed by the terrain " << r.ledger.absorbed_objects << ", photon by photon " << sum / n);
    CHECK(r.ledger.absorbed_objects == Approx(sum / n).epsilon(1e-12));
    CHECK(r.ledger.absorbed_bottom == 0.0);
    CHECK(r.bottom_ed.value == 0.0);
    CHECK(std::abs(r.ledger.imbalance()) < 1e-12);

    // The exact expectation, and the quadrature checked on one triangle against the closed form
    // (the second divided difference of exp: 2 A sum_k e^{f_k} / prod_{j != k} (f_k - f_j), f = -c h).
    const Tri one{{0.0, 0.0, 1.0}, {1.0, 0.0, 2.0}, {0.0, 1.0, 3.5}, {}};
    const double f[] = {-c * 1.0, -c * 2.0, -c * 3.5};
    const double closed = std::exp(f[0]) / ((f[0] - f[1]) * (f[0] - f[2])) + std::exp(f[1]) / ((f[1] - f[0]) * (f[1] - f[2])) +
                          std::exp(f[2]) / ((f[2] - f[0]) * (f[2] - f[1]));
    CHECK(beer_lambert_over(one, c) == Approx(closed).epsilon(1e-14));
    std::vector<double> h;
    for (unsigned j = 0; j < terrain.ny(); ++j)
        for (unsigned i = 0; i < terrain.nx(); ++i) h.push_back(terrain.node_depth(i, j));
    double integral = 0.0, area = 0.0;
    for (const Tri& t : triangles_of(h, terrain.nx(), terrain.ny(), section)) {
        integral += beer_lambert_over(t, c);
        area += beer_lambert_over(t, 0.0);
    }
    CHECK(area == Approx(section * section).epsilon(1e-14));
    const double expected = t_surface * integral / (section * section);
    double mean = 0.0, var = 0.0;
    for (unsigned b = 0; b < s.batches; ++b) mean += batch_sum[b] / batch_photons[b] / s.batches;
    for (unsigned b = 0; b < s.batches; ++b) var += std::pow(batch_sum[b] / batch_photons[b] - mean, 2);
    const double se = std::sqrt(var / (s.batches * (s.batches - 1.0)));
    WARN("non-scattering: terrain absorbed " << r.ledger.absorbed_objects << " +- " << se << " (SE), exact " << expected
                                             << ": " << (r.ledger.absorbed_objects - expected) / se << " SE");
    CHECK(std::abs(r.ledger.absorbed_objects - expected) <= 4.0 * se);
    // The depths vary: a flat bottom at the mean depth would absorb less (exp is convex), by more than 4 SE.
    CHECK(std::abs(t_surface * std::exp(-c * 2.0) - expected) > 4.0 * se);
}

TEST_CASE("Height field with scattering: the ledger closes with what the terrain absorbs, nothing passes through it") {
    // w0 = 0.8, c = 0.5 1/m, forward-peaked HG (g 0.8), terrain albedo 0.3: photons reflect off
    // the terrain (cosine-weighted about the triangle's normal, moved 1e-9 m off it), scatter
    // back onto it, into hollows and against slopes, many times. No roulette: the ledger closes
    // photon by photon, exactly in analog mode and to rounding with weights; 1e-9 relative
    // bounds the rounding of 40,000-term sums (about 1e-12) with a wide margin. The terrain
    // covers the whole section: a photon reaching the slab's floor under it would have slipped
    // through it, so absorbed_bottom must be exactly 0. The two modes estimate the same Eu.
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    const HeightField terrain = hills(ObjectMaterial::lambertian(0.3));
    const auto analog = trace(water, terrain, terrain_settings(AbsorptionMode::analog));
    const auto weighted = trace(water, terrain, terrain_settings(AbsorptionMode::continuous));
    for (const auto* r : {&analog, &weighted}) {
        const EnergyLedger& l = r->ledger;
        INFO("absorbed by the terrain " << l.absorbed_objects << ", in the water " << l.absorbed << ", escaped "
                                        << l.escaped_up << ", imbalance " << l.imbalance());
        CHECK(l.absorbed_objects > 0.1);
        CHECK(l.escaped_up > 0.001);
        CHECK(l.absorbed_bottom == 0.0);
        CHECK(l.transmitted == 0.0);
        CHECK(r->bottom_ed.value == 0.0);
        CHECK(std::abs(l.imbalance()) <= 1e-9 * l.incident);
    }
    testing::check_agree(analog.irradiance[1][Eu], weighted.irradiance[1][Eu], "Eu at 0.5 m");
    testing::check_agree(analog.irradiance[1][Ed], weighted.irradiance[1][Ed], "Ed at 0.5 m");
    WARN("scattering: terrain absorbed " << weighted.ledger.absorbed_objects << " (weighted), "
                                         << analog.ledger.absorbed_objects << " (analog); imbalance "
                                         << weighted.ledger.imbalance() << ", " << analog.ledger.imbalance());
}

TEST_CASE("Height field: the first pass is the same for 1 and 2 threads; a terrain below the floor is refused") {
    const HgWater water = HgWater::from_albedo(0.5, 0.8, HenyeyGreensteinPhase(0.8));
    std::vector<double> albedo;
    for (int k = 0; k < 16; ++k) albedo.push_back(0.05 * k);
    const HeightField mapped = hills(ObjectMaterial::mapped(AlbedoMap(4, 4, section, albedo)));
    const auto run = [&](TransportSettings s) { return trace(water, mapped, s); };
    testing::require_same_for_1_and_2_threads(AbsorptionMode::continuous, run);
    testing::require_same_for_1_and_2_threads(AbsorptionMode::analog, run);
    const HeightField deeper(2, 2, section, floor_depth + 1.0, {1.0, 1.0, 1.0, 1.0}, ObjectMaterial::absorbing());
    CHECK_THROWS_WITH(trace(water, deeper, terrain_settings(AbsorptionMode::continuous)),
                      Catch::Contains("object bounds' bottom depth"));
    const HeightField wider = HeightField(2, 2, 2.0 * section, floor_depth, {1.0, 1.0, 1.0, 1.0}, ObjectMaterial::absorbing());
    CHECK_THROWS_WITH(trace(water, wider, terrain_settings(AbsorptionMode::continuous)),
                      Catch::Contains("object bounds' highest x, y"));
}
