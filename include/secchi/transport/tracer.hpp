#pragma once
// The first pass (manual 3.3): equal-flux photons from a light source (a policy: a collimated
// sun and a uniform sky, a parametric sky, or a traced atmosphere; scene/source.hpp),
// refracted through the surface (a policy: flat, wind-blown facets, or a surface with
// geometry such as a sinusoidal wave, met where the photon's path crosses it; scene/surface.hpp),
// exponential free paths (eq. 3.17), absorption or scattering by the albedo (3.3.5), storage
// of scattering events in the photon map (3.3.6), Fresnel reflection and refraction at the
// surface from below, the bottom (a policy: scene/bottom.hpp), opaque objects in the water (a
// policy: scene/geometry.hpp; none by default), and irradiance detectors. Light
// going up from the surface into the air is handed to the source when the source can send it
// back (a traced atmosphere: the coupled system), and comes down onto the surface again or
// leaves. Every photon's weight ends in the energy ledger. The per-event rules (free flight,
// absorption mode, storage, scattering angles, limits) are EventPhysics's (event_physics.hpp),
// shared with LaneTracer, which schedules photons in SIMD lanes.
//
// Parallel and reproducible: photon i draws only from its own counter-based stream
// (seed, i); photons are processed in fixed blocks, and block results are merged in block
// order, so the output is bit-identical for any thread count.
#include "secchi/core/config.hpp"
#include "secchi/core/memory.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/core/stats.hpp"
#include "secchi/map/record.hpp"
#include "secchi/map/surface_record.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/scene/flat_surface.hpp"
#include "secchi/scene/geometry.hpp"
#include "secchi/scene/source.hpp"
#include "secchi/scene/sun_and_sky.hpp"
#include "secchi/scene/surface.hpp"
#include "secchi/scene/wave_surface.hpp"
#include "secchi/scene/slab.hpp"
#include "secchi/transport/blocks.hpp"
#include "secchi/transport/bottom_grid.hpp"
#include "secchi/transport/event_physics.hpp"
#include "secchi/transport/irradiance_planes.hpp"
#include "secchi/transport/ledger.hpp"
#include "secchi/core/parallel.hpp"
#include "secchi/transport/record_flux.hpp"
#include "secchi/transport/settings.hpp"
#include <algorithm>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

namespace secchi::SECCHI_ISA {

/// The plane irradiances just above the surface (z = 0+): the downward one, Ed(0+) = direct +
/// diffuse, counted at every arrival of light from the air (light an atmosphere sends back
/// counts again), and the upward one Eu(0+) (light leaving the surface into the air).
struct AboveSurface {
    Estimate ed_direct;   ///< straight from the sun's disk, never scattered
    Estimate ed_diffuse;  ///< everything else arriving from the air (sky, atmosphere)
    Estimate eu;          ///< going up from the surface: specular reflection and water-leaving light
};

/// What the first pass produces. Irradiances are in the units of the source's plane irradiance
/// (LightSource::plane_irradiance(): E_perp cos(zenith) at the surface, or at the top of an
/// atmosphere).
template <PhotonRecord Record>
struct TransportResult {
    std::vector<double> depths;
    std::vector<std::array<Estimate, 4>> irradiance;  ///< per depth, indexed by IrradianceKind
    Estimate bottom_ed;                               ///< Ed arriving at the bottom (0 without one)
    /// Ed arriving at the bottom per bin of settings.bottom_bins per side (index iy n + ix;
    /// bottom_grid.hpp); empty when bottom_bins = 0.
    std::vector<Estimate> bottom_ed_bins;
    AboveSurface above;                               ///< Ed(0+) direct and diffuse, Eu(0+)
    EnergyLedger ledger;                              ///< normalised per incident photon
    std::vector<Record> records;                      ///< the photon map, in photon order
    /// The surface photon map (settings.surface_map): the map photons' arrivals on objects and
    /// an opaque bottom, in photon order; each carries weight x map_flux.per_record.
    std::vector<SurfacePhoton> surface_photons;
    RecordFlux map_flux;                              ///< what a record carries (the source's plane irradiance x area / map photons)
    std::uint64_t photons = 0, map_photons = 0;
    unsigned batches = 0;
};

namespace detail {
/// What a block's photons produce: tallies, ledger, records (in chunks from the run's pool).
template <class Record>
struct BlockResult {
    BlockResult(std::size_t depths, ChunkPool<Record>* pool, std::size_t bins = 0)
        : tally(depths), bottom_bins(bins, 0.0), records(pool) {}

