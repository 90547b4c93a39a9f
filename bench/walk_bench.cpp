// walk_bench: secchi's photon tracer against bare random walks (a benchmark, never part of the
// tests), so that BENCHMARKS.md can say how far the tracer is from the walks the performance
// issue names as yardsticks, measured in one run on one core.
//   walk_bench [--quick] [--photons N] [--md FILE]
//
// The bare walk: photons enter the half-space z >= 0 at the origin heading down (+z), with
// exponential free paths (c = 1, s = -ln u), absorption with probability 1 - w0 (w0 = 0.9),
// Henyey-Greenstein scattering (g = 0.9) and a 16-byte record (float position, two 16-bit
// direction codes) stored per scattering event; a photon ends when absorbed or when it leaves
// through z = 0. Events = records stored. Variants:
//  - scalar double with xoshiro256+ (the "bare scalar random walk", libm log/sin/cos);
//  - scalar double with secchi's Philox4x32-10 streams, one per photon (PhotonRng);
//  - scalar float with xoshiro256+ (logf, sinf, cosf);
//  - lanes: one photon per SIMD lane (std::experimental::simd of doubles at the target's
//    native width), the log, sine and cosine by branch-free polynomials, xoshiro256+ or
//    Philox per lane; a lane whose photon ends starts the next one. And the same in float
//    lanes (twice as many) with Philox.
// And secchi: PhotonTracer, LaneTracer and LaneTracer in float lanes on the same problem (slab 42 m deep, detectors at
// 1, 5, 10 m, CompactRecord with Jensen's direction bytes, analog absorption: secchi_bench's
// events_per_s_per_core_hg), with their ratios to each walk. Like the bare walks, which write
// into one vector reserved once, the tracers write each run's map into the previous run's
// memory (run(std::move(records))); one more row gives LaneTracer with fresh memory every run,
// which pays the kernel's page faults.
//
// Like every benchmark, this program is built with -march=native where the compiler accepts it
// (bench/CMakeLists.txt, SECCHI_BENCH_NATIVE) so that the lanes use the machine's widest vectors.
#include "bench_problems.hpp"
#include "bench_timing.hpp"
#include "secchi/io/cli.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/solver/plane_parallel.hpp"
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>
#if SECCHI_HAS_LANES
#define SECCHI_WALK_LANES 1
#endif

