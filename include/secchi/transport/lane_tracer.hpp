#pragma once
// The first pass with photons in lanes: PhotonTracer's physics (manual 3.3: free paths of
// eq. 3.17, absorption or scattering by the albedo, equal-flux storage, Fresnel surface,
// bottom, detectors, energy ledger) traced for lanes::lane_width photons at once. The step
// every photon takes between events (free path, flight, absorption, storage, phase
// sampling, rotation) runs on SIMD vectors, one photon per lane, through the same rules
// PhotonTracer applies to one photon (EventPhysics, event_physics.hpp: written once for both);
// what only some photons meet (surface, bottom, a detector's plane, the end of a photon and
// the start of the next) goes through PhotonTracer's own per-photon functions, lane by lane;
// roulette and depth importance's level changes through PhotonTracer's arithmetic lane by
// lane, their uniforms from the lanes' next Philox blocks computed at once (next_words). The
// two differ only in their schedule and share one signature (the FirstPassTracer concept).
//
// Same problem, same estimates (within their standard errors; tests/test_lane_tracer.cpp),
// not the same photons: each step draws one Philox block (four uniforms: free path,
// absorption or storage, psi, phi) from the photon's stream, and a per-photon event draws
// from the stream's next block, so the random numbers a photon uses differ from
// PhotonTracer's. Still bit-identical for any thread count: a block of photons always
// fills the lanes in the same order, and records and sums follow the lanes' order. The
// photons' histories are the same for any lane count (any target); the records' order and
// the sums' last bits are not (core/lanes.hpp).
//
// Depth importance (importance.hpp) as PhotonTracer's: at the start of every step a photon
// whose depth lies at another level than its own is split or rouletted (PhotonTracer's
// change_level_to, lane by lane), its split-off copies queued, each with its depth's span, and
// taken by the next lanes that come free before new photons are launched; a scattering event
// is stored with probability w I(z) (copies where w I > 1, lane by lane), I(z) at the record's
// stored depth; roulette acts on w 2^L. Whether a depth keeps its lane's level is two
// comparisons per lane with the depths where its level holds (ImportanceLevels::span, kept per
// lane and narrowed by a relative 1e-6 so that the record's rounded depth shares it:
// inner_span); a lane outside looks its level up. Without depth importance the step is
// compiled without any of this. A copy draws from its own stream: the parent's stream from a
// Philox block derived from the parent's next block and the copy's number (split_block), so
// that its history does not depend on which lane takes it.
//
// Backscatter bias (importance.hpp) as PhotonTracer's, in the vectors: the scattering angle's
// uniform drawn from the biased density and the weight times 1 / q (BackscatterBiasOf<Real>:
// in float lanes its bounds and weights in float); an event whose weight exceeds 1 stores
// further copies of its record, as with depth importance.
//
// Depth-varying water (a Medium that is not depth_independent, e.g. StratifiedWater): the
// step stays in the vectors but for what depends on depth, which goes lane by lane in double
// through the medium, as PhotonTracer computes it for one photon: the free path
// (Medium::distance_to of -ln u, manual 3.3.4), the albedo at the event's depth, the optical
// path of continuous absorption along a flight and to a detector's plane (Medium::optical_path;
// its exponential then in the vectors, as in homogeneous water), and the scattering direction
// from the depth's mixture of phase functions (eq. 5.5-5.6). Homogeneous water computes these
// in the vectors from its constants.
//
// Without objects in the water (scene/geometry.hpp: LaneTracer has no geometry parameter; its
// base is PhotonTracer with NoGeometry), with weighted photons where depth importance is on
// (absorption implicit or continuous), without upward importance or a surface map; use
// PhotonTracer for those. Phase functions with a per-lane inverse CDF (cos_psi(Reals), e.g.
// Henyey-Greenstein, or a table with the trapezoid convention such as Petzold) sample in the
// vectors; any other samples lane by lane.
//
// In lanes of doubles (LaneTracer<M, R>) or of floats (FloatLaneTracer<M, R> =
// LaneTracer<M, R, float>: twice the lanes per vector, 8 with AVX2). In float lanes a step's
// uniforms are the top 24 bits of the same Philox words (uniform_float_from_bits), so a
// photon's history follows the double lanes' one closely until rounding sends it another
// way; positions, directions and weights are rounded to float between events, each a
// relative 6e-8 (the map's records hold float positions anyway); the kernels (log, exp,
// sin_cos, rotation, HG, the direction bytes) are within bounds set by float rounding
// (tests/test_lane_tracer.cpp). A flight to the floor ends on float(floor depth), and a
// detector plane on the bottom is the next float shallower, so the bottom's plane counts
// every photon arriving (tested against the ledger). The tallies are summed in float per
// lane for at most flush_steps steps, then in double. The canonical problems 1 and 2 come
// out within 0.04 combined standard errors of the double lanes' (BENCHMARKS.md).
#include "secchi/core/config.hpp"
#include "secchi/core/lanes.hpp"
#include "secchi/map/record_lanes.hpp"
#include "secchi/transport/tracer.hpp"
#include <cmath>
#include <cstdint>
#include <vector>

