#pragma once
// A weighted sum of phase functions of one type (manual eq. 5.28, models "hgpf" and
// "schlick" of sections 5.8.3-5.8.4):
//   p(psi) = sum_i w_i p_i(psi),   w_i >= 0 normalised internally to sum 1,
// so p is normalised when every p_i is. Mean cosine sum_i w_i g_i, backscatter fraction
// sum_i w_i B_i. Sampling is exact: u1 picks component i with probability w_i and, rescaled
// to its interval, is reused as that component's u1 (so a sample still takes two uniforms);
// the density of the result is the mixture itself, pdf = sum_i w_i pdf_i = eval.
#include "secchi/core/config.hpp"
#include <algorithm>
#include <cmath>
#include <span>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "secchi/core/error.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/phase_function.hpp"
#include "secchi/optics/phase/schlick.hpp"

namespace secchi::SECCHI_ISA {

template <PhaseFunction P>
class PhaseMixture : public SampledByDirection<PhaseMixture<P>> {
public:
    /// weights: one per component, >= 0 and finite, not all 0 (any scale).
    PhaseMixture(std::vector<P> components, std::vector<double> weights)
        : components_(std::move(components)), weights_(std::move(weights)) {
        require(!components_.empty(), "components.size()", components_.size(), "a mixture needs a component");
        require(weights_.size() == components_.size(), "weights.size()", weights_.size(),
                "must equal the number of components (G and W of manual eq. 5.28)");
        double sum = 0.0;
        for (std::size_t i = 0; i < weights_.size(); ++i) {
            require(std::isfinite(weights_[i]) && weights_[i] >= 0.0, indexed_name("weights", i), weights_[i],
                    "weights must be finite and non-negative");
            sum += weights_[i];
        }
        require(sum > 0.0, "sum of weights", sum, "at least one weight must be positive");
        cum_.push_back(0.0);
        for (double& w : weights_) {
            w /= sum;
            cum_.push_back(cum_.back() + w);
        }
        cum_.back() = 1.0;
    }

    /// Eq. 5.28.
    double eval(double cos_psi) const {
        double p = 0.0;
        for (std::size_t i = 0; i < components_.size(); ++i)
            if (weights_[i] > 0.0) p += weights_[i] * components_[i].eval(cos_psi);
        return p;
    }
    /// The density of sample(): sum_i w_i pdf_i (equal to eval for exact components).
    double pdf(double cos_psi) const {
        double p = 0.0;
        for (std::size_t i = 0; i < components_.size(); ++i)
            if (weights_[i] > 0.0) p += weights_[i] * components_[i].pdf(cos_psi);
        return p;
    }

    /// Component i with cum_i <= u1 < cum_{i+1} (zero-weight components have empty
    /// intervals), then that component sampled with (u1 - cum_i) / w_i and u2; the density
    /// is the mixture's.
    /// The direction alone (what transport needs; sample(u1, u2), SampledByDirection, adds its density): the
    /// chosen component's direction, itself without density where the component can skip it.
    PhaseDirection sample_direction(double u1, double u2) const {
        const auto it = std::upper_bound(cum_.begin() + 1, cum_.end() - 1, u1);
        std::size_t i = static_cast<std::size_t>(it - cum_.begin()) - 1;
        while (weights_[i] <= 0.0 && i > 0) --i;  // u1 == 1 lands past a trailing zero weight
        const double v = std::clamp((u1 - cum_[i]) / weights_[i], 0.0, 1.0);
        return sample_direction_of(components_[i], v, u2);
    }

    /// Normalised weights (sum 1).
    const std::vector<double>& weights() const { return weights_; }
    const std::vector<P>& components() const { return components_; }

    /// Union of the components' kinks, for the integrator.
    std::vector<double> breakpoints() const {
        std::vector<double> b;
        for (const P& c : components_) {
            const auto bc = breakpoints_of(c);
            b.insert(b.end(), bc.begin(), bc.end());
        }
        std::sort(b.begin(), b.end());
        b.erase(std::unique(b.begin(), b.end()), b.end());
        return b;
    }

    std::string name() const {
        std::ostringstream s;
        s << "mixture(";
        for (std::size_t i = 0; i < components_.size(); ++i)
            s << (i ? ", " : "") << weights_[i] << " " << components_[i].name();
        s << ")";
        return s.str();
    }

private:
    std::vector<P> components_;
    std::vector<double> weights_, cum_;  // normalised weights; cum_[i] = w_0 + ... + w_{i-1}
};

namespace detail {
template <class P>
PhaseMixture<P> mixture_of(std::span<const double> params, std::span<const double> weights) {
    require(params.size() == weights.size(), "W.size()", weights.size(), "must equal G.size() (manual eq. 5.28)");
    std::vector<P> comps;
    for (double x : params) comps.emplace_back(x);
    return PhaseMixture<P>(std::move(comps), std::vector<double>(weights.begin(), weights.end()));
}
}  // namespace detail

/// Manual model "hgpf": HG components with asymmetry parameters g (array G) and weights w (W).
inline PhaseMixture<HenyeyGreensteinPhase> hg_mixture(std::span<const double> g, std::span<const double> w) {
    return detail::mixture_of<HenyeyGreensteinPhase>(g, w);
}

/// Manual model "schlick": Schlick components with parameters k (array G) and weights w (W).
inline PhaseMixture<SchlickPhase> schlick_mixture(std::span<const double> k, std::span<const double> w) {
    return detail::mixture_of<SchlickPhase>(k, w);
}

}  // namespace secchi
