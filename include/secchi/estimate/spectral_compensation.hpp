#pragma once
// Spectral "bias" compensation (manual 3.5.2): the radiance of every band of a spectral map
// (solver/spectral.hpp: each record carries one band) with its brightness from a small, local
// search over all bands and its spectral shape from a larger search per band.
//
// The estimator. For a ray and band k, let P_k(r) be the photon-map terms of band k's radiance
// estimate with collection radius r (RadianceEstimator's per-batch terms, estimate/radiance.hpp:
// eq. 3.22's sum over band k's photons in the collection volume of radius r, each weighted with
// band k's own optics, i.e. its phase function pbar_omega and its transmittance along the ray,
// times the surface's transmission for a ray from the air and including the ray reflected at
// the surface from below). Then
//   core total (3.5.2.1):       T   = sum_k P_k(r_core)
//   shares (3.5.2.2):           s_k = P_k(r_spectral) / sum_j P_j(r_spectral)
//   compensated radiance:       L_k = T s_k + X_k
// where X_k are band k's terms not drawn from the photons (the sky seen directly or through the
// surface, the Lambertian bottom's A Ed / pi: RadianceSum's exact and shared terms), which are
// the same at both radii and are not compensated.
// "The density across all bands" of the manual's core search is, for radiance, T: each band's
// photons enter with that band's optics (with the same optics in every band it is the plain
// estimate from the photons of all bands). Consequences:
//  - sum_k (L_k - X_k) = T: the bands' photon-map radiances add up to the local, core total;
//  - r_spectral = r_core gives L_k = P_k(r_core) + X_k, the per-band estimate;
//  - where the ratios between the bands' radiances are the same over the spectral search's
//    volume as over the core's (the manual's assumption that the spectral shape varies slowly
//    relative to intensity), E[s_k] is the true share (up to the ratio's O(1/N) bias, N the
//    photons of the spectral search) and L_k is unbiased, with the noise of the core search
//    over all bands, ~1/sqrt(bands) of one band's when the bands are alike, plus the small noise of
//    the shares. L_k's relative noise is about T's, which the brightest bands set: a band much
//    dimmer than the others may come out noisier than its own per-band estimate (e.g. Case-1
//    water's red bands beside its blue ones, examples/spectral_case1.cpp);
//  - where the ratios vary across the spectral volume, s_k is the ratio of the bands' averages
//    over it, not at the core: a bias. E.g. a horizontal ray, whose cylinder spans depths
//    z +- r_spectral, in water whose bands' radiances fall with depth as exp(-K_k z): the
//    cylinder's average of exp(-K y) over its disk is 2 I_1(K r) / (K r) times the axis'
//    value, so the share of a band of larger K comes out high by about (K_k^2 - <K^2>) r^2 / 8.
//    Vertical rays in horizontally homogeneous water see no such bias: a wider cylinder spans
//    the same depths.
// The compensation is applied per ray (each ray is one search of the manual); a sum or mean over
// rays is the sum or mean of the rays' compensated radiances.
//
// Standard error: L_k is a ratio of sums that share photons (the core cylinder lies within the
// spectral one, and band k's photons enter T and s_k both), so it is not a mean of per-batch
// estimates. Its SE is the delete-one-batch jackknife (core/stats.hpp: jackknife_estimate): the
// same compensation from the other B - 1 batches' sums, for each batch b; for a sum over rays
// the rays' replicates are summed first. The jackknife is the delta method's linearised
// variance (Efron & Tibshirani 1993, 11.5) with the covariance of T and the shares taken from the
// batches, without writing that covariance out; the value is the compensation of all batches
// pooled, not a mean of per-batch ratios (each a ratio of 1/B of the photons, with B times the
// ratio's bias). The bottom term's SE (shared by every ray) is added beside it, as in RadianceSum.
//
// Cost: the manual advises to "reuse the results from the original, core search" (3.5.2.3).
// With VoiCylinder (a NestedCollectionVolume, estimate/collection.hpp), one search per ray
// segment serves every band and both radii: the spectral cylinder's photons, each band's within
// that band's segment (its length follows the band's attenuation), the core cylinder's among
// them by their distance from the axis. StepSpheres' spheres follow the segment's length, so
// each band's segment is searched on its own, once for both radii (the spectral spheres, the
// core ones' photons among them): bands searches per segment instead of 2 x bands. Either way
// the same photons, values and weights as the searches one band and one radius at a time. The
// collection volume's boundary bias compensation (manual 3.5.1) applies at both radii.
//
// Threads: as RadianceEstimator: built once, then radiance() and add() from any number of
// threads; average() runs its rays in parallel and merges in ray order (bit-identical for any
// thread count).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/map/photon_map.hpp"
#include "secchi/core/parallel.hpp"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