#if SECCHI_HAS_LANES
namespace secchi::SECCHI_ISA {

/// exp(-tau) per lane for optical paths tau >= 0 (lanes::exp, in Real): the transmittance of
/// flights, LaneAbsorption's and LaneMediumAbsorption's. In floats within a relative 4 float ulp
/// of exp(-tau) (lanes::exp), 0 where tau > 87; in doubles exp_table's value (core/math.hpp), 0
/// where tau > 707 (e^-707 < 1e-307).
template <class Real>
SECCHI_KERNEL lanes::LanesOf<Real> transmittance_of_optical_path(const lanes::LanesOf<Real>& tau) {
    using V = lanes::LanesOf<Real>;
    const V x = -tau;
    if constexpr (std::same_as<Real, float>) {
        return lanes::exp(x);
    } else {  // lanes::exp holds exp_table's values inside (-708, 709) only
        V out = lanes::exp(lanes::stdx::max(x, V(-707.0)));
        lanes::stdx::where(x < -707.0, out) = 0.0;
        return out;
    }
}

/// Absorption along straight flights in homogeneous water, one flight per lane: the
/// transmittance exp(-a s) over path lengths s (transmittance_of_optical_path). LaneTracer's
/// weights decay by it with continuous absorption, and so do its detectors' scores on the way to
/// their planes (IrradiancePlanes::record_lanes). In floats within a relative (a s + 8) 2^-24 of
/// exp(-a s) (the product a s rounds once; lanes::exp is within 4 float ulp of exp). (A flight
/// is at most a free path long, -ln u / b with continuous absorption, so a s is large only in
/// water that absorbs far more than it scatters.)
template <class Real>
struct LaneAbsorption {
    Real a;  ///< absorption coefficient (1/m)
    /// exp(-a s) over flights of length s per lane (from any depth z0, along any direction uz).
    [[nodiscard]] SECCHI_KERNEL lanes::LanesOf<Real> transmittance(const lanes::LanesOf<Real>& /*z0*/,
                                                                   const lanes::LanesOf<Real>& /*uz*/,
                                                                   const lanes::LanesOf<Real>& s) const {
        return transmittance_of_optical_path<Real>(a * s);
    }
};

/// Absorption along straight flights in depth-varying water (a Medium whose coefficients
/// depend on depth), one flight per lane: exp(-int_0^s a(z0 + uz t) dt), the optical path from
/// the medium (Medium::optical_path, exact for StratifiedWater's linear profiles: manual 3.3.4)
/// lane by lane in double, as PhotonTracer computes it for one photon, rounded to Real, and its
/// exponential in the vectors (transmittance_of_optical_path). (Not libm's exp lane by lane: a
/// function that returns a vector and calls it enters libm's SSE code with the vector
/// registers' upper halves in use, which Intel cores pay for on every instruction.)
template <Medium M, class Real>
struct LaneMediumAbsorption {
    const M& medium;
    [[nodiscard]] lanes::LanesOf<Real> transmittance(const lanes::LanesOf<Real>& z0, const lanes::LanesOf<Real>& uz,
                                                     const lanes::LanesOf<Real>& s) const {
        const lanes::LanesOf<Real> tau([&](auto l) {
            return static_cast<Real>(medium.optical_path(Coefficient::absorption, z0[l], uz[l], s[l]));
        });
        return transmittance_of_optical_path<Real>(tau);
    }
};

/// Real: the lanes' precision. double by default; float doubles the lanes per vector (8 with
/// AVX2) for about 1.5 times the speed (BENCHMARKS.md), with positions,
/// directions and weights rounded to float between events (a relative 6e-8; the map's records
/// hold floats anyway), and detector tallies summed in float over at most flush_steps steps
/// per lane before they join the block's double sums.
/// Surface: the air-water surface policy (scene/surface.hpp), met lane by lane as PhotonTracer does.
/// Source: the light source (scene/source.hpp), whose photons (and, for a traced atmosphere,
/// the light it sends back) are followed lane by lane by PhotonTracer's launch and surface
/// crossing.
/// Detector: the irradiance detectors (IrradianceDetector, with record_lanes for
/// flights in lanes), IrradiancePlanes by default.
/// BottomPolicy: the bottom (BottomModel, scene/bottom.hpp), met lane by lane as PhotonTracer does.
template <Medium M, PhotonRecord Record, class Real = double, AirWaterSurface Surface = FlatSurface,
          LightSource Source = SunAndSky, IrradianceDetector Detector = IrradiancePlanes,
          BottomModel BottomPolicy = Bottom>
    requires std::default_initializable<Record> &&
             (std::same_as<Real, double> || std::same_as<Real, float>)
class LaneTracer : private PhotonTracer<M, Record, Surface, Source, Detector, BottomPolicy> {
    using Base = PhotonTracer<M, Record, Surface, Source, Detector, BottomPolicy>;
    using typename Base::PhotonState;
    using Reals = lanes::LanesOf<Real>;
    using Mask = typename Reals::mask_type;
    using Vec3 = Vec3Of<Reals>;
    static constexpr int width = lanes::width_of<Real>;
    static constexpr auto aligned = lanes::aligned;
    static constexpr bool in_floats = std::same_as<Real, float>;
    /// Float lanes add their tallies and absorbed weight into doubles every flush_steps steps
    /// (so each float sum has at most that many terms: relative rounding below 64 x 6e-8).
    static constexpr std::uint64_t flush_steps = 64;

public:
    using typename Base::medium_type, typename Base::record_type, typename Base::surface_type,
        typename Base::source_type, typename Base::detector_type, typename Base::slab_type;
    using real_type = Real;  ///< the lanes' precision

