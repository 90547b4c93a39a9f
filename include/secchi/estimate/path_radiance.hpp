#pragma once
// In-scattered radiance along a ray from the photon map (the second pass, manual 3.4-3.5):
//   L(r_a) = sum over collected photons of Phi(z) * pbar_omega(psi) * w_i * exp(-c' t)  (eq. 3.18 / 3.22)
// where Phi(z) is the flux of a record stored at depth z (the map's own normalisation,
// transport/record_flux.hpp: Phi, or Phi / I(z) under depth importance), pbar_omega the phase
// function averaged over the collection solid angle omega around the scattering direction
// (eq. 3.5), w_i the collection volume's length/volume weight, and t the photon's distance
// along the ray from the ray's start (the attenuation to the ray's end point, where the
// radiance is wanted). c' = c - b f is the ray's attenuation when the phase function's peak
// within the cone (a share f of the scattering) is transmitted along the ray rather than
// collected (optics/phase/cone_average.hpp); c where it is averaged.
// Photons are stored at scattering events, so the map density is b E_o: no extra factor b.
// In stratified water pbar_omega is the mixture at the photon's depth (eq. 5.5) and exp(-c' t)
// becomes exp(-int c' dt) along the ray: the RayOptics policy supplies both.
// Standard error: each photon belongs to one of B batches; each batch alone is an estimate
// with flux B * Phi per photon.
// The map's photons lie in the section [0, W)^2 of a horizontally periodic water body: any ray
// (any origin, direction and length, crossing the seams any number of times) collects from
// the section's photons and their periodic images, t being the distance along the unwrapped
// ray (the volumes' periodic gather, estimate/periodic_ray.hpp). The collection radius must be
// < W/2.
//
// Vertical rays (every nadir or zenith ray, e.g. nadir_ray_grid's) through a map of records
// whose direction stores its polar angle as a byte (CompactRecord): there cos psi depends on
// that byte alone, so the optics may tabulate their angular part for the 256 possible
// values of cos psi and look it up per photon, skipping the direction decode, the dot product
// and the phase function's interpolation. The values are the same on every ray of one
// direction (+z or -z): the estimator builds the two directions' tables once, when it is
// constructed (a few microseconds), and every estimate() and accumulate() call looks them up.
// (Built per accumulate() call, they would make a short ray of ~60 photons 4 times as slow:
// docs/design-notes.md.) The result is bit-identical to the per-photon formula
// (see detail::vertical_cosines for why); optics without the tabulated form, other records and other rays take the per-photon formula.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/estimate/collection.hpp"
#include "secchi/estimate/periodic_ray.hpp"
#include "secchi/map/photon_map.hpp"
#include "secchi/map/record.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/chord_table.hpp"
#include "secchi/transport/record_flux.hpp"
#include "secchi/core/parallel.hpp"
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <ranges>
#include <span>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

struct RadianceEstimate {
    Estimate radiance;
    std::uint64_t photons_touched = 0;  ///< collected photons over all rays
    std::size_t rays = 0;
};

/// The water's part of eq. 3.18 for one photon: in_scatter(z, cos_psi, ray, t) =
/// pbar_omega(psi) at the photon's depth z times the ray's transmittance from its start over t,
/// transmittance(ray, t), which also carries light from where the ray ends (a bottom).
template <class O>
concept RayOptics = requires(const O o, double z, double cos_psi, Ray ray, double t) {
    { o.in_scatter(z, cos_psi, ray, t) } -> std::convertible_to<double>;
    { o.transmittance(ray, t) } -> std::convertible_to<double>;
};

/// How far along `ray` the light beyond adds at most a share `threshold` of its own: the distance
/// t at which the optics' transmittance from the ray's start falls to `threshold` (bisection on
/// the monotone transmittance, to 1e-9 relative), or ray.t_max if it is reached first.
template <RayOptics Optics>
double length_to_transmittance(const Optics& optics, const Ray& ray, double threshold) {
    require(threshold > 0.0 && threshold < 1.0, "ray transmittance", threshold, "must lie in (0, 1)");
    const auto beyond = [&](double t) { return optics.transmittance(ray, t) <= threshold; };
    double hi = 1.0;
    while (!beyond(hi) && hi < ray.t_max) {
        hi *= 2.0;
        require(hi < 1e7, "ray transmittance", threshold, "is not reached within 1e7 m: the water is too clear");
    }
    if (!beyond(hi)) return ray.t_max;
    double lo = 0.0;
    for (int i = 0; i < 60 && hi - lo > 1e-9 * hi; ++i) (beyond(0.5 * (lo + hi)) ? hi : lo) = 0.5 * (lo + hi);
    return std::min(hi, ray.t_max);
}