    std::vector<IrradianceTally> tally;  // per depth
    std::vector<double> bottom_bins;     // weight arriving on the bottom per bin (bottom_grid.hpp)
    double bottom_ed = 0;
    double ed_direct = 0, ed_diffuse = 0, eu_air = 0;  // just above the surface (AboveSurface)
    EnergyLedger ledger;
    RecordChunks<Record> records;
    std::vector<SurfacePhoton> surface;  // arrivals on objects and the bottom (settings.surface_map)
};

}  // namespace detail

/// The blocks one process traces when a first pass is split among processes
/// (solver/mpi_plane_parallel.hpp): [first, last) of make_blocks' list (blocks.hpp), clamped
/// to it; every block by default.
struct BlockRange {
    std::size_t first = 0;
    std::size_t last = SIZE_MAX;
};

/// A first pass traced in part (run_part): every block, every block's result slot (the blocks
/// not traced here keep empty tallies, for another process's to be gathered into), and the
/// records of the blocks traced here, in block order. merge_part turns it into the
/// TransportResult once the slots hold every block's tallies.
template <class Record>
struct FirstPassPart {
    std::vector<detail::Block> blocks;
    std::vector<detail::BlockResult<Record>> results;
    std::vector<Record> records;
    BlockRange traced;  ///< the blocks traced here (clamped)
};

/// input_error naming the photons or the map photons unless what a first pass of `s` allocates
/// at the least fits in the physical memory, `runs` times over (a spectral map keeps every
/// band's records): each block's bookkeeping and tallies, and one record per map photon (a
/// stored photon scatters at least once, on average more). Checked before anything is allocated.
template <PhotonRecord Record>
void require_first_pass_fits_in_memory(const TransportSettings& s, double runs = 1.0) {
    const double blocks = static_cast<double>(s.photons / std::max<std::uint64_t>(s.block_size, 1) + s.batches);
    const double per_block = sizeof(detail::Block) + sizeof(detail::BlockResult<Record>) +
                             static_cast<double>(s.depths.size()) * sizeof(IrradianceTally) +
                             static_cast<double>(s.bottom_bins) * s.bottom_bins * sizeof(double);
    require_fits_in_memory(blocks * per_block, "photons", s.photons);
    require_fits_in_memory(blocks * per_block + runs * static_cast<double>(s.map_photons) * sizeof(Record),
                           "map photons", s.map_photons);
}

/// The policies: the water (Medium), what a stored event keeps (PhotonRecord), the air-water
/// surface (AirWaterSurface or GeometricSurface), the light source (LightSource), the irradiance detectors
/// (IrradianceDetector), the bottom (BottomModel, scene/bottom.hpp) and the objects in the
/// water (SceneGeometry, scene/geometry.hpp: NoGeometry, the default, compiles to the tracer
/// without objects); the per-event rules are EventPhysics's, set by the settings.
template <Medium M, PhotonRecord Record, SurfacePolicy Surface = FlatSurface, LightSource Source = SunAndSky,
          IrradianceDetector Detector = IrradiancePlanes, BottomModel BottomPolicy = Bottom,
          SceneGeometry Geometry = NoGeometry>
class PhotonTracer {
    /// A surface with geometry (wave_surface.hpp) lies between its crest and trough depths;
    /// a flat or faceted one on the mean plane z = 0.
    static constexpr bool wavy = GeometricSurface<Surface>;
    static_assert(!wavy || depth_independent<M>,
                  "a surface with geometry needs a depth-independent medium (the water above the mean plane "
                  "has no layer of a stratified one)");

public:
    using medium_type = M;
    using record_type = Record;
    using surface_type = Surface;
    using source_type = Source;
    using detector_type = Detector;
    using slab_type = BasicSlab<BottomPolicy>;
    using geometry_type = Geometry;

    /// The photons come from `source` (scene/source.hpp). The objects of `geometry` lie in the
    /// section, [0, W] x [0, W] horizontally, and between the surface and the floor; they
    /// repeat with the section's period (scene/geometry.hpp).
    PhotonTracer(const M& medium, const slab_type& slab, const Surface& surface, const Source& source,
                 TransportSettings settings, Geometry geometry = Geometry{})
        : medium_(medium), slab_(slab), surface_(surface), source_(source), s_(validated(std::move(settings))),
          geometry_(checked_geometry(std::move(geometry), slab, surface)), grid_(s_.bottom_bins, slab.width()),
          detectors_(s_.depths, s_.grazing_cosine, slab.floor_depth()),
          physics_(s_, slab.floor_depth(), surface_top(surface)), importance_on_(s_.importance.enabled()),
          levels_(s_.importance, medium), bias_(backscatter_bias(medium, s_)), upward_(upward_importance(s_)),
          w0_(albedo_at(medium, 0.0)),
          sun_direction_(source.beam_direction()),
          sun_hit_(fixed_sun_hit(surface, sun_direction_)) {
        if constexpr (wavy) check_wave(surface, slab, source, s_);
        if (!std::isfinite(slab.floor_depth())) {
            // Infinitely deep water has no cut-off (light returns from any depth, attenuated by
            // the diffuse attenuation, which can be far below c): photons end only by absorption
            // (and Russian roulette on their weight), so the water must absorb at depth.
            const double a_deep = medium.coefficient(Coefficient::absorption, 1e6);
            require(a_deep > 0.0, "absorption coefficient at depth (1/m)", a_deep,
                    "must be > 0 in infinitely deep water (photons end by absorption); give a bottom or an escape depth");
            require(s_.absorption == AbsorptionMode::analog || s_.roulette_weight > 0.0, "roulette weight",
                    s_.roulette_weight, "must be > 0 in infinitely deep water (weighted photons end by roulette)");
        }
    }

    /// A collimated sun and a uniform sky beside it (black by default) just above the surface
    /// (SunAndSky): a photon comes from the sky with probability E_sky / (E_sun + E_sky).
    PhotonTracer(const M& medium, const slab_type& slab, const Surface& surface, const CollimatedSun& sun,
                 TransportSettings settings, UniformSky sky = UniformSky{})
        requires std::same_as<Source, SunAndSky>
        : PhotonTracer(medium, slab, surface, SunAndSky(sun, sky), std::move(settings)) {}

    /// Traces the photons. The map's records go into `storage` (cleared first): pass the
    /// records of an earlier run (`std::move(result.records)`) to reuse their memory, which
    /// spares the page faults of fresh memory (about a sixth of LaneTracer's time; docs/design-notes.md).
    TransportResult<Record> run(std::vector<Record> storage = {}) const {
        return merge_part(run_part(BlockRange{}, std::move(storage)));
    }

    /// Traces only the blocks `range` (a process's share of a first pass split among
    /// processes); run() is merge_part(run_part(BlockRange{})).
    FirstPassPart<Record> run_part(BlockRange range, std::vector<Record> storage = {}) const {
        return trace_part(
            [this](const detail::Block& block, detail::BlockResult<Record>& out) { trace_block(block, out); }, range,
            std::move(storage));
    }

