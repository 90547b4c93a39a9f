#pragma once
// Timing and table cells shared by the benchmark programs: every figure is the median of
// repeated timed runs, reported with its spread (min-max).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace secchi::bench {

struct Timing {
    double median = 0, lo = 0, hi = 0;  ///< seconds
};

/// The median of `v` (the upper one of an even count).
inline double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

/// Seconds of one run of `work`.
inline double seconds(const std::function<void()>& work) {
    const auto t0 = std::chrono::steady_clock::now();
    work();
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Times `work` `repeats` times (after `setup`, outside the timer, each time).
inline Timing time_runs(int repeats, const std::function<void()>& setup, const std::function<void()>& work) {
    std::vector<double> t;
    for (int i = 0; i < repeats; ++i) {
        setup();
        t.push_back(seconds(work));
    }
    std::sort(t.begin(), t.end());
    return {median(t), t.front(), t.back()};
}
inline Timing time_runs(int repeats, const std::function<void()>& work) {
    return time_runs(repeats, [] {}, work);
}

/// time(a) / time(b) over `rounds` rounds, each running a then b: median [min-max] of the
/// rounds' ratios. Two variants timed in separate blocks each see whatever load the shared
/// machine had during their block; a round's pair sees about the same, so the paired ratio is
/// the steadier comparison (the guide's "ratios measured in one run").
inline Timing paired_ratio(int rounds, const std::function<void()>& a, const std::function<void()>& b) {
    std::vector<double> r;
    for (int i = 0; i < rounds; ++i) {
        const double ta = seconds(a);
        r.push_back(ta / seconds(b));
    }
    std::sort(r.begin(), r.end());
    return {median(r), r.front(), r.back()};
}

inline std::string fmt(const char* f, double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, f, v);
    return buf;
}
/// "median [min-max]" of a rate derived from times: rate = amount / t.
inline std::string rate_cell(const Timing& t, double amount) {
    return fmt("%.4g", amount / t.median) + " [" + fmt("%.3g", amount / t.hi) + "-" + fmt("%.3g", amount / t.lo) + "]";
}
inline std::string time_cell(const Timing& t, double scale, const char* f = "%.3g") {
    return fmt(f, t.median * scale) + " [" + fmt(f, t.lo * scale) + "-" + fmt(f, t.hi * scale) + "]";
}

}  // namespace secchi::bench