    /// The photons come from `source` (scene/source.hpp).
    LaneTracer(const M& medium, const slab_type& slab, const Surface& surface, const Source& source,
               TransportSettings settings)
        : Base(medium, slab, surface, source, supported(std::move(settings))),
          key_({static_cast<std::uint32_t>(this->s_.seed), static_cast<std::uint32_t>(this->s_.seed >> 32)}),
          path_coefficient_(static_cast<Real>(
              medium.coefficient(this->physics_.path_coefficient(), 0.0))),
          absorption_coefficient_(static_cast<Real>(medium.coefficient(Coefficient::absorption, 0.0))),
          spans_(lane_spans(this->levels_)), lane_bias_(Base::bias_.template in<Real>()) {}

    /// A collimated sun and a uniform sky beside it (SunAndSky), as PhotonTracer's.
    LaneTracer(const M& medium, const slab_type& slab, const Surface& surface, const CollimatedSun& sun,
               TransportSettings settings, UniformSky sky = UniformSky{})
        requires std::same_as<Source, SunAndSky>
        : LaneTracer(medium, slab, surface, SunAndSky(sun, sky), std::move(settings)) {}

    /// As PhotonTracer::run: `storage` (cleared first) receives the map's records.
    TransportResult<Record> run(std::vector<Record> storage = {}) const {
        return merge_part(run_part(BlockRange{}, std::move(storage)));
    }

    /// As PhotonTracer::run_part: only the blocks `range`.
    FirstPassPart<Record> run_part(BlockRange range, std::vector<Record> storage = {}) const {
        return this->trace_part(
            [this](const detail::Block& block, detail::BlockResult<Record>& out) { trace_block(block, out); }, range,
            std::move(storage));
    }
    using Base::merge_part;

private:
    static TransportSettings supported(TransportSettings s) {
        require(!s.importance.enabled() || s.absorption != AbsorptionMode::analog, "depth importance (cosine)",
                s.importance.cosine, "needs weighted photons in LaneTracer (absorption implicit or continuous, not analog)");
        require(!s.surface_map, "surface map", "on", "is not kept by LaneTracer; use PhotonTracer");
        require(s.upward_importance == 0.0, "upward importance", s.upward_importance,
                "is not drawn by LaneTracer; use PhotonTracer");
        return s;
    }

    /// A span as the lanes keep it: inner bounds, level and I(z) in Real.
    struct LaneSpan {
        Real lo, hi, level, factor;
    };

    /// A photon split off by depth importance, waiting for a lane: the parent's lane values
    /// after the split (its weight already divided), its stream and block (split_block), its
    /// map slot and its depth's span (the parent's: a lane taking the copy then has no span to
    /// look up). Held as the lanes hold them, a copy goes into a lane without conversions.
    struct Lanes;
    struct Copy {
        Real x, y, z, dx, dy, dz, w, order, level, level_scale;
        LaneSpan span;
        std::uint64_t photon, block;
        bool stores;
        std::uint8_t batch;

        /// Lane l's photon, its stream starting at `first_block`; constructed in the queue
        /// (a Copy built apart and then copied whole is read back by wide loads from the
        /// narrower stores that built it: a stall of the store forwarding).
        Copy(const Lanes& L, int l, std::uint64_t first_block)
            : x(L.x[l]), y(L.y[l]), z(L.z[l]), dx(L.dx[l]), dy(L.dy[l]), dz(L.dz[l]), w(L.w[l]), order(L.order[l]),
              level(L.level[l]), level_scale(L.level_scale[l]),
              span{L.span_lo[l], L.span_hi[l], L.span_level[l], L.span_factor[l]}, photon(L.photon[l]),
              block(first_block), stores(L.stores[l]), batch(L.batch[l]) {}
    };

    /// The photons in the lanes, one per lane, as structure of arrays.
    struct Lanes {
        alignas(64) Real x[width], y[width], z[width], dx[width], dy[width], dz[width], w[width];
        alignas(64) Real order[width];     ///< scattering order (exact below 2^24 in a float)
        alignas(64) Real absorbed[width];  ///< weight absorbed in the water, per lane (summed at the end)
        /// The backscatter bias's weight changes, per lane (summed at the end): added where its
        /// factor is above 1, removed where below (the ledger's roulette entries, as PhotonTracer's).
        alignas(64) Real bias_gained[width], bias_killed[width];
        alignas(64) bool alive[width];
        alignas(64) bool stores[width];      ///< whether the photon's events go into the map
        std::uint8_t batch[width];           ///< and in which batch
        std::uint64_t photon[width];         ///< the photon's index: its random stream
        std::uint64_t block[width];          ///< its stream's next Philox block
        alignas(64) Real level[width];     ///< depth-importance level L of the photon (exact in Real)
        alignas(64) Real level_scale[width];  ///< 2^L: roulette acts on w 2^L (kept with depth importance)
        /// The depths [span_lo, span_hi) where the level is span_level and I(z) span_factor
        /// (ImportanceLevels::span narrowed by span_margin: inner_span, importance.hpp).
        alignas(64) Real span_lo[width], span_hi[width], span_level[width], span_factor[width];
        std::vector<std::array<Reals, 4>> tally;  ///< per depth, per lane (summed at the end)
        std::vector<Copy> copies;            ///< split-off photons waiting for a lane (taken last first)
    };

    /// The first Philox blocks of the block's next photons (up to one per lane), computed
    /// together in the vectors: launching a photon then starts from its block 0 here.
    struct Launches {
        std::uint64_t first = 0, count = 0, used = 0;
        std::uint32_t bits[4][width];
    };

    /// The four uniforms of one step, per lane.
    struct StepUniforms {
        alignas(64) Real path[width], absorb_or_store[width], psi[width], phi[width];
    };

