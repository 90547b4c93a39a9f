#pragma once
// Mobley et al. 1993, "Comparison of numerical models for computing underwater light
// fields", Applied Optics 32(36):7484-7504, Table 5: the average of the models (value) and
// their spread s/x (coefficient of variation), relative to E_perp = 1 W m^-2 nm^-1 on the
// surface (problem 4: at the top of the atmosphere; its s/x is the models' systematic offset).
// Transcribed from ../shared/reference/canonical_problems.md section 4.
#include <array>
#include <string_view>

namespace secchi::conformance {

struct ReferenceValue {
    std::string_view problem;
    double depth;  ///< optical depth tau (problems 1, 2, 5, 6) or metres (problem 3)
    std::string_view quantity;
    double value;
    double spread;  ///< s/x
};

inline constexpr std::array<ReferenceValue, 69> m93_table5{{
    {"1a", 1, "Ed", 3.66e-1, 0.002},  {"1a", 1, "Eou", 3.72e-1, 0.005},  {"1a", 1, "Lu", 4.85e-2, 0.015},
    {"1a", 5, "Ed", 4.33e-2, 0.003},  {"1a", 5, "Eou", 4.35e-2, 0.007},  {"1a", 5, "Lu", 5.59e-3, 0.052},
    {"1a", 10, "Ed", 3.16e-3, 0.015}, {"1a", 10, "Eou", 3.20e-3, 0.038}, {"1a", 10, "Lu", 4.37e-4, 0.091},
    {"1b", 1, "Ed", 1.41e-1, 0.001},  {"1b", 1, "Eou", 1.34e-2, 0.003},  {"1b", 1, "Lu", 1.72e-3, 0.044},
    {"1b", 5, "Ed", 1.07e-3, 0.005},  {"1b", 5, "Eou", 1.00e-4, 0.039},  {"1b", 5, "Lu", 1.37e-5, 0.288},
    {"1b", 10, "Ed", 2.93e-6, 0.102}, {"1b", 10, "Eou", 3.00e-7, 0.308}, {"1b", 10, "Lu", 3.39e-8, 0.197},
    {"2a", 1, "Ed", 4.13e-1, 0.001},  {"2a", 1, "Eou", 9.31e-2, 0.021},  {"2a", 1, "Lu", 6.99e-3, 0.063},
    {"2a", 5, "Ed", 1.87e-1, 0.005},  {"2a", 5, "Eou", 4.63e-2, 0.017},  {"2a", 5, "Lu", 3.26e-3, 0.055},
    {"2a", 10, "Ed", 6.85e-2, 0.010}, {"2a", 10, "Eou", 1.65e-2, 0.014}, {"2a", 10, "Lu", 1.21e-3, 0.109},
    {"2b", 1, "Ed", 1.62e-1, 0.000},  {"2b", 1, "Eou", 9.66e-4, 0.023},  {"2b", 1, "Lu", 5.47e-5, 0.060},
    {"2b", 5, "Ed", 2.27e-3, 0.002},  {"2b", 5, "Eou", 1.37e-5, 0.063},  {"2b", 5, "Lu", 6.24e-7, 0.355},
    {"2b", 10, "Ed", 1.30e-5, 0.047}, {"2b", 10, "Eou", 7.28e-8, 0.187}, {"2b", 10, "Lu", 4.02e-9, 0.248},
    {"3", 5, "Ed", 2.30e-1, 0.006},   {"3", 5, "Eou", 4.34e-2, 0.025},   {"3", 5, "Lu", 3.13e-3, 0.054},
    {"3", 25, "Ed", 1.62e-3, 0.028},  {"3", 25, "Eou", 2.86e-4, 0.038},  {"3", 25, "Lu", 2.12e-5, 0.061},
    {"3", 60, "Ed", 5.23e-5, 0.071},  {"3", 60, "Eou", 5.13e-6, 0.036},  {"3", 60, "Lu", 3.57e-7, 0.434},
    {"4", 1, "Ed", 3.23e-1, 0.076},   {"4", 1, "Eou", 7.13e-2, 0.091},   {"4", 1, "Lu", 5.63e-3, 0.111},
    {"4", 5, "Ed", 1.49e-1, 0.072},   {"4", 5, "Eou", 3.57e-2, 0.076},   {"4", 5, "Lu", 2.77e-3, 0.141},
    {"4", 10, "Ed", 5.56e-2, 0.070},  {"4", 10, "Eou", 1.31e-2, 0.073},  {"4", 10, "Lu", 9.60e-4, 0.107},
    {"5", 1, "Ed", 1.14e-1, 0.012},   {"5", 1, "Eou", 3.55e-2, 0.020},   {"5", 1, "Lu", 2.09e-3, 0.031},
    {"5", 5, "Ed", 4.33e-2, 0.009},   {"5", 5, "Eou", 1.22e-2, 0.028},   {"5", 5, "Lu", 7.63e-4, 0.036},
    {"5", 10, "Ed", 1.48e-2, 0.007},  {"5", 10, "Eou", 3.65e-3, 0.020},  {"5", 10, "Lu", 2.49e-4, 0.025},
    {"6", 1, "Ed", 1.62e-1, 0.000},   {"6", 1, "Eou", 9.81e-4, 0.010},   {"6", 1, "Lu", 6.84e-5, 0.020},
    {"6", 5, "Ed", 2.28e-3, 0.003},   {"6", 5, "Eou", 2.28e-3, 0.002},   {"6", 5, "Lu", 3.60e-4, 0.010},
}};

/// The DIRSIG photon-mapping results for problem 3 (the manual's Table 7.1, column PM), for
/// the report beside ours.
inline constexpr std::array<ReferenceValue, 9> dirsig_table71_problem3{{
    {"3", 5, "Ed", 2.13e-1, 0},  {"3", 5, "Eou", 4.26e-2, 0},  {"3", 5, "Lu", 3.18e-3, 0},
    {"3", 25, "Ed", 1.46e-3, 0}, {"3", 25, "Eou", 2.54e-4, 0}, {"3", 25, "Lu", 1.83e-5, 0},
    {"3", 60, "Ed", 3.46e-5, 0}, {"3", 60, "Eou", 3.42e-6, 0}, {"3", 60, "Lu", 3.84e-7, 0},
}};

}  // namespace secchi::conformance