/// cos psi for each of the 256 values of a record's polar code, along one ray.
using CodedCosines = std::array<double, 256>;

/// Optics that can fix their angular part for one ray along which cos psi takes only the 256
/// values cos_psi[k]: o.for_cosines(cos_psi) returns an object f (held for the ray) with
///   f.in_scatter(z, k, ray, t) == o.in_scatter(z, cos_psi[k], ray, t)   bit for bit,
/// for every code k and every z, ray, t. Optional: RayOptics without it stay on the per-photon path.
template <class O>
concept CodedRayOptics = RayOptics<O> && requires(const O o, const CodedCosines& cos_psi, double z,
                                                  std::uint8_t k, Ray ray, double t) {
    { o.for_cosines(cos_psi).in_scatter(z, k, ray, t) } -> std::convertible_to<double>;
};

namespace detail {
/// The coded optics of the two vertical directions (+z, -z) for optics O with the tabulated
/// form (Coded: CodedRayOptics and compact records), else nothing.
template <class O, bool Coded>
struct VerticalTablesOf {
    using type = std::nullptr_t;
};
template <class O>
struct VerticalTablesOf<O, true> {
    using type = std::array<decltype(std::declval<const O&>().for_cosines(std::declval<const CodedCosines&>())), 2>;
};

/// cos psi = -dot(d, u) of a photon of polar code k on a vertical ray u = (0, 0, uz), uz = +-1,
/// for each k: -(cos_theta_k uz). It equals the per-photon formula bit for bit, whatever the
/// photon's azimuth: GLM's dot for dvec3 is (dx ux + dy uy) + dz uz. With ux, uy = +-0 and
/// dx, dy finite, dx ux and dy uy are zeros (of either sign) and so is their sum; dz uz = +-dz
/// is exact and nonzero (|cos_theta_k| >= sin(pi/512) for the bin centres), and a zero added
/// to a nonzero number gives that number exactly. Negation is exact. (Were the compiler to
/// contract the dot into fused multiply-adds, fma(dy, uy, zero) is a zero and fma(dz, uz, zero)
/// = dz uz exactly: the same.)
template <PolarCodedRecord R>
CodedCosines vertical_cosines(double uz) {
    CodedCosines cos_psi{};
    for (std::size_t k = 0; k < cos_psi.size(); ++k)
        cos_psi[k] = -(PolarCode<R>::cosine(static_cast<std::uint8_t>(k)) * uz);
    return cos_psi;
}
}  // namespace detail

/// Homogeneous water: one cone-averaged phase function and exp(-c' t), c' = c - b f with f
/// the share of the scattering the cone transmits (its transmitted_fraction(); 0 when the
/// peak is averaged). The phase function is looked up in a ChordTable (no acos per photon;
/// optics/phase/chord_table.hpp).
struct HomogeneousRayOptics {
    /// cone: a ConeAveragedPhase (or anything with eval(cos_psi) and transmitted_fraction());
    /// c, b: the water's attenuation and scattering coefficients (1/m).
    template <class ConePhase>
    HomogeneousRayOptics(const ConePhase& cone, double c, double b)
        : phase(cone), attenuation(c - b * cone.transmitted_fraction()) {
        require(std::isfinite(c) && std::isfinite(b) && b >= 0.0 && b <= c, "scattering coefficient b (1/m)", b,
                "must lie in [0, c] (c = " + std::to_string(c) + ")");
    }
    ChordTable phase;
    double attenuation;  ///< c' (1/m): the ray's attenuation
    [[nodiscard]] double in_scatter(double z, double cos_psi, const Ray& ray, double t) const {
        return along_path(phase.eval(cos_psi), z, ray, t);
    }
    /// The phase value p times the rest of eq. 3.18: the transmittance exp(-c' t). (The one
    /// place of that product: for_cosines' lookups stay bit-identical to in_scatter.)
    [[nodiscard]] double along_path(double p, double, const Ray& ray, double t) const {
        return p * transmittance(ray, t);
    }
    [[nodiscard]] double transmittance(const Ray&, double t) const { return exp_table(-attenuation * t); }