    void trace_block(const detail::Block& block, detail::BlockResult<Record>& out) const {
        Lanes lanes{};
        lanes.tally.assign(this->detectors_.size(), {Reals(Real(0)), Reals(Real(0)), Reals(Real(0)), Reals(Real(0))});
        Launches launches;
        launches.first = block.begin;
        for (int l = 0; l < width; ++l) start(lanes, l, launches, block.end, out);
        if (this->importance_on_)
            steps<true>(lanes, launches, block.end, out);
        else
            steps<false>(lanes, launches, block.end, out);
        flush(lanes, out);
    }

    /// Steps until every lane is parked; the step compiled with or without depth importance.
    template <bool with_importance>
    SECCHI_KERNEL void steps(Lanes& L, Launches& next, std::uint64_t end, detail::BlockResult<Record>& out) const {
        for (std::uint64_t steps = 1; any_of(Mask(L.alive, aligned)); ++steps) {
            step<with_importance>(L, next, end, out);
            if (in_floats && steps % flush_steps == 0) flush(L, out);
        }
    }

    /// Adds the lanes' absorbed weight, the bias's weight changes and the tallies to the
    /// block's sums (in lane order), and zeroes them.
    static void flush(Lanes& L, detail::BlockResult<Record>& out) {
        const auto add = [](double& sum, Real* lane_sums) {
            for (int l = 0; l < width; ++l) sum += lane_sums[l];
            std::fill(lane_sums, lane_sums + width, Real(0));
        };
        add(out.ledger.absorbed, L.absorbed);
        add(out.ledger.roulette_gained, L.bias_gained);
        add(out.ledger.roulette_killed, L.bias_killed);
        for (std::size_t i = 0; i < L.tally.size(); ++i)
            for (int k = 0; k < 4; ++k) {
                for (int l = 0; l < width; ++l) out.tally[i][k] += L.tally[i][k][l];
                L.tally[i][k] = Reals(Real(0));
            }
    }

    /// Puts the block's next photon that enters the water into lane l (PhotonTracer::launch),
    /// or parks the lane when the block has none left: a parked lane has zero weight, stores
    /// nothing, and every per-lane action skips it.
    void start(Lanes& L, int l, Launches& next, std::uint64_t end, detail::BlockResult<Record>& out) const {
        if (!L.copies.empty()) {
            take_copy(L, l, L.copies.back());
            L.copies.pop_back();
            return;
        }
        while (next.used < next.count || next.first + next.count < end) {
            if (next.used == next.count) prepare(next, end);
            const std::uint64_t u = next.used++, i = next.first + u;
            PhotonRng rng(this->s_.seed, i, 0, {next.bits[0][u], next.bits[1][u], next.bits[2][u], next.bits[3][u]});
            PhotonState p;
            if (!this->launch(p, rng, out)) continue;
            put(L, l, p);
            L.photon[l] = i;
            L.block[l] = rng.next_block();
            const auto slot = this->map_slot(i);
            L.stores[l] = slot.stores;
            L.batch[l] = slot.batch;
            L.alive[l] = true;
            return;
        }
        put(L, l, PhotonState{{0.0, 0.0, 0.5 * this->slab_.floor_depth()}, {0.0, 0.0, 1.0}, 0.0, 0});
        L.photon[l] = L.block[l] = 0;
        L.stores[l] = false;
        L.batch[l] = 0;
        L.alive[l] = false;
    }

    /// Lane l takes copy c (as put() of its photon would: a copy's depth lies in its span
    /// unless it lay within span_margin of a bound when split; change_levels).
    void take_copy(Lanes& L, int l, const Copy& c) const {
        L.x[l] = c.x, L.y[l] = c.y, L.z[l] = c.z;
        L.dx[l] = c.dx, L.dy[l] = c.dy, L.dz[l] = c.dz;
        L.w[l] = c.w, L.order[l] = c.order, L.level[l] = c.level, L.level_scale[l] = c.level_scale;
        set_span(L, l, c.span);
        if (!in_span(L, l)) look_up_span(L, l);
        L.photon[l] = c.photon;
        L.block[l] = c.block;
        L.stores[l] = c.stores;
        L.batch[l] = c.batch;
        L.alive[l] = true;
    }

    static PhotonState photon(const Lanes& L, int l) {
        return {{L.x[l], L.y[l], L.z[l]}, {L.dx[l], L.dy[l], L.dz[l]}, L.w[l], static_cast<unsigned>(L.order[l]),
                static_cast<int>(L.level[l])};
    }
    /// Lane l takes photon p (and, with depth importance, 2^L and the span of its depth where
    /// they changed: a span is a property of the depth, whichever photon is there).
    void put(Lanes& L, int l, const PhotonState& p) const {
        const auto real = [](double v) { return static_cast<Real>(v); };
        L.x[l] = real(p.pos.x), L.y[l] = real(p.pos.y), L.z[l] = real(p.pos.z);
        L.dx[l] = real(p.dir.x), L.dy[l] = real(p.dir.y), L.dz[l] = real(p.dir.z);
        L.w[l] = real(p.w);
        L.order[l] = static_cast<Real>(p.order);
        const Real level = static_cast<Real>(p.level);
        if (!this->importance_on_) {
            L.level[l] = level;
            return;
        }
        if (level != L.level[l] || L.level_scale[l] == Real(0)) {  // (0: a lane's first photon)
            L.level[l] = level;
            L.level_scale[l] = static_cast<Real>(times_power_of_two(1.0, p.level));
        }
        if (!in_span(L, l)) look_up_span(L, l);
    }