namespace {

using namespace secchi;
using namespace secchi::bench;

constexpr double g_hg = 0.9, w0 = 0.9;

struct WalkRecord {  // 16 bytes, as the bare walk stores
    float x, y, z;
    std::int16_t dz, dx;
};
static_assert(sizeof(WalkRecord) == 16);

template <class Real>
WalkRecord walk_record(Real x, Real y, Real z, Real dx, Real dz) {
    return {static_cast<float>(x), static_cast<float>(y), static_cast<float>(z), static_cast<std::int16_t>(dz * Real(32000)),
            static_cast<std::int16_t>(dx * Real(32000))};
}

/// One step of xoshiro256+ (Blackman and Vigna 2018) on state words of type W: 64-bit
/// integers, or SIMD vectors of them (one generator per lane).
template <class W>
W xoshiro_next(W (&s)[4]) {
    const W r = s[0] + s[3], t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = (s[3] << 45) | (s[3] >> 19);
    return r;
}

/// xoshiro256+: the top bits as a uniform in (0, 1).
class Xoshiro {
public:
    explicit Xoshiro(std::uint64_t seed) {
        for (auto& w : s_) w = splitmix(seed);
    }
    std::uint64_t next() { return xoshiro_next(s_); }
    template <class Real>
    Real uniform() {
        if constexpr (sizeof(Real) == 4) return (static_cast<float>(next() >> 40) + 0.5f) * 0x1p-24f;
        else return (static_cast<double>(next() >> 11) + 0.5) * 0x1p-53;
    }
    static std::uint64_t splitmix(std::uint64_t& x) {
        std::uint64_t z = (x += 0x9E3779B97F4A7C15ull);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
        return z ^ (z >> 31);
    }

private:
    std::uint64_t s_[4];
};

/// One photon of the scalar bare walk; `uniform()` draws from its generator.
template <class Real, class Uniform>
void scalar_photon(Uniform&& uniform, std::vector<WalkRecord>& out) {
    constexpr Real g = Real(g_hg), one = 1, two_pi_r = Real(two_pi);
    Real x = 0, y = 0, z = 0, dx = 0, dy = 0, dz = 1;
    for (;;) {
        const Real s = -std::log(uniform());
        x += dx * s;
        y += dy * s;
        z += dz * s;
        if (z < 0 || uniform() >= Real(w0)) return;
        out.push_back(walk_record(x, y, z, dx, dz));
        const Real t = (one - g * g) / (one - g + 2 * g * uniform());
        const Real ct = (one + g * g - t * t) / (2 * g), st = std::sqrt(std::max(Real(0), one - ct * ct));
        const Real phi = two_pi_r * uniform(), cp = std::cos(phi), sp = std::sin(phi);
        if (std::abs(dz) > Real(0.99999)) {
            dx = st * cp;
            dy = st * sp;
            dz = dz > 0 ? ct : -ct;  // about the pole: psi measured from +z or -z
        } else {
            const Real d = std::sqrt(one - dz * dz);
            const Real nx = st * (dx * dz * cp - dy * sp) / d + dx * ct, ny = st * (dy * dz * cp + dx * sp) / d + dy * ct;
            dz = -st * cp * d + dz * ct;
            dx = nx;
            dy = ny;
        }
    }
}

template <class Real>
std::size_t scalar_walk_xoshiro(std::uint64_t photons, std::vector<WalkRecord>& out) {
    Xoshiro rng(1);
    for (std::uint64_t i = 0; i < photons; ++i) scalar_photon<Real>([&] { return rng.uniform<Real>(); }, out);
    return out.size();
}

std::size_t scalar_walk_philox(std::uint64_t photons, std::vector<WalkRecord>& out) {
    for (std::uint64_t i = 0; i < photons; ++i) {
        PhotonRng rng(1, i);
        scalar_photon<double>([&] { return rng.uniform(); }, out);
    }
    return out.size();
}

#ifdef SECCHI_WALK_LANES
// The lanes, their log (core/lanes.hpp) and sin_cos (core/math.hpp) are the library's.
namespace stdx = std::experimental;
using V = lanes::Reals;
using U = lanes::Words;
constexpr int lane_count = lanes::lane_width;

/// Four uniforms per lane and step: xoshiro256+ per lane.
class XoshiroLanes {
public:
    using Lanes = V;
    static constexpr int width = lane_count;
    XoshiroLanes() {
        std::uint64_t seed = 1, w[4][lane_count];
        for (int l = 0; l < lane_count; ++l)
            for (auto& row : w) row[l] = Xoshiro::splitmix(seed);
        for (int k = 0; k < 4; ++k) s_[k] = U([&](auto l) { return w[k][l]; });
    }
    void start(int, std::uint64_t) {}
    void draw(V (&u)[4]) {
        for (auto& v : u) v = (stdx::static_simd_cast<V>(xoshiro_next(s_) >> 11) + 0.5) * 0x1p-53;
    }

private:
    U s_[4];
};

/// Four uniforms per lane and step: one Philox4x32-10 block of the lane's photon stream
/// (lanes::philox_uniforms, LaneTracer's draw), in lanes of Real (double or float).
template <class Real = double>
class PhiloxLanes {
public:
    using Lanes = lanes::LanesOf<Real>;
    static constexpr int width = lanes::width_of<Real>;
    void start(int lane, std::uint64_t photon) {
        ctr_[lane] = 0;
        stream_[lane] = photon;
    }
    void draw(Lanes (&u)[4]) {
        alignas(64) Real w[4][width];
        lanes::philox_uniforms(ctr_, stream_, key_, {w[0], w[1], w[2], w[3]});
        for (int k = 0; k < 4; ++k) u[k] = Lanes(w[k], lanes::aligned);
        for (auto& c : ctr_) ++c;
    }

private:
    alignas(64) std::uint64_t ctr_[width] = {};
    alignas(64) std::uint64_t stream_[width] = {};
    lanes::PhiloxKey key_{{1, 0}};  // seed 1
};

/// The bare walk with one photon per lane, branch-free except where a photon ends (lanes of
/// doubles, or of floats with Philox: twice as many per vector).
template <class Rng>
std::size_t lanes_walk(std::uint64_t photons, std::vector<WalkRecord>& out) {
    using W = typename Rng::Lanes;
    using T = typename W::value_type;
    constexpr int width = Rng::width;
    constexpr T g = T(g_hg), one = 1;
    Rng rng;
    W x(T(0)), y(T(0)), z(T(0)), dx(T(0)), dy(T(0)), dz(one);
    std::uint64_t next = 0;
    int live = 0;
    bool alive[width] = {};
    auto start = [&](int l) {  // lane l takes the next photon, or idles (parked above z = 0)
        alive[l] = next < photons;
        live += alive[l];
        if (alive[l]) rng.start(l, next++);
        x[l] = y[l] = dx[l] = dy[l] = T(0);
        z[l] = alive[l] ? T(0) : T(-1e30);
        dz[l] = one;
    };
    for (int l = 0; l < width; ++l) start(l);
    std::size_t n = 0;
    out.resize(1 << 20);
    while (live > 0) {
        W u[4];
        rng.draw(u);
        const W s = -lanes::log(u[0]);
        x += dx * s;
        y += dy * s;
        z += dz * s;
        const auto ends = (z < T(0)) || (u[1] >= T(w0));
        if (n + width > out.size()) out.resize(2 * out.size());
        for (int l = 0; l < width; ++l) {  // every lane writes; the count advances for kept events
            out[n] = walk_record<T>(x[l], y[l], z[l], dx[l], dz[l]);
            n += !ends[l];
        }
        const W t = (one - g * g) / (one - g + T(2) * g * u[2]);
        const W ct = (one + g * g - t * t) / (T(2) * g), st = stdx::sqrt(stdx::max(W(T(0)), one - ct * ct));
        const auto [sp, cp] = sin_cos(W(T(two_pi) * u[3]));
        // The frame of secchi::rotate_direction (Duff et al. 2017), branch-free.
        const W sign = stdx::copysign(W(one), dz), a = -one / (sign + dz), b = dx * dy * a;
        const W sc = st * cp, ss = st * sp;
        const W nx = sc * (one + sign * dx * dx * a) + ss * b + ct * dx;
        const W ny = sc * (sign * b) + ss * (sign + dy * dy * a) + ct * dy;
        const W nz = -(sc * sign * dx) - ss * dy + ct * dz;
        const W norm = T(1.5) - T(0.5) * (nx * nx + ny * ny + nz * nz);
        dx = nx * norm;
        dy = ny * norm;
        dz = nz * norm;
        if (stdx::any_of(ends))
            for (int l = 0; l < width; ++l)
                if (ends[l] && alive[l]) {
                    --live;
                    start(l);
                }
    }
    out.resize(n);
    return n;
}
#endif

/// A secchi tracer (PhotonTracer or LaneTracer) on the problem of secchi_bench's
/// events_per_s_per_core_hg; its records' mean depth (the same walk's check) goes to
/// `mean_depth`. With `reuse`, the map's records go into the memory of the previous run's
/// (as the bare walks reuse theirs), else into fresh memory.
template <template <class...> class Tracer>
std::size_t secchi_tracer(std::uint64_t photons, double& mean_depth, std::vector<CompactRecord>* reuse) {
    auto records = trace_slab<CompactRecord, Tracer>(HenyeyGreensteinPhase(g_hg), w0, 0.0, 1.0, photons, 1,
                                                     AbsorptionMode::analog,
                                                     reuse ? std::move(*reuse) : std::vector<CompactRecord>{})
                       .records;
    mean_depth = 0;
    for (const auto& r : records) mean_depth += r.z;
    mean_depth /= static_cast<double>(records.size());
    const std::size_t events = records.size();
    if (reuse) *reuse = std::move(records);
    return events;
}

struct Variant {
    std::string name;
    std::function<std::size_t(std::uint64_t)> run;  ///< traces `photons` photons, returns the events
    std::function<double()> mean_depth;              ///< of the last run's events (not timed)
};

}  // namespace