    /// For one ray with only 256 values of cos psi (CodedRayOptics): the phase function at each.
    struct Coded {
        const HomogeneousRayOptics& optics;
        CodedCosines phase;  ///< phase.eval(cos_psi[k])
        [[nodiscard]] double in_scatter(double z, std::uint8_t k, const Ray& ray, double t) const {
            return optics.along_path(phase[k], z, ray, t);
        }
#if SECCHI_HAS_LANES
        /// in_scatter for lanes::lane_width photons at once: out[l] for code[l] and t[l] (z
        /// and the ray do not enter), the same values, with the transmittances through
        /// lanes::exp (core/lanes.hpp). `out` is vector-aligned.
        void in_scatter_lanes(const std::uint8_t* code, const double* t, double* out) const {
            using lanes::Reals;
            const Reals x = -optics.attenuation * Reals(t, lanes::stdx::element_aligned);  // as along_path
            if (!all_of(x > -708.0 && x < 709.0)) {  // exp_table's special values
                for (int l = 0; l < lanes::lane_width; ++l) out[l] = in_scatter(0.0, code[l], Ray{}, t[l]);
                return;
            }
            alignas(64) double p[lanes::lane_width];
            for (int l = 0; l < lanes::lane_width; ++l) p[l] = phase[code[l]];
            (Reals(p, lanes::aligned) * lanes::exp(x)).copy_to(out, lanes::aligned);
        }
#endif
    };
    [[nodiscard]] Coded for_cosines(const CodedCosines& cos_psi) const {
        Coded out{*this, {}};
        for (std::size_t k = 0; k < cos_psi.size(); ++k) out.phase[k] = phase.eval(cos_psi[k]);
        return out;
    }
};

/// Depth-varying water (a StratifiedWater): the components' cone-averaged phase functions
/// weighted by b_i(z) / b(z) (eq. 5.5-5.6), and exp(-int c' dt) along the ray, with
/// c'(z) = c(z) - sum_i b_i(z) f_i (f_i: the share of component i's scattering its cone transmits).
template <class Water>
struct StratifiedRayOptics {
    /// cones: one cone-averaged phase function per scattering component, in order (as many as
    /// the water has, where it says: water.components()): a std::vector of one cone type, or a
    /// std::tuple of one cone per component (e.g. water.transform_phases of a typed water).
    template <class Cones>
    StratifiedRayOptics(const Water& water_, const Cones& cones) : water(water_) {
        const std::size_t n = count_of(cones);
        if constexpr (requires { water_.components(); })
            require(n == water_.components(), "cones", n,
                    "needs one cone-averaged phase function per scattering component of the water");
        if constexpr (max_components > 0)
            require(n <= max_components, "cones", n, "exceeds the water's max_components");
        phases.reserve(n);
        for_each_cone(cones, [&](const auto& cone) {
            phases.emplace_back(cone);
            transmitted.push_back(cone.transmitted_fraction());
        });
    }
    /// The optics refer to the water: a temporary one would be gone before the first query.
    template <class Cones>
    StratifiedRayOptics(const Water&&, const Cones&) = delete;
    const Water& water;
    std::vector<ChordTable> phases;
    std::vector<double> transmitted;  ///< f_i of each component's cone
    [[nodiscard]] double in_scatter(double z, double cos_psi, const Ray& ray, double t) const {
        return along_path(water.mixture(z, [&](std::size_t i) { return phases[i].eval(cos_psi); }), z, ray, t);
    }
    /// The mixture's phase value p at depth z times the rest of eq. 3.18: the ray's
    /// transmittance over its first t metres. (The one place of that product: for_cosines'
    /// lookups stay bit-identical to in_scatter.)
    [[nodiscard]] double along_path(double p, double, const Ray& ray, double t) const {
        return p * transmittance(ray, t);
    }
    /// exp(-int_0^t c' dt') along the ray.
    [[nodiscard]] double transmittance(const Ray& ray, double t) const {
        double tau = water.optical_path(Coefficient::attenuation, ray.origin.z, ray.direction.z, t);
        for (std::size_t i = 0; i < transmitted.size(); ++i)
            if (transmitted[i] > 0.0)
                tau -= transmitted[i] * water.component_optical_path(i, ray.origin.z, ray.direction.z, t);
        return exp_table(-tau);
    }

