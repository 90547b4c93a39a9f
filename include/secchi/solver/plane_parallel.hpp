#pragma once
// A plane-parallel problem end to end (the canonical problems' set-up, M93 section 3):
// homogeneous water of attenuation c and albedo w0 (problems 1, 2, 4, 5, 6), or depth-varying
// water (problem 3, solve_stratified), under a light source (a collimated sun and a black or
// uniform sky at the surface, a parametric sky, or a traced atmosphere above the surface:
// problem 4; scene/source.hpp), a flat or wind-blown surface (problem 5), optional bottom. First pass: photons traced, irradiance
// detectors tallied, the map stored. Second pass: the map built into the chosen store and nadir radiance Lu
// estimated at each depth from a grid of vertical rays with the store's collection volume
// (k-d tree: spheres at n steps; VOI octree: the cylinder). Every output carries its SE.
//
// Shards (PlaneParallelConfig::shards = S): the map's batches are split into S equal, contiguous
// ranges, each range's records (in their first-pass order) built into a map of its own; batch
// k's per-batch Lu sum (estimate/radiance.hpp's RadianceSum) is taken from the one shard holding
// it, and the terms not drawn from photons (sky, bottom) from shard 0. S = 1 is the single map.
// A shard's map visits its photons in the same order whichever process builds it, so the
// result depends on S but not on how the shards are spread over processes (PassSplit below;
// solver/mpi_plane_parallel.hpp): a seed and an S give the same bits for any number of ranks
// dividing S and any number of threads. Another S adds Lu's per-batch terms in another order
// (the last digits change; the irradiances do not). The cost: every ray queries S stores
// instead of one; measured, Lu with 4 shards took 0.87-0.96 times as long as with one map (VOI
// octree, 4 million records: the cost is per photon gathered; BENCHMARKS.md, "Distributed
// runs"). On one process, S > 1 copies the records into the shards before the full list is
// freed (twice the records' memory for a moment).
#include "secchi/core/config.hpp"
#include "secchi/estimate/radiance.hpp"
#include "secchi/map/brute_force.hpp"
#include "secchi/map/kdtree.hpp"
#if __has_include(<nanoflann.hpp>)  // the optional nanoflann adaptor (CMake: secchi::nanoflann)
#include "secchi/map/nanoflann_store.hpp"
#define SECCHI_HAS_NANOFLANN 1
#endif
#include "secchi/map/store_names.hpp"
#include "secchi/transport/lane_tracer.hpp"
#include "secchi/map/voi_grid.hpp"
#include "secchi/map/voi_octree.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/optics/stratified_water.hpp"
#include "secchi/optics/phase/cone_average.hpp"
#include "secchi/scene/any_source.hpp"
#include "secchi/scene/any_surface.hpp"
#include "secchi/transport/tracer.hpp"
#include <algorithm>
#include <chrono>
#include <concepts>
#include <cstdint>
#include <deque>
#include <iomanip>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace secchi::SECCHI_ISA {

/// Which first pass traces the photons: PhotonTracer, or LaneTracer (photons in SIMD lanes;
/// depth importance with weighted photons only; the same estimates, faster
/// where the target has wide vectors) in lanes of doubles ("lanes") or of floats ("lanes-float": twice the
/// lanes, the photons' state rounded to float between events).
enum class TracerKind { photon, lanes, float_lanes };

/// The --tracer names (core/names.hpp), in the order the usage texts list them.
inline const std::vector<NamedValue<TracerKind>>& tracer_names() {
    static const std::vector<NamedValue<TracerKind>> names{
        {{"photon", {}, "PhotonTracer, one photon at a time"}, TracerKind::photon},
        {{"lanes", {}, "LaneTracer, photons in SIMD lanes of doubles"}, TracerKind::lanes},
        {{"lanes-float", {}, "LaneTracer in lanes of floats, twice as many per vector"}, TracerKind::float_lanes},
    };
    return names;
}

inline TracerKind parse_tracer(const std::string& s) { return parse_named(tracer_names(), "tracer", s); }

