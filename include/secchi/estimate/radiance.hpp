#pragma once
// The whole radiance a ray sees in or above the plane-parallel water body of a photon map:
// manual eq. 3.18, the in-scattered path radiance along the ray plus the radiance where the ray
// ends, carried to the ray's origin by the ray's transmittance T:
//     L(ray) = integral_0^t_end J(t) T(t) dt + T(t_end) L_end
// The ray looks along ray.direction (z positive down); the light it sees travels the other way.
// In water (origin z >= 0):
//  - the path term is the photon-map estimate (estimate/path_radiance.hpp) from the origin to
//    t_end, the nearest of: the surface (looking up), the bottom (looking down), the ray's own
//    t_max (where a host's object stops it: the host adds that object's radiance times
//    transmittance(ray)), or where T falls to RadianceSettings::ray_transmittance (the
//    in-scattered light beyond adds at most about that share); a boundary the ray reaches adds
//    its term however faint T is there;
//  - at a Lambertian bottom, L_end = A Ed(bottom) / pi, Ed(bottom) from the first pass
//    (M93 eq. 11; the bottom reflects equally in every direction); a transparent bottom has
//    nothing lit below it;
//  - at a flat surface, seen from below along a look direction d (the light travels along
//    v = -d, downward), L_end = R_w L_w(d') + (1 - R_w) (n_w / n_a)^2 L_sky(v_a):
//    upwelling light reflected into v, R_w the Fresnel reflectance (1 beyond the critical
//    angle), L_w(d') the water's radiance seen looking down along the mirror direction
//    d' = (d_x, d_y, -d_z) from the surface point (the same estimate, recursively: a downward ray
//    never meets the surface again); and the sky light refracted into v, v_a its direction in
//    air (Snell), with the n^2 law of radiance across an interface (Mobley 1994, "Light and
//    Water", eq. 4.28: L / n^2 is conserved, times the Fresnel transmittance).
// Above the water (origin z < 0; no attenuation in air):
//  - a ray looking up or level sees the sky, L_sky(-d);
//  - a ray looking down meets the surface (unless its t_max ends it first) and sees the sky
//    reflected there, R_a L_sky(d_r), d_r = (-d_x, -d_y, d_z), plus the water-leaving radiance
//    transmitted through it, (1 - R_a) (n_a / n_w)^2 L_w(d_w), d_w the look direction refracted
//    into the water.
// The direct sun is a delta in direction and is not part of L: direct_sun(point) gives its beam
// (direction and E_perp) at any point, for a host that renders it, e.g. as a disk or a glint.
// A surface the second pass does not model (wind-blown, MapScene::flat_surface empty), and a
// sky that is not known in closed form (a traced atmosphere's), are refused where a ray needs
// them, with the reason.
//
// Standard error: the photon-map terms are kept per batch (RadianceSum), so that sums over rays
// (pixels, integrals over directions) keep their covariance; the bottom term's SE comes from
// the first pass's Ed(bottom), shared by every ray, so it adds linearly over rays.
//
// Threads: built once, then radiance(), add() and direct_sun() may be called from any number of
// threads at once; average() runs its rays in parallel and merges in ray order (bit-identical
// for any thread count).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/estimate/path_radiance.hpp"
#include "secchi/map/photon_map.hpp"
#include "secchi/scene/fresnel.hpp"
#include "secchi/core/parallel.hpp"
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

struct RadianceSettings {
    /// An in-water ray that meets no boundary integrates its path radiance until its
    /// transmittance falls to this (the light beyond adds at most about this share).
    double ray_transmittance = 1e-4;
};

/// A weighted sum of radiance estimates over rays: the photon-map terms per batch (entry k is
/// what batch k alone estimates), the exact terms (sky), and the terms shared by every ray
/// (bottom), whose SE adds linearly.
class RadianceSum {
public:
    explicit RadianceSum(unsigned batches) : per_batch_(batches, 0.0) {}

