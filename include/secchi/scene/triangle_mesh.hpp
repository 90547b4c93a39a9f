#pragma once
// A closed triangle mesh: the boundary of an opaque solid in the water, as a renderer hands it
// over (vertices in metres, z positive down; triangles as vertex indices), with its material.
// The data of scene/embree_mesh.hpp's SceneGeometry; no dependency here.
//
// Contract (checked by validated(), each failure an input_error naming the mesh, the
// triangle or vertex, and the value):
//  - finite vertices, indices in range, no degenerate triangle (|(v1 - v0) x (v2 - v0)| > 0);
//  - closed and consistently oriented: every directed edge (a, b) of a triangle appears in
//    exactly one triangle and its reverse (b, a) in exactly one other (a 2-manifold without
//    boundary), so that the mesh separates an inside from the outside;
//  - normals n = (v1 - v0) x (v2 - v0) point out of the solid: the enclosed volume by the
//    divergence theorem, V = (1/6) sum_triangles v0 . (v1 x v2), is positive (it is the
//    negative of the volume when every triangle is wound the other way).
// Photons are outside every solid, so a photon meets a mesh only on the outer side of a
// triangle (dot(n, d) < 0); scene/embree_mesh.hpp relies on it.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/geometry.hpp"
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

struct TriangleMesh {
    std::vector<vec3> vertices;                          ///< metres
    std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into vertices, wound with n outward
    ObjectMaterial material;

    [[nodiscard]] vec3 normal(std::size_t i) const {  ///< the unit outward normal of triangle i
        const auto& t = triangles[i];
        return glm::normalize(glm::cross(vertices[t[1]] - vertices[t[0]], vertices[t[2]] - vertices[t[0]]));
    }
    [[nodiscard]] Bounds bounds() const {
        Bounds b;
        for (const vec3& v : vertices) b = b.merged({v, v});
        return b;
    }
    /// The enclosed volume (m^3), V = (1/6) sum v0 . (v1 x v2) (positive when n points out).
    [[nodiscard]] double volume() const {
        double v = 0.0;
        for (const auto& t : triangles)
            v += glm::dot(vertices[t[0]], glm::cross(vertices[t[1]], vertices[t[2]])) / 6.0;
        return v;
    }
};

/// `mesh` after the checks of the contract above; `name` names it in the messages.
inline TriangleMesh validated(TriangleMesh mesh, const std::string& name = "mesh") {
    mesh.material = ObjectMaterial::checked(std::move(mesh.material));
    require(!mesh.triangles.empty(), name + " triangle count", 0, "must be > 0");
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
        for (int k = 0; k < 3; ++k)
            require(std::isfinite(mesh.vertices[i][k]), indexed_name(name + " vertex", i) + " coordinate",
                    mesh.vertices[i][k], "must be finite");
    std::unordered_map<std::uint64_t, int> directed;  // (a << 32 | b) -> uses of the edge a -> b
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
        const auto& t = mesh.triangles[i];
        for (const std::uint32_t v : t)
            require(v < mesh.vertices.size(), indexed_name(name + " triangle", i) + " vertex index", v,
                    "must be below the vertex count, " + std::to_string(mesh.vertices.size()));
        const vec3 n = glm::cross(mesh.vertices[t[1]] - mesh.vertices[t[0]], mesh.vertices[t[2]] - mesh.vertices[t[0]]);
        require(glm::length(n) > 0.0, indexed_name(name + " triangle", i) + " area (m^2)", glm::length(n) / 2.0,
                "must be > 0 (three distinct, non-collinear vertices)");
        for (int e = 0; e < 3; ++e)
            ++directed[static_cast<std::uint64_t>(t[e]) << 32 | t[(e + 1) % 3]];
    }
    for (const auto& [edge, uses] : directed) {
        const auto a = static_cast<std::uint32_t>(edge >> 32), b = static_cast<std::uint32_t>(edge);
        const auto reverse = directed.find(static_cast<std::uint64_t>(b) << 32 | a);
        const std::string which = name + " edge " + std::to_string(a) + "->" + std::to_string(b);
        require(uses == 1, which + " uses", uses, "must be 1: each directed edge in one triangle (consistent winding)");
        require(reverse != directed.end(), which + " reverse uses", 0,
                "must be 1: the mesh must be closed (every edge shared by two triangles)");
    }
    require(mesh.volume() > 0.0, name + " enclosed volume (m^3)", mesh.volume(),
            "must be > 0: wind the triangles so that (v1 - v0) x (v2 - v0) points out of the solid");
    return mesh;
}

/// The 12 triangles of the box [lo, hi], wound outward.
inline TriangleMesh box_mesh(const vec3& lo, const vec3& hi, ObjectMaterial m) {
    TriangleMesh mesh;
    for (int i = 0; i < 8; ++i) mesh.vertices.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
    // Each face as a quad (a, b, c, d) counter-clockwise seen from outside: triangles abc, acd.
    constexpr std::uint32_t faces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : faces) {
        mesh.triangles.push_back({f[0], f[1], f[2]});
        mesh.triangles.push_back({f[0], f[2], f[3]});
    }
    mesh.material = m;
    return validated(std::move(mesh), "box mesh");
}

/// A sphere of centre c and radius r as 2 s (rings - 1) triangles: `rings` >= 2 bands of polar
/// angle, `segments` >= 3 of azimuth, the vertices on the sphere (the mesh is inscribed).
inline TriangleMesh sphere_mesh(const vec3& c, double r, unsigned rings, unsigned segments, ObjectMaterial m) {
    require(rings >= 2, "sphere mesh rings", rings, "must be >= 2");
    require(segments >= 3, "sphere mesh segments", segments, "must be >= 3");
    require(std::isfinite(r) && r > 0.0, "sphere mesh radius (m)", r, "must be finite and > 0");
    TriangleMesh mesh;
    mesh.vertices.push_back(c + vec3(0.0, 0.0, -r));  // pole 0: theta = 0
    for (unsigned i = 1; i < rings; ++i) {
        const double theta = pi * i / rings;
        for (unsigned j = 0; j < segments; ++j) {
            const double phi = two_pi * j / segments;
            mesh.vertices.push_back(c + r * vec3(std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), -std::cos(theta)));
        }
    }
    const auto south = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(c + vec3(0.0, 0.0, r));
    auto ring = [segments](unsigned i, unsigned j) { return 1 + (i - 1) * segments + j % segments; };
    for (unsigned j = 0; j < segments; ++j) {
        mesh.triangles.push_back({0, ring(1, j + 1), ring(1, j)});
        for (unsigned i = 1; i + 1 < rings; ++i) {
            mesh.triangles.push_back({ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)});
            mesh.triangles.push_back({ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)});
        }
        mesh.triangles.push_back({south, ring(rings - 1, j), ring(rings - 1, j + 1)});
    }
    mesh.material = m;
    return validated(std::move(mesh), "sphere mesh");
}

}  // namespace secchi