    /// The first pass's result from a part whose result slots hold every block's tallies (the
    /// whole pass traced here, or the other processes' tallies gathered into it): the tallies
    /// merged in block order, whichever process traced a block, so the sums are the same
    /// bits; the records are the part's.
    TransportResult<Record> merge_part(FirstPassPart<Record>&& part) const {
        return merge(part.blocks, part.results, std::move(part.records));
    }

protected:  // the per-event physics, shared with LaneTracer (lane_tracer.hpp)
    /// Traces the blocks `range` with `trace_block(block, result)` on the settings' threads;
    /// the records go into the map in block order as blocks finish (blocks.hpp).
    template <class TraceBlock>
    FirstPassPart<Record> trace_part(TraceBlock&& trace_block, BlockRange range, std::vector<Record> storage) const {
        FirstPassPart<Record> part;
        part.blocks = detail::make_blocks(s_.photons, s_.batches, s_.block_size);
        const std::size_t n = part.blocks.size(), first = std::min(range.first, n), last = std::min(range.last, n);
        require(first <= last, "block range", range.first, "must not start after its end");
        part.traced = {first, last};
        detail::ChunkPool<Record> pool;
        part.results.reserve(n);
        for (std::size_t i = 0; i < n; ++i) part.results.emplace_back(detectors_.size(), &pool, grid_.size());
        const std::vector<detail::Block> here(part.blocks.begin() + static_cast<std::ptrdiff_t>(first),
                                              part.blocks.begin() + static_cast<std::ptrdiff_t>(last));
        const auto results = std::span(part.results).subspan(first, last - first);
        detail::OrderedRecords<Record> map(here, s_.map_photons, std::move(storage));
        parallel_for(here.size(), s_.threads, [&](std::size_t i) {
            trace_block(here[i], results[i]);
            map.finished(i, results);
        });
        part.records = map.take();
        // Every block's chunks went into the map; none refers to the pool, which ends here.
        for (auto& r : part.results) r.records = detail::RecordChunks<Record>();
        return part;
    }

    static TransportSettings validated(TransportSettings s) {
        s.validate();
        require(s.batches <= record_max_batches<Record>(), "batches", s.batches,
                "exceeds what the photon record can label (CompactRecord: 64)");
        require_first_pass_fits_in_memory<Record>(s);
        return s;
    }

    /// The objects lie in the section, below the surface's lowest point (the mean plane, or a
    /// wave's troughs) and above the floor.
    static Geometry checked_geometry(Geometry g, const slab_type& slab, const Surface& surface) {
        const Bounds b = g.bounds();
        if (b.empty()) return g;
        const double w = slab.width();
        require(b.lo.x >= 0.0 && b.lo.y >= 0.0, "object bounds' lowest x, y (m)", std::min(b.lo.x, b.lo.y),
                "must be >= 0 (objects lie in the section [0, W]^2)");
        require(b.hi.x <= w && b.hi.y <= w, "object bounds' highest x, y (m)", std::max(b.hi.x, b.hi.y),
                "must not exceed the section width (objects lie in the section [0, W]^2)");
        require(b.lo.z >= surface_bottom(surface), "object bounds' top depth (m)", b.lo.z,
                wavy ? "must be at or below the wave's troughs (its amplitude)" : "must be >= 0 (below the surface)");
        require(b.hi.z <= slab.floor_depth(), "object bounds' bottom depth (m)", b.hi.z,
                "must not be below the floor (the bottom or the escape depth)");
        return g;
    }

    struct PhotonState {
        vec3 pos, dir;
        double w;
        unsigned order;
        int level = 0;  ///< depth-importance level (importance.hpp)
    };

    /// Where a photon's stored events go: whether it stores at all, and its batch.
    struct MapSlot {
        bool stores;
        std::uint8_t batch;
    };

    void trace_block(const detail::Block& block, detail::BlockResult<Record>& out) const {
        std::vector<PhotonState> pending;  // split-off photons, traced depth first
        for (std::uint64_t i = block.begin; i < block.end; ++i) trace_photon(i, out, pending);
    }

    /// Follows photon `index` from the sun until it leaves, is absorbed or is stopped, and
    /// then every photon split off it (in a fixed order, from the same random stream).
    void trace_photon(std::uint64_t index, detail::BlockResult<Record>& out, std::vector<PhotonState>& pending) const {
        PhotonRng rng(s_.seed, index);
        PhotonState p;
        if (!launch(p, rng, out)) return;
        const MapSlot slot = map_slot(index);
        follow(p, rng, out, slot, pending);
        while (!pending.empty()) {
            p = pending.back();
            pending.pop_back();
            follow(p, rng, out, slot, pending);
        }
    }

    /// A photon from the source at a uniform point of the section (its first draws from
    /// `rng`), to the surface and through it. False if it does not enter the water. (The
    /// horizontal path a photon takes through an atmosphere is not followed: the plane-parallel
    /// atmosphere is the same everywhere, so where in the periodic section its light arrives
    /// changes no horizontally averaged quantity, and a uniform point stays a uniform point.)
    bool launch(PhotonState& p, PhotonRng& rng, detail::BlockResult<Record>& out) const {
        p = PhotonState{{slab_.width() * rng.uniform(), slab_.width() * rng.uniform(), 0.0}, sun_direction_, 1.0, 0};
        out.ledger.incident += 1.0;
        const SourcePhoton sp = source_.emit(rng);
        if (!arrives(sp, p.w, out)) return false;
        p.dir = sp.dir;
        if constexpr (wavy) {  // from a uniform point of the plane over the crests down to the surface
            p.pos.z = surface_.crest_depth();
            const auto t = surface_.first_crossing(p.pos, p.dir, Side::air, air_path_limit(p));
            if (!t) return leaves_in_air(p, out.ledger.surface_reflected, out);
            p.pos += p.dir * *t;
            return cross_wave(p, rng, Side::air, out.ledger.surface_reflected, out);
        } else {
            const SurfaceHit h = sp.beam ? sun_hit(rng) : surface_.hit(p.dir, Side::air, rng);
            return cross_surface(p, rng, Side::air, h, out.ledger.surface_reflected, out);  // lost light: surface_reflected
        }
    }

    /// Books a photon the source followed: its weight w into Ed(0+) if it arrives at the
    /// surface (true), else into the ledger's account for its fate.
    static bool arrives(const SourcePhoton& sp, double w, detail::BlockResult<Record>& out) {
        switch (sp.fate) {
            case SourceFate::arrives: (sp.direct ? out.ed_direct : out.ed_diffuse) += w; return true;
            case SourceFate::to_space: out.ledger.to_space += w; return false;
            case SourceFate::absorbed: out.ledger.absorbed_air += w; return false;
        }
        return false;
    }

