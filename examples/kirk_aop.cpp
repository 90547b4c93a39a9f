// Kirk's AOP relations (manual section 7.5; canonical_problems.md section 7) from the first
// pass alone: the irradiance detectors, no photon map. Sun at nadir, level surface
// (n = 1.34), black sky, infinitely deep homogeneous water.
//
// 1. Irradiance reflectance just below the surface, R(0) = Eu(0) / Ed(0), against
//    R(0) = C b_b / (a + b_b) (manual eq. 7.2): C about 0.33 at nadir (Gordon et al. 1975,
//    Gordon and Morel 1983), or Kirk's C(mu0) = -0.629 mu0 + 0.975 = 0.346 (eq. 7.4).
//    Petzold particles, a = 1 /m, b chosen for k = b_b / (a + b_b) as in eq. 7.5 with the
//    function's own b_b / b.
// 2. The euphotic depth z1% (where Ed falls to 1 % of Ed(0)) against Kirk 1994's
//    Kd_bar / a = (1 / mu0) (1 + G b / a)^(1/2) (eq. 7.8-7.9), and against the 1991 form G'
//    (eq. 7.10): a = 0.1 /m, Henyey-Greenstein with mean cosine 0.8, b varied (the manual's
//    a = 0.1, b = 0.9 gave 19.3 m simulated against 19.9 m from the 1994 relation).
//
// Both relations are approximate fits (the manual, 7.5.4: "inherently an approximate one"),
// so this prints the comparison; it passes or fails nothing.
//
//   build/examples/kirk_aop [--photons N] [--threads T]     (default 200000 photons, 2 threads)
#include <secchi/io/cli.hpp>
#include <secchi/optics/phase/henyey_greenstein.hpp>
#include <secchi/optics/phase/petzold.hpp>
#include <secchi/transport/tracer.hpp>
#include <cmath>
#include <cstdio>
#include <string_view>
#include <vector>

using namespace secchi;

namespace {

template <class Phase>
TransportResult<CompactRecord> trace(const Phase& phase, double a, double b, const TransportSettings& s) {
    const HomogeneousWater<Phase> water(a, b, phase);
    return PhotonTracer<HomogeneousWater<Phase>, CompactRecord>(water, Slab(1.0, Bottom{}), FlatSurface(1.34),
                                                                CollimatedSun(0.0), s)
        .run();
}

/// x / y with the standard error of independent estimates (first order).
Estimate ratio(const Estimate& x, const Estimate& y) {
    const double r = x.value / y.value;
    return {r, std::abs(r) * std::hypot(x.se / x.value, y.se / y.value)};
}

void reflectance_table(const TransportSettings& base) {
    const auto petzold = petzold_m93();
    const double bb_over_b = phase_moments(petzold).backscatter_fraction;
    const double kirk_c = -0.629 * 1.0 + 0.975;  // eq. 7.4 at mu0 = 1 (sun at nadir)
    std::printf("R(0) = Eu(0)/Ed(0), Petzold (b_b/b = %.5f), a = 1 /m, sun at nadir\n", bb_over_b);
    std::printf("%8s %8s %24s %10s %12s %12s\n", "k", "b (1/m)", "R(0) +- SE", "R(0)/k", "0.33 k", "Kirk C k");
    TransportSettings s = base;
    s.depths = {0.0};
    for (const double k : {0.005, 0.01, 0.02, 0.05, 0.1, 0.15}) {
        const double a = 1.0, b = k * a / ((1.0 - k) * bb_over_b);  // eq. 7.5: k = b_b / (a + b_b)
        const auto r = trace(petzold, a, b, s);
        const Estimate reflectance = ratio(r.irradiance[0][Eu], r.irradiance[0][Ed]);
        std::printf("%8.3f %8.3f %13.5e +- %8.1e %10.4f %12.5e %12.5e\n", k, b, reflectance.value, reflectance.se,
                    reflectance.value / k, 0.33 * k, kirk_c * k);
    }
}

/// The depth where Ed(z) falls to `fraction` of Ed(0), by linear interpolation of ln Ed
/// between the detector depths (-1 if it does not fall that far), with its standard error
/// from the relative errors of Ed there and of Ed(0), over the local log slope.
Estimate depth_of_fraction(const TransportResult<CompactRecord>& r, const std::vector<double>& depths, double fraction) {
    const Estimate& e0 = r.irradiance[0][Ed];
    const double target = std::log(fraction * e0.value);
    for (std::size_t i = 1; i < depths.size(); ++i) {
        const Estimate& lo = r.irradiance[i - 1][Ed];
        const Estimate& hi = r.irradiance[i][Ed];
        if (!(hi.value > 0.0) || std::log(hi.value) > target) continue;
        const double l0 = std::log(lo.value), l1 = std::log(hi.value), slope = (l0 - l1) / (depths[i] - depths[i - 1]);
        const double z = depths[i - 1] + (l0 - target) / slope;
        return {z, std::hypot(hi.se / hi.value, e0.se / e0.value) / slope};
    }
    return {-1.0, 0.0};
}

void euphotic_depth_table(const TransportSettings& base) {
    const double a = 0.1, mean_cosine = 0.8, mu0 = 1.0;
    const double g_1994 = mu0 * (2.127 / mean_cosine - 1.895) - 0.618 / mean_cosine + 0.490;  // eq. 7.9
    const double g_1991 = mu0 * (2.236 / mean_cosine - 2.447) - 0.849 / mean_cosine + 0.739;  // eq. 7.10
    auto kirk_depth = [&](double b, double g) {  // z1% = ln(100) / Kd_bar, eq. 7.8
        return std::log(100.0) / (a / mu0 * std::sqrt(1.0 + g * b / a));
    };
    std::printf("\nz1%% (Ed = 1 %% of Ed(0)), Henyey-Greenstein mean cosine %.1f, a = %.1f /m, sun at nadir\n",
                mean_cosine, a);
    std::printf("%8s %20s %14s %14s\n", "b (1/m)", "z1% +- SE (m)", "Kirk 1994 (m)", "Kirk 1991 (m)");
    TransportSettings s = base;
    s.depths.clear();
    for (double z = 0.0; z <= 50.0; z += 0.5) s.depths.push_back(z);
    for (const double b : {0.2, 0.5, 0.9, 1.5, 3.0}) {
        const auto r = trace(HenyeyGreensteinPhase(mean_cosine), a, b, s);
        const Estimate z1 = depth_of_fraction(r, s.depths, 0.01);
        std::printf("%8.2f %11.2f +- %5.2f %14.2f %14.2f\n", b, z1.value, z1.se, kirk_depth(b, g_1994),
                    kirk_depth(b, g_1991));
    }
}

}  // namespace

int main(int argc, char** argv) {
    constexpr std::string_view usage =
        "usage: kirk_aop [--photons N] [--threads T]   (defaults: 200000 photons, 2 threads)\n"
        "Prints R(0) against C b_b/(a + b_b) and the euphotic depth against Kirk's relations.\n";
    return run_program(argc, argv, "kirk_aop", usage, [&] {
        const CommandLine cl(argc, argv, {"photons", "threads"});
        TransportSettings s;
        s.photons = cl.count("photons", 200000);
        s.threads = cl.threads(2);
        s.absorption = AbsorptionMode::continuous;
        s.validate();
        reflectance_table(s);
        euphotic_depth_table(s);
        return 0;
    });
}
