#pragma once
// Triangle meshes in the water through Embree 3 (Debian: libembree-dev; the secchi::embree
// CMake target): a SceneGeometry (scene/geometry.hpp) over closed meshes
// (scene/triangle_mesh.hpp), so that a renderer can hand secchi the solids of its own scene.
//
// closest_hit(o, d, t_max): one rtcIntersect1 in Embree's BVH (single precision), then the
// distance again in double on the plane of the triangle found: t = (v0 - o) . n / (d . n)
// (n its outward normal, computed in double from the mesh's vertices). So the hit point lies
// on the triangle's plane to double rounding (the tracer leaves a surface by 1e-9 m after a
// reflection), and a box given as a mesh yields the distances and normals of AxisBox.
//  - Only the outer side of a triangle is met (dot(n, d) < 0; an intersection filter rejects
//    the inner side): photons are outside every solid, and the triangle a photon has just left
//    is behind it, seen from its inner side.
//  - A ray starting on a surface and moving into it meets it at t = 0: the query starts
//    `backoff` before o (128 single-precision units of the scene's largest coordinate L,
//    1.5e-5 L), and a hit up to that far behind o counts at t = 0 (the photon is on the
//    surface, to the precision of the BVH).
//  - Limits of single precision: a ray passing within about 1e-7 L of an edge can slip between
//    two triangles and miss the solid; one starting on a surface and moving into it at a
//    grazing angle (cosine with the normal below about 1e-2) may not meet it; a photon within
//    the backoff of a concave edge may meet the neighbouring face at t = 0. (The tracer starts
//    no flight on a surface moving in: a reflected photon leaves it.)
// Thread safety: queries are const and may run concurrently (Embree's committed scenes are);
// copies share the built scene.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/scene/geometry.hpp"
#include "secchi/scene/triangle_mesh.hpp"
#include <embree3/rtcore.h>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

class EmbreeMesh {
public:
    static constexpr bool has_objects = true;

    /// Builds Embree's BVH over `meshes` (each validated: closed, wound outward); mesh i has
    /// material index i.
    explicit EmbreeMesh(std::vector<TriangleMesh> meshes) {
        auto built = std::make_shared<Scene>();
        Scene& s = *built;
        require(!meshes.empty(), "mesh count", 0, "must be > 0 (NoGeometry is the scene without objects)");
        s.device = rtcNewDevice(nullptr);
        if (!s.device) throw std::runtime_error("Embree: rtcNewDevice failed (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
        s.scene = rtcNewScene(s.device);
        rtcSetSceneBuildQuality(s.scene, RTC_BUILD_QUALITY_HIGH);
        double largest = 1.0;
        for (std::size_t i = 0; i < meshes.size(); ++i) {
            s.meshes.push_back(validated(std::move(meshes[i]), indexed_name("mesh", i)));
            const TriangleMesh& m = s.meshes.back();
            bounds_ = bounds_.merged(m.bounds());
            for (const vec3& v : m.vertices) largest = std::max({largest, std::abs(v.x), std::abs(v.y), std::abs(v.z)});
        }
        for (std::size_t i = 0; i < s.meshes.size(); ++i) {
            TriangleMesh& m = s.meshes[i];
            s.normals.emplace_back();
            for (std::size_t t = 0; t < m.triangles.size(); ++t) s.normals.back().push_back(m.normal(t));
            attach(s, m, s.normals.back(), static_cast<unsigned>(i));
        }
        rtcCommitScene(s.scene);
        if (const RTCError e = rtcGetDeviceError(s.device); e != RTC_ERROR_NONE)
            throw std::runtime_error("Embree: scene build failed (error " + std::to_string(e) + ")");
        backoff_ = 128.0 * std::numeric_limits<float>::epsilon() * largest;
        scene_ = std::move(built);
    }

    [[nodiscard]] std::optional<ObjectHit> closest_hit(const vec3& o, const vec3& d, double t_max) const {
        if (!(t_max > 0.0)) return std::nullopt;
        const vec3 start = o - backoff_ * d;
        RTCIntersectContext context;
        rtcInitIntersectContext(&context);
        RTCRayHit rh{};
        rh.ray.org_x = static_cast<float>(start.x), rh.ray.org_y = static_cast<float>(start.y),
        rh.ray.org_z = static_cast<float>(start.z);
        rh.ray.dir_x = static_cast<float>(d.x), rh.ray.dir_y = static_cast<float>(d.y), rh.ray.dir_z = static_cast<float>(d.z);
        rh.ray.tnear = 0.0f;
        // Unbounded: a single-precision distance errs by the rounding of the origin over the
        // cosine with the normal, without bound at grazing incidence; the closest hit's
        // distance is cut at t_max in double below.
        rh.ray.tfar = INFINITY;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_->scene, &context, &rh);
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return std::nullopt;
        const TriangleMesh& m = scene_->meshes[rh.hit.geomID];
        const vec3& n = scene_->normals[rh.hit.geomID][rh.hit.primID];
        const double t = std::max(0.0, glm::dot(m.vertices[m.triangles[rh.hit.primID][0]] - o, n) / glm::dot(d, n));
        if (!(t < t_max)) return std::nullopt;
        return ObjectHit{t, o + d * t, n, rh.hit.geomID};
    }
    [[nodiscard]] const ObjectMaterial& material(std::uint32_t index) const { return scene_->meshes[index].material; }
    [[nodiscard]] Bounds bounds() const { return bounds_; }
    /// "Embree 3.13.5": the version secchi was compiled against.
    static std::string version() {
        return "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
               std::to_string(RTC_VERSION_PATCH);
    }
    [[nodiscard]] std::size_t triangle_count() const {
        std::size_t n = 0;
        for (const TriangleMesh& m : scene_->meshes) n += m.triangles.size();
        return n;
    }

private:
    struct Scene {
        RTCDevice device = nullptr;
        RTCScene scene = nullptr;
        std::vector<TriangleMesh> meshes;
        std::vector<std::vector<vec3>> normals;  ///< per mesh, per triangle: unit, outward (double)
        Scene() = default;
        Scene(const Scene&) = delete;
        Scene& operator=(const Scene&) = delete;
        ~Scene() {
            if (scene) rtcReleaseScene(scene);
            if (device) rtcReleaseDevice(device);
        }
    };