    /// How much narrower than ImportanceLevels::span a lane's span is kept, relative to the
    /// bound (inner_span, importance.hpp): more than a depth's change when a record stores it
    /// (float: 6e-8), so that a depth inside the kept span is stored at a depth of its level.
    static constexpr double span_margin = 1e-6;

    /// Every span of the levels, made once (spans_).
    static std::vector<LaneSpan> lane_spans(const ImportanceLevels& levels) {
        std::vector<LaneSpan> spans;
        for (std::uint32_t j = 0; j < levels.span_count(); ++j) {
            const auto span = levels.span_at(j);
            const InnerSpan<Real> inner = inner_span<Real>(span, span_margin);
            spans.push_back({inner.lo, inner.hi, static_cast<Real>(span.level), static_cast<Real>(span.factor)});
        }
        return spans;
    }

    /// Lane l's span from its depth (ImportanceLevels::index_of: the levels' guide).
    [[gnu::noinline]] void look_up_span(Lanes& L, int l) const {
        set_span(L, l, spans_[this->levels_.index_of(static_cast<double>(L.z[l]))]);
    }
    static void set_span(Lanes& L, int l, const LaneSpan& span) {
        L.span_lo[l] = span.lo;
        L.span_hi[l] = span.hi;
        L.span_level[l] = span.level;
        L.span_factor[l] = span.factor;
    }

    /// Whether lane l's depth lies in its kept span.
    static bool in_span(const Lanes& L, int l) { return L.z[l] >= L.span_lo[l] && L.z[l] < L.span_hi[l]; }
    /// Whether each lane's depth lies in its kept span.
    static Mask in_span(const Lanes& L) {
        const Reals z(L.z, aligned);
        return z >= Reals(L.span_lo, aligned) && z < Reals(L.span_hi, aligned);
    }

    /// The first Philox block of copy i (1, 2, ...) of a photon split when its stream's next
    /// block was `next`: SplitMix64's finaliser (Steele, Lea and Flood 2014) of the pair, in
    /// the upper half of the 64-bit block counter, where no launched photon's own blocks reach
    /// (they count up from 0). A copy's copies derive theirs from its blocks in the same way.
    static std::uint64_t split_block(std::uint64_t next, std::uint64_t i) {
        std::uint64_t z = next + i * 0x9E3779B97F4A7C15ull;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return (z ^ (z >> 31)) | (std::uint64_t{1} << 63);
    }

    /// Depth importance at the start of a step (PhotonTracer::follow's change_level): every
    /// lane whose depth lies at another level than its photon's is split (the copies queued)
    /// or rouletted; a lane whose photon ends takes the next, which is checked in turn; lanes
    /// left without a photon take queued copies. A lane's depth level is its span's (looked up
    /// first where the depth has left it), or computed where the depth lies within span_margin
    /// of a bound. The roulettes' uniforms come from the moved lanes' next blocks at once
    /// (next_words).
    [[gnu::noinline]] void change_levels(Lanes& L, Launches& next, std::uint64_t end,
                                         detail::BlockResult<Record>& out) const {
        alignas(64) std::uint32_t word[width];
        for (Mask check = Mask(L.alive, aligned); any_of(check);) {
            check = check && Mask(L.alive, aligned);
            lanes::for_each(check && !in_span(L), [&](int l) { look_up_span(L, l); });
            const Mask spanned = in_span(L);
            const Mask moved = check && !(spanned && Reals(L.span_level, aligned) == Reals(L.level, aligned));
            check = Mask(false);
            if (none_of(moved)) continue;
            next_words(L, moved && !(spanned && Reals(L.span_level, aligned) > Reals(L.level, aligned)), word);
            lanes::for_each(moved, [&](int l) {
                const int level = spanned[l] ? static_cast<int>(L.span_level[l]) : this->levels_.level(L.z[l]);
                change_lane_level(L, l, level, word[l], out.ledger);
                if (!L.alive[l]) {
                    start(L, l, next, end, out);
                    check[l] = L.alive[l];
                }
            });
            if (L.copies.empty()) continue;
            for (int l = 0; l < width && !L.copies.empty(); ++l)
                if (!L.alive[l]) {
                    start(L, l, next, end, out);
                    check[l] = true;
                }
        }
    }

    /// PhotonTracer::change_level_to on lane l's photon, its uniform (if it needs one: a level
    /// lower than its photon's) from `word`, the first word of the lane's next block: the
    /// photon split into 2^k (k = the levels' difference, at most 2^20 at once) of weight
    /// w / 2^k, the copies queued, or rouletted with survival 2^k (k < 0) and weight w / 2^k.
    /// PhotonTracer's arithmetic in double, so that the lanes give its bits.
    void change_lane_level(Lanes& L, int l, int level, std::uint32_t word, EnergyLedger& ledger) const {
        const int k = level - static_cast<int>(L.level[l]);
        if (k == 0) return;
        const double w = static_cast<double>(L.w[l]);
        if (k > 0) {
            const int split = std::min(k, 20);
            set_level(L, l, static_cast<int>(L.level[l]) + split);
            L.w[l] = static_cast<Real>(times_power_of_two(w, -split));
            for (std::uint64_t i = 1; i < (std::uint64_t{1} << split); ++i)
                L.copies.emplace_back(L, l, split_block(L.block[l], i));
            return;
        }
        set_level(L, l, level);
        survive_or_end(L, l, w, times_power_of_two(1.0, k), word, ledger);  // I_new / I_old < 1
    }