    [[nodiscard]] std::span<double> per_batch() { return per_batch_; }
    [[nodiscard]] std::span<const double> per_batch() const { return per_batch_; }
    void add_exact(double value) { exact_ += value; }
    void add_shared(double value, double se) {
        shared_ += value;
        shared_se_ += se;
    }
    void count_photons(std::uint64_t n) { photons_touched_ += n; }
    /// Adds another sum (of the same map's batches) times `weight` (>= 0).
    void merge(const RadianceSum& other, double weight = 1.0) {
        require(other.per_batch_.size() == per_batch_.size(), "batches", other.per_batch_.size(),
                "differ from this sum's (" + std::to_string(per_batch_.size()) + ")");
        for (std::size_t k = 0; k < per_batch_.size(); ++k) per_batch_[k] += weight * other.per_batch_[k];
        exact_ += weight * other.exact_;
        shared_ += weight * other.shared_;
        shared_se_ += weight * other.shared_se_;
        photons_touched_ += other.photons_touched_;
    }
    /// The sum divided by `divisor` (e.g. the rays' count for their mean), with its SE: the
    /// batches' scatter, and the shared terms' SE beside it.
    [[nodiscard]] Estimate estimate(double divisor = 1.0) const {
        const Estimate batches = batch_estimate(per_batch_);
        return {(batches.value + exact_ + shared_) / divisor, std::hypot(batches.se, shared_se_) / divisor};
    }
    [[nodiscard]] std::uint64_t photons_touched() const { return photons_touched_; }
    /// The terms not drawn from the photons (exact and shared), and the shared terms' SE.
    [[nodiscard]] double outside_batches() const { return exact_ + shared_; }
    [[nodiscard]] double shared_se() const { return shared_se_; }

private:
    std::vector<double> per_batch_;
    double exact_ = 0.0, shared_ = 0.0, shared_se_ = 0.0;
    std::uint64_t photons_touched_ = 0;
};

template <class Store, CollectionVolume Volume, RayOptics Optics>
class RadianceEstimator {
public:
    /// optics: the water's for every band of the map, or (per_band) each band's own.
    RadianceEstimator(const PhotonMap<Store>& map, Volume volume, Optics optics, Radius radius,
                      RadianceSettings settings = {})
        : RadianceEstimator(map, std::move(volume), std::vector<Optics>(map.bands(), optics), radius, settings) {}
    RadianceEstimator(const PhotonMap<Store>& map, Volume volume, std::vector<Optics> per_band, Radius radius,
                      RadianceSettings settings = {})
        : path_(map, std::move(volume), std::move(per_band), radius), settings_(settings) {
        require(settings.ray_transmittance > 0.0 && settings.ray_transmittance < 1.0, "ray transmittance",
                settings.ray_transmittance, "must lie in (0, 1)");
    }
    /// A temporary map would be gone before the estimator's first query.
    RadianceEstimator(const PhotonMap<Store>&&, Volume, Optics, Radius, RadianceSettings = {}) = delete;
    RadianceEstimator(const PhotonMap<Store>&&, Volume, std::vector<Optics>, Radius, RadianceSettings = {}) = delete;

    [[nodiscard]] const PhotonMap<Store>& map() const { return path_.map(); }
    [[nodiscard]] const PathRadianceEstimator<Store, Volume, Optics>& path() const { return path_; }

    /// The radiance (W m^-2 nm^-1 sr^-1, in the source's units) arriving at ray.origin against
    /// ray.direction in band `band`, with its SE. ray.t_max may be INFINITY.
    [[nodiscard]] Estimate radiance(const Ray& ray, unsigned band = 0) const {
        RadianceSum sum(map().batches());
        add(ray, band, 1.0, sum);
        return sum.estimate();
    }

    /// Adds weight times the ray's radiance to `sum`.
    void add(const Ray& ray, unsigned band, double weight, RadianceSum& sum) const {
        walk(ray, band, weight, sum, [&](const Ray& segment, double w) { add_path(segment, band, w, sum); });
    }

    /// A segment of a ray's path in the water and the weight its photon-map estimate carries in
    /// the ray's radiance (transmittances and Fresnel factors to the ray's origin).
    struct PathSegment {
        Ray ray;
        double weight;
    };
    /// add() without the photon map: the terms outside it (sky, bottom) go to `sum`, the path
    /// segments whose photon-map estimates the radiance needs are appended to `segments`, in
    /// add()'s order, for a caller that estimates them itself (e.g. every band from one search:
    /// estimate/spectral_compensation.hpp). The segments' directions and origins are the same
    /// in every band; their lengths and weights follow the band's attenuation.
    void add_outside_map(const Ray& ray, unsigned band, double weight, RadianceSum& sum,
                         std::vector<PathSegment>& segments) const {
        walk(ray, band, weight, sum, [&](const Ray& segment, double w) { segments.push_back({segment, w}); });
    }

    /// The mean radiance of a set of rays in band `band` (e.g. the rays of one pixel, or a grid
    /// of parallel rays in a horizontally homogeneous water body), with its SE. Rays run on
    /// `threads` threads; their sums are merged in ray order.
    [[nodiscard]] Estimate average(const std::vector<Ray>& rays, unsigned band, unsigned threads,
                                   std::uint64_t* photons_touched = nullptr) const {
        const RadianceSum sum = sum_over(rays, band, threads);
        if (photons_touched) *photons_touched = sum.photons_touched();
        return sum.estimate(static_cast<double>(rays.size()));
    }