/// The light source of a plane-parallel problem (scene/source.hpp): a collimated sun (E_perp = 1)
/// and a uniform sky at the surface, a parametric sky (sun disk and Harrison-Coombes sky) at
/// the surface, or a traced atmosphere above it (E_perp = 1 at its top).
enum class SourceKind { sun_and_sky, parametric_sky, atmosphere };

/// The --source names (core/names.hpp), in the order the usage texts list them.
inline const std::vector<NamedValue<SourceKind>>& source_names() {
    static const std::vector<NamedValue<SourceKind>> names{
        {{"sun", {}, "a collimated sun, E_perp = 1, and a uniform sky at the surface"}, SourceKind::sun_and_sky},
        {{"parametric-sky", {}, "a 0.53 deg sun disk and Harrison and Coombes' clear sky at the surface"},
         SourceKind::parametric_sky},
        {{"atmosphere", {}, "a traced plane-parallel atmosphere, E_perp = 1 at its top"}, SourceKind::atmosphere},
    };
    return names;
}

inline SourceKind parse_source(const std::string& s) { return parse_named(source_names(), "source", s); }

struct PlaneParallelConfig {
    double attenuation = 1.0;      ///< c (1/m); depths are in metres, so tau = c z
    double albedo = 0.9;           ///< w0 = b / c
    double sun_zenith_deg = 60.0;
    double sky_irradiance = 0.0;   ///< a uniform sky's plane irradiance beside the sun's E_perp = 1 (0: black)
    SourceKind source = SourceKind::sun_and_sky;
    ParametricSkySpec parametric_sky;  ///< with SourceKind::parametric_sky (its sun zenith: sun_zenith_deg)
    AtmosphereSpec atmosphere;         ///< with SourceKind::atmosphere (its sun zenith: sun_zenith_deg)
    /// The refractive index of water at the surface (1.0 = no interface). Unset: the medium's
    /// own (a material's REFRACTIVE_INDEX_MODEL at the run's wavelength), or M93's 1.34 where
    /// the medium has none; set, it overrides the medium's.
    std::optional<double> water_index;
    FacetSlopes slopes;            ///< a wind-blown surface's facet slopes (scene/wind_blown_surface.hpp); all 0: flat
    FacetSampling facets = FacetSampling::projected_area;  ///< how a wind-blown surface's facets are met
    Shadowing shadowing = Shadowing::none;                ///< whether its waves hide the light leaving it
    Bottom bottom;                 ///< depth in metres
    TransportSettings transport;   ///< photons, map photons, seed, threads, batches, depths, absorption
    StoreKind store = StoreKind::voi;
    double radius = 0.05;          ///< collection radius (m)
    unsigned steps = 64;           ///< k-d tree: spheres along each ray (eq. 3.18)
    double omega = 0.005;          ///< collection solid angle (sr), eq. 3.5
    ConePeak cone_peak = ConePeak::transmitted;  ///< the phase function's peak within the cone (cone_average.hpp)
    /// Lu integrates the path radiance along each ray down to where the ray's transmittance
    /// has fallen to this (the light beyond adds at most about this share), or to the bottom.
    double ray_transmittance = 1e-4;
    unsigned ray_grid = 10;        ///< K x K vertical rays per depth
    double section_width = 1.0;    ///< m, periodic horizontal section
    bool keep_map = false;         ///< return the stored records (for images)
    TracerKind tracer = TracerKind::photon;
    /// Maps the second pass builds, each from an equal, contiguous range of the batches
    /// (a divisor of transport.batches; see above). 1: one map.
    unsigned shards = 1;
    /// Depth importance chosen by the library where transport.importance is off: mu_i = 1 to
    /// the deepest detector when the water absorbs tau_a >= ln 2 down to it
    /// (default_depth_importance, transport/importance.hpp), with any tracer that splits the
    /// photons (LaneTracer only weighted ones: not with analog absorption). slab's default; off
    /// here, so that a caller's settings stand as given.
    bool auto_importance = false;
};

struct DepthResult {
    double depth = 0;
    std::array<Estimate, 4> irradiance{};  ///< Ed, Eu, Eod, Eou
    Estimate lu;                           ///< nadir radiance (upwelling)
    std::uint64_t photons_touched = 0;
};

