#pragma once
// Every Monte Carlo output carries its standard error from independent batches: photons are
// split into B batches by photon index; the estimate is the mean of the batch means and its
// standard error is their sample standard deviation / sqrt(B) (design notes; B >= 16).
#include "secchi/core/config.hpp"
#include "secchi/core/math.hpp"
#include <cmath>
#include <span>

namespace secchi::SECCHI_ISA {

struct Estimate {
    double value = 0.0;
    double se = 0.0;  ///< standard error of `value`
    [[nodiscard]] double relative_se() const { return value != 0.0 ? se / std::abs(value) : INFINITY; }
};

/// Mean and standard error of independent, identically distributed batch estimates. The sum
/// of squares by mul_add (core/math.hpp), so that every program rounds it alike (the Python
/// module's SE is the slab program's, bit for bit, in a build for an FMA machine too).
inline Estimate batch_estimate(std::span<const double> batch_values) {
    const double n = static_cast<double>(batch_values.size());
    if (batch_values.empty()) return {};
    double mean = 0.0;
    for (double v : batch_values) mean += v;
    mean /= n;
    if (batch_values.size() < 2) return {mean, INFINITY};
    double ss = 0.0;
    for (double v : batch_values) ss = mul_add(v - mean, v - mean, ss);
    return {mean, std::sqrt(ss / (n - 1.0) / n)};
}

/// A statistic that is not a mean of the batches (e.g. a ratio of batch sums), with the
/// delete-one-batch jackknife's standard error (Efron & Tibshirani 1993, "An Introduction to
/// the Bootstrap", eq. 11.5): `value` from all B batches pooled, leave_one_out[b] the same
/// statistic from the other B - 1 batches; se = sqrt((B - 1) / B * sum_b (theta_b - theta_bar)^2).
/// For a mean of the batches it is batch_estimate's SE exactly. B < 2: se infinite.
inline Estimate jackknife_estimate(double value, std::span<const double> leave_one_out) {
    const double n = static_cast<double>(leave_one_out.size());
    if (leave_one_out.size() < 2) return {value, INFINITY};
    double mean = 0.0;
    for (double v : leave_one_out) mean += v;
    mean /= n;
    double ss = 0.0;
    for (double v : leave_one_out) ss = mul_add(v - mean, v - mean, ss);
    return {value, std::sqrt((n - 1.0) / n * ss)};
}

}  // namespace secchi
