#pragma once
// In-scattered radiance along a ray from the photon map (the second pass, manual 3.4-3.5):
//   L(r_a) = sum over collected photons of Phi * pbar_omega(psi) * w_i * exp(-c t)  (eq. 3.18 / 3.22)
// where Phi is the flux per map photon, pbar_omega the phase function averaged over the
// collection solid angle omega around the scattering direction (eq. 3.5), w_i the
// collection volume's length/volume weight, and t the photon's distance along the ray from
// the ray's start (the attenuation to the ray's end point, where the radiance is wanted).
// Photons are stored at scattering events, so the map density is b E_o: no extra factor b.
// In stratified water pbar_omega is the mixture at the photon's depth (eq. 5.5) and exp(-c t)
// becomes exp(-int c dt) along the ray: the RayOptics policy supplies both.
// Standard error: each photon belongs to one of B batches; each batch alone is an estimate
// with flux B * Phi per photon.
#include "secchi/core/stats.hpp"
#include "secchi/estimate/collection.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/chord_table.hpp"
#include "secchi/transport/importance.hpp"
#include "secchi/transport/parallel.hpp"
#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace secchi {

struct RadianceEstimate {
    Estimate radiance;
    std::uint64_t photons_touched = 0;  ///< collected photons over all rays
    std::size_t rays = 0;
};

/// The water's part of eq. 3.18 for one photon: in_scatter(z, cos_psi, ray, t) =
/// pbar_omega(psi) at the photon's depth z times the transmittance from the ray's start over t.
template <class O>
concept RayOptics = requires(const O o, double z, double cos_psi, Ray ray, double t) {
    { o.in_scatter(z, cos_psi, ray, t) } -> std::convertible_to<double>;
};

/// Homogeneous water: one cone-averaged phase function and exp(-c t). The phase function is
/// looked up in a ChordTable (no acos per photon; optics/phase/chord_table.hpp).
struct HomogeneousRayOptics {
    template <class ConePhase>
    HomogeneousRayOptics(const ConePhase& cone, double attenuation_) : phase(cone), attenuation(attenuation_) {}
    ChordTable phase;
    double attenuation;
    [[nodiscard]] double in_scatter(double, double cos_psi, const Ray&, double t) const {
        return phase.eval(cos_psi) * std::exp(-attenuation * t);
    }
};

/// Depth-varying water (a StratifiedWater): the components' cone-averaged phase functions
/// weighted by b_i(z) / b(z) (eq. 5.5-5.6), and exp(-int c) along the ray. With depth
/// importance in the first pass, a photon stored at depth z carries the flux Phi / I(z).
template <class Water>
struct StratifiedRayOptics {
    /// cones: one cone-averaged phase function per scattering component, in order.
    template <class ConePhase>
    StratifiedRayOptics(const Water& water_, const std::vector<ConePhase>& cones, ImportanceLevels importance_ = {})
        : water(water_), phases(cones.begin(), cones.end()), importance(importance_) {}
    const Water& water;
    std::vector<ChordTable> phases;
    ImportanceLevels importance;  ///< the first pass's (transport/importance.hpp)
    [[nodiscard]] double in_scatter(double z, double cos_psi, const Ray& ray, double t) const {
        const double p = water.mixture(z, [&](std::size_t i) { return phases[i].eval(cos_psi); });
        const double tau = water.optical_path(Coefficient::attenuation, ray.origin.z, ray.direction.z, t);
        return p * std::exp(-tau) / importance.factor(z);
    }
};

template <class Store, CollectionVolume Volume, RayOptics Optics>
class PathRadianceEstimator {
public:
    PathRadianceEstimator(const Store& store, Volume volume, Optics optics, double flux_per_photon, unsigned batches,
                          Radius radius)
        : store_(store), volume_(std::move(volume)), optics_(std::move(optics)), flux_(flux_per_photon),
          batches_(batches), radius_(radius) {
        require(batches >= 1 && batches <= max_batches, "batches", batches, "must be in [1, 256]");
    }

    static constexpr unsigned max_batches = 256;  ///< as TransportSettings allows

    /// Adds the per-batch photon sums of one ray (light arriving at ray.origin travelling
    /// opposite to ray.direction) to batch_sums; returns the photons touched.
    std::uint64_t accumulate(const Ray& ray, std::span<double> batch_sums) const {
        std::uint64_t touched = 0;
        const auto& records = store_.records();
        volume_.gather(store_, ray, radius_, [&](std::uint32_t index, double t, double weight) {
            const auto& rec = records[index];
            const double cos_psi = -glm::dot(rec.direction(), ray.direction);
            batch_sums[rec.batch()] += weight * optics_.in_scatter(rec.position().z, cos_psi, ray, t);
            ++touched;
        });
        return touched;
    }

    /// Radiance averaged over a set of rays (e.g. a grid of parallel rays in a horizontally
    /// homogeneous water body), with its batch standard error. Rays run in parallel; the
    /// sums are merged in ray order (bit-identical for any thread count).
    RadianceEstimate estimate(const std::vector<Ray>& rays, unsigned threads) const {
        std::vector<std::vector<double>> per_ray(rays.size(), std::vector<double>(batches_, 0.0));
        std::vector<std::uint64_t> touched(rays.size(), 0);
        parallel_for(rays.size(), threads, [&](std::size_t i) {
            // Sums on this thread's stack, copied out once: the rays' own vectors may share a
            // cache line with a neighbour's that another thread is adding to.
            std::array<double, max_batches> sums{};
            touched[i] = accumulate(rays[i], std::span(sums.data(), batches_));
            std::copy_n(sums.begin(), batches_, per_ray[i].begin());
        });
        std::vector<double> batch(batches_, 0.0);
        RadianceEstimate out;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            for (unsigned b = 0; b < batches_; ++b) batch[b] += per_ray[i][b];
            out.photons_touched += touched[i];
        }
        const double scale = flux_ * batches_ / static_cast<double>(rays.size());
        for (double& v : batch) v *= scale;
        out.radiance = batch_estimate(batch);
        out.rays = rays.size();
        return out;
    }

private:
    const Store& store_;
    Volume volume_;
    Optics optics_;
    double flux_;
    unsigned batches_;
    Radius radius_;
};

/// A K x K grid of parallel vertical rays looking straight down from depth z over the
/// section [0, W)^2, at the centres of the grid cells (at least W/(2K) from the wrap seam),
/// each of length `length`.
inline std::vector<Ray> nadir_ray_grid(double z, double length, unsigned k, double width) {
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(k) * k);
    for (unsigned i = 0; i < k; ++i)
        for (unsigned j = 0; j < k; ++j)
            rays.push_back({{(i + 0.5) * width / k, (j + 0.5) * width / k, z}, {0.0, 0.0, 1.0}, length});
    return rays;
}

}  // namespace secchi