struct PlaneParallelResult {
    std::string phase_name;
    PhaseMoments moments{};
    std::uint64_t photons_traced = 0, photons_stored = 0;
    double seconds = 0, seconds_transport = 0, seconds_build = 0, seconds_collect = 0;
    std::size_t store_bytes = 0;
    double flux_per_map_photon = 0;  ///< W nm^-1 per stored photon
    std::vector<DepthResult> depths;
    EnergyLedger ledger;
    Estimate bottom_ed;
    AboveSurface above;             ///< Ed(0+) direct and diffuse, Eu(0+), in the source's units
    double source_irradiance = 0;   ///< the plane irradiance the photons represent (the source's units)
    std::string source_name;
    std::vector<CompactRecord> map;  ///< only with keep_map
    DepthImportance importance;      ///< the depth importance the first pass used
    std::string importance_choice;   ///< how it was chosen (PlaneParallelConfig::auto_importance)
};

namespace detail {
inline double seconds_since(std::chrono::steady_clock::time_point t0) {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The light source cfg describes, its sun at cfg.sun_zenith_deg.
inline AnySource source_of(const PlaneParallelConfig& cfg) {
    switch (cfg.source) {
        case SourceKind::parametric_sky: {
            ParametricSkySpec spec = cfg.parametric_sky;
            spec.sun_zenith_deg = cfg.sun_zenith_deg;
            return ParametricSky(spec);
        }
        case SourceKind::atmosphere: {
            AtmosphereSpec spec = cfg.atmosphere;
            spec.sun_zenith_deg = cfg.sun_zenith_deg;
            return TracedAtmosphere(spec);
        }
        case SourceKind::sun_and_sky: break;
    }
    return SunAndSky(CollimatedSun(cfg.sun_zenith_deg), UniformSky(cfg.sky_irradiance));
}

/// One process runs the whole problem: the default PassSplit (see PassSplit).
struct SingleProcess {
    [[nodiscard]] unsigned rank() const { return 0; }
    [[nodiscard]] unsigned ranks() const { return 1; }
    template <class Record>
    void gather_tallies(FirstPassPart<Record>&) const {}
    [[nodiscard]] std::uint64_t total(std::uint64_t n) const { return n; }
    void gather_lu(std::vector<RadianceSum>&, unsigned, unsigned) const {}
};

/// The blocks of batches [first_batch, last_batch) (make_blocks lists them batch by batch).
inline BlockRange blocks_of_batches(const TransportSettings& s, unsigned first_batch, unsigned last_batch) {
    const auto blocks = make_blocks(s.photons, s.batches, s.block_size);
    auto at = [&](unsigned batch) {
        return static_cast<std::size_t>(std::ranges::lower_bound(blocks, batch, {}, &Block::batch) - blocks.begin());
    };
    return {at(first_batch), at(last_batch)};
}

/// The first pass by the tracer cfg.tracer names, through `surface`, from `source`: this
/// process's batches traced, the other processes' tallies gathered, merged in block order.
template <PhotonRecord Record, Medium M, AirWaterSurface Surface, class Split>
TransportResult<Record> first_pass_through(const M& medium, const Slab& slab, const Surface& surface,
                                           const AnySource& source, const PlaneParallelConfig& cfg, const Split& split) {
    const unsigned b = cfg.transport.batches;
    require(split.ranks() == 1 || !cfg.transport.surface_map, "surface map", "on",
            "is not gathered across processes (each keeps its own photons' arrivals): use one process");
    const BlockRange range = split.ranks() == 1 ? BlockRange{}
                                                : blocks_of_batches(cfg.transport, b * split.rank() / split.ranks(),
                                                                    b * (split.rank() + 1) / split.ranks());
    auto run = [&](const auto& tracer) {
        auto part = tracer.run_part(range);
        split.gather_tallies(part);
        return tracer.merge_part(std::move(part));
    };
#if SECCHI_HAS_LANES
    if (cfg.tracer == TracerKind::lanes)
        return run(LaneTracer<M, Record, double, Surface, AnySource>(medium, slab, surface, source, cfg.transport));
    if (cfg.tracer == TracerKind::float_lanes)
        return run(FloatLaneTracer<M, Record, Surface, AnySource>(medium, slab, surface, source, cfg.transport));
#endif
    require(cfg.tracer == TracerKind::photon, "tracer", cfg.tracer == TracerKind::lanes ? "lanes" : "lanes-float",
            "needs <experimental/simd> (LaneTracer), which this compiler lacks");
    return run(PhotonTracer<M, Record, Surface, AnySource>(medium, slab, surface, source, cfg.transport));
}

/// The surface's refractive index of water: cfg's override, else the medium's own, else 1.34.
template <Medium M>
double water_index_of(const M& medium, const PlaneParallelConfig& cfg) {
    if (cfg.water_index) return *cfg.water_index;
    if constexpr (requires { { medium.refractive_index() } -> std::convertible_to<std::optional<double>>; })
        if (const std::optional<double> n = medium.refractive_index()) return *n;
    return 1.34;
}

/// The surface cfg describes: flat (no slopes), or wind-blown.
inline AnySurface surface_of(double water_index, const PlaneParallelConfig& cfg) {
    if (cfg.slopes.flat()) return FlatSurface(water_index);
    return WindBlownSurface(cfg.slopes, water_index, cfg.facets, 1.0, cfg.shadowing);
}

/// The first pass through the surface cfg describes, held as an AnySurface (one dispatch per
/// photon at the surface), so that each tracer is compiled once for both kinds.
template <PhotonRecord Record, Medium M, class Split = SingleProcess>
TransportResult<Record> first_pass(const M& medium, const Slab& slab, const AnySource& source,
                                   const PlaneParallelConfig& cfg, const Split& split = {}) {
    return first_pass_through<Record>(medium, slab, surface_of(water_index_of(medium, cfg), cfg), source, cfg, split);
}

/// Eou at a depth on a Lambertian bottom: everything travelling up there has just left the
/// bottom with the same radiance A Ed / pi in every upward direction, so Eou = 2 pi A Ed / pi =
/// 2 Eu exactly, Eu being the flux the bottom's plane counts leaving it. (The plane's own
/// crossing estimate, the sum of w / |mu| over the light leaving the bottom, has the same mean
/// and a larger variance. M93's problem 6 checks Eou = Ed at its bottom, where A = 0.5.)
inline void eou_on_lambertian_bottom(const Bottom& bottom, std::vector<DepthResult>& depths) {
    if (bottom.kind() != BottomKind::lambertian) return;
    for (auto& d : depths)
        if (d.depth >= bottom.depth()) d.irradiance[Eou] = {2.0 * d.irradiance[Eu].value, 2.0 * d.irradiance[Eu].se};
}

/// Sets cfg.transport.importance by default_depth_importance where cfg.auto_importance asks
/// for it (see there) and says how the run's depth importance was chosen.
template <Medium M>
std::string choose_depth_importance(const M& medium, PlaneParallelConfig& cfg) {
    auto& t = cfg.transport;
    if (!cfg.auto_importance) return t.importance.enabled() ? "given" : "off";
    if (t.importance.enabled()) return "given";
    if (t.depths.empty()) return "auto: off (no detectors)";
    const double deepest = t.deepest_detector();
    const DepthImportance chosen = default_depth_importance(medium, deepest);
    std::ostringstream why;
    why << std::setprecision(3) << "absorption optical depth " << medium.optical_path(Coefficient::absorption, 0.0, 1.0, deepest)
        << " to the deepest detector";
    if (!chosen.enabled()) {
        why << ", below ln 2";
        return "auto: off (" + why.str() + ")";
    }
    if (cfg.tracer != TracerKind::photon && t.absorption == AbsorptionMode::analog)
        return "auto: off (" + why.str() +
               ", but the lanes tracers split weighted photons only: --absorption implicit or continuous, or --tracer photon, would split)";
    t.importance = chosen;
    return "auto: mu_i = 1 (" + why.str() + ")";
}

/// The length of the nadir ray from depth z: down to where the optics' transmittance falls to
/// cfg.ray_transmittance, or to the bottom.
template <RayOptics Optics>
double nadir_ray_length(const Optics& optics, double z, const PlaneParallelConfig& cfg) {
    const double to_bottom = cfg.bottom.depth() - z;  // +inf without a bottom
    return length_to_transmittance(optics, Ray{{0.0, 0.0, z}, {0.0, 0.0, 1.0}, to_bottom}, cfg.ray_transmittance);
}

}  // namespace detail

namespace detail {
/// A first pass of a plane-parallel problem: the tracer's result (with the records), what it
/// measured as a PlaneParallelResult (all but Lu and the store's figures), and the scene as the
/// second pass sees it.
template <class Record>
struct FirstPass {
    TransportResult<Record> transport;
    PlaneParallelResult result;
    MapScene scene;
};

/// The first pass; with a split among processes (PassSplit), complete on rank 0 only, and
/// every process's transport.records its own batches'.
template <PhotonRecord Record, Medium M, class Split = SingleProcess>
FirstPass<Record> run_first_pass(const M& medium, PlaneParallelConfig cfg,
                                 std::chrono::steady_clock::time_point t0, const Split& split = {}) {
    const std::string importance_choice = choose_depth_importance(medium, cfg);
    const Slab slab(cfg.section_width, cfg.bottom);
    const AnySource source = source_of(cfg);
    auto tr = first_pass<Record>(medium, slab, source, cfg, split);
    MapScene scene{slab, std::nullopt, SkyLight::of(source)};
    if (cfg.slopes.flat()) scene.flat_surface = FlatSurface(water_index_of(medium, cfg));

    PlaneParallelResult out;
    out.above = tr.above;
    out.source_irradiance = source.plane_irradiance();
    out.source_name = source.name();
    out.photons_traced = tr.photons;
    out.photons_stored = split.total(tr.records.size());
    out.ledger = tr.ledger;
    out.bottom_ed = tr.bottom_ed;
    out.flux_per_map_photon = tr.map_flux.per_record;
    out.importance = cfg.transport.importance;
    out.importance_choice = importance_choice;
    out.seconds_transport = seconds_since(t0);
    for (std::size_t i = 0; i < tr.depths.size(); ++i) out.depths.push_back({tr.depths[i], tr.irradiance[i], {}, 0});
    eou_on_lambertian_bottom(cfg.bottom, out.depths);
    if constexpr (std::is_same_v<Record, CompactRecord>)
        if (cfg.keep_map) out.map = tr.records;
    return {std::move(tr), std::move(out), std::move(scene)};
}
}  // namespace detail

namespace detail {
/// A shard's records: those of batches [first, last), in their order (shard_records).
template <class Record>
std::vector<Record> records_of_batches(const std::vector<Record>& records, unsigned first, unsigned last) {
    std::vector<Record> out;
    for (const Record& r : records)
        if (r.batch() >= first && r.batch() < last) out.push_back(r);
    return out;
}

/// The Lu sums of shards [first_shard, last_shard) of `shards`, over one depth's rays, as one
/// RadianceSum: the first shard's whole sum (with the sky and bottom terms), every later
/// shard's batches taken from that shard.
template <class Estimators>
RadianceSum shard_sum(const Estimators& estimators, const std::vector<Ray>& rays, unsigned batches, unsigned shards,
                      unsigned first_shard, unsigned threads) {
    RadianceSum sum = estimators.front().sum_over(rays, 0, threads);
    for (std::size_t j = 1; j < estimators.size(); ++j) {
        const RadianceSum s = estimators[j].sum_over(rays, 0, threads);
        const unsigned shard = first_shard + static_cast<unsigned>(j);
        for (unsigned k = batches * shard / shards; k < batches * (shard + 1) / shards; ++k)
            sum.per_batch()[k] = s.per_batch()[k];
        sum.count_photons(s.photons_touched());
    }
    return sum;
}
}  // namespace detail

/// How a problem is spread over processes (solver/mpi_plane_parallel.hpp's MpiSplit), or not
/// (detail::SingleProcess, the default). Rank r of R traces the batches [B r / R, B (r+1) / R)
/// and builds the shards [S r / R, S (r+1) / R) from its own records, which requires that a
/// photon's map batch is its first-pass batch (map photons = photons, divisible by the
/// batches). gather_tallies brings every block's tallies into rank 0's part (merged there in
/// block order); total sums a count over the ranks onto rank 0; gather_lu brings each depth's
/// per-batch Lu sums of batches [first, last) of every rank into rank 0's sums.
template <class S>
concept PassSplit = requires(const S& split, FirstPassPart<CompactRecord>& part, std::vector<RadianceSum>& sums) {
    { split.rank() } -> std::convertible_to<unsigned>;
    { split.ranks() } -> std::convertible_to<unsigned>;
    split.gather_tallies(part);
    { split.total(std::uint64_t{}) } -> std::convertible_to<std::uint64_t>;
    split.gather_lu(sums, 0u, 1u);
};

/// Any PassSplit as one type, for programs that run the same solver on one process and spread
/// over processes (examples/slab.cpp and slab_mpi.cpp): instantiated with an AnyPassSplit, the
/// solver is compiled once for both. A copy of the split is held (SingleProcess and MpiSplit are
/// small values: counts and a communicator handle); a run's five exchanges (rank, ranks,
/// gather_tallies, total, gather_lu) go through virtual calls, none inside a photon or ray loop.
/// The first pass's records are CompactRecords (gather_tallies takes their parts only).
class AnyPassSplit {
public:
    AnyPassSplit() : AnyPassSplit(detail::SingleProcess{}) {}
    template <class S>
        requires(!std::same_as<S, AnyPassSplit> && PassSplit<S>)
    AnyPassSplit(S split) : split_(std::make_shared<const Held<S>>(std::move(split))) {}