/// The two radii of the compensation (m).
struct SpectralCompensation {
    double core_radius = 0.0;      ///< r_core: the local search over all bands (manual 3.5.2.1)
    double spectral_radius = 0.0;  ///< r_spectral >= r_core: the expanded search per band (3.5.2.2)
};

/// Compensated radiances of every band summed over rays (with weights): per band the pooled
/// value, its B leave-one-batch-out replicates, the terms outside the photon map and the shared
/// terms' SE (see the header).
class CompensatedSum {
public:
    CompensatedSum(std::size_t bands, unsigned batches)
        : bands_(bands), batches_(batches), value_(bands, 0.0), replicates_(bands * batches, 0.0), outside_(bands, 0.0),
          shared_se_(bands, 0.0) {}

    [[nodiscard]] std::size_t bands() const { return bands_; }
    [[nodiscard]] unsigned batches() const { return batches_; }
    [[nodiscard]] std::uint64_t photons_touched() const { return photons_touched_; }

    /// Adds weight times one ray's compensated radiances: core[k] and spectral[k] are band k's
    /// RadianceSum of the ray at r_core and at r_spectral (every band, each of this sum's batches).
    void add_ray(std::span<const RadianceSum> core, std::span<const RadianceSum> spectral, double weight) {
        require(core.size() == bands_ && spectral.size() == bands_, "bands of a ray's sums", core.size(),
                "must be the compensated sum's bands at both radii");
        const unsigned nb = batches_;
        // Each band's batch totals at both radii.
        std::vector<double> core_total(bands_, 0.0), spectral_total(bands_, 0.0);
        for (std::size_t k = 0; k < bands_; ++k) {
            for (unsigned b = 0; b < nb; ++b) {
                core_total[k] += core[k].per_batch()[b];
                spectral_total[k] += spectral[k].per_batch()[b];
            }
            outside_[k] += weight * core[k].outside_batches();
            shared_se_[k] += weight * core[k].shared_se();
            photons_touched_ += core[k].photons_touched() + spectral[k].photons_touched();
        }
        // All batches pooled: T = sum_k mean_b P_kb(r_core); shares from the totals.
        double t = 0.0, s = 0.0;
        for (std::size_t k = 0; k < bands_; ++k) {
            t += core_total[k];
            s += spectral_total[k];
        }
        t /= nb;
        for (std::size_t k = 0; k < bands_; ++k) value_[k] += weight * compensated(t, spectral_total[k], s);
        // Batch b left out: the same from the other nb - 1 batches.
        if (nb < 2) return;
        for (unsigned b = 0; b < nb; ++b) {
            double tb = 0.0, sb = 0.0;
            for (std::size_t k = 0; k < bands_; ++k) {
                tb += core_total[k] - core[k].per_batch()[b];
                sb += spectral_total[k] - spectral[k].per_batch()[b];
            }
            tb /= nb - 1;
            for (std::size_t k = 0; k < bands_; ++k)
                replicates_[k * nb + b] += weight * compensated(tb, spectral_total[k] - spectral[k].per_batch()[b], sb);
        }
    }