    /// The map batch of photon `index`, if its events are stored.
    MapSlot map_slot(std::uint64_t index) const {
        const bool stores = index < s_.map_photons;
        return {stores, static_cast<std::uint8_t>(stores ? index * s_.batches / s_.map_photons : 0)};
    }

    /// One photon in the water until it ends: free flights (event_physics.hpp) to the next
    /// interaction, or to the surface or the floor.
    void follow(PhotonState& p, PhotonRng& rng, detail::BlockResult<Record>& out, MapSlot slot,
                std::vector<PhotonState>& pending) const {
        const Coefficient path_kind = physics_.path_coefficient();
        [[maybe_unused]] int stuck = 0;  // meetings with the surface in a row without leaving it
        while (true) {
            if (importance_on_ && !change_level(p, rng, out.ledger, pending)) return;
            const double s = medium_.distance_to(path_kind, p.pos.z, p.dir.z, -std::log(rng.uniform()));
            FreeFlight<double> f = physics_.free_flight(p.pos.z, p.dir.z, s);
            if constexpr (wavy) {  // the flight ends where it first reaches the surface
                const auto t = surface_.first_crossing(p.pos, p.dir, Side::water, f.t);
                if (t) f = {*t, p.pos.z + p.dir.z * *t, true, false};
                // A photon that meets the surface again within twice the offset it was given off
                // it has not left it: a surface policy whose normal or crossings disagree with its
                // shape. Stopped (truncated) after max_surface_hits such meetings, not followed for ever.
                stuck = t && *t <= 2.0 * surface_offset ? stuck + 1 : 0;
                if (stuck > max_surface_hits) {
                    out.ledger.truncated += p.w;
                    return;
                }
            }
            if constexpr (Geometry::has_objects) {  // the flight ends where it first meets an object
                if (const auto hit = periodic_closest_hit(geometry_, slab_.width(), p.pos, p.dir, f.t)) {
                    fly(p, hit->t, p.pos.z + p.dir.z * hit->t, out);
                    keep_arrival(p, hit->point, hit->normal, hit->material, slot, out);
                    if (!reflect_at_object(p, rng, out.ledger, *hit)) return;
                    continue;
                }
            }
            fly(p, f.t, f.z1, out);
            const bool goes_on = f.to_surface || f.to_floor ? meet_boundary(p, rng, out, f.to_surface, slot)
                                                            : interact(p, rng, out, slot);
            if (!goes_on) return;
        }
    }

    /// A photon that flew to the surface (Fresnel reflection or escape) or to the floor (Ed at
    /// the bottom; the bottom's reflection, or transmission). False if it leaves or ends.
    bool meet_boundary(PhotonState& p, PhotonRng& rng, detail::BlockResult<Record>& out, bool surface,
                       MapSlot slot = {}) const {
        if (surface) return leave_or_reflect_at_surface(p, rng, out);
        if (slab_.has_bottom()) {
            out.bottom_ed += p.w;
            if (grid_.size()) out.bottom_bins[grid_.bin(slab_.wrap(p.pos.x), slab_.wrap(p.pos.y))] += p.w;
            if (!slab_.bottom().transmits())
                keep_arrival(p, {p.pos.x, p.pos.y, slab_.floor_depth()}, vec3(0.0, 0.0, -1.0), SurfacePhoton::bottom, slot, out);
        }
        return reflect_at_bottom(p, rng, out.ledger);
    }

    /// A map photon's arrival on an opaque surface into the surface photon map (settings.surface_map).
    void keep_arrival(const PhotonState& p, const vec3& point, const vec3& normal, std::uint32_t surface, MapSlot slot,
                      detail::BlockResult<Record>& out) const {
        if (!s_.surface_map || !slot.stores) return;
        out.surface.push_back({{slab_.wrap(point.x), slab_.wrap(point.y), point.z}, normal, p.w, surface, slot.batch});
    }

    /// Distance (m) by which a photon reflected by an object leaves its surface along the
    /// normal, so that its next flight does not meet the same surface again at a rounding
    /// distance (a hit point computed in doubles lies up to a few ulps inside the solid).
    static constexpr double object_offset = 1e-9;

    /// Reflection with reflectance rho by a surface that absorbs the rest (the bottom, an
    /// object): weight x rho (implicit capture, continuous), or survival with probability rho
    /// (analog); what is not reflected goes to `absorbed`. False if the photon ends.
    bool survives_reflection(PhotonState& p, PhotonRng& rng, double rho, double& absorbed) const {
        if (!physics_.analog()) {
            absorbed += p.w * (1.0 - rho);
            p.w *= rho;
            return true;
        }
        if (rng.uniform() < rho) return true;
        absorbed += p.w;
        return false;
    }

    /// A photon that met an object (`hit`, scene/geometry.hpp): absorbed by a black surface
    /// (albedo 0 at the point met), else reflected Lambertian-ly, weight x A (implicit capture, continuous) or
    /// surviving with probability A (analog), the rest absorbed by the object; the direction
    /// cosine-weighted about the normal (pdf cos theta / pi), as at a Lambertian bottom. A glossy
    /// material (rho_s > 0, scene/ward.hpp) reflects with A = rho_d + rho_s in the same way, then
    /// takes its glossy lobe with probability rho_s / A: a direction drawn from the lobe, the
    /// photon's weight times the draw's (its mean is the lobe's directional albedo over rho_s,
    /// at most 1, a draw's at most 2; a draw below the surface is absorbed), with weighted
    /// photons only (analog ones are refused); a photon of weight w > 1 stores floor(w) records
    /// and one more with probability frac(w), so that records keep their equal flux.
    /// False if the photon ends.
    bool reflect_at_object(PhotonState& p, PhotonRng& rng, EnergyLedger& ledger, const ObjectHit& hit) const {
        const ObjectMaterial& material = geometry_.material(hit.material);  // (a reference: no copy of the map's shared_ptr per hit)
        const double diffuse = material.albedo_at(hit.point), albedo = diffuse + material.specular;
        if (albedo == 0.0) {
            ledger.absorbed_objects += p.w;
            return false;
        }
        if (material.specular > 0.0 && physics_.analog())
            reject("object glossy albedo", material.specular,
                   "needs weighted photons (absorption continuous or implicit): a glossy reflection's weight is not 0 or 1");
        if (!survives_reflection(p, rng, albedo, ledger.absorbed_objects)) return false;
        const bool glossy = material.specular > 0.0 && rng.uniform() * albedo >= diffuse;
        const double u1 = rng.uniform(), u2 = rng.uniform();
        if (glossy) {
            const GlossyDraw g = material.lobe.sample(-p.dir, hit.normal, u1, u2);
            ledger.absorbed_objects += p.w * (1.0 - g.weight);  // negative where the draw's weight exceeds 1
            p.w *= g.weight;
            if (g.weight == 0.0) return false;
            p.dir = g.direction;
        } else {
            p.dir = lambertian_direction(hit.normal, u1, u2);
        }
        p.pos += hit.normal * object_offset;
        p.pos.z = std::clamp(p.pos.z, 0.0, slab_.floor_depth());
        return roulette(p, rng, ledger);
    }