    /// A tuple's cones one by one, or a range's.
    template <class Cones>
    static constexpr bool is_tuple = requires { std::tuple_size<Cones>::value; };
    template <class Cones>
    static std::size_t count_of(const Cones& cones) {
        if constexpr (is_tuple<Cones>) return std::tuple_size_v<Cones>;
        else return std::size(cones);
    }
    template <class Cones, class F>
    static void for_each_cone(const Cones& cones, F&& f) {
        if constexpr (is_tuple<Cones>) std::apply([&](const auto&... c) { (f(c), ...); }, cones);
        else for (const auto& c : cones) f(c);
    }

    /// Up to this many components can be tabulated per ray (for_cosines); 0: none.
    static constexpr std::size_t max_components = [] {
        if constexpr (requires { Water::max_components; }) return std::size_t{Water::max_components};
        else return std::size_t{0};
    }();

    /// For one ray with only 256 values of cos psi (CodedRayOptics): each component's phase
    /// function at each; the mixture weights b_i(z) / b(z) stay per photon, as does the path.
    struct Coded {
        const StratifiedRayOptics& optics;
        /// phase[k * n + i] = phases[i].eval(cos_psi[k]), n = phases.size(): one code's values together.
        std::array<double, 256 * max_components> phase;
        [[nodiscard]] double in_scatter(double z, std::uint8_t k, const Ray& ray, double t) const {
            const double* pk = phase.data() + k * optics.phases.size();
            return optics.along_path(optics.water.mixture(z, [&](std::size_t i) { return pk[i]; }), z, ray, t);
        }
    };
    [[nodiscard]] Coded for_cosines(const CodedCosines& cos_psi) const
        requires(max_components > 0)
    {
        const std::size_t n = phases.size();  // <= max_components: the water's components (constructor)
        Coded out{*this, {}};
        for (std::size_t k = 0; k < cos_psi.size(); ++k)
            for (std::size_t i = 0; i < n; ++i) out.phase[k * n + i] = phases[i].eval(cos_psi[k]);
        return out;
    }
};

template <class Store, CollectionVolume Volume, RayOptics Optics>
class PathRadianceEstimator {
public:
    /// map: the photons and their normalisation, batches and periodic section
    /// (map/photon_map.hpp); optics: the water's, for every band; the collection radius must be
    /// < half the section width.
    PathRadianceEstimator(const PhotonMap<Store>& map, Volume volume, Optics optics, Radius radius)
        : PathRadianceEstimator(map, std::move(volume), std::vector<Optics>(map.bands(), optics), radius) {}
    /// The same with each band's own optics (the water's IOPs at each band's wavelength), in
    /// the map's band order.
    PathRadianceEstimator(const PhotonMap<Store>& map, Volume volume, std::vector<Optics> per_band, Radius radius)
        : map_(map), volume_(std::move(volume)), optics_(std::make_shared<const std::vector<Optics>>(std::move(per_band))),
          tables_(vertical_tables()), radius_(radius), section_(map.section_width()) {
        require(optics_->size() == map.bands(), "optics per band", optics_->size(),
                "must be one per band of the map (" + std::to_string(map.bands()) + ")");
        section_.require_radius(radius.value());
    }
    /// A temporary map would be gone before the estimator's first query.
    PathRadianceEstimator(const PhotonMap<Store>&&, Volume, Optics, Radius) = delete;
    PathRadianceEstimator(const PhotonMap<Store>&&, Volume, std::vector<Optics>, Radius) = delete;

    static constexpr unsigned max_batches = 256;  ///< as TransportSettings allows

    /// Adds the per-batch photon sums of one ray (light arriving at ray.origin travelling
    /// opposite to ray.direction) in band `band` to batch_sums (at least the map's batches
    /// entries); returns the photons touched. A batch's sum times batch_scale() is that
    /// batch's estimate of the ray's path radiance.
    std::uint64_t accumulate(const Ray& ray, std::span<double> batch_sums, unsigned band = 0) const {
        require(batch_sums.size() >= map_.batches(), "batch_sums size", batch_sums.size(),
                "must hold one sum per batch (the map's batches)");
        require(band < map_.bands(), "band", band, "is not among the map's bands (" + std::to_string(map_.bands()) + ")");
        return accumulate_ray(ray, batch_sums, band);
    }