    /// The rays' radiances added together (weight 1 each) as one RadianceSum, in parallel, merged in ray order.
    [[nodiscard]] RadianceSum sum_over(const std::vector<Ray>& rays, unsigned band, unsigned threads) const {
        std::vector<RadianceSum> per_ray(rays.size(), RadianceSum(map().batches()));
        parallel_for(rays.size(), threads, [&](std::size_t i) { add(rays[i], band, 1.0, per_ray[i]); });
        RadianceSum total(map().batches());
        for (const auto& s : per_ray) total.merge(s);
        return total;
    }

    /// The ray's transmittance to where it ends: T in water, times the Fresnel transmittance and
    /// the n^2 factor where it crosses the surface from the air (what a host multiplies its own
    /// object's radiance by, at t_max). An object must lie in the medium the ray reaches: a ray
    /// from the water whose t_max lies beyond the surface or the bottom is refused.
    [[nodiscard]] double transmittance(const Ray& ray, unsigned band = 0) const {
        if (ray.origin.z < 0.0) {
            if (ray.direction.z <= 0.0) return 1.0;
            const double t_s = -ray.origin.z / ray.direction.z;
            if (t_s >= ray.t_max) return 1.0;
            const Crossing into = from_air(ray.direction);
            return into.transmitted * transmittance(Ray{surface_point(ray, t_s), into.direction, ray.t_max - t_s}, band);
        }
        const Boundary boundary = boundary_of(ray);
        require(ray.t_max <= boundary.t, "ray length (m)", ray.t_max,
                "reaches beyond the water (the surface or the bottom, " + std::to_string(boundary.t) +
                    " m along the ray): the transmittance is that of a ray in the water");
        return path_.optics(band).transmittance(ray, ray.t_max);
    }

    /// The sun's direct beam at `point` (a delta in direction, not part of radiance()): above
    /// the water the source's; in water refracted by the flat surface, its E_perp times the
    /// Fresnel transmittance, cos(theta_a) / cos(theta_w) (the beam's cross-section narrows),
    /// and the water's transmittance along the beam.
    [[nodiscard]] DirectBeam direct_sun(const vec3& point, unsigned band = 0) const {
        const DirectBeam& sun = map().scene().light.sun();
        if (point.z < 0.0) return sun;
        require_in_water(point.z);
        const FlatSurface& s = surface("the sun's beam in water");
        const vec3 v = s.transmit_into_water(sun.direction);
        const double e = sun.e_perp * (1.0 - s.reflectance_from_air(sun.direction)) * sun.direction.z / v.z;
        const double t = point.z / v.z;
        return {v, e * path_.optics(band).transmittance(Ray{point, -v, t}, t)};
    }

    /// The distance along a ray in the water to the bottom: (D - z) / d_z looking down with a
    /// bottom at depth D, else infinite.
    [[nodiscard]] double bottom_distance(const Ray& ray) const {
        const double bottom = map().bottom().depth();  // +inf: none
        return ray.direction.z > 0.0 && std::isfinite(bottom) ? (bottom - ray.origin.z) / ray.direction.z : INFINITY;
    }

private:
    /// Where a ray from a point in the water meets the water's boundary: the surface (looking
    /// up), the bottom (looking down, if there is one), or nothing (t infinite).
    enum class End { none, surface, bottom };
    struct Boundary {
        End end;
        double t;
    };
    Boundary boundary_of(const Ray& ray) const {
        require_in_water(ray.origin.z);
        if (ray.direction.z < 0.0) return {End::surface, ray.origin.z / -ray.direction.z};
        const double t = bottom_distance(ray);
        return {std::isfinite(t) ? End::bottom : End::none, t};
    }

    /// A direction crossing the surface and the radiance factor (1 - R) (n_from / n_to)^2.
    struct Crossing {
        vec3 direction;
        double reflectance;
        double transmitted;
    };

    const FlatSurface& surface(const char* what) const {
        const auto& s = map().scene().flat_surface;
        if (!s) reject("surface", "wind-blown", std::string("is not modelled by the second pass, which ") + what + " needs");
        return *s;
    }
    void require_in_water(double z) const {
        const double bottom = map().bottom().depth();
        require(!(z > bottom), "ray origin depth (m)", z, "lies below the bottom (" + std::to_string(bottom) + " m)");
    }
    double sky(const vec3& travel) const {
        const SkyLight& light = map().scene().light;
        if (!light.sky_known())
            reject("sky", "traced atmosphere", "has no closed-form radiance: rays that see the sky are not estimated");
        return light.sky_radiance(travel);
    }
    static vec3 surface_point(const Ray& ray, double t) {
        vec3 p = ray.origin + t * ray.direction;
        p.z = 0.0;
        return p;
    }
    /// A look direction d from the air (d.z > 0) into the water.
    Crossing from_air(const vec3& d) const {
        const FlatSurface& s = surface("a ray from the air into the water");
        const double r = s.reflectance_from_air(d), n = s.air_index() / s.water_index();
        return {s.transmit_into_water(d), r, (1.0 - r) * n * n};
    }

