#pragma once
// Every Monte Carlo output carries its standard error from independent batches: photons are
// split into B batches by photon index; the estimate is the mean of the batch means and its
// standard error is their sample standard deviation / sqrt(B) (design notes; B >= 16).
#include "secchi/core/config.hpp"
#include <cmath>
#include <span>

namespace secchi::SECCHI_ISA {

struct Estimate {
    double value = 0.0;
    double se = 0.0;  ///< standard error of `value`
    [[nodiscard]] double relative_se() const { return value != 0.0 ? se / std::abs(value) : INFINITY; }
};

/// Mean and standard error of independent, identically distributed batch estimates.
inline Estimate batch_estimate(std::span<const double> batch_values) {
    const double n = static_cast<double>(batch_values.size());
    if (batch_values.empty()) return {};
    double mean = 0.0;
    for (double v : batch_values) mean += v;
    mean /= n;
    if (batch_values.size() < 2) return {mean, INFINITY};
    double ss = 0.0;
    for (double v : batch_values) ss += (v - mean) * (v - mean);
    return {mean, std::sqrt(ss / (n - 1.0) / n)};
}

}  // namespace secchi