    /// Adds another sum (of the same bands and batches).
    void merge(const CompensatedSum& other) {
        require(other.bands_ == bands_ && other.batches_ == batches_, "bands", other.bands_,
                "and batches must be this sum's");
        for (std::size_t i = 0; i < value_.size(); ++i) value_[i] += other.value_[i];
        for (std::size_t i = 0; i < replicates_.size(); ++i) replicates_[i] += other.replicates_[i];
        for (std::size_t i = 0; i < outside_.size(); ++i) {
            outside_[i] += other.outside_[i];
            shared_se_[i] += other.shared_se_[i];
        }
        photons_touched_ += other.photons_touched_;
    }

    /// Band k's compensated radiance divided by `divisor` (e.g. the rays' count for their mean),
    /// with its SE: the jackknife's over the batches, and the shared terms' beside it.
    [[nodiscard]] Estimate estimate(unsigned band, double divisor = 1.0) const {
        require(band < bands_, "band", band, "is not among the compensated sum's bands");
        const Estimate photons = jackknife_estimate(
            value_[band], std::span<const double>(replicates_).subspan(std::size_t{band} * batches_, batches_));
        return {(photons.value + outside_[band]) / divisor, std::hypot(photons.se, shared_se_[band]) / divisor};
    }
    /// Every band's estimate(k, divisor), in band order.
    [[nodiscard]] std::vector<Estimate> estimates(double divisor = 1.0) const {
        std::vector<Estimate> out;
        for (std::size_t k = 0; k < bands_; ++k) out.push_back(estimate(static_cast<unsigned>(k), divisor));
        return out;
    }

private:
    /// T * band / all: the core total times the band's share. The spectral search collects every
    /// photon the core one does (its volume contains the core's, each photon adds > 0), so
    /// all == 0 comes with T == 0: no photon-map radiance in any band.
    static double compensated(double t, double band, double all) {
        if (all > 0.0) return t * (band / all);
        require(t == 0.0, "core total radiance", t,
                "comes with no photons in the spectral search: the collection volume at r_spectral must contain r_core's");
        return 0.0;
    }

    std::size_t bands_;
    unsigned batches_;
    std::vector<double> value_;       ///< per band: sum over rays of weight * L_k's photon part
    std::vector<double> replicates_;  ///< [k * batches + b]: the same with batch b left out
    std::vector<double> outside_;     ///< per band: the exact and shared terms
    std::vector<double> shared_se_;   ///< per band: the shared terms' SE (adds linearly)
    std::uint64_t photons_touched_ = 0;
};

template <class Store, CollectionVolume Volume, RayOptics Optics>
class SpectralCompensationEstimator {
public:
    /// map: a spectral map of 2 or more bands; per_band: each band's optics, in the map's band
    /// order; radii: 0 < r_core <= r_spectral < half the section width.
    SpectralCompensationEstimator(const PhotonMap<Store>& map, Volume volume, std::vector<Optics> per_band,
                                  SpectralCompensation radii, RadianceSettings settings = {})
        : radii_(checked(map, radii)), core_(map, volume, per_band, Radius(radii_.core_radius), settings),
          spectral_(map, std::move(volume), std::move(per_band), Radius(radii_.spectral_radius), settings) {}
    /// The same optics in every band.
    SpectralCompensationEstimator(const PhotonMap<Store>& map, Volume volume, Optics optics, SpectralCompensation radii,
                                  RadianceSettings settings = {})
        : SpectralCompensationEstimator(map, std::move(volume), std::vector<Optics>(map.bands(), optics), radii, settings) {}
    /// A temporary map would be gone before the estimator's first query.
    SpectralCompensationEstimator(const PhotonMap<Store>&&, Volume, std::vector<Optics>, SpectralCompensation,
                                  RadianceSettings = {}) = delete;
    SpectralCompensationEstimator(const PhotonMap<Store>&&, Volume, Optics, SpectralCompensation,
                                  RadianceSettings = {}) = delete;