int main(int argc, char** argv) {
    if (CommandLine::wants_help(argc, argv)) {
        std::cout << "usage: walk_bench [--quick] [--photons N] [--md FILE]\n";
        return 0;
    }
    try {
        const CommandLine cl(argc, argv, {"md", "photons"}, {"quick"});
        const bool quick = cl.has("quick");
        const int repeats = quick ? 3 : 7;
        const auto photons = static_cast<std::uint64_t>(cl.number("photons", quick ? 1e5 : 4e5));
        std::ofstream md_file;
        if (cl.has("md")) md_file.open(cl.text("md"));
        auto out = [&](const std::string& line) {
            std::cout << line << "\n";
            if (md_file.is_open()) md_file << line << "\n";
        };

        std::vector<WalkRecord> records;
        records.reserve(photons * 12);
        auto walk = [&](auto f) { return [&records, f](std::uint64_t n) { records.clear(); return f(n, records); }; };
        auto walk_depth = [&] {
            double sum = 0;
            for (const auto& r : records) sum += r.z;
            return sum / static_cast<double>(records.size());
        };
        double photon_tracer_depth = 0, lane_tracer_depth = 0, float_lane_tracer_depth = 0, lane_tracer_fresh_depth = 0,
               float_lane_tracer_fresh_depth = 0;
        std::vector<CompactRecord> photon_tracer_map, lane_tracer_map, float_lane_tracer_map;
        std::vector<Variant> variants{
            {"secchi PhotonTracer (HG, slab, detectors, CompactRecord; map memory reused)",
             [&](std::uint64_t n) { return secchi_tracer<PhotonTracer>(n, photon_tracer_depth, &photon_tracer_map); },
             [&] { return photon_tracer_depth; }},
#if SECCHI_HAS_LANES
            {"secchi LaneTracer (" + std::to_string(lanes::lane_width) +
                 " double lanes; the same problem; map memory reused)",
             [&](std::uint64_t n) { return secchi_tracer<LaneTracer>(n, lane_tracer_depth, &lane_tracer_map); },
             [&] { return lane_tracer_depth; }},
            {"secchi LaneTracer in float lanes (" + std::to_string(lanes::width_of<float>) +
                 " float lanes; FloatLaneTracer; map memory reused)",
             [&](std::uint64_t n) { return secchi_tracer<FloatLaneTracer>(n, float_lane_tracer_depth, &float_lane_tracer_map); },
             [&] { return float_lane_tracer_depth; }},
            {"secchi LaneTracer, fresh map memory every run",
             [&](std::uint64_t n) { return secchi_tracer<LaneTracer>(n, lane_tracer_fresh_depth, nullptr); },
             [&] { return lane_tracer_fresh_depth; }},
            {"secchi LaneTracer in float lanes, fresh map memory every run",
             [&](std::uint64_t n) { return secchi_tracer<FloatLaneTracer>(n, float_lane_tracer_fresh_depth, nullptr); },
             [&] { return float_lane_tracer_fresh_depth; }},
#endif
            {"bare walk, scalar double, xoshiro256+", walk(scalar_walk_xoshiro<double>), walk_depth},
            {"bare walk, scalar double, Philox per photon", walk(scalar_walk_philox), walk_depth},
            {"bare walk, scalar float, xoshiro256+", walk(scalar_walk_xoshiro<float>), walk_depth},
        };
#ifdef SECCHI_WALK_LANES
        const std::string width = std::to_string(lane_count) + " double lanes";
        variants.push_back({"bare walk, " + width + ", xoshiro256+ per lane", walk(lanes_walk<XoshiroLanes>), walk_depth});
        variants.push_back({"bare walk, " + width + ", Philox per photon", walk(lanes_walk<PhiloxLanes<double>>), walk_depth});
        variants.push_back({"bare walk, " + std::to_string(lanes::width_of<float>) + " float lanes, Philox per photon",
                            walk(lanes_walk<PhiloxLanes<float>>), walk_depth});
#endif
        out("| variant | events | mean event depth | events/s per core, median [min-max] | PhotonTracer / variant | "
            "LaneTracer / variant | LaneTracer in float lanes / variant |");
        out("|---|---|---|---|---|---|---|");
        struct Row {
            std::size_t events;
            Timing t;
            double mean_depth;
        };
        std::vector<Row> rows;  // PhotonTracer's first, then LaneTracer's and its float lanes' (where built)
        for (const auto& v : variants) {
            std::size_t events = 0;
            const Timing t = time_runs(repeats, [&] { events = v.run(photons); });
            rows.push_back({events, t, v.mean_depth()});
        }
        auto rate = [&](std::size_t i) { return static_cast<double>(rows[i].events) / rows[i].t.median; };
        for (std::size_t i = 0; i < rows.size(); ++i)
            out("| " + variants[i].name + " | " + std::to_string(rows[i].events) + " | " + fmt("%.4f", rows[i].mean_depth) +
                " | " + rate_cell(rows[i].t, static_cast<double>(rows[i].events)) + " | " + fmt("%.2f", rate(0) / rate(i)) +
                " | " + (SECCHI_HAS_LANES ? fmt("%.2f", rate(1) / rate(i)) : std::string("-")) + " | " +
                (SECCHI_HAS_LANES ? fmt("%.2f", rate(2) / rate(i)) : std::string("-")) + " |");
        out("");
        out(std::to_string(photons) + " photons per run, median of " + std::to_string(repeats) +
            " runs, 1 thread. HG g = 0.9, w0 = 0.9; see bench/walk_bench.cpp for the walks. The events and their mean "
            "depth check that every variant traces the same walk (secchi's photons also end at its 42 m floor); "
            "events per photon have a standard deviation of about 9, so totals of independent runs differ by a few "
            "times 9 sqrt(photons).");
        return 0;
    } catch (const std::exception& e) {
        std::cerr << "walk_bench: " << e.what() << "\n";
        return 1;
    }
}