    [[nodiscard]] unsigned rank() const { return split_->rank(); }
    [[nodiscard]] unsigned ranks() const { return split_->ranks(); }
    void gather_tallies(FirstPassPart<CompactRecord>& part) const { split_->gather_tallies(part); }
    [[nodiscard]] std::uint64_t total(std::uint64_t n) const { return split_->total(n); }
    void gather_lu(std::vector<RadianceSum>& sums, unsigned first, unsigned last) const {
        split_->gather_lu(sums, first, last);
    }

private:
    struct Split {
        virtual ~Split() = default;
        [[nodiscard]] virtual unsigned rank() const = 0;
        [[nodiscard]] virtual unsigned ranks() const = 0;
        virtual void gather_tallies(FirstPassPart<CompactRecord>& part) const = 0;
        [[nodiscard]] virtual std::uint64_t total(std::uint64_t n) const = 0;
        virtual void gather_lu(std::vector<RadianceSum>& sums, unsigned first, unsigned last) const = 0;
    };
    template <class S>
    struct Held final : Split {
        explicit Held(S s) : split(std::move(s)) {}
        unsigned rank() const override { return split.rank(); }
        unsigned ranks() const override { return split.ranks(); }
        void gather_tallies(FirstPassPart<CompactRecord>& part) const override { split.gather_tallies(part); }
        std::uint64_t total(std::uint64_t n) const override { return split.total(n); }
        void gather_lu(std::vector<RadianceSum>& sums, unsigned first, unsigned last) const override {
            split.gather_lu(sums, first, last);
        }
        S split;
    };
    std::shared_ptr<const Split> split_;
};

static_assert(PassSplit<AnyPassSplit>);

/// The plane-parallel problem in any Medium: first pass, map, and Lu with `optics` (the
/// water's part of eq. 3.18 for the collection solid angle cfg.omega).
/// cfg.attenuation and cfg.albedo are not used: the medium says everything.
/// Spread over processes by `split` (PassSplit), the result is complete on rank 0; on the
/// other ranks it holds their own share only.
template <PhotonRecord Record = CompactRecord, Medium M, RayOptics Optics, PassSplit Split = detail::SingleProcess>
PlaneParallelResult solve_plane_parallel_in(const M& medium, const Optics& optics, PlaneParallelConfig cfg,
                                            const Split& split = {}) {
    const auto t0 = std::chrono::steady_clock::now();
    const unsigned batches = cfg.transport.batches, shards = cfg.shards, ranks = split.ranks();
    require(shards >= 1 && batches % shards == 0, "shards", shards,
            "must be >= 1 and divide the batches (" + std::to_string(batches) + ")");
    require(shards % ranks == 0, "shards", shards,
            "must be a multiple of the processes (" + std::to_string(ranks) + "): each builds whole shards");
    if (ranks > 1) {
        require(cfg.transport.map_photons == cfg.transport.photons, "map photons", cfg.transport.map_photons,
                "must equal the photons (" + std::to_string(cfg.transport.photons) +
                    ") in a run spread over processes: each builds its maps from the photons it traced");
        require(cfg.transport.photons % batches == 0, "photons", cfg.transport.photons,
                "must be a multiple of the batches (" + std::to_string(batches) +
                    ") in a run spread over processes: a photon's map batch is then its first-pass batch");
    }
    require(cfg.radius > 0 && cfg.radius < 0.5 * cfg.section_width, "radius", cfg.radius,
            "must be > 0 and < section_width / 2 (the collection volume's images come from the neighbouring sections)");
    require(cfg.ray_transmittance > 0.0 && cfg.ray_transmittance < 1.0, "ray transmittance", cfg.ray_transmittance,
            "must lie in (0, 1)");
    require(cfg.steps >= 1, "steps", cfg.steps, "must be >= 1 (spheres along each ray)");
    require(cfg.ray_grid >= 1 && cfg.ray_grid <= 1000, "ray grid", cfg.ray_grid, "must be 1 to 1000 (K x K rays per depth)");
    // Infinitely deep water is traced without a cut-off (photons end by absorption and roulette);
    // the map keeps the events down to the deepest Lu ray's end, plus the collection radius.
    if (cfg.transport.map_photons > 0) {
        double map_depth = 0.0;
        for (double z : cfg.transport.depths) map_depth = std::max(map_depth, z + detail::nadir_ray_length(optics, z, cfg));
        cfg.transport.map_depth = map_depth + cfg.radius;
    }
    auto first = detail::run_first_pass<Record>(medium, cfg, t0, split);
    PlaneParallelResult& out = first.result;
    if (first.transport.map_photons > 0) {
        const StepSpheres spheres(cfg.steps, 0.0, cfg.bottom.depth());
        const VoiCylinder cylinder(0.0, cfg.bottom.depth());
        // Lu at every depth with the store's natural collection volume: the whole radiance of
        // K x K nadir rays (estimate/radiance.hpp: the path radiance down to where the
        // transmittance falls to cfg.ray_transmittance or to the bottom, plus a Lambertian
        // bottom's A Ed(bottom) / pi carried up by the ray's transmittance), from this
        // process's shards, each a map of its batches' records (one shard: every record here).
        const unsigned first_shard = shards * split.rank() / ranks, last_shard = shards * (split.rank() + 1) / ranks;
        auto run = [&]<class Store>(std::type_identity<Store>, const auto& volume, auto... store_args) {
            const TransportResult<Record>& tr = first.transport;
            std::deque<PhotonMap<Store>> maps;
            for (unsigned j = first_shard; j < last_shard; ++j) {
                std::vector<Record> records = last_shard - first_shard == 1
                                                  ? std::move(first.transport.records)
                                                  : detail::records_of_batches(tr.records, batches * j / shards,
                                                                               batches * (j + 1) / shards);
                maps.emplace_back(Store(std::move(records), store_args...), tr.map_flux, tr.batches, first.scene,
                                  tr.bottom_ed);
            }
            std::vector<Record>().swap(first.transport.records);
            out.store_bytes = 0;
            for (const auto& map : maps) out.store_bytes += map.store().memory_bytes();
            out.seconds_build = detail::seconds_since(t0) - out.seconds_transport;
            std::deque<RadianceEstimator<Store, std::remove_cvref_t<decltype(volume)>, Optics>> estimators;
            for (const auto& map : maps)
                estimators.emplace_back(map, volume, optics, Radius(cfg.radius), RadianceSettings{cfg.ray_transmittance});
            std::vector<RadianceSum> sums;
            for (const auto& d : out.depths)
                sums.push_back(detail::shard_sum(estimators, nadir_ray_grid(d.depth, INFINITY, cfg.ray_grid, cfg.section_width),
                                                 batches, shards, first_shard, cfg.transport.threads));
            split.gather_lu(sums, batches * first_shard / shards, batches * last_shard / shards);
            const double rays = static_cast<double>(cfg.ray_grid) * cfg.ray_grid;
            for (std::size_t i = 0; i < sums.size(); ++i) {
                out.depths[i].lu = sums[i].estimate(rays);
                out.depths[i].photons_touched = sums[i].photons_touched();
            }
        };
        switch (cfg.store) {
            case StoreKind::kdtree: run(std::type_identity<KdTreeStore<Record>>{}, spheres); break;
            case StoreKind::nanoflann:
#if SECCHI_HAS_NANOFLANN
                run(std::type_identity<NanoflannStore<Record>>{}, spheres);
                break;
#else
                reject("store", "nanoflann", "needs nanoflann.hpp (nanoflann 1.4), which this build did not find");
#endif
            case StoreKind::voi: run(std::type_identity<VoiOctreeStore<Record>>{}, cylinder); break;
            case StoreKind::voi_grid: run(std::type_identity<VoiGridStore<Record>>{}, cylinder, Radius(cfg.radius)); break;
            case StoreKind::brute_force: run(std::type_identity<BruteForceStore<Record>>{}, cylinder); break;
        }
        out.seconds_collect = detail::seconds_since(t0) - out.seconds_transport - out.seconds_build;
    }
    out.seconds = detail::seconds_since(t0);
    return std::move(out);
}

/// A plane-parallel problem's first pass and its photon map, for a caller's own second pass
/// (estimate/radiance.hpp: radiance along any ray).
template <class Store>
struct MappedWater {
    PlaneParallelResult first_pass;  ///< irradiances, ledger, above-surface values (no Lu)
    PhotonMap<Store> map;
};

/// Traces cfg's first pass in `medium` and builds its photon map into a Store (e.g.
/// VoiGridStore<CompactRecord>, whose constructor's arguments after the records are
/// store_args). Events are stored down to cfg.transport.map_depth: set it below the deepest
/// point a query's collection volume reaches (deeper queries are refused). cfg.store,
/// cfg.radius and the Lu settings are not used.
template <class Store, Medium M, class... StoreArgs>
MappedWater<Store> trace_photon_map(const M& medium, const PlaneParallelConfig& cfg, StoreArgs&&... store_args) {
    auto first = detail::run_first_pass<typename PhotonMap<Store>::Record>(medium, cfg, std::chrono::steady_clock::now());
    return {std::move(first.result), PhotonMap<Store>::from_first_pass(std::move(first.transport), std::move(first.scene),
                                                                      std::forward<StoreArgs>(store_args)...)};
}

/// The cone-averaged phase functions' tables, computed on the problem's threads.
inline ConeTable cone_table(const PlaneParallelConfig& cfg) { return {.threads = cfg.transport.threads}; }

/// Homogeneous water of attenuation cfg.attenuation and albedo cfg.albedo with one phase function.
/// Spread over processes by `split` (PassSplit), the result is complete on rank 0.
template <PhaseFunction Phase, PhotonRecord Record = CompactRecord, PassSplit Split = detail::SingleProcess>
PlaneParallelResult solve_plane_parallel(const Phase& phase, const PlaneParallelConfig& cfg, const Split& split = {}) {
    const auto medium = HomogeneousWater<Phase>::from_albedo(cfg.attenuation, cfg.albedo, phase);
    const ConeAveragedPhase<Phase> cone(phase, cfg.omega, cfg.cone_peak, cone_table(cfg));
    auto out = solve_plane_parallel_in<Record>(medium, HomogeneousRayOptics(cone, medium.attenuation(), medium.scattering()),
                                               cfg, split);
    out.phase_name = phase.name();
    out.moments = phase_moments(phase);
    return out;
}

/// Depth-varying water: each scattering component's phase function averaged over cfg.omega.
template <PhotonRecord Record = CompactRecord, PhaseFunction... Phases>
PlaneParallelResult solve_stratified(const StratifiedWater<Phases...>& water, const PlaneParallelConfig& cfg) {
    const auto cones =
        water.transform_phases([&](const auto& p) { return ConeAveragedPhase(p, cfg.omega, cfg.cone_peak, cone_table(cfg)); });
    const StratifiedRayOptics optics(water, cones);
    auto out = solve_plane_parallel_in<Record>(water, optics, cfg);
    out.phase_name = "mixture";
    water.for_each_phase([&](const auto& p) {
        out.phase_name += ' ';
        out.phase_name += p.name();
    });
    return out;
}

}  // namespace secchi