    /// Splitting (deeper level) or Russian roulette (shallower level) to the photon's
    /// current depth-importance level. False if the photon is killed.
    bool change_level(PhotonState& p, PhotonRng& rng, EnergyLedger& ledger, std::vector<PhotonState>& pending) const {
        return change_level_to(levels_.level(p.pos.z), p, rng, ledger, pending);
    }
    /// change_level where the caller knows the level of the photon's depth.
    bool change_level_to(int level, PhotonState& p, PhotonRng& rng, EnergyLedger& ledger,
                         std::vector<PhotonState>& pending) const {
        const int k = level - p.level;
        if (k == 0) return true;
        if (k > 0) {  // split into 2^k photons of weight w / 2^k (at most 2^20 at once: a photon
                      // left below its level splits again at its next step, or stores copies)
            const int split = std::min(k, 20);
            p.level += split;
            p.w = times_power_of_two(p.w, -split);
            for (int i = 1; i < (1 << split); ++i) pending.push_back(p);
            return true;
        }
        p.level += k;
        const double ratio = times_power_of_two(1.0, k);  // I_new / I_old < 1
        if (rng.uniform() < ratio) {  // survive with probability 2^k (k < 0), weight / 2^k
            ledger.roulette_gained += p.w / ratio - p.w;
            p.w /= ratio;
            return true;
        }
        ledger.roulette_killed += p.w;
        return false;
    }

    /// At the surface from below: reflect (Fresnel, total internal reflection) or escape.
    bool leave_or_reflect_at_surface(PhotonState& p, PhotonRng& rng, detail::BlockResult<Record>& out) const {
        if constexpr (wavy) {
            return cross_wave(p, rng, Side::water, out.ledger.escaped_up, out);
        } else {
            p.pos.z = 0.0;
            return cross_surface(p, rng, Side::water, surface_.hit(p.dir, Side::water, rng), out.ledger.escaped_up, out);
        }
    }

    /// Distance (m) by which a photon leaving a surface with geometry is moved off it along
    /// the local normal, to the side it goes on in (its next search starts off the surface).
    static constexpr double surface_offset = 1e-9;

    /// The photon is on a surface with geometry (wave_surface.hpp), arriving from `side`:
    /// reflected or refracted at the local facet with the Fresnel probability (always a random
    /// choice: reflected light can meet the surface again), until it is in the water (true) or
    /// leaves upward through the plane over the crests (false: its weight goes to `left`,
    /// the ledger's entry for light leaving through the surface). Light in the air moving
    /// down, or up towards a neighbouring crest, meets the surface again where its path
    /// crosses it. After max_surface_hits hits the photon stops, its weight truncated.
    bool cross_wave(PhotonState& p, PhotonRng& rng, Side side, double& left, detail::BlockResult<Record>& out) const
        requires wavy
    {
        for (int hits = 1;; ++hits) {
            const SurfaceHit h = surface_.hit_at(p.pos, p.dir, side);
            const bool reflect = rng.uniform() < h.reflectance;
            p.dir = h.direction(reflect);
            const bool in_water = (side == Side::air) != reflect;
            p.pos += surface_.normal_into_water(p.pos.x, p.pos.y) * (in_water ? surface_offset : -surface_offset);
            if (in_water) return true;
            const auto t = surface_.first_crossing(p.pos, p.dir, Side::air, air_path_limit(p));
            if (!t) return leaves_in_air(p, left, out);
            if (hits == max_surface_hits) break;
            p.pos += p.dir * *t;
            side = Side::air;
        }
        out.ledger.truncated += p.w;
        return false;
    }

    /// How far a photon in the air can go before it is above the crests moving up (gone) or
    /// must have met the surface (below the troughs moving down); infinite when horizontal.
    double air_path_limit(const PhotonState& p) const requires wavy {
        if (p.dir.z < 0.0) return std::max(0.0, (surface_.crest_depth() - p.pos.z) / p.dir.z);
        if (p.dir.z > 0.0) return std::max(0.0, (surface_.trough_depth() - p.pos.z) / p.dir.z);
        return INFINITY;
    }

    /// A photon in the air that does not meet the surface again: gone upward (Eu(0+)).
    static bool leaves_in_air(const PhotonState& p, double& left, detail::BlockResult<Record>& out) {
        out.eu_air += p.w;
        left += p.w;
        return false;
    }

    /// The top of the flights (EventPhysics): the mean plane, or the crests of a surface with geometry.
    static double surface_top(const Surface& surface) {
        if constexpr (wavy) return surface.crest_depth();
        else return 0.0;
    }
    /// The surface's lowest point: the mean plane, or the troughs of a surface with geometry.
    static double surface_bottom(const Surface& surface) {
        if constexpr (wavy) return surface.trough_depth();
        else return 0.0;
    }

