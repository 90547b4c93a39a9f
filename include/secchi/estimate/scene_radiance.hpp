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
//  - at an object: L_end = A E_obj / pi, A its albedo at the point met and E_obj the irradiance
//    there from the surface photon map (estimate/surface_irradiance.hpp; the first pass run
//    with TransportSettings::surface_map), its SE beside it; black objects (A = 0) need no
//    map. Without a map a ray meeting an object of albedo > 0 is refused, naming it, as is
//    one meeting a glossy object (scene/ward.hpp: its light needs the incident directions);
//  - at a Lambertian bottom: L_end = A Ed / pi (M93 eq. 11), Ed that of the bin the ray meets
//    (bins over the periodic section) if bins are given, else the surface map's at the point
//    met if one is given, else the wrapped estimator's bottom (lit evenly); the SE beside it
//    (shared by every ray meeting that bin or disc: it adds linearly, as the uniform bottom's
//    in RadianceEstimator);
//  - beyond that, the wrapped estimator's terms (the path, the surface and the sky above it).
// A bin is the average Ed over its area, so the bottom's light is resolved to a bin (and the
// Lambertian bottom's SE is per bin, larger than the uniform bottom's); the surface map
// resolves it to the gather disc's radius.
// Rays start in the water (origin depth >= 0): a camera above the surface is not modelled here.
// Threads: as RadianceEstimator's (const, any number of threads at once).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/estimate/surface_irradiance.hpp"
#include "secchi/scene/geometry.hpp"
#include "secchi/transport/bottom_grid.hpp"
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

template <class Estimator, SceneGeometry Geometry>
class SceneRadianceEstimator {
public:
    /// est: the water's radiance (its map's first pass traced `geometry`); bottom_ed_bins: that
    /// first pass's TransportResult::bottom_ed_bins (n x n, index iy n + ix), or empty;
    /// surface: the irradiance from that first pass's surface photon map, or none.
    SceneRadianceEstimator(const Estimator& est, Geometry geometry, std::vector<Estimate> bottom_ed_bins = {},
                           std::shared_ptr<const SurfaceIrradiance> surface = nullptr)
        : est_(est), geometry_(std::move(geometry)), bins_(std::move(bottom_ed_bins)),
          grid_(side_of(bins_.size()), est.map().section_width()), surface_(std::move(surface)) {
        require((bins_.empty() && !surface_) || est.map().bands() == 1, "bands", est.map().bands(),
                "must be 1 for a bottom in bins or a surface map (the first pass keeps one band)");
        for (const Estimate& e : bins_)
            require(std::isfinite(e.value) && e.value >= 0.0, "bottom Ed bin", e.value, "must be finite and >= 0");
    }
    SceneRadianceEstimator(const Estimator&&, Geometry, std::vector<Estimate> = {},
                           std::shared_ptr<const SurfaceIrradiance> = nullptr) = delete;  // would dangle

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
        const double t_bottom = est_.bottom_distance(ray);
        const double t_limit = std::min(ray.t_max, t_bottom);
        const auto hit = periodic_closest_hit(geometry_, map().section_width(), ray.origin, ray.direction, t_limit);
        if (hit) {  // an object ends the ray: the path to it, then the light it sends back
            const ObjectMaterial& material = geometry_.material(hit->material);  // (a reference where the geometry keeps it: no shared_ptr copy per hit)
            if (material.specular > 0.0)
                reject("object glossy albedo", material.specular,
                       "is not modelled by the second pass (a glossy surface's light needs the directions of the light "
                       "arriving on it, which the surface map does not keep), object " + std::to_string(hit->material));
            const double albedo = material.albedo_at(hit->point);
            est_.add(Ray{ray.origin, ray.direction, hit->t}, band, weight, sum);
            if (albedo == 0.0) return;
            if (!surface_)
                reject("object albedo", albedo, "needs a surface photon map in the second pass (the light leaving a "
                                                "Lambertian object is A E / pi; TransportSettings::surface_map), object " +
                                                    std::to_string(hit->material));
            add_lambertian(ray, hit->t, albedo / std::numbers::pi, surface_->irradiance(hit->point, hit->normal), band,
                           weight, sum);
            return;
        }
        if ((bins_.empty() && !surface_) || !(t_bottom <= ray.t_max)) {  // lit evenly, or ends before the bottom
            est_.add(ray, band, weight, sum);
            return;
        }
        // The path up to the bottom (t_max just short of it: the wrapped estimator then adds no
        // bottom term), then the bottom's light from its bin or its gather disc.
        est_.add(Ray{ray.origin, ray.direction, std::nextafter(t_bottom, 0.0)}, band, weight, sum);
        const vec3 p = ray.origin + t_bottom * ray.direction;
        const double w = map().section_width();
        const Estimate ed = bins_.empty() ? surface_->irradiance(p, vec3(0.0, 0.0, -1.0))
                                          : bins_[grid_.bin(periodic_wrap(p.x, w), periodic_wrap(p.y, w))];
        add_lambertian(ray, t_bottom, map().bottom().radiance_per_irradiance(), ed, band, weight, sum);
    }

private:
    /// weight T(t) (f_r E) for the ray ended at t on a Lambertian surface of f_r = A / pi lit by E.
    void add_lambertian(const Ray& ray, double t, double f_r, const Estimate& e, unsigned band, double weight,
                        RadianceSum& sum) const {
        const double per_e = weight * f_r * est_.transmittance(Ray{ray.origin, ray.direction, t}, band);
        if (per_e > 0.0) sum.add_shared(per_e * e.value, per_e * e.se);
    }

    static unsigned side_of(std::size_t bins) {
        const auto n = static_cast<unsigned>(std::lround(std::sqrt(static_cast<double>(bins))));
        require(static_cast<std::size_t>(n) * n == bins, "bottom Ed bins", bins, "must be n x n (TransportResult::bottom_ed_bins)");
        return n;
    }

    const Estimator& est_;
    Geometry geometry_;
    std::vector<Estimate> bins_;
    BottomGrid grid_;
    std::shared_ptr<const SurfaceIrradiance> surface_;
};

}  // namespace secchi
