#pragma once
// The second pass over a 3-D scene: the radiance a ray from a point in the water sees when opaque
// objects (scene/geometry.hpp) stand in the water and the bottom is lit unevenly (shadows,
// caustics: the first pass's Ed on the bottom in bins, transport/bottom_grid.hpp). It wraps a
// RadianceEstimator (estimate/radiance.hpp) as a host renderer would (that estimator's
// contract: a ray stopped at t_max by the host's object, the host adding that object's radiance
// times transmittance(ray)):
//     L(ray) = integral_0^t_end J(t) T(t) dt + T(t_end) L_end
// with t_end the nearest of the objects' first hit (their periodic copies included), the
// bottom, and what the wrapped estimator ends the ray at (the surface, its own t_max);
//  - at an object: L_end = 0. The objects the second pass models are black (albedo 0): the
//    light leaving a Lambertian object, A E_obj / pi, needs the irradiance on the object
//    (a surface photon map), which secchi does not keep; a ray meeting an object of albedo > 0
//    is refused, naming it;
//  - at a Lambertian bottom: L_end = A Ed_bin / pi (M93 eq. 11, with the Ed of the bin the ray
//    meets, bins over the periodic section), the bin's SE beside it (shared by every ray
//    meeting that bin: it adds linearly, as the uniform bottom's in RadianceEstimator);
//  - beyond that, the wrapped estimator's terms (the path, the surface and the sky above it).
// A bin is the average Ed over its area, so the bottom's light is resolved to a bin (and the
// Lambertian bottom's SE is per bin, larger than the uniform bottom's).
// Rays start in the water (origin depth >= 0): a camera above the surface is not modelled here.
// Threads: as RadianceEstimator's (const, any number of threads at once).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/scene/geometry.hpp"
#include "secchi/transport/bottom_grid.hpp"
#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

template <class Estimator, SceneGeometry Geometry>
class SceneRadianceEstimator {
public:
    /// est: the water's radiance (its map's first pass traced `geometry`); bottom_ed_bins: that
    /// first pass's TransportResult::bottom_ed_bins (n x n, index iy n + ix), or empty for a
    /// bottom lit evenly (its Ed the map's).
    SceneRadianceEstimator(const Estimator& est, Geometry geometry, std::vector<Estimate> bottom_ed_bins = {})
        : est_(est), geometry_(std::move(geometry)), bins_(std::move(bottom_ed_bins)),
          grid_(side_of(bins_.size()), est.map().section_width()) {
        require(bins_.empty() || est.map().bands() == 1, "bands", est.map().bands(),
                "must be 1 for a bottom in bins (the first pass bins one band)");
        for (const Estimate& e : bins_)
            require(std::isfinite(e.value) && e.value >= 0.0, "bottom Ed bin", e.value, "must be finite and >= 0");
    }
    SceneRadianceEstimator(const Estimator&&, Geometry, std::vector<Estimate> = {}) = delete;  // would dangle

    [[nodiscard]] const auto& map() const { return est_.map(); }

    [[nodiscard]] Estimate radiance(const Ray& ray, unsigned band = 0) const {
        RadianceSum sum(map().batches());
        add(ray, band, 1.0, sum);
        return sum.estimate();
    }

    /// Adds weight times the ray's radiance to `sum` (render() calls this).
    void add(const Ray& ray, unsigned band, double weight, RadianceSum& sum) const {
        require(ray.origin.z >= 0.0, "ray origin depth (m)", ray.origin.z,
                "must be >= 0: the scene's second pass starts rays in the water");
        const double bottom = map().bottom().depth();
        const double t_bottom = ray.direction.z > 0.0 && std::isfinite(bottom) ? (bottom - ray.origin.z) / ray.direction.z : INFINITY;
        const double t_limit = std::min(ray.t_max, t_bottom);
        const auto hit = periodic_closest_hit(geometry_, map().section_width(), ray.origin, ray.direction, t_limit);
        if (hit) {  // a black object ends the ray: the path to it, nothing from it
            const double albedo = geometry_.material(hit->material).albedo_at(hit->point);
            if (albedo > 0.0)
                reject("object albedo", albedo, "is not modelled by the second pass (only black objects: the light leaving "
                                                "a Lambertian object needs its irradiance), object " +
                                                    std::to_string(hit->material));
            est_.add(Ray{ray.origin, ray.direction, hit->t}, band, weight, sum);
            return;
        }
        if (bins_.empty() || !(t_bottom <= ray.t_max)) {  // no bins, or the ray ends before the bottom
            est_.add(ray, band, weight, sum);
            return;
        }
        // The path up to the bottom (t_max just short of it: the wrapped estimator then adds no
        // bottom term), then the bottom's light from the bin the ray meets.
        est_.add(Ray{ray.origin, ray.direction, std::nextafter(t_bottom, 0.0)}, band, weight, sum);
        const double per_ed = weight * map().bottom().radiance_per_irradiance() *
                              est_.transmittance(Ray{ray.origin, ray.direction, t_bottom}, band);
        if (per_ed <= 0.0) return;
        const vec3 p = ray.origin + t_bottom * ray.direction;
        const double w = map().section_width();
        const Estimate& ed = bins_[grid_.bin(p.x - w * std::floor(p.x / w), p.y - w * std::floor(p.y / w))];
        sum.add_shared(per_ed * ed.value, per_ed * ed.se);
    }

private:
    static unsigned side_of(std::size_t bins) {
        const auto n = static_cast<unsigned>(std::lround(std::sqrt(static_cast<double>(bins))));
        require(static_cast<std::size_t>(n) * n == bins, "bottom Ed bins", bins, "must be n x n (TransportResult::bottom_ed_bins)");
        return n;
    }

    const Estimator& est_;
    Geometry geometry_;
    std::vector<Estimate> bins_;
    BottomGrid grid_;
};

}  // namespace secchi