    /// What a surface with geometry asks of the scene: it repeats over the section; the
    /// detector planes and the floor lie below its troughs (the objects: checked_geometry); a
    /// source that takes light back (a traced atmosphere) is not coupled to it.
    static void check_wave(const Surface& surface, const slab_type& slab, const Source& source,
                           const TransportSettings& s) requires wavy {
        require(surface.periodic_in(slab.width()), "section width (m)", slab.width(),
                "must hold whole wavelengths of the surface in x and y (k W / 2 pi whole numbers)");
        const double trough = surface.trough_depth();
        for (const double z : s.depths)
            require(z >= trough, "detector depth (m)", z, "must be at or below the wave's troughs (its amplitude)");
        require(slab.floor_depth() > trough, "bottom or escape depth (m)", slab.floor_depth(),
                "must be below the wave's troughs (its amplitude)");
        require(!source.returns_light(), "light source", "a traced atmosphere",
                "cannot be coupled to a surface with geometry (light leaving the water is not returned)");
    }

    /// The photon meets the surface from `side` (its first hit `h`) until it is in the water
    /// moving down (true) or in the air moving up (false: its weight goes to `left`, the
    /// ledger's entry for light leaving through the surface). Reflection or transmission is
    /// chosen with the Fresnel probability, except that on the air side, where reflected light
    /// leaves the water body for good, photons that are not analog take the expected value: the
    /// weight times R leaves and the weight times 1 - R is transmitted (so every sun photon
    /// enters through a flat surface). A wind-blown surface's tilted facet can send a photon
    /// back across the surface (reflected down on the air side, transmitted down into the air,
    /// or up in the water): it then meets the surface again, ignoring shadowing as M93's
    /// problem 5 does. After max_surface_hits hits the photon stops, its weight truncated.
    /// Under a source that returns light (a scattering atmosphere) reflected light is not gone:
    /// the choice is then always random, and a photon in the air moving up is handed to the
    /// source (LightSource::reenter), which sends it back down onto the surface (another
    /// max_surface_hits hits from there) or books where it ended.
    bool cross_surface(PhotonState& p, PhotonRng& rng, Side side, SurfaceHit h, double& left,
                       detail::BlockResult<Record>& out) const {
        const bool coupled = source_.returns_light();
        for (int hits = 1;; ++hits) {
            const bool from_air = side == Side::air;
            bool reflect;
            if (from_air && !physics_.analog() && h.reflected.z < 0.0 && !coupled && !may_hide()) {
                const double reflected = p.w * h.reflectance;
                left += reflected;  // expected value: the weight carries the transmittance
                out.eu_air += reflected;
                p.w *= 1.0 - h.reflectance;
                reflect = false;
            } else {
                reflect = rng.uniform() < h.reflectance;
            }
            p.dir = h.direction(reflect);
            const bool in_water = from_air != reflect;  // the side the photon is now on
            const bool leaves_surface = in_water ? p.dir.z > 0.0 : p.dir.z < 0.0;
            if (leaves_surface && hidden(p.dir, rng)) {  // the other waves are in its way: it meets the surface again
                if (hits == max_surface_hits) break;
                side = in_water ? Side::water : Side::air;
                h = surface_.hit(p.dir, side, rng);
                continue;
            }
            if (in_water && p.dir.z > 0.0) return true;
            if (!in_water && p.dir.z < 0.0) {
                out.eu_air += p.w;
                if (!coupled) {
                    left += p.w;
                    return false;
                }
                const SourcePhoton back = source_.reenter(p.dir, rng);
                if (!arrives(back, p.w, out)) return false;
                p.dir = back.dir;
                side = Side::air;
                h = surface_.hit(p.dir, side, rng);
                hits = 0;
                continue;
            }
            if (hits == max_surface_hits) break;
            side = in_water ? Side::water : Side::air;  // back across the surface: another facet
            h = surface_.hit(p.dir, side, rng);
        }
        out.ledger.truncated += p.w;
        return false;
    }

    /// Whether the surface may hide light leaving it (wind_blown_surface.hpp, Shadowing::smith).
    bool may_hide() const {
        if constexpr (requires { surface_.hides(); }) return surface_.hides();
        else return false;
    }
    /// Whether light leaving the surface along `dir` is hidden by the other waves (draws only
    /// where the surface may hide it).
    bool hidden(const vec3& dir, PhotonRng& rng) const {
        if constexpr (requires { surface_.hidden(dir, rng); }) return surface_.hidden(dir, rng);
        else return false;
    }

    /// The hit of a photon of the source's collimated beam: computed once where it draws no
    /// random numbers (fixed_hit_from_air, scene/surface.hpp).
    SurfaceHit sun_hit(PhotonRng& rng) const requires(!wavy) {
        return sun_hit_ ? *sun_hit_ : surface_.hit(sun_direction_, Side::air, rng);
    }
    static std::optional<SurfaceHit> fixed_sun_hit(const Surface& surface, const vec3& sun_direction) {
        if constexpr (wavy) return std::nullopt;  // met at a different facet by every photon
        else return fixed_hit_from_air(surface, sun_direction);
    }
    static constexpr int max_surface_hits = 64;

    /// At the floor: transmission out of the water body, or reflection by the bottom's BRDF
    /// (scene/bottom.hpp): weight x rho(in) in implicit capture, or survival with probability
    /// rho(in) in analog mode, then a direction drawn with pdf f_r mu_out / rho.
    bool reflect_at_bottom(PhotonState& p, PhotonRng& rng, EnergyLedger& ledger) const {
        const BottomPolicy& b = slab_.bottom();
        if (b.transmits()) {
            ledger.transmitted += p.w;
            return false;
        }
        const double rho = b.reflectance(p.dir);
        if (!survives_reflection(p, rng, rho, ledger.absorbed_bottom)) return false;
        const double u1 = rng.uniform(), u2 = rng.uniform();
        p.dir = b.reflected_direction(p.dir, u1, u2);
        p.pos.z = b.depth();
        return roulette(p, rng, ledger);
    }

