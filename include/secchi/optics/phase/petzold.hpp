#pragma once
// Petzold's average particle phase function (Petzold 1972, San Diego harbour, pure water
// removed) as tabulated in Mobley, Gentili, Gordon, Jin, Kattawar, Morel, Reinersman, Stamnes
// and Stavn, "Comparison of numerical models for computing underwater light fields",
// Applied Optics 32(36):7484-7504, 1993 (M93), Table 2; manual section 5.8.6. M93: "use linear
// interpolation" between the tabulated angles and p(psi) = p(0.12589) (0.12589/psi)^1.346
// below 0.12589 deg. Which reading of that is canonical is fixed in canonical_problems.md
// (section 2, problem 2): PetzoldReading below.
#include "secchi/core/config.hpp"
#include <array>
#include <optional>
#include <utility>
#include <vector>

#include "secchi/optics/phase/tabulated.hpp"

namespace secchi::SECCHI_ISA {

struct PetzoldNode {
    double angle_deg;
    double value;  ///< 1/sr
};

/// M93 Table 2 (angle in degrees : value in 1/sr), copied from canonical_problems.md, section 3.
inline constexpr std::array<PetzoldNode, 55> petzold_m93_table{{
    {0.10000, 1.76661e3}, {0.12589, 1.29564e3}, {0.15849, 9.50172e2}, {0.19953, 6.99092e2},
    {0.25119, 5.13687e2}, {0.31623, 3.76373e2}, {0.39811, 2.76318e2}, {0.50119, 2.18839e2},
    {0.63096, 1.44369e2}, {0.79433, 1.02241e2}, {1.0000, 7.16082e1},  {1.2589, 4.95803e1},
    {1.5849, 3.39511e1},  {1.9953, 2.28129e1},  {2.5119, 1.51622e1},  {3.1623, 1.00154e1},
    {3.9811, 6.57957},    {5.0119, 4.29530},    {6.3096, 2.80690},    {7.9433, 1.81927},
    {10.0, 1.15257},      {15.0, 4.89344e-1},   {20.0, 2.44424e-1},   {25.0, 1.47151e-1},
    {30.0, 8.60848e-2},   {35.0, 5.93075e-2},   {40.0, 4.20985e-2},   {45.0, 3.06722e-2},
    {50.0, 2.27533e-2},   {55.0, 1.69904e-2},   {60.0, 1.31254e-2},   {65.0, 1.04625e-2},
    {70.0, 8.48826e-3},   {75.0, 6.97601e-3},   {80.0, 5.84232e-3},   {85.0, 4.95306e-3},
    {90.0, 4.29232e-3},   {95.0, 3.78161e-3},   {100.0, 3.40405e-3},  {105.0, 3.11591e-3},
    {110.0, 2.91222e-3},  {115.0, 2.79696e-3},  {120.0, 2.68568e-3},  {125.0, 2.57142e-3},
    {130.0, 2.47603e-3},  {135.0, 2.37667e-3},  {140.0, 2.32898e-3},  {145.0, 2.31308e-3},
    {150.0, 2.36475e-3},  {155.0, 2.50584e-3},  {160.0, 2.66183e-3},  {165.0, 2.83472e-3},
    {170.0, 3.03046e-3},  {175.0, 3.09206e-3},  {180.0, 3.15366e-3},
}};
static_assert(petzold_m93_table.back().angle_deg == 180.0, "M93 Table 2 has 55 nodes, 0.1 to 180 deg");

/// M93's small-angle power law exponent: p ~ psi^-1.346 below 0.12589 deg.
inline constexpr double petzold_m93_exponent = 1.346;

/// The readings of Table 2 (canonical_problems.md, section 2, problem 2):
///  - canonical ("petzold"): all 55 nodes from 0.1 deg, p linear in angle between them, p held at
///    p(0.1 deg) below 0.1 deg (no power law), normalised numerically to 1: b_b/b 0.0184, mean
///    cosine 0.92. Its backscatter fraction is the one published for this function (0.0183:
///    Mobley 1994, "Light and Water"; the average-particle function of Hydrolight, one of the
///    M93 models). The particle function of problems 2-6 and of the Kirk checks.
///  - trapezoid ("petzold-trapezoid"): M93's stated rule, the nodes from 0.12589 deg with
///    2 pi p sin(psi) trapezoidal in psi and the power law p(0.12589) (0.12589/psi)^1.346 below
///    0.12589 deg (the 0.1-deg entry lies inside the power law, which it agrees with to 1e-4);
///    raw integral 1.002, b_b/b 0.01809.
///  - linear ("petzold-linear"): p linear in angle from 0.12589 deg, the same power law; raw
///    integral 1.020, b_b/b 0.01779.
enum class PetzoldReading { canonical, trapezoid, linear };

inline TabulatedPhase petzold_m93(PetzoldReading reading = PetzoldReading::canonical) {
    std::vector<double> angle, value;
    const std::size_t first = reading == PetzoldReading::canonical ? 0 : 1;
    for (std::size_t i = first; i < petzold_m93_table.size(); ++i) {
        angle.push_back(petzold_m93_table[i].angle_deg);
        value.push_back(petzold_m93_table[i].value);
    }
    switch (reading) {
        case PetzoldReading::canonical:
            return TabulatedPhase(angle, value, TabulatedConvention::linear_p, std::nullopt, "petzold");
        case PetzoldReading::trapezoid:
            return TabulatedPhase(angle, value, TabulatedConvention::trapezoid, petzold_m93_exponent, "petzold-trapezoid");
        case PetzoldReading::linear:
            break;
    }
    return TabulatedPhase(angle, value, TabulatedConvention::linear_p, petzold_m93_exponent, "petzold-linear");
}

}  // namespace secchi