    /// The ray's terms (manual eq. 3.18, the header): those outside the photon map into `sum`,
    /// each path segment in the water to path(segment, weight).
    template <class Path>
    void walk(const Ray& ray, unsigned band, double weight, RadianceSum& sum, Path&& path) const {
        require(std::isfinite(ray.origin.x) && std::isfinite(ray.origin.y) && std::isfinite(ray.origin.z),
                "ray origin", ray.origin.z, "must be finite");
        require(std::abs(glm::length(ray.direction) - 1.0) < 1e-9, "ray direction length", glm::length(ray.direction),
                "must be 1 (a unit vector)");
        require(ray.t_max >= 0.0, "ray length (m)", ray.t_max, "must be >= 0 (INFINITY: unbounded)");
        require(band < map().bands(), "band", band, "is not among the map's bands (" + std::to_string(map().bands()) + ")");
        if (ray.origin.z < 0.0) add_from_air(ray, band, weight, sum, path);
        else add_in_water(ray, band, weight, sum, path);
    }

    template <class Path>
    void add_from_air(const Ray& ray, unsigned band, double weight, RadianceSum& sum, Path& path) const {
        const vec3& d = ray.direction;
        if (d.z <= 0.0) {
            sum.add_exact(weight * sky(-d));
            return;
        }
        const double t_s = -ray.origin.z / d.z;
        if (t_s > ray.t_max) return;  // the host's object, in the air
        const Crossing into = from_air(d);
        if (into.reflectance > 0.0) sum.add_exact(weight * into.reflectance * sky({-d.x, -d.y, d.z}));
        add_in_water(Ray{surface_point(ray, t_s), into.direction, ray.t_max - t_s}, band, weight * into.transmitted, sum, path);
    }

    template <class Path>
    void add_in_water(const Ray& ray, unsigned band, double weight, RadianceSum& sum, Path& path) const {
        const vec3& d = ray.direction;
        const auto [end, t_boundary] = boundary_of(ray);
        const Optics& optics = path_.optics(band);
        const double t_end = std::min(ray.t_max, t_boundary);
        const double t_path = length_to_transmittance(optics, Ray{ray.origin, d, t_end}, settings_.ray_transmittance);
        path(Ray{ray.origin, d, t_path}, weight);
        // The boundary's light is added however faint the path to it (no photons to gather).
        if (end == End::none || ray.t_max < t_boundary) return;  // ended in the water

        const double w = weight * optics.transmittance(ray, t_boundary);
        if (end == End::bottom) {  // L = Ed(bottom) x L/Ed of the bottom (A / pi: M93 eq. 11)
            const double per_ed = w * map().bottom().radiance_per_irradiance();
            const Estimate& ed = map().bottom_ed(band);
            if (per_ed > 0.0) sum.add_shared(per_ed * ed.value, per_ed * ed.se);
            return;
        }
        // The surface from below: internal reflection of the upwelling light, the sky refracted in.
        const FlatSurface& s = surface("a ray from the water up to the surface");
        const vec3 p = surface_point(ray, t_boundary);
        const vec3 mirror{d.x, d.y, -d.z};  // looks down
        const double r = s.reflectance_from_water(-mirror);
        if (r > 0.0) add_in_water(Ray{p, mirror, INFINITY}, band, w * r, sum, path);
        if (r < 1.0) {
            const double n = s.water_index() / s.air_index();
            sum.add_exact(w * (1.0 - r) * n * n * sky(s.transmit_into_air(-d)));
        }
    }

    /// weight times the photon-map estimate along the ray, per batch.
    void add_path(const Ray& ray, unsigned band, double weight, RadianceSum& sum) const {
        if (ray.t_max <= 0.0) return;
        std::array<double, PhotonMap<Store>::max_batches> photons{};
        const unsigned batches = map().batches();
        sum.count_photons(path_.accumulate(ray, std::span(photons.data(), batches), band));
        const double scale = weight * path_.batch_scale();
        auto out = sum.per_batch();
        for (unsigned k = 0; k < batches; ++k) out[k] += scale * photons[k];
    }

    PathRadianceEstimator<Store, Volume, Optics> path_;
    RadianceSettings settings_;
};

}  // namespace secchi