    /// accumulate() for every band at once and at two radii, from one search (the spectral
    /// compensation's reuse of its core search, manual 3.5.2.3): along `ray`, band k's photons
    /// over its own segment, the prefix of length lengths[k] (-inf: none; ray.t_max the
    /// longest), add to outer_sums[k * batches + batch] as accumulate() at this
    /// estimator's radius would over that segment, and those inside the inner volume of radius
    /// `inner` (<= the radius) to inner_sums likewise, as an estimator of radius `inner` would
    /// (the same photons, values and weights; the sums in the outer search's order). A volume
    /// whose segments are not cuts of a longer search (Volume::cut_from_longer_search false:
    /// the step spheres) takes segments of the ray's whole length only. Returns the photons
    /// added to outer_sums and to inner_sums.
    std::pair<std::uint64_t, std::uint64_t> accumulate_nested(const Ray& ray, std::span<const double> lengths, Radius inner,
                                                               std::span<double> outer_sums, std::span<double> inner_sums) const
        requires NestedCollectionVolume<Volume>
    {
        const unsigned batches = map_.batches();
        require(lengths.size() == map_.bands() && outer_sums.size() >= lengths.size() * batches &&
                    inner_sums.size() >= lengths.size() * batches,
                "bands of the nested sums", lengths.size(), "must be the map's bands, each with its batches");
        require_within_map(ray);
        for (const double length : lengths) {  // (a band's photons beyond the search would be missed)
            require(!(length > ray.t_max), "band segment length (m)", length,
                    "must not exceed the searched ray's length (" + std::to_string(ray.t_max) + " m)");
            if constexpr (!Volume::cut_from_longer_search)
                require(!(length > 0.0) || length == ray.t_max, "band segment length (m)", length,
                        "must be the searched ray's length (" + std::to_string(ray.t_max) + " m) or none: " + volume_.name() +
                            " follows the segment's length, so a shorter segment's photons are not among its search's");
        }
        std::pair<std::uint64_t, std::uint64_t> touched{0, 0};
        const auto& records = map_.store().records();
        volume_.gather_nested(map_.store(), ray, radius_, inner, section_,
                              [&](std::uint32_t index, double t, double w_outer, double w_inner) {
                                  const auto& rec = records[index];
                                  const unsigned band = rec.band();
                                  if constexpr (Volume::cut_from_longer_search) {
                                      if (!(t <= lengths[band])) return;
                                  } else if (!(lengths[band] > 0.0)) {
                                      return;
                                  }
                                  const double value = photon_in_scatter(optics(band), rec, ray, t);
                                  const std::size_t slot = std::size_t{band} * batches + rec.batch();
                                  outer_sums[slot] += photon_weight(rec, w_outer) * value;
                                  ++touched.first;
                                  if (w_inner == 0.0) return;
                                  inner_sums[slot] += photon_weight(rec, w_inner) * value;
                                  ++touched.second;
                              });
        return touched;
    }

    /// The flux of a record (at importance 1) times the batches: a batch's photon sum times
    /// this is that batch's estimate (each batch alone stands for all the photons).
    [[nodiscard]] double batch_scale() const { return map_.flux().per_record * map_.batches(); }
    [[nodiscard]] const PhotonMap<Store>& map() const { return map_; }
    [[nodiscard]] const Optics& optics(unsigned band = 0) const { return (*optics_)[band]; }
    [[nodiscard]] Radius radius() const { return radius_; }