    /// Mesh `m` as Embree geometry `id`: its vertices and triangles copied into Embree's
    /// buffers, the filter keeping only outer sides (user data: its normals).
    static void attach(Scene& s, const TriangleMesh& m, const std::vector<vec3>& normals, unsigned id) {
        RTCGeometry g = rtcNewGeometry(s.device, RTC_GEOMETRY_TYPE_TRIANGLE);
        auto* v = static_cast<float*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.vertices.size()));
        auto* t = static_cast<unsigned*>(
            rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), m.triangles.size()));
        if (!v || !t) throw std::runtime_error("Embree: buffer allocation failed");
        for (std::size_t i = 0; i < m.vertices.size(); ++i)
            for (int k = 0; k < 3; ++k) v[3 * i + k] = static_cast<float>(m.vertices[i][k]);
        for (std::size_t i = 0; i < m.triangles.size(); ++i)
            for (int k = 0; k < 3; ++k) t[3 * i + k] = m.triangles[i][k];
        rtcSetGeometryUserData(g, const_cast<vec3*>(normals.data()));
        rtcSetGeometryIntersectFilterFunction(g, &outer_side_only);
        rtcCommitGeometry(g);
        rtcAttachGeometryByID(s.scene, g, id);
        rtcReleaseGeometry(g);
    }

    /// Embree's intersection filter: rejects a hit on a triangle's inner side, dot(n, d) >= 0.
    static void outer_side_only(const RTCFilterFunctionNArguments* args) {
        const auto* normals = static_cast<const vec3*>(args->geometryUserPtr);
        for (unsigned i = 0; i < args->N; ++i) {
            if (args->valid[i] != -1) continue;
            const vec3& n = normals[RTCHitN_primID(args->hit, args->N, i)];
            const double dn = n.x * RTCRayN_dir_x(args->ray, args->N, i) + n.y * RTCRayN_dir_y(args->ray, args->N, i) +
                              n.z * RTCRayN_dir_z(args->ray, args->N, i);
            if (dn >= 0.0) args->valid[i] = 0;
        }
    }

    std::shared_ptr<const Scene> scene_;
    Bounds bounds_;
    double backoff_ = 0.0;  ///< m: the query starts this far behind the origin
};

static_assert(SceneGeometry<EmbreeMesh>);

}  // namespace secchi
