#pragma once
// The Rayleigh-based model (manual section 5.8.5, eq. 5.29, model "rayleigh"):
//   p(psi) = k1 (1 + k2 cos^2 psi),   k2 > -1,
// normalised when 2 pi k1 int_{-1}^{1} (1 + k2 mu^2) dmu = 4 pi k1 (1 + k2/3) = 1, i.e.
//   k1 = 1 / (4 pi (1 + k2/3)).
// The manual makes that normalisation the user's job; here k1 is always computed from k2,
// and from_k1_k2() rejects a user's k1 that is more than 1 % off it. Pure water (manual
// eq. 5.2, after Mobley 1994): k1 = 0.06225, k2 = 0.835 (normalised k1 = 0.0622507).
// RayleighPhase (M93 problem 1) is the case k2 = 1. Mean cosine 0, backscatter fraction 1/2.
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_function.hpp"

namespace secchi::SECCHI_ISA {

class RayleighLikePhase : public SampledByDirection<RayleighLikePhase> {
public:
    explicit RayleighLikePhase(double k2) : k2_(k2), k1_(1.0 / (four_pi * (1.0 + k2 / 3.0))) {
        require(std::isfinite(k2) && k2 > -1.0, "k2", k2,
                "the Rayleigh-like model needs k2 > -1 (p = k1 (1 + k2 cos^2) positive)");
    }

    /// Eq. 5.29 with the normalised k1 and a user's k1 checked against it (within 1 %).
    static RayleighLikePhase from_k1_k2(double k1, double k2) {
        const RayleighLikePhase p(k2);
        std::ostringstream why;
        why << "eq. 5.29 is normalised only for k1 = 1/(4 pi (1 + k2/3)) = " << p.k1() << " (k2 = " << k2
            << "); K1 must be within 1 % of it";
        require(std::isfinite(k1) && std::abs(k1 / p.k1() - 1.0) <= 0.01, "K1", k1, why.str());
        return p;
    }

    double eval(double cos_psi) const { return k1_ * (1.0 + k2_ * cos_psi * cos_psi); }
    double pdf(double cos_psi) const { return eval(cos_psi); }

    /// Exact inverse CDF. The CDF in mu, 2 pi k1 ((mu + 1) + k2 (mu^3 + 1)/3) = u, is the
    /// cubic k2 mu^3 + 3 mu = q with q = (2u - 1)(3 + k2), odd in mu and q.
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density).
    PhaseDirection sample_direction(double u1, double u2) const { return {cos_psi(u1), two_pi * u2}; }

    /// The inverse CDF above, for a double or for a SIMD vector of doubles or floats (photons
    /// in lanes, transport/lane_tracer.hpp): the same Newton steps, each lane stopping where
    /// its own root stops.
    template <class Real>
    Real cos_psi(Real u1) const {
        using std::abs;
        using T = scalar_t<Real>;
        const Real q = (T(2) * u1 - T(1)) * T(3.0 + k2_);
        return unit_with_sign_of(q) * solve_cubic(abs(q));  // std::copysign(root, q): the root is >= 0
    }

    double k1() const { return k1_; }
    double k2() const { return k2_; }

    std::string name() const {
        std::ostringstream s;
        s << "rayleigh_like(k2=" << k2_ << ")";
        return s.str();
    }

private:
    /// The root mu in [0, 1] of h(mu) = k2 mu^3 + 3 mu - aq (0 <= aq <= 3 + k2). h is
    /// increasing there (h' = 3 (1 + k2 mu^2) > 0 for k2 > -1), convex for k2 >= 0 and concave
    /// for k2 < 0, so Newton from mu = 1 (resp. 0) converges monotonically without overshoot;
    /// it stops when rounding ends the monotone progress (in lanes: each lane where its own
    /// progress ends, the loop when every lane's has).
    template <class Real>
    Real solve_cubic(const Real& aq) const {
        using std::max, std::min;
        using T = scalar_t<Real>;
        const bool convex = k2_ >= 0.0;
        const T k2 = static_cast<T>(k2_);
        Real mu(convex ? T(1) : T(0));
        for (int iter = 0; iter < 200; ++iter) {
            const Real h = (k2 * mu * mu + T(3)) * mu - aq, dh = T(3) * (T(1) + k2 * mu * mu);
            const Real next = min(max(mu - h / dh, Real(T(0))), Real(T(1)));  // std::clamp(., 0, 1)
            const auto progress = convex ? next < mu : next > mu;
            if (!any_lane(progress)) break;
            mu = select(progress, next, mu);
        }
        return mu;
    }

    double k2_, k1_;
};

/// Pure water, manual eq. 5.2: k1 = 0.06225, k2 = 0.835 (k1 as published, checked).
inline RayleighLikePhase pure_water_phase() { return RayleighLikePhase::from_k1_k2(0.06225, 0.835); }

}  // namespace secchi