    /// Radiance averaged over a set of rays (e.g. a grid of parallel rays in a horizontally
    /// homogeneous water body) in the map's first band, with its batch standard error. Rays run in parallel; the
    /// sums are merged in ray order (bit-identical for any thread count).
    RadianceEstimate estimate(const std::vector<Ray>& rays, unsigned threads) const {
        std::vector<std::vector<double>> per_ray(rays.size(), std::vector<double>(map_.batches(), 0.0));
        std::vector<std::uint64_t> touched(rays.size(), 0);
        parallel_for(rays.size(), threads, [&](std::size_t i) {
            // Sums on this thread's stack, copied out once: the rays' own vectors may share
            // a cache line with a neighbour's that another thread is adding to.
            std::array<double, max_batches> sums{};
            touched[i] = accumulate_ray(rays[i], std::span(sums.data(), map_.batches()), 0);
            std::copy_n(sums.begin(), map_.batches(), per_ray[i].begin());
        });
        std::vector<double> batch(map_.batches(), 0.0);
        RadianceEstimate out;
        for (std::size_t i = 0; i < rays.size(); ++i) {
            for (unsigned b = 0; b < map_.batches(); ++b) batch[b] += per_ray[i][b];
            out.photons_touched += touched[i];
        }
        const double scale = batch_scale() / static_cast<double>(rays.size());
        for (double& v : batch) v *= scale;
        out.radiance = batch_estimate(batch);
        out.rays = rays.size();
        return out;
    }

private:
    using Record = typename PhotonMap<Store>::Record;
    /// What the store's records() returns: a reference to its vector, or a range of values.
    using StoreRecords = decltype(std::declval<const Store&>().records());

    /// Whether vertical rays take the coded path: records with a polar code, optics that
    /// tabulate their angular part.
    static constexpr bool coded_rays = PolarCodedRecord<Record> && CodedRayOptics<Optics>;

    /// The coded optics of the two vertical directions, [0] for +z and [1] for -z (coded_rays;
    /// else nothing). cos psi takes the same 256 values on every ray of one direction
    /// (vertical_cosines), so one table serves them all (a table costs a few microseconds: 256
    /// phase lookups scattered over the phase table). They refer to the optics of band 0, which
    /// they share; they serve maps of one band (several: the per-photon path, which picks the band).
    using VerticalTables = typename detail::VerticalTablesOf<Optics, coded_rays>::type;
    [[nodiscard]] std::shared_ptr<const VerticalTables> vertical_tables() const {
        if constexpr (coded_rays)
            return std::make_shared<const VerticalTables>(
                VerticalTables{optics_->front().for_cosines(detail::vertical_cosines<Record>(1.0)),
                               optics_->front().for_cosines(detail::vertical_cosines<Record>(-1.0))});
        else
            return nullptr;
    }

    /// Refuses a ray of no finite length, or whose collection volume reaches below the depth
    /// the map stored events to: its estimate would miss photons.
    void require_within_map(const Ray& ray) const {
        require(std::isfinite(ray.t_max) && ray.t_max >= 0.0, "ray length (m)", ray.t_max, "must be finite and >= 0");
        const double deepest = std::max(ray.origin.z, ray.origin.z + ray.t_max * ray.direction.z) +
                               radius_.value() * sin_from_cos(ray.direction.z);
        if (deepest > map_.flux().stored_to_depth)
            reject("ray depth (m)", deepest,
                   "lies below the depth the photon map stored events to (" + std::to_string(map_.flux().stored_to_depth) +
                       " m): trace with a deeper TransportSettings::map_depth");
    }

    /// accumulate() for one ray: the coded sum on a vertical ray (with coded_rays, in a map of
    /// one band), else the per-photon one (require_within_map first).
    std::uint64_t accumulate_ray(const Ray& ray, std::span<double> batch_sums, unsigned band) const {
        require_within_map(ray);
        if constexpr (coded_rays)
            if (is_vertical(ray) && map_.bands() == 1) return accumulate_coded(ray, batch_sums, (*tables_)[ray.direction.z > 0.0 ? 0 : 1]);
        const Optics& band_optics = optics(band);
        return sum_photons(ray, batch_sums, band, [&](const Record& rec, double t) { return photon_in_scatter(band_optics, rec, ray, t); });
    }

    /// The water's part of eq. 3.18 (`optics`: the record's band's) for a photon at distance t along the ray.
    static double photon_in_scatter(const Optics& optics, const Record& rec, const Ray& ray, double t) {
        const double cos_psi = -glm::dot(rec.direction(), ray.direction);
        return optics.in_scatter(rec.position().z, cos_psi, ray, t);
    }

    /// A photon's weight in the sums: the collection volume's, times the record's relative flux
    /// where the map's is not uniform.
    [[nodiscard]] double photon_weight(const Record& rec, double volume_weight) const {
        return map_.flux().is_uniform() ? volume_weight : volume_weight * relative_flux(rec);
    }