    /// Moves the photon by path length s to depth z1 (its z + uz s, or 0 exactly on a flight
    /// to the surface), tallying the detectors it passes (and, with continuous absorption,
    /// attenuating its weight by exp(-int a ds)).
    void fly(PhotonState& p, double s, double z1, detail::BlockResult<Record>& out) const {
        const Flight flight{p.pos.z, z1, p.dir.z, s, p.w};
        if (physics_.continuous()) detectors_.record(flight, medium_, out.tally.data());
        else detectors_.record(flight, NoAbsorption{}, out.tally.data());
        p.pos += p.dir * s;
        p.pos.z = z1;
        if (physics_.continuous()) {
            const double w = p.w * std::exp(-medium_.optical_path(Coefficient::absorption, flight.z0, flight.uz, s));
            out.ledger.absorbed += p.w - w;
            p.w = w;
        }
    }

    /// An interaction in the water (event_physics.hpp): the scattering-order limit, absorption
    /// by the albedo, storage of the scattering event, a new direction from the phase function.
    /// False if the photon ends.
    bool interact(PhotonState& p, PhotonRng& rng, detail::BlockResult<Record>& out, MapSlot slot) const {
        if (physics_.beyond_order(p.order)) {
            out.ledger.truncated += p.w;
            return false;
        }
        double w0;
        if constexpr (depth_independent<M>) w0 = w0_;
        else w0 = albedo_at(medium_, p.pos.z);
        const Absorption<double> a = physics_.absorb(p.w, physics_.absorption_draws() ? rng.uniform() : 0.0, w0);
        out.ledger.absorbed += a.absorbed;
        if (a.ends) return false;
        p.w = a.w;
        if (slot.stores) store_event(p, rng, out, slot.batch);
        ++p.order;
        const double u_psi = rng.uniform(), u_phi = rng.uniform();
        if constexpr (depth_independent<M>) {  // (upward importance is refused for any other medium)
            // Only for a photon whose weight relative to its level is at most 1, so that no
            // weight exceeds 1 / (1 - eps) there (importance.hpp: the mixture's weights would
            // otherwise compound over many scatterings).
            if (upward_.enabled() && times_power_of_two(p.w, p.level) <= 1.0) {
                scatter_upward(p, rng, u_psi, u_phi, out.ledger);
                return roulette(p, rng, out.ledger);
            }
        }
        const BackscatterBias::Draw draw = bias_.draw(u_psi);
        const ScatteringAngles<double> angles = EventPhysics::angles(medium_, p.pos.z, draw.u, u_phi);
        p.dir = rotate_direction(p.dir, angles.cos_psi, angles.phi);
        reweight(p, draw.weight, out.ledger);
        return roulette(p, rng, out.ledger);
    }

    /// A biased draw's weight factor (1 / q, importance.hpp) on the photon, booked as roulette's.
    static void reweight(PhotonState& p, double factor, EnergyLedger& ledger) {
        if (factor == 1.0) return;
        const double w = p.w * factor;
        (w > p.w ? ledger.roulette_gained : ledger.roulette_killed) += std::abs(w - p.w);
        p.w = w;
    }

    /// The new direction under upward importance (importance.hpp): from the lobe about straight
    /// up with probability eps (one more uniform), else from the phase function; the weight
    /// times p / q, p the phase function's density of the new direction.
    void scatter_upward(PhotonState& p, PhotonRng& rng, double u_psi, double u_phi, EnergyLedger& ledger) const
        requires depth_independent<M>
    {
        const auto phase_angles = [&](double u1, double u2) {
            const ScatteringAngles<double> a = EventPhysics::angles(medium_, p.pos.z, u1, u2);
            return PhaseDirection{a.cos_psi, a.phi};
        };
        const auto density = [&](double cos_psi) { return medium_.phase().pdf(cos_psi); };
        const UpwardImportance::Scatter s = upward_.scatter(p.dir, rng.uniform(), u_psi, u_phi, phase_angles, density);
        p.dir = s.dir;
        reweight(p, s.weight, ledger);
    }

    /// The settings' upward importance (importance.hpp), for homogeneous water (the phase
    /// function's density at the scattering point: one phase function); refused for any other.
    static UpwardImportance upward_importance(const TransportSettings& s) {
        if (s.upward_importance == 0.0) return {};
        if constexpr (depth_independent<M>) {
            return UpwardImportance(s.upward_importance, s.upward_lobe);
        } else {
            reject("upward importance", s.upward_importance, "needs homogeneous water (one phase function)");
        }
    }

    /// The settings' backscatter bias (importance.hpp) for a depth-independent medium whose
    /// phase function names its backward uniforms; refused for any other.
    static BackscatterBias backscatter_bias(const M& medium, const TransportSettings& s) {
        if (s.backscatter_bias == 0.0) return {};
        if constexpr (BackscatterBiasable<M>) {
            const auto [begin, end] = medium.phase().backward_uniforms();
            return BackscatterBias(s.backscatter_bias, begin, end);
        } else {
            reject("backscatter bias", s.backscatter_bias,
                   "needs homogeneous water whose phase function names its backward uniforms (Henyey-Greenstein, a table, Fournier-Forand)");
        }
    }

    /// Stores the scattering event by the equal-flux rule (EventPhysics::keeps). With depth or
    /// upward importance, EventPhysics::copies records, each carrying Phi / (I(z) D(mu))
    /// (importance.hpp).
    /// Events below the map's depth are not stored; they draw their uniform all the same, so
    /// that the photon's later draws do not depend on that depth.
    void store_event(const PhotonState& p, PhotonRng& rng, detail::BlockResult<Record>& out,
                     std::uint8_t map_batch) const {
        const Record rec = record_of(p, map_batch);
        if (!importance_on_ && !upward_.enabled()) {
            const double u = physics_.storage_draws() ? rng.uniform() : 0.0;
            if (p.w > 1.0) {  // (after a glossy reflection) floor(w) records, one more with probability frac(w)
                const double copies = EventPhysics::copies(p.w, 1.0, u);
                if (physics_.in_map(p.pos.z))
                    for (double i = 0; i < copies; ++i) out.records.push_back(rec);
            } else if (physics_.keeps(p.w, u, p.pos.z)) {
                out.records.push_back(rec);
            }
            return;
        }
        // The flux a record carries is set by its stored (rounded) depth and direction: use the same here.
        const double importance = record_importance(levels_, upward_, rec.position().z, rec.direction().z);
        const double copies = EventPhysics::copies(p.w, importance, rng.uniform());
        if (!physics_.in_map(p.pos.z)) return;
        for (double i = 0; i < copies; ++i) out.records.push_back(rec);
    }

