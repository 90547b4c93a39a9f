#pragma once
// A weighted histogram of scattering angles psi (bins of equal width over [0, pi]), checked
// against a phase function's exact probabilities: the tests of the biased direction draws
// (backscatter bias, upward importance), whose weighted angles must follow the phase function.
#include <catch2/catch.hpp>

#include "secchi/core/math.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace secchi::test {

/// Henyey-Greenstein's probability of mu <= x (mu the cosine from the lobe's axis), exact:
/// (1 - g^2) / (2 g) (1 / sqrt(1 + g^2 - 2 g x) - 1 / (1 + g)), for g != 0.
inline double hg_cdf(double g, double x) {
    return (1.0 - g * g) / (2.0 * g) * (1.0 / std::sqrt(1.0 + g * g - 2.0 * g * x) - 1.0 / (1.0 + g));
}

class WeightedAngles {
public:
    explicit WeightedAngles(int bins) : bins_(bins), s1_(bins), s2_(bins) {}

    void add(double psi, double weight) {
        const int bin = std::min(bins_ - 1, static_cast<int>(psi / pi * bins_));
        s1_[bin] += weight;
        s2_[bin] += weight * weight;
    }

    /// Over n draws, each bin's weighted frequency within 4 SE of the weighted mean (plus 1e-12)
    /// of probability(lo, hi), the phase function's exact probability of psi in [lo, hi).
    template <class Probability>
    void check(int n, const Probability& probability) const {
        int far = 0;
        for (int i = 0; i < bins_; ++i) {
            const double mean = s1_[i] / n, se = std::sqrt(std::max(s2_[i] / n - mean * mean, 0.0) / n);
            const double exact = probability(i * pi / bins_, (i + 1) * pi / bins_);
            INFO("bin " << i << ": " << mean << " +- " << se << " exact " << exact);
            CHECK(std::abs(mean - exact) <= 4.0 * se + 1e-12);
            far += std::abs(mean - exact) > 4.0 * se + 1e-12 ? 1 : 0;
        }
        CHECK(far == 0);
    }

private:
    int bins_;
    std::vector<double> s1_, s2_;
};

}  // namespace secchi::test
