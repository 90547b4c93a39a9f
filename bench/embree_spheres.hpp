#pragma once
// The optional comparator of the search benchmarks (issue 4): Embree 3 collecting every sphere
// that a ray segment hits, the reference for the fastest ray-sphere collection on a CPU.
// Built only where CMake finds Embree 3 (Debian: libembree-dev); never part of the tests.
//
// Each record is a sphere of radius r around its position (Embree's RTC_GEOMETRY_TYPE_SPHERE_POINT,
// in Embree's BVH at medium build quality: at high quality Embree may call the filter more
// than once for one primitive, which would count it twice; high ran no faster here). A query is one rtcIntersect1 over [0, t_max] whose
// intersection filter counts the sphere and rejects the hit, so that the traversal goes on to
// every sphere along the segment. A sphere reports its entry hit (normal against the ray)
// and, once that is rejected, its exit hit; the exit counts only for a sphere that holds the
// ray's origin, which has no entry hit in [0, t_max] (count_and_reject). So the spheres
// counted are those whose centre lies within r of the segment (the capsule), except a sphere
// that holds the whole segment (impossible in the benchmarks: every ray is longer than 2r):
// the VOI search's cylinder plus two half-spheres at its ends. search_bench prints the counts.
//
// Embree's point leaves refer to the vertex buffer by index, so the buffer's order matters:
// the benchmark passes the records in the VOI grid's cell order (spatially coherent, as every
// store of secchi keeps its own records). Records in random order ran at 0.6 times that
// rate (the vertex loads miss the cache), 1e6 uniform points, Zen 3.
#include "secchi/map/record.hpp"
#include "secchi/map/store.hpp"
#include <embree3/rtcore.h>
#include <cmath>
#include <cstdint>
#include <ranges>
#include <stdexcept>
#include <string>
#include <vector>

namespace secchi::bench {

class EmbreeSpheres {
public:
    /// records: a sized random-access range of CompactRecords (a store's records()).
    template <std::ranges::random_access_range Records>
    EmbreeSpheres(const Records& records, double radius)
        : device_(rtcNewDevice(nullptr)), radius_(static_cast<float>(radius)) {
        if (!device_) throw std::runtime_error("Embree: rtcNewDevice failed");
        if (!rtcGetDeviceProperty(device_, RTC_DEVICE_PROPERTY_POINT_GEOMETRY_SUPPORTED))
            throw std::runtime_error("Embree: this build has no point geometry");
        scene_ = rtcNewScene(device_);
        rtcSetSceneBuildQuality(scene_, RTC_BUILD_QUALITY_MEDIUM);
        RTCGeometry spheres = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
        auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(spheres, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT4,
                                                              4 * sizeof(float), records.size()));
        for (std::size_t i = 0; i < records.size(); ++i) {
            const CompactRecord r = records[i];
            v[4 * i] = r.x, v[4 * i + 1] = r.y, v[4 * i + 2] = r.z, v[4 * i + 3] = static_cast<float>(radius);
        }
        rtcSetGeometryIntersectFilterFunction(spheres, &count_and_reject);
        rtcCommitGeometry(spheres);
        rtcAttachGeometry(scene_, spheres);
        rtcReleaseGeometry(spheres);
        rtcCommitScene(scene_);
        if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree: scene build failed");
    }
    ~EmbreeSpheres() {
        rtcReleaseScene(scene_);
        rtcReleaseDevice(device_);
    }
    EmbreeSpheres(const EmbreeSpheres&) = delete;
    EmbreeSpheres& operator=(const EmbreeSpheres&) = delete;

    /// "Embree 3.13.5": the version this was built with.
    static std::string version() {
        return "Embree " + std::to_string(RTC_VERSION_MAJOR) + "." + std::to_string(RTC_VERSION_MINOR) + "." +
               std::to_string(RTC_VERSION_PATCH);
    }

    /// The number of spheres the segment [origin, origin + t_max direction] hits (see above).
    std::uint64_t count_along(const Ray& ray) const {
        Query q;
        rtcInitIntersectContext(&q.context);
        q.radius = radius_;
        RTCRayHit rh{};
        rh.ray.org_x = static_cast<float>(ray.origin.x), rh.ray.org_y = static_cast<float>(ray.origin.y),
        rh.ray.org_z = static_cast<float>(ray.origin.z);
        rh.ray.dir_x = static_cast<float>(ray.direction.x), rh.ray.dir_y = static_cast<float>(ray.direction.y),
        rh.ray.dir_z = static_cast<float>(ray.direction.z);
        rh.ray.tnear = 0.0f;
        rh.ray.tfar = static_cast<float>(ray.t_max);
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(scene_, &q.context, &rh);
        return q.count;
    }

private:
    /// The intersect context with the query's own state after it (Embree passes the context
    /// pointer to the filter; the standard-layout struct starts with it).
    struct Query {
        RTCIntersectContext context;
        float radius = 0.0f;
        std::uint64_t count = 0;
    };

    /// Counts a sphere at its entry hit, or at its exit hit if its entry lies before the ray's
    /// origin: for a hit at t on the sphere with outward normal n, the chord's other end is at
    /// t - 2 r (d . n) / |n| (d: the unit ray direction), so the exit hit t1 counts when
    /// t1 - 2 r (d . n) / |n| < 0 (the origin inside). Embree hands the filter the hit's t as
    /// the ray's tfar; no memory beyond the hit is read.
    static void count_and_reject(const RTCFilterFunctionNArguments* args) {
        auto* q = reinterpret_cast<Query*>(args->context);
        for (unsigned i = 0; i < args->N; ++i) {
            if (args->valid[i] != -1) continue;
            const float nx = RTCHitN_Ng_x(args->hit, args->N, i), ny = RTCHitN_Ng_y(args->hit, args->N, i),
                        nz = RTCHitN_Ng_z(args->hit, args->N, i);
            const float dx = RTCRayN_dir_x(args->ray, args->N, i), dy = RTCRayN_dir_y(args->ray, args->N, i),
                        dz = RTCRayN_dir_z(args->ray, args->N, i);
            const float dn = nx * dx + ny * dy + nz * dz;
            if (dn < 0.0f || RTCRayN_tfar(args->ray, args->N, i) * std::sqrt(nx * nx + ny * ny + nz * nz) < 2.0f * q->radius * dn)
                ++q->count;
            args->valid[i] = 0;  // rejected: the traversal continues
        }
    }

    RTCDevice device_;
    RTCScene scene_ = nullptr;
    float radius_;
};

}  // namespace secchi::bench