    /// The flux of a record relative to the map's per_record (1 / (I(z) D(mu)), record_flux.hpp).
    [[nodiscard]] double relative_flux(const Record& rec) const {
        const RecordFlux& f = map_.flux();
        return f.is_uniform() ? 1.0 : f.at(rec.position().z, rec.direction().z) / f.per_record;
    }

    /// The same sum on a vertical ray: cos psi from the photon's polar code through the table
    /// of the ray's direction (vertical_cosines; bit-identical to the per-photon formula).
    template <class Coded>
    std::uint64_t accumulate_coded(const Ray& ray, std::span<double> batch_sums, const Coded& coded) const {
#if SECCHI_HAS_LANES
        if constexpr (requires(const std::uint8_t* k, const double* t, double* out) { coded.in_scatter_lanes(k, t, out); }) {
            if (map_.flux().is_uniform()) {
                CodedRuns<Coded> sum{map_.store().records(), coded, ray, batch_sums};
                volume_.gather(map_.store(), ray, radius_, section_, sum);
                return sum.touched;
            }
        }
#endif
        return sum_photons(ray, batch_sums, 0, [&](const Record& rec, double t) {
            return coded.in_scatter(rec.position().z, PolarCode<Record>::of(rec), ray, t);
        });
    }

#if SECCHI_HAS_LANES
    /// accumulate_coded's visitor where the coded optics compute lanes of photons at once
    /// (in_scatter_lanes): a run of photons from the collection volume (ChunkVisitor) goes
    /// through lanes::lane_width photons at a time, each group's values added to the batch
    /// sums in order: the same sums, bit for bit, as one photon at a time. Each group reads
    /// its records once, for the code and the batch (1.06-1.12 times the grid's estimate rate
    /// against codes for 64 photons, then their values, then their sums: docs/design-notes.md).
    template <class Coded>
    struct CodedRuns {
        StoreRecords records;
        const Coded& coded;
        const Ray& ray;
        std::span<double> batch_sums;
        std::uint64_t touched = 0;

        void operator()(std::uint32_t index, double t, double weight) {
            const auto& rec = records[index];
            batch_sums[rec.batch()] += weight * coded.in_scatter(rec.position().z, PolarCode<Record>::of(rec), ray, t);
            ++touched;
        }
        void photons(std::uint32_t base, const std::uint32_t* offset, const double* t, std::uint32_t n, double weight) {
            constexpr std::uint32_t width = lanes::lane_width;
            std::uint32_t k = 0;
            for (; k + width <= n; k += width) {
                std::uint8_t code[width], batch[width];
                alignas(64) double value[width];
                for (std::uint32_t l = 0; l < width; ++l) {
                    const auto& rec = records[base + offset[k + l]];
                    code[l] = PolarCode<Record>::of(rec);
                    batch[l] = rec.batch();
                }
                coded.in_scatter_lanes(code, t + k, value);
                for (std::uint32_t l = 0; l < width; ++l) batch_sums[batch[l]] += weight * value[l];
            }
            touched += k;
            for (; k < n; ++k) (*this)(base + offset[k], t[k], weight);  // counts its own
        }
    };
#endif

    /// batch_sums[batch] += weight * in_scatter(record, t) (times the record's relative flux)
    /// over the photons of band `band` the volume collects.
    template <class InScatter>
    std::uint64_t sum_photons(const Ray& ray, std::span<double> batch_sums, unsigned band, InScatter&& in_scatter) const {
        std::uint64_t touched = 0;
        const auto& records = map_.store().records();
        const bool one_band = map_.bands() == 1;
        volume_.gather(map_.store(), ray, radius_, section_, [&](std::uint32_t index, double t, double weight) {
            const auto& rec = records[index];
            if (!one_band && rec.band() != band) return;
            batch_sums[rec.batch()] += photon_weight(rec, weight) * in_scatter(rec, t);
            ++touched;
        });
        return touched;
    }

    const PhotonMap<Store>& map_;
    Volume volume_;
    /// On the heap, so that the tables' references to it hold in every copy of the estimator.
    std::shared_ptr<const std::vector<Optics>> optics_;
    std::shared_ptr<const VerticalTables> tables_;  ///< vertical_tables(), built once
    Radius radius_;
    PeriodicSection section_;
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
