#pragma once
// Checks shared by the phase-function tests: the sampling histogram (spfhist, manual 7.3.4,
// as a chi-square test against 99.9 % quantiles), normalisation and pdf == eval for any
// PhaseFunction, sample_direction == sample()'s direction bit for bit, the closed-form HG
// backscatter fraction, and input_error messages.
#include <catch2/catch.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <string>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/core/rng.hpp"
#include "secchi/optics/medium.hpp"
#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::test {

/// 99.9 % quantile of chi-square with dof degrees of freedom (Wilson and Hilferty 1931):
/// dof (1 - h + z sqrt(h))^3, h = 2 / (9 dof), z = 3.0902 the standard normal 99.9 % point.
double chi2_quantile_999(int dof) {
    const double z = 3.090232306167813, h = 2.0 / (9.0 * dof);
    return dof * std::pow(1.0 - h + z * std::sqrt(h), 3);
}

template <class P>
auto pdf_of_psi(const P& p) {
    return [&p](double psi) { return static_cast<double>(p.pdf(std::cos(psi))); };
}

/// Bin edges in psi, equiprobable under the pdf: the numerical CDF on a fine grid (log-spaced
/// below 0.1 rad), inverted by linear interpolation. Only the binning depends on this; the
/// expected counts are integrated exactly over whatever edges result.
template <class P>
std::vector<double> equiprobable_edges(const P& p, int bins) {
    const auto bps = breakpoints_of(p);
    std::vector<double> grid{0.0};
    for (int i = 0; i <= 2000; ++i) grid.push_back(1e-7 * std::pow(1e6, i / 2000.0));
    for (int i = 1; i <= 2000; ++i) grid.push_back(0.1 + (pi - 0.1) * i / 2000.0);
    std::vector<double> cdf{0.0};
    for (std::size_t j = 0; j + 1 < grid.size(); ++j)
        cdf.push_back(cdf.back() + integrate_solid_angle(pdf_of_psi(p), grid[j], grid[j + 1], bps));
    std::vector<double> edges{0.0};
    std::size_t j = 0;
    for (int k = 1; k < bins; ++k) {
        const double target = cdf.back() * k / bins;
        while (cdf[j + 1] < target) ++j;
        const double w = (target - cdf[j]) / (cdf[j + 1] - cdf[j]);
        edges.push_back(grid[j] + w * (grid[j + 1] - grid[j]));
    }
    edges.push_back(pi);
    return edges;
}

double chi_square(const std::vector<double>& observed, const std::vector<double>& expected) {
    double chi2 = 0.0;
    for (std::size_t k = 0; k < observed.size(); ++k)
        chi2 += (observed[k] - expected[k]) * (observed[k] - expected[k]) / expected[k];
    return chi2;
}

struct HistogramResult {
    double chi2_psi, chi2_phi, limit_psi, limit_phi;
    bool samples_valid;  // cos_psi in [-1, 1], phi in [0, 2 pi), sample.pdf == pdf(cos_psi)
};

/// spfhist (manual 7.3.4) as a test: histogram 10^6 samples of `sampler` in 200 bins of psi
/// equiprobable under `reference`, expected counts = N * (integral of reference's pdf over
/// each bin); and 100 equal bins of phi.
template <class S, class R>
HistogramResult sampling_histogram(const S& sampler, const R& reference, std::uint64_t seed) {
    const int n = 1000000, bins = 200, phi_bins = 100;
    const auto edges = equiprobable_edges(reference, bins);
    const auto bps = breakpoints_of(reference);
    std::vector<double> expected, observed(bins, 0.0), phi_obs(phi_bins, 0.0);
    double total = 0.0;
    for (int k = 0; k < bins; ++k) {
        expected.push_back(n * integrate_solid_angle(pdf_of_psi(reference), edges[k], edges[k + 1], bps));
        total += expected.back();
    }
    REQUIRE(total == Approx(n).epsilon(1e-6));
    PhotonRng rng(seed, 0);
    bool valid = true;
    for (int i = 0; i < n; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const PhaseSample s = sampler.sample(u1, u2);
        valid = valid && s.cos_psi >= -1.0 && s.cos_psi <= 1.0 && s.phi >= 0.0 && s.phi < two_pi &&
                s.pdf == sampler.pdf(s.cos_psi) && std::isfinite(s.pdf) && s.pdf > 0.0;
        const double psi = std::acos(s.cos_psi);
        const auto k = std::upper_bound(edges.begin(), edges.end(), psi) - edges.begin() - 1;
        observed[static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(k, 0, bins - 1))] += 1.0;
        phi_obs[std::min<std::size_t>(static_cast<std::size_t>(s.phi / two_pi * phi_bins), phi_bins - 1)] += 1.0;
    }
    const std::vector<double> phi_exp(phi_bins, double(n) / phi_bins);
    return {chi_square(observed, expected), chi_square(phi_obs, phi_exp), chi2_quantile_999(bins - 1),
            chi2_quantile_999(phi_bins - 1), valid};
}