    [[nodiscard]] const PhotonMap<Store>& map() const { return core_.map(); }
    [[nodiscard]] SpectralCompensation radii() const { return radii_; }
    /// The per-band (uncompensated) estimators at r_core and at r_spectral.
    [[nodiscard]] const RadianceEstimator<Store, Volume, Optics>& core() const { return core_; }
    [[nodiscard]] const RadianceEstimator<Store, Volume, Optics>& spectral() const { return spectral_; }

    /// Every band's compensated radiance (as RadianceEstimator::radiance: arriving at ray.origin
    /// against ray.direction) with its SE, in band order.
    [[nodiscard]] std::vector<Estimate> radiance(const Ray& ray) const {
        CompensatedSum sum = empty_sum();
        add(ray, 1.0, sum);
        return sum.estimates();
    }

    /// Adds weight times the ray's compensated radiances to `sum`.
    void add(const Ray& ray, double weight, CompensatedSum& sum) const {
        const unsigned batches = map().batches();
        std::vector<RadianceSum> at_core(map().bands(), RadianceSum(batches)), at_spectral(map().bands(), RadianceSum(batches));
        if constexpr (NestedCollectionVolume<Volume>) {
            add_from_one_search(ray, at_core, at_spectral);
        } else {
            for (std::size_t k = 0; k < at_core.size(); ++k) {
                const auto band = static_cast<unsigned>(k);
                core_.add(ray, band, 1.0, at_core[k]);
                spectral_.add(ray, band, 1.0, at_spectral[k]);
            }
        }
        sum.add_ray(at_core, at_spectral, weight);
    }

    /// The mean compensated radiance of a set of rays per band, with its SE. Rays run on
    /// `threads` threads; their sums are merged in ray order.
    [[nodiscard]] std::vector<Estimate> average(const std::vector<Ray>& rays, unsigned threads,
                                                std::uint64_t* photons_touched = nullptr) const {
        const CompensatedSum sum = sum_over(rays, threads);
        if (photons_touched) *photons_touched = sum.photons_touched();
        return sum.estimates(static_cast<double>(rays.size()));
    }

    /// The rays' compensated radiances added together (weight 1 each), in parallel, merged in ray order.
    [[nodiscard]] CompensatedSum sum_over(const std::vector<Ray>& rays, unsigned threads) const {
        std::vector<CompensatedSum> per_ray(rays.size(), empty_sum());
        parallel_for(rays.size(), threads, [&](std::size_t i) { add(rays[i], 1.0, per_ray[i]); });
        CompensatedSum total = empty_sum();
        for (const auto& s : per_ray) total.merge(s);
        return total;
    }