    /// Russian roulette on lane l's photon of weight w: it survives with probability p (its
    /// uniform from `word`, the lane's next block), its weight w / p, or ends; the ledger's
    /// roulette entries as PhotonTracer's.
    static void survive_or_end(Lanes& L, int l, double w, double p, std::uint32_t word, EnergyLedger& ledger) {
        ++L.block[l];  // the uniform's block
        if (uniform_from_bits(word) < p) {
            ledger.roulette_gained += w / p - w;
            L.w[l] = static_cast<Real>(w / p);
        } else {
            ledger.roulette_killed += w;
            L.alive[l] = false;
        }
    }

    /// Lane l's photon's level and 2^level.
    static void set_level(Lanes& L, int l, int level) {
        L.level[l] = static_cast<Real>(level);
        L.level_scale[l] = static_cast<Real>(times_power_of_two(1.0, level));
    }

    /// The first 32-bit word of the next Philox block of each lane in `need` (the next draw of
    /// a PhotonRng on the lane's stream): every lane's at once where Philox runs in the
    /// vectors, else lane by lane.
    void next_words(const Lanes& L, const Mask& need, std::uint32_t* word) const {
        if (none_of(need)) return;
#if SECCHI_PHILOX_VECTOR
        alignas(64) std::uint32_t unused[3][width];
        lanes::philox_words<width>(L.block, L.photon, key_, {word, unused[0], unused[1], unused[2]});
#else
        lanes::for_each(need, [&](int l) { word[l] = philox_block(L.block[l], L.photon[l], key_.words)[0]; });
#endif
    }

    /// PhotonTracer::roulette on lane l's photon (due where w 2^L falls below the threshold,
    /// checked again in double), its uniform from `word` as change_lane_level's.
    void roulette_lane(Lanes& L, int l, std::uint32_t word, EnergyLedger& ledger) const {
        const double w = static_cast<double>(L.w[l]);
        if (this->physics_.roulette_due(times_power_of_two(w, static_cast<int>(L.level[l]))))
            survive_or_end(L, l, w, this->s_.roulette_survival, word, ledger);
    }

    /// Runs a per-photon event `event(p, rng) -> bool` (false: the photon ends) on lane l's
    /// photon, drawing from its stream's next unused blocks.
    template <class Event>
    void per_photon(Lanes& L, int l, Event&& event) const {
        PhotonState p = photon(L, l);
        PhotonRng rng(this->s_.seed, L.photon[l], L.block[l]);
        L.alive[l] = event(p, rng);
        L.block[l] = rng.next_block();
        put(L, l, p);
    }

    /// Block 0 of the streams of the block's next `width` photons, in the vectors: the
    /// launches of the photons after those already launched.
    void prepare(Launches& next, std::uint64_t end) const {
        next.first += next.count;
        next.count = std::min<std::uint64_t>(width, end - next.first);
        next.used = 0;
        alignas(64) std::uint64_t first_block[width] = {}, stream[width];
        for (int l = 0; l < width; ++l) stream[l] = next.first + l;
        lanes::philox_words<width>(first_block, stream, key_, {next.bits[0], next.bits[1], next.bits[2], next.bits[3]});
    }

    /// One Philox block per lane, as four uniforms.
    void draw(Lanes& L, StepUniforms& u) const {
        lanes::philox_uniforms(L.block, L.photon, key_, {u.path, u.absorb_or_store, u.psi, u.phi});
        for (auto& b : L.block) ++b;
    }

    /// Every lane's photon to its next event: PhotonTracer::follow's loop body, per lane.
    /// Inlined into trace_block's loop with its helpers (fly, store_events, the records, the
    /// detectors): as calls, they pass vectors through memory, 13 % of LaneTracer's
    /// instructions (valgrind; docs/design-notes.md).
    template <bool with_importance>
    SECCHI_KERNEL void step(Lanes& L, Launches& next, std::uint64_t end, detail::BlockResult<Record>& out) const {
        if constexpr (with_importance) change_levels(L, next, end, out);
        StepUniforms u;
        draw(L, u);
        const Mask alive(L.alive, aligned);
        const EventPhysics& physics = this->physics_;
        // Free path (eq. 3.17): s = -ln(u) / c (b with continuous absorption), cut at the
        // surface or the floor if the photon gets there first.
        const Reals z(L.z, aligned), dz(L.dz, aligned);
        const FreeFlight<Reals> flight = physics.free_flight(z, dz, free_path(z, dz, Reals(u.path, aligned)));
        fly(L, alive, flight.t, flight.z1);
        const Mask at_boundary = alive && (flight.to_surface || flight.to_floor);
        const Mask inside = alive && !at_boundary;
        const Vec3 before{Reals(L.dx, aligned), Reals(L.dy, aligned), dz};
        const Reals w(L.w, aligned);  // after the flight

        // PhotonTracer::interact for the lanes inside: the scattering-order limit, absorption
        // by the albedo, storage, and a new direction from the phase function.
        const Mask truncated = inside && physics.beyond_order(Reals(L.order, aligned));
        const Mask interacts = inside && !truncated;
        const Reals u_absorb_or_store(u.absorb_or_store, aligned);
        const Absorption<Reals> absorption = physics.absorb(w, u_absorb_or_store, albedo(Reals(L.z, aligned)));
        const Mask absorbed = interacts && absorption.ends;
        Reals absorbed_weight(L.absorbed, aligned);
        lanes::stdx::where(interacts, absorbed_weight) = absorbed_weight + absorption.absorbed;
        absorbed_weight.copy_to(L.absorbed, aligned);
        const Reals w_after = absorption.w;
        const Mask scatters = interacts && !absorbed;
        // The scattering angle's uniform, and with backscatter bias its biased draw and the
        // weight's factor 1 / q (PhotonTracer::interact, importance.hpp).
        Reals u_psi(u.psi, aligned), w_scattered = w_after;
        if (lane_bias_.enabled()) draw_biased(L, scatters, u_psi, w_scattered);
        const auto [cos_psi, phi] = EventPhysics::angles(this->medium_, Reals(L.z, aligned), u_psi, Reals(u.phi, aligned));
        const Vec3 after = rotate_direction(before, cos_psi, phi);

        store_events<with_importance>(L, scatters, w_after, u_absorb_or_store, out);
        scatter(L, scatters, w_scattered, after);
        const Mask roulette = scatters && physics.roulette_due(with_importance ? w_scattered * Reals(L.level_scale, aligned)
                                                                               : w_scattered);
        // What only some photons meet, in one pass over their lanes in lane order (each kind
        // of event adds to its own ledger entries, so their sums keep the lanes' order); a lane
        // whose photon ended takes the block's next one.
        alignas(64) std::uint32_t word[width];
        next_words(L, roulette, word);
        lanes::for_each(at_boundary || truncated || absorbed || roulette, [&](int l) {
            if (at_boundary[l]) {
                const bool surface = flight.to_surface[l];
                per_photon(L, l, [&](PhotonState& p, PhotonRng& rng) { return this->meet_boundary(p, rng, out, surface); });
            } else if (truncated[l]) {
                out.ledger.truncated += L.w[l];
                L.alive[l] = false;
            } else if (absorbed[l]) {
                L.alive[l] = false;
            } else {
                roulette_lane(L, l, word[l], out.ledger);
            }
            if (!L.alive[l]) start(L, l, next, end, out);
        });
    }