/// (c): p's own sampler against p's pdf.
template <class P>
void check_sampling(const P& p, std::uint64_t seed) {
    const HistogramResult h = sampling_histogram(p, p, seed);
    CHECK(h.samples_valid);
    INFO("chi2(psi) = " << h.chi2_psi << " limit " << h.limit_psi << "; chi2(phi) = " << h.chi2_phi);
    CHECK(h.chi2_psi < h.limit_psi);
    CHECK(h.chi2_phi < h.limit_phi);
}

/// Bitwise equality of doubles (tells -0.0 from 0.0; a NaN equals the same NaN).
inline bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

/// Two forms of one stratified water (e.g. a typed StratifiedWater and its AnyPhaseFunction
/// form): how many of n pairs of uniforms from PhotonRng(seed, 0) give, at depth z, a phase
/// sample, a scattering direction (equal to the sample's cos_psi) or a phase value eval_phase(z,
/// 2 u1 - 1) that differ between them in any bit.
template <class A, class B>
int phase_mismatches_at(const A& a, const B& b, double z, std::uint64_t seed, int n) {
    PhotonRng rng(seed, 0);
    int mismatches = 0;
    for (int i = 0; i < n; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        const PhaseSample x = a.sample_phase(z, u1, u2), y = b.sample_phase(z, u1, u2);
        const PhaseDirection c = scattering_direction(a, z, u1, u2), d = scattering_direction(b, z, u1, u2);
        if (!same_bits(x.cos_psi, y.cos_psi) || !same_bits(x.phi, y.phi) || !same_bits(x.pdf, y.pdf)) ++mismatches;
        if (!same_bits(c.cos_psi, d.cos_psi) || !same_bits(c.phi, d.phi) || !same_bits(c.cos_psi, x.cos_psi)) ++mismatches;
        const double mu = 2.0 * u1 - 1.0;
        if (!same_bits(a.eval_phase(z, mu), b.eval_phase(z, mu))) ++mismatches;
    }
    return mismatches;
}

/// (d): sample_direction_of(p, u1, u2), i.e. p.sample_direction where p has one, is exactly
/// the cos_psi and phi of p.sample(u1, u2), bit for bit, over n pairs of uniforms from
/// PhotonRng and the extreme uniforms 2^-53 and 1 - 2^-53.
template <class P>
void check_direction_sampler(const P& p, std::uint64_t seed, int n = 10000) {
    PhotonRng rng(seed, 1);
    int mismatches = 0;
    const auto compare = [&](double u1, double u2) {
        const PhaseSample s = p.sample(u1, u2);
        const PhaseDirection d = sample_direction_of(p, u1, u2);
        if (same_bits(d.cos_psi, s.cos_psi) && same_bits(d.phi, s.phi)) return;
        if (mismatches++ == 0)
            UNSCOPED_INFO(std::setprecision(17) << "first mismatch at u1 = " << u1 << ", u2 = " << u2 << ": ("
                                                << d.cos_psi << ", " << d.phi << ") != (" << s.cos_psi << ", "
                                                << s.phi << ")");
    };
    for (double u1 : {0x1p-53, 0.5, 1.0 - 0x1p-53})
        for (double u2 : {0x1p-53, 1.0 - 0x1p-53}) compare(u1, u2);
    for (int i = 0; i < n; ++i) {
        const double u1 = rng.uniform(), u2 = rng.uniform();
        compare(u1, u2);
    }
    CHECK(mismatches == 0);
}

/// The checks (a)-(d) every phase function must pass.
template <class P>
void check_phase_function(const P& p, std::uint64_t seed) {
    INFO(p.name());
    const PhaseMoments m = phase_moments(p);
    CHECK(std::abs(m.normalisation - 1.0) < 1e-6);  // (a)
    for (double mu : {-1.0, -0.99999, -0.5, 0.0, 0.3, 0.9, 0.999, 0.99999999, 1.0 - 1e-15, 1.0}) {
        CHECK(p.pdf(mu) == p.eval(mu));  // (b)
        CHECK(std::isfinite(p.eval(mu)));
        CHECK(p.eval(mu) > 0.0);
    }
    check_sampling(p, seed);  // (c)
    check_direction_sampler(p, seed);  // (d)
}

/// The message of the secchi::input_error that f() throws ("" if it throws nothing; any
/// other exception escapes and fails the test).
template <class F>
std::string input_error_message(F&& f) {
    try {
        f();
    } catch (const input_error& e) {
        return e.what();
    }
    return "";
}

/// HG backscatter fraction in closed form: (1 - g)/(2 g) ((1 + g)/sqrt(1 + g^2) - 1).
double hg_backscatter(double g) {
    return g == 0.0 ? 0.5 : (1.0 - g) / (2.0 * g) * ((1.0 + g) / std::sqrt(1.0 + g * g) - 1.0);
}

}  // namespace secchi::test