    /// A sum of this map's bands and batches.
    [[nodiscard]] CompensatedSum empty_sum() const { return CompensatedSum(map().bands(), map().batches()); }

private:
    /// The ray's sums of every band at both radii (what core_.add and spectral_.add give per
    /// band) from one search per path segment (manual 3.5.2.3): the spectral cylinder, its
    /// photons of each band within that band's segment, the core cylinder's among them; or,
    /// for a volume that follows the segment's length (step spheres), one search per band's
    /// segment for both radii. The terms outside the map (sky, bottom) go to the core sums,
    /// which CompensatedSum reads them from.
    void add_from_one_search(const Ray& ray, std::vector<RadianceSum>& at_core, std::vector<RadianceSum>& at_spectral) const
        requires NestedCollectionVolume<Volume>
    {
        using Segments = std::vector<typename RadianceEstimator<Store, Volume, Optics>::PathSegment>;
        const std::size_t bands = at_core.size();
        const unsigned batches = map().batches();
        std::vector<Segments> segments(bands);
        for (std::size_t k = 0; k < bands; ++k)
            spectral_.add_outside_map(ray, static_cast<unsigned>(k), 1.0, at_core[k], segments[k]);
        for (std::size_t k = 1; k < bands; ++k)
            require(segments[k].size() == segments[0].size(), "path segments of band " + std::to_string(k), segments[k].size(),
                    "differ in number from band 0's (" + std::to_string(segments[0].size()) + ")");
        std::vector<double> lengths(bands), outer(bands * batches), inner(bands * batches);
        std::vector<double> one_band(bands, -INFINITY);  // a single band's lengths (volumes that follow the segment)
        const double scale = spectral_.path().batch_scale();
        // One search at both radii along `searched` for the bands of `of_bands` (their segment
        // j's lengths, none: -inf), added to their sums with their segments' weights.
        auto add_nested = [&](const Ray& searched, std::span<const double> of_bands, std::size_t j) {
            std::fill(outer.begin(), outer.end(), 0.0);
            std::fill(inner.begin(), inner.end(), 0.0);
            const auto [outer_photons, inner_photons] =
                spectral_.path().accumulate_nested(searched, of_bands, Radius(radii_.core_radius), outer, inner);
            for (std::size_t k = 0; k < bands; ++k) {
                if (!(of_bands[k] > 0.0)) continue;
                const double w = segments[k][j].weight * scale;
                auto to_spectral = at_spectral[k].per_batch(), to_core = at_core[k].per_batch();
                for (unsigned b = 0; b < batches; ++b) {
                    to_spectral[b] += w * outer[k * batches + b];
                    to_core[b] += w * inner[k * batches + b];
                }
            }
            at_spectral[0].count_photons(outer_photons);
            at_core[0].count_photons(inner_photons);
        };
        for (std::size_t j = 0; j < segments[0].size(); ++j) {
            const Ray& shared = segments[0][j].ray;
            double longest = 0.0;
            for (std::size_t k = 0; k < bands; ++k) {
                const Ray& own = segments[k][j].ray;
                require(own.origin == shared.origin && own.direction == shared.direction,
                        "path segment", j, "of band " + std::to_string(k) + " differs from band 0's in origin or direction");
                lengths[k] = own.t_max > 0.0 ? own.t_max : -INFINITY;  // (none: as add(), no photons)
                longest = std::max(longest, own.t_max);
            }
            if (!(longest > 0.0)) continue;
            if constexpr (Volume::cut_from_longer_search) {  // every band's segment from the longest one's search
                add_nested(Ray{shared.origin, shared.direction, longest}, lengths, j);
            } else {  // one search per band, for both radii
                for (std::size_t k = 0; k < bands; ++k) {
                    if (!(lengths[k] > 0.0)) continue;
                    one_band[k] = lengths[k];
                    add_nested(segments[k][j].ray, one_band, j);
                    one_band[k] = -INFINITY;
                }
            }
        }
    }

    static SpectralCompensation checked(const PhotonMap<Store>& map, SpectralCompensation radii) {
        require(map.bands() >= 2, "bands", map.bands(),
                "must be >= 2: spectral compensation (manual 3.5.2) shares one core search among a spectral map's bands");
        const double core = radii.core_radius, spectral = radii.spectral_radius;
        require(std::isfinite(core) && core > 0.0, "core radius (m)", core, "must be finite and > 0");
        require(std::isfinite(spectral) && spectral > 0.0, "spectral radius (m)", spectral, "must be finite and > 0");
        std::string why = "must be >= the core radius (";
        why += std::to_string(core);
        why += " m): the expanded search contains the core one (manual 3.5.2.2)";
        require(spectral >= core, "spectral radius (m)", spectral, why);
        std::string half = "must be < half the section width (W = ";
        half += std::to_string(map.section_width());
        half += " m)";
        require(spectral < 0.5 * map.section_width(), "spectral radius (m)", spectral, half);
        return radii;
    }

    SpectralCompensation radii_;  ///< first: checked before the estimators are built
    RadianceEstimator<Store, Volume, Optics> core_;
    RadianceEstimator<Store, Volume, Optics> spectral_;
};

}  // namespace secchi
