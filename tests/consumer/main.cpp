// Uses the installed headers: a Henyey-Greenstein phase function's moments.
#include <secchi/optics/phase/henyey_greenstein.hpp>
#include <cmath>
#include <cstdio>

int main() {
    const auto m = secchi::phase_moments(secchi::HenyeyGreensteinPhase(0.8));
    std::printf("mean cosine %.6f\n", m.mean_cosine);
    return std::abs(m.mean_cosine - 0.8) < 1e-6 ? 0 : 1;
}