    /// PhotonTracer::fly per lane (path length t to depth z1): the detectors, continuous
    /// absorption (the weight times exp(-a t), and the detectors' scores decayed to their
    /// planes: PhotonTracer's arithmetic with lanes::exp for std::exp), the move.
    SECCHI_KERNEL void fly(Lanes& L, const Mask& alive, const Reals& t, const Reals& z1) const {
        const Reals z(L.z, aligned), dz(L.dz, aligned), w(L.w, aligned);
        const auto decay = absorption_along_flights();
        if (!this->physics_.continuous()) this->detectors_.record_lanes(z, z1, dz, t, w, alive, L.tally.data());
        else this->detectors_.record_lanes(z, z1, dz, t, w, alive, L.tally.data(), decay);
        (Reals(L.x, aligned) + Reals(L.dx, aligned) * t).copy_to(L.x, aligned);
        (Reals(L.y, aligned) + Reals(L.dy, aligned) * t).copy_to(L.y, aligned);
        z1.copy_to(L.z, aligned);
        if (!this->physics_.continuous()) return;
        const Reals decayed = w * decay.transmittance(z, dz, t);
        Reals absorbed(L.absorbed, aligned), weight = w;
        lanes::stdx::where(alive, absorbed) = absorbed + (w - decayed);
        lanes::stdx::where(alive, weight) = decayed;
        absorbed.copy_to(L.absorbed, aligned);
        weight.copy_to(L.w, aligned);
    }

    /// Equal-flux storage (EventPhysics::keeps, as PhotonTracer::store_event): an event is kept
    /// if u < w, with depth importance if u < w I(z) (I at the record's depth: the lane's span's
    /// factor, looked up where the depth has left the span), and a lane with w I > 1 adds
    /// floor(w I - 1 + u) copies of its record (expected copies w I in all: EventPhysics::copies).
    /// The records are made for all lanes at once (LaneRecords) and the kept ones appended in
    /// lane order, the further copies after them.
    template <bool with_importance>
    SECCHI_KERNEL void store_events(Lanes& L, const Mask& scatters, const Reals& w, const Reals& u,
                                    detail::BlockResult<Record>& out) const {
        const Mask candidates = scatters && Mask(L.stores, aligned);
        Reals weighted = w;  // w I(z)
        if constexpr (with_importance) weighted = importance_weighted(L, candidates, w);
        const Mask keep = candidates && this->physics_.keeps(weighted, u, Reals(L.z, aligned));
        if (none_of(keep)) return;
        const Vec3 position{this->slab_.wrap(Reals(L.x, aligned)), this->slab_.wrap(Reals(L.y, aligned)),
                            Reals(L.z, aligned)};
        const Vec3 direction{Reals(L.dx, aligned), Reals(L.dy, aligned), Reals(L.dz, aligned)};
        Record* room = out.records.room(width);
        out.records.commit(LaneRecords<Record>::make_kept(position, direction, band_index{this->s_.band}, L.batch,
                                                          lanes::bits_of(keep), room));
        // Weights above 1 come from depth importance (w I) and from backscatter bias's forward factor.
        if (any_of(keep && weighted > Real(1))) store_copies(L, keep, weighted, u, position, direction, out);
    }

    /// w I(z) per lane, I at the record's depth: the lane's span's factor, looked up where the
    /// depth has left the span, and computed for the record's depth where it lies within
    /// span_margin of a bound.
    [[gnu::noinline]] Reals importance_weighted(Lanes& L, const Mask& candidates, const Reals& w) const {
        lanes::for_each(candidates && !in_span(L), [&](int l) { look_up_span(L, l); });
        Reals weighted = w * Reals(L.span_factor, aligned);
        lanes::for_each(candidates && !in_span(L), [&](int l) {
            weighted[l] = w[l] * static_cast<Real>(this->levels_.factor(stored_depth(L, l)));
        });
        return weighted;
    }

