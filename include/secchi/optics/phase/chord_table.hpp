#pragma once
// A phase function (or any function of cos psi) for the second pass's inner loop, where it is
// evaluated once per collected photon: tabulated on a grid uniform in the half chord
//   s = sin(psi / 2) = sqrt((1 - cos psi) / 2)   (half the distance between the two unit vectors)
// and linear in s between nodes. Finding the node takes a square root and a multiplication,
// where a grid in psi needs an acos (and a search where it is not uniform).
//
// The grid suits forward-peaked functions: near psi = 0, s ~ psi / 2, so the spacing in angle is
// 2 / n rad (0.007 deg for the default n = 16384), finer than any cone the estimator averages
// over (manual eq. 3.5: alpha = 2.3 deg for omega = 0.005 sr); near psi = pi it is coarser
// (about 2 deg), where natural-water phase functions are flat. Interpolation error is measured
// against the source in test_chord_table.cpp.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

namespace secchi::SECCHI_ISA {

class ChordTable {
public:
    /// f: any callable or object with eval(cos_psi); n: grid intervals in s over [0, 1].
    template <class F>
    explicit ChordTable(const F& f, std::size_t n = 16384) : n_(static_cast<double>(n)) {
        require(n >= 2, "n", n, "a chord table needs at least 2 intervals");
        value_.resize(n + 1);
        for (std::size_t i = 0; i <= n; ++i) {
            const double s = static_cast<double>(i) / static_cast<double>(n);
            value_[i] = f.eval(1.0 - 2.0 * s * s);  // cos psi = 1 - 2 s^2
        }
        value_.push_back(value_.back());  // eval reads i + 1 at s = 1
    }

    /// The tabulated function at cos_psi, linear in s = sqrt((1 - cos psi) / 2).
    double eval(double cos_psi) const {
        const double x = std::sqrt(std::clamp(0.5 * (1.0 - cos_psi), 0.0, 1.0)) * n_;
        const auto i = static_cast<std::size_t>(x);
        const double w = x - static_cast<double>(i);
        return value_[i] + w * (value_[i + 1] - value_[i]);
    }

    std::size_t intervals() const { return value_.size() - 2; }

private:
    double n_;
    std::vector<double> value_;
};

}  // namespace secchi
