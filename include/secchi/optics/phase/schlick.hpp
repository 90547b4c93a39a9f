#pragma once
// Schlick phase function (Blasi, Le Saec and Schlick 1993; manual section 4.13.2, eq. 4.73,
// model "schlick" of section 5.8.4): a rational approximation of Henyey-Greenstein,
//   p(psi) = (1 - k^2) / (4 pi (1 - k cos psi)^2),   |k| < 1,
// with psi the scattering angle from the forward direction. Sign convention: k > 0 scatters
// forward, like HG's g (the manual: k is "analogous to g", "approximately the average
// cosine"); Blasi et al. write 1 + k cos with k < 0 forward because their angle is measured
// from the reversed incident direction. The mean cosine is not k but (see mean_cosine())
//   g = 1/k - (1 - k^2) atanh(k) / k^2   (= 2k/3 + O(k^3) for small k).
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class SchlickPhase : public SampledByDirection<SchlickPhase> {
public:
    explicit SchlickPhase(double k) : k_(k) {
        require(std::abs(k) < 1.0, "k", k, "the Schlick parameter needs |k| < 1");
    }

    /// Eq. 4.73; 1 - k mu written as (1 - k) + k (1 - mu): no cancellation near the peak.
    double eval(double cos_psi) const {
        const double d = (1.0 - k_) + k_ * (1.0 - cos_psi);
        return (1.0 - k_ * k_) / (four_pi * d * d);
    }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// Exact inverse CDF. The CDF in mu is (1 - k^2)/(2k) (1/(1 - k mu) - 1/(1 + k)) = u;
    /// solved and simplified with s = 2u - 1 it is the Moebius map mu = (s + k) / (1 + k s),
    /// which has no 0/0 as k -> 0 (isotropic, mu = s) and gives mu = +-1 at s = +-1.
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density).
    PhaseDirection sample_direction(double u1, double u2) const { return {cos_psi(u1), two_pi * u2}; }

    /// The inverse CDF above, for a double or for a SIMD vector of doubles or floats (photons
    /// in lanes, transport/lane_tracer.hpp): the same operations in the same order.
    template <class Real>
    Real cos_psi(Real u1) const {
        using T = scalar_t<Real>;
        const Real s = T(2) * u1 - T(1);
        const T k = T(k_);
        return clamp_cosine((s + k) / (T(1) + k * s));
    }

    /// g = 2 pi int p cos sin dpsi in closed form (series for small |k|, where the closed
    /// form cancels): 1/k - (1 - k^2) atanh(k)/k^2 = 2k/3 + 2k^3/15 + 2k^5/35 + ...
    double mean_cosine() const {
        const double k = k_;
        if (std::abs(k) < 1e-3) return k * (2.0 / 3.0 + k * k * (2.0 / 15.0 + k * k * 2.0 / 35.0));
        return 1.0 / k - (1.0 - k * k) * std::atanh(k) / (k * k);
    }

    double k() const { return k_; }

    std::string name() const {
        std::ostringstream s;
        s << "schlick(k=" << k_ << ")";
        return s.str();
    }

private:
    double k_;
};

}  // namespace secchi