    /// The further copies of the kept lanes' records where w I > 1: floor(w I - 1 + u) each.
    [[gnu::noinline]] void store_copies(const Lanes& L, const Mask& keep, const Reals& weighted, const Reals& u,
                                        const Vec3& position, const Vec3& direction,
                                        detail::BlockResult<Record>& out) const {
        lanes::for_each(keep && weighted > Real(1), [&](int l) {
            const Record rec = record(L, l, position, direction);
            for (double i = std::floor(weighted[l] - 1.0 + u[l]); i > 0; --i) out.records.push_back(rec);
        });
    }

    /// Lane l's record from the wrapped position and direction.
    Record record(const Lanes& L, int l, const Vec3& position, const Vec3& direction) const {
        return Record::make(vec3(position.x[l], position.y[l], position.z[l]),
                            vec3(direction.x[l], direction.y[l], direction.z[l]), band_index{this->s_.band}, L.batch[l]);
    }

    /// The depth at which lane l's record stores its position (the record's own rounding).
    double stored_depth(const Lanes& L, int l) const {
        return Record::make(vec3(0.0, 0.0, L.z[l]), vec3(0.0, 0.0, 1.0), band_index{0}, 0).position().z;
    }

    /// Each lane's free path from its uniform u (eq. 3.17): -ln(u) / k in homogeneous water (k =
    /// c, or b with continuous absorption); in depth-varying water the distance along the
    /// lane's direction from its depth at which the optical path of k reaches -ln(u)
    /// (Medium::distance_to, manual 3.3.4), lane by lane in double as PhotonTracer::follow
    /// computes it (infinite where an upward photon reaches the surface first: the flight then
    /// ends there).
    SECCHI_KERNEL Reals free_path(const Reals& z, const Reals& dz, const Reals& u) const {
        const Reals tau = -lanes::log(u);
        if constexpr (depth_independent<M>) {
            return tau / path_coefficient_;
        } else {
            const Coefficient k = this->physics_.path_coefficient();
            return Reals([&](auto l) { return static_cast<Real>(this->medium_.distance_to(k, z[l], dz[l], tau[l])); });
        }
    }

    /// The single-scattering albedo for the lanes at depths z: one value in homogeneous water,
    /// else each lane's at its depth (albedo_at, in double, as PhotonTracer::interact), only
    /// where the absorption mode reads it (not with continuous absorption).
    SECCHI_KERNEL auto albedo(const Reals& z) const {
        if constexpr (depth_independent<M>) {
            return this->w0_;
        } else {
            if (this->physics_.continuous()) return Reals(Real(1));
            return Reals([&](auto l) { return static_cast<Real>(albedo_at(this->medium_, z[l])); });
        }
    }

    /// The weight's decay along flights with continuous absorption (and the detectors' scores
    /// on the way to their planes): exp(-a s) in homogeneous water, the medium's absorption
    /// optical path in depth-varying water.
    auto absorption_along_flights() const {
        if constexpr (depth_independent<M>) return LaneAbsorption<Real>{absorption_coefficient_};
        else return LaneMediumAbsorption<M, Real>{this->medium_};
    }

    /// Backscatter bias for the scattering lanes: u_psi becomes the biased draw, w the weight
    /// times 1 / q, and the change is booked per lane (PhotonTracer::reweight).
    void draw_biased(Lanes& L, const Mask& scatters, Reals& u_psi, Reals& w) const {
        const auto draw = lane_bias_.draw(u_psi);
        u_psi = draw.u;
        const Reals biased = w * draw.weight;
        Reals gained(L.bias_gained, aligned), killed(L.bias_killed, aligned);
        lanes::stdx::where(scatters && biased > w, gained) = gained + (biased - w);
        lanes::stdx::where(scatters && biased < w, killed) = killed + (w - biased);
        gained.copy_to(L.bias_gained, aligned);
        killed.copy_to(L.bias_killed, aligned);
        w = biased;
    }

    /// The scattered lanes take their new direction and weight, one order higher.
    static void scatter(Lanes& L, const Mask& scatters, const Reals& w, const Vec3& after) {
        auto update = [&](Real* v, const Reals& value) {
            Reals current(v, aligned);
            lanes::stdx::where(scatters, current) = value;
            current.copy_to(v, aligned);
        };
        update(L.dx, after.x);
        update(L.dy, after.y);
        update(L.dz, after.z);
        update(L.w, w);
        update(L.order, Reals(L.order, aligned) + Real(1));
    }

    lanes::PhiloxKey key_;              ///< the seed as Philox's key (PhotonRng's)
    Real path_coefficient_;             ///< c, or b with continuous absorption (1/m; homogeneous water)
    Real absorption_coefficient_;       ///< a (1/m): continuous absorption's decay along flights (the same)
    std::vector<LaneSpan> spans_;       ///< the depth importance's spans (one, unbounded, without it)
    BackscatterBiasOf<Real> lane_bias_;  ///< PhotonTracer's backscatter bias in Real (off by default)
};

/// LaneTracer in float lanes (twice the lanes per vector), with PhotonTracer's parameters.
template <Medium M, PhotonRecord Record, AirWaterSurface Surface = FlatSurface, LightSource Source = SunAndSky,
          IrradianceDetector Detector = IrradiancePlanes>
using FloatLaneTracer = LaneTracer<M, Record, float, Surface, Source, Detector>;

}  // namespace secchi
#endif