    /// The record of a scattering event at the photon's position (wrapped into the section)
    /// with its direction before scattering.
    Record record_of(const PhotonState& p, std::uint8_t map_batch) const {
        const vec3 wrapped{slab_.wrap(p.pos.x), slab_.wrap(p.pos.y), p.pos.z};
        return Record::make(wrapped, p.dir, band_index{s_.band}, map_batch);
    }

    /// Russian roulette on the photon's weight (its cumulative survival probability),
    /// relative to its importance level (w I: the weight an unsplit photon would have).
    bool roulette(PhotonState& p, PhotonRng& rng, EnergyLedger& ledger) const {
        if (!physics_.roulette_due(times_power_of_two(p.w, p.level))) return true;
        if (rng.uniform() < s_.roulette_survival) {
            const double w = p.w / s_.roulette_survival;
            ledger.roulette_gained += w - p.w;
            p.w = w;
            return true;
        }
        ledger.roulette_killed += p.w;
        return false;
    }

    TransportResult<Record> merge(const std::vector<detail::Block>& blocks,
                                  const std::vector<detail::BlockResult<Record>>& results,
                                  std::vector<Record> records) const {
        const std::size_t nd = detectors_.size();
        std::vector<std::vector<IrradianceTally>> batch_tally(s_.batches, std::vector<IrradianceTally>(nd));
        std::vector<double> batch_bottom(s_.batches, 0.0), batch_photons(s_.batches, 0.0);
        std::vector<std::vector<double>> batch_bins(s_.batches, std::vector<double>(grid_.size(), 0.0));
        std::vector<std::array<double, 3>> batch_above(s_.batches, {0.0, 0.0, 0.0});
        TransportResult<Record> r;
        r.records = std::move(records);
        for (std::size_t i = 0; i < blocks.size(); ++i) {  // fixed order: deterministic sums
            const auto& blk = blocks[i];
            const auto& res = results[i];
            r.surface_photons.insert(r.surface_photons.end(), res.surface.begin(), res.surface.end());
            for (std::size_t d = 0; d < nd; ++d)
                for (int k = 0; k < 4; ++k) batch_tally[blk.batch][d][k] += res.tally[d][k];
            batch_bottom[blk.batch] += res.bottom_ed;
            for (std::size_t k = 0; k < grid_.size(); ++k) batch_bins[blk.batch][k] += res.bottom_bins[k];
            batch_above[blk.batch][0] += res.ed_direct;
            batch_above[blk.batch][1] += res.ed_diffuse;
            batch_above[blk.batch][2] += res.eu_air;
            batch_photons[blk.batch] += static_cast<double>(blk.end - blk.begin);
            r.ledger += res.ledger;
        }
        const double ed0 = source_.plane_irradiance();  // what the photons shot represent
        std::vector<double> values(s_.batches);
        auto estimate = [&](auto&& value_of_batch) {
            for (unsigned b = 0; b < s_.batches; ++b) values[b] = ed0 * value_of_batch(b) / batch_photons[b];
            return batch_estimate(values);
        };
        r.depths = detectors_.depths();
        r.irradiance.resize(nd);
        for (std::size_t d = 0; d < nd; ++d)
            for (int k = 0; k < 4; ++k) r.irradiance[d][k] = estimate([&](unsigned b) { return batch_tally[b][d][k]; });
        r.bottom_ed = estimate([&](unsigned b) { return batch_bottom[b]; });
        r.bottom_ed_bins.resize(grid_.size());
        const double area_ratio = grid_.area_ratio();
        for (std::size_t k = 0; k < grid_.size(); ++k)
            r.bottom_ed_bins[k] = estimate([&](unsigned b) { return area_ratio * batch_bins[b][k]; });
        r.above.ed_direct = estimate([&](unsigned b) { return batch_above[b][0]; });
        r.above.ed_diffuse = estimate([&](unsigned b) { return batch_above[b][1]; });
        r.above.eu = estimate([&](unsigned b) { return batch_above[b][2]; });
        const double n = static_cast<double>(s_.photons);
        for (double* f : r.ledger.entries()) *f /= n;
        r.photons = s_.photons;
        r.map_photons = s_.map_photons;
        r.batches = s_.batches;
        r.map_flux = {s_.map_photons ? ed0 * slab_.width() * slab_.width() / static_cast<double>(s_.map_photons) : 0.0,
                      levels_, s_.map_depth, upward_};
        return r;
    }

    const M& medium_;
    slab_type slab_;
    Surface surface_;
    Source source_;
    TransportSettings s_;
    Geometry geometry_;
    BottomGrid grid_;  ///< Ed on the bottom per bin (settings.bottom_bins)
    Detector detectors_;
    EventPhysics physics_;  ///< the per-event rules of the settings
    bool importance_on_;
    ImportanceLevels levels_;
    BackscatterBias bias_;  ///< the scattering angle's biased draw (off by default)
    UpwardImportance upward_;  ///< the direction's draw from a lobe about straight up, and storage by direction (off by default)
    double w0_;  ///< the albedo of a depth-independent medium
    vec3 sun_direction_;                 ///< of the photons of the source's collimated beam
    std::optional<SurfaceHit> sun_hit_;  ///< their hit, where it is the same for all (a flat surface)
};

/// A first pass: built from a medium, the slab, a surface, a source and the settings, and run
/// into a TransportResult (the records into the storage given, cleared first). PhotonTracer
/// traces one photon at a time; LaneTracer (lane_tracer.hpp) schedules photons in SIMD lanes
/// with the same per-event rules (event_physics.hpp).
template <class T>
concept FirstPassTracer =
    std::constructible_from<T, const typename T::medium_type&, const typename T::slab_type&, const typename T::surface_type&,
                            const typename T::source_type&, TransportSettings> &&
    requires(const T& tracer, std::vector<typename T::record_type> storage) {
        { tracer.run(std::move(storage)) } -> std::same_as<TransportResult<typename T::record_type>>;
    };

}  // namespace secchi
