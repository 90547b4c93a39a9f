#pragma once
// The "data" phase-function model (manual section 5.8.2): a user's table of phase-function
// values on scattering-angle samples theta (degrees) or, with the MUSAMPLES flag, on cosine
// samples mu = cos(theta) (the manual's preferred sampling, eq. 5.25). The manual leaves the
// normalisation 2 pi int p sin dtheta = 1 to the user; here a table whose raw integral (under
// the chosen interpolation convention, TabulatedPhase::raw_integral()) is off 1 by more than
// 5 % is rejected as unnormalised (a wrong unit or a missing 2 pi, not a rounding), and any
// smaller deviation is normalised away exactly. Petzold's table (M93) is off by 0.2 % under
// the trapezoid convention and 2 % with p linear in angle, so it passes.
#include "secchi/core/config.hpp"
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/optics/phase/tabulated.hpp"

namespace secchi::SECCHI_ISA {

/// Largest accepted |raw integral - 1| of a user's table.
inline constexpr double table_normalisation_tolerance = 0.05;

/// Throws input_error unless |raw_integral - 1| <= 5 %.
inline void check_normalisation(double raw_integral) {
    require(std::isfinite(raw_integral) && std::abs(raw_integral - 1.0) <= table_normalisation_tolerance,
            "table integral 2 pi int p sin dtheta", raw_integral,
            "unnormalised table: a phase-function table must integrate to 1 within 5 % (manual 5.8.2)");
}

/// A table on angle samples (degrees, strictly increasing in [0, 180]), checked and
/// normalised (TabulatedPhase validates the nodes).
inline TabulatedPhase tabulated_from_theta_samples(std::span<const double> theta_deg, std::span<const double> p,
                                                   TabulatedConvention convention = TabulatedConvention::linear_p,
                                                   std::string name = "data(theta)") {
    TabulatedPhase t(std::vector<double>(theta_deg.begin(), theta_deg.end()), std::vector<double>(p.begin(), p.end()),
                     convention, std::nullopt, std::move(name));
    check_normalisation(t.raw_integral());
    return t;
}

/// Largest angular width (degrees) of a segment of a table built from mu samples.
inline constexpr double mu_table_max_step_deg = 0.25;

/// A table on cosine samples (MUSAMPLES; mu strictly monotone in [-1, 1], either order),
/// read as p linear in mu between samples (the manual integrates such tables over mu, eq.
/// 5.25). TabulatedPhase interpolates in angle, and equally spaced mu are sparse in angle
/// near 0 and 180 deg (width sqrt(2 dmu)), so each mu interval is cut into equal angle steps
/// of at most 0.25 deg, with p at the new nodes interpolated linearly in mu: the table then
/// follows the linear-in-mu reading to ~1e-5 relative (tests/test_phase_models.cpp). The
/// angles are acos(mu) (mu = -1 gives 180 deg exactly); the table is checked and normalised.
inline TabulatedPhase tabulated_from_mu_samples(std::span<const double> mu, std::span<const double> p,
                                                TabulatedConvention convention = TabulatedConvention::linear_p,
                                                std::string name = "data(mu)") {
    require(mu.size() == p.size(), "p.size()", p.size(), "must equal mu.size()");
    require(mu.size() >= 2, "mu.size()", mu.size(), "a table needs at least 2 nodes");
    const bool increasing = mu.back() > mu.front();
    std::vector<double> m, v;  // in decreasing mu = increasing angle
    for (std::size_t j = 0; j < mu.size(); ++j) {
        const std::size_t i = increasing ? mu.size() - 1 - j : j;
        require(std::isfinite(mu[i]) && mu[i] >= -1.0 && mu[i] <= 1.0, "mu", mu[i], "cosines must lie in [-1, 1]");
        require(j == 0 || mu[i] < m.back(), "mu", mu[i], "cosines must be strictly monotone");
        m.push_back(mu[i]);
        v.push_back(p[i]);
    }
    std::vector<double> angle, value;
    for (std::size_t i = 0; i < m.size(); ++i) {
        const double a = std::acos(m[i]) / pi * 180.0;
        if (i > 0) {  // interior nodes of the interval (m[i-1], m[i]), p linear in mu
            const double a0 = angle.back();
            const int steps = static_cast<int>(std::ceil((a - a0) / mu_table_max_step_deg));
            for (int s = 1; s < steps; ++s) {
                const double as = a0 + (a - a0) * s / steps, x = std::cos(as * deg);
                const double w = (m[i - 1] - x) / (m[i - 1] - m[i]);
                angle.push_back(as);
                value.push_back(v[i - 1] + w * (v[i] - v[i - 1]));
            }
        }
        angle.push_back(a);
        value.push_back(v[i]);
    }
    return tabulated_from_theta_samples(angle, value, convention, std::move(name));
}

}  // namespace secchi
