#pragma once
// Water whose IOPs vary with depth (canonical problem 3; manual 3.3.4 and 5.4).
//
// The profile is given at depth nodes z_0 = 0 <= z_1 <= ... <= z_N: the absorption a(z_k) and,
// for each scattering component i (manual eq. 5.4), b_i(z_k) with its phase function p_i.
// Between nodes every coefficient is linear in depth; below z_N it stays at its z_N value.
// A repeated depth (z_k = z_{k+1}) makes a jump: two layers of different water.
//
// Linear coefficients make the optical depth from the surface, K(z) = int_0^z k dz', a
// piecewise quadratic, so both transport queries are exact (the manual's "linear model of
// the optical depth solved by a quadratic", 3.3.4):
//   optical path of a flight  tau = (K(z1) - K(z0)) / uz,
//   free path for a target tau: K(z1) = K(z0) + tau uz, solved in the node interval by the
//   stable root x = 2 dK / (k_j + sqrt(k_j^2 + 2 m dK)) of m x^2 / 2 + k_j x = dK (slope m).
// Near-horizontal flights (|uz| < 1e-6) use the local coefficient: over such a flight the
// depth changes by less than 1e-6 per metre travelled.
//
// The phase function at depth z is the mixture sum_i (b_i / b) p_i (manual eq. 5.5-5.6).
// sample_phase (and sample_direction, the same without the density) picks component i with
// probability b_i(z) / b(z) using u1, then reuses u1 rescaled to its interval, so sampling
// still takes two uniforms.
//
// The components' phase types are part of the water's type:
//   StratifiedWater<P>           any number of components (1 to 8), all of type P, in a
//                                std::vector<P>; P = AnyPhaseFunction where the types are known
//                                at run time only (iop::stratify of a material file);
//   StratifiedWater<P0, P1, ...> one component per listed type, in a std::tuple<P0, P1, ...>
//                                (e.g. problem 3's Rayleigh water and Petzold particles): every
//                                component is called on its own type, with no variant.
// Both forms share one implementation and give the same numbers for the same phase functions:
// the component is chosen by the same arithmetic, then called on its type.
//
// How finely a smooth model (e.g. a Gaussian chlorophyll profile) must be sampled is the
// caller's choice: linear interpolation errs by at most h^2 max|k''| / 8 for node spacing h.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/core/math.hpp"
#include "secchi/optics/medium.hpp"
#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

/// A depth profile of IOPs at nodes (see the header comment).
struct DepthProfile {
    std::vector<double> depth;                    ///< z_k (m), nondecreasing, depth[0] = 0
    std::vector<double> absorption;               ///< a(z_k) (1/m)
    std::vector<std::vector<double>> scattering;  ///< scattering[i][k] = b_i(z_k) (1/m)
};

namespace detail {

/// The scattering components' phase functions of a StratifiedWater<Phases...>.
template <class... Phases>
class StratifiedPhases;

/// Any number of components of one type, in order.
template <PhaseFunction Phase>
class StratifiedPhases<Phase> {
public:
    using phase_type = Phase;
    using storage_type = std::vector<Phase>;

    [[nodiscard]] std::size_t components() const { return phases_.size(); }
    [[nodiscard]] const std::vector<Phase>& phases() const { return phases_; }
    /// f(p_i) for component i < components().
    template <class F>
    decltype(auto) visit_phase(std::size_t i, F&& f) const {
        return f(phases_[i]);
    }
    /// f(p_i) for each component, as a std::vector.
    template <class F>
    [[nodiscard]] auto transform_phases(F&& f) const {
        std::vector<std::decay_t<std::invoke_result_t<F&, const Phase&>>> out;
        out.reserve(phases_.size());
        for (const auto& p : phases_) out.push_back(f(p));
        return out;
    }

protected:
    explicit StratifiedPhases(std::vector<Phase> phases) : phases_(std::move(phases)) {}

private:
    std::vector<Phase> phases_;
};

/// One component per type, in order: each is called on its own type.
template <PhaseFunction P0, PhaseFunction P1, PhaseFunction... Rest>
class StratifiedPhases<P0, P1, Rest...> {
public:
    using storage_type = std::tuple<P0, P1, Rest...>;

    [[nodiscard]] static constexpr std::size_t components() { return 2 + sizeof...(Rest); }
    [[nodiscard]] const storage_type& phases() const { return phases_; }
    /// f(p_i) for component i < components() (f returns the same type for every component).
    template <std::size_t I = 0, class F>
    auto visit_phase(std::size_t i, F&& f) const {
        if constexpr (I + 1 == components()) {
            return f(std::get<I>(phases_));
        } else {
            if (i == I) return f(std::get<I>(phases_));
            return visit_phase<I + 1>(i, f);
        }
    }
    /// f(p_i) for each component, as a std::tuple.
    template <class F>
    [[nodiscard]] auto transform_phases(F&& f) const {
        return std::apply([&](const auto&... p) { return std::make_tuple(f(p)...); }, phases_);
    }

protected:
    explicit StratifiedPhases(storage_type phases) : phases_(std::move(phases)) {}

private:
    storage_type phases_;
};

}  // namespace detail

/// Depth-varying water with scattering components of the phase types Phases (see the header
/// comment: one type for a vector of components, several for one component each).
template <PhaseFunction... Phases>
class StratifiedWater : public detail::StratifiedPhases<Phases...> {
    using Components = detail::StratifiedPhases<Phases...>;

public:
    static constexpr std::size_t max_components = 8;
    static_assert(sizeof...(Phases) >= 1 && sizeof...(Phases) <= max_components,
                  "StratifiedWater: 1 to 8 phase types");
    /// The phase functions: std::vector<P> for StratifiedWater<P>, std::tuple<P0, P1, ...> else.
    using storage_type = typename Components::storage_type;

    /// refractive_index: the water's real index of refraction at the run's wavelength, where the
    /// medium's description gives one (a material's REFRACTIVE_INDEX_MODEL, manual 5.9); the
    /// solver's surface takes it unless told otherwise.
    StratifiedWater(DepthProfile profile, storage_type phases, std::optional<double> refractive_index = {})
        : Components(std::move(phases)), z_(std::move(profile.depth)), b_i_(std::move(profile.scattering)),
          refractive_index_(refractive_index) {
        if (refractive_index_)
            require(std::isfinite(*refractive_index_) && *refractive_index_ >= 1.0, "refractive index of water",
                    *refractive_index_, "must be finite and >= 1");
        validate(profile.absorption);
        const std::size_t n = z_.size();
        k_[0] = std::move(profile.absorption);
        k_[1].assign(n, 0.0);
        for (const auto& bi : b_i_)
            for (std::size_t j = 0; j < n; ++j) k_[1][j] += bi[j];
        k_[2].resize(n);
        for (std::size_t j = 0; j < n; ++j) k_[2][j] = k_[0][j] + k_[1][j];
        for (int c = 0; c < 3; ++c) {
            cumulative_[c] = cumulate(k_[c]);
            index_cumulative(c);
        }
        for (const auto& bi : b_i_) component_cumulative_.push_back(cumulate(bi));
        detect_uniform_spacing();
    }

    using Components::components;
    using Components::phases;
    using Components::transform_phases;
    using Components::visit_phase;
    /// f(p_i) for each component in order.
    template <class F>
    void for_each_phase(F&& f) const {
        for (std::size_t i = 0; i < components(); ++i) visit_phase(i, f);
    }
    [[nodiscard]] std::optional<double> refractive_index() const { return refractive_index_; }
    [[nodiscard]] const std::vector<double>& depths() const { return z_; }

    /// k(z) (1/m), linear between nodes.
    [[nodiscard]] double coefficient(Coefficient k, double z) const { return interpolate(k_[index(k)], z); }
    /// b_i(z) (1/m) of scattering component i.
    [[nodiscard]] double component_scattering(std::size_t i, double z) const { return interpolate(b_i_[i], z); }
    /// Optical depth from the surface to z, K(z) = int_0^z k dz'.
    [[nodiscard]] double optical_depth(Coefficient k, double z) const {
        return integral_to(k_[index(k)], cumulative_[index(k)], z);
    }

    [[nodiscard]] double optical_path(Coefficient k, double z, double uz, double s) const {
        return path_of(k_[index(k)], cumulative_[index(k)], z, uz, s);
    }
    /// int b_i over a flight of length s from depth z with direction cosine uz: component i's
    /// scattering optical path.
    [[nodiscard]] double component_optical_path(std::size_t i, double z, double uz, double s) const {
        return path_of(b_i_[i], component_cumulative_[i], z, uz, s);
    }

    [[nodiscard]] double distance_to(Coefficient k, double z, double uz, double tau) const {
        if (std::abs(uz) < horizontal) {
            const double v = coefficient(k, z);
            return v > 0.0 ? tau / v : INFINITY;
        }
        const double target = optical_depth(k, z) + tau * uz;
        if (target < 0.0) return INFINITY;  // upward: reaches the surface first
        return (depth_at_optical_depth(k, target) - z) / uz;
    }

    /// Direction from the mixture at depth z (eq. 5.5-5.6), with the mixture's density there.
    [[nodiscard]] PhaseSample sample_phase(double z, double u1, double u2) const {
        const PhaseDirection d = sample_direction(z, u1, u2);
        return {d.cos_psi, d.phi, eval_phase(z, d.cos_psi)};
    }
    /// The direction of sample_phase(z, u1, u2) without its density (what transport needs).
    [[nodiscard]] PhaseDirection sample_direction(double z, double u1, double u2) const {
        return choose_component(z, u1, [&](const auto& p, double v) { return sample_direction_of(p, v, u2); });
    }

    /// sum_i (b_i(z) / b(z)) f(i): a mixture over the components at depth z (eq. 5.5-5.6),
    /// e.g. of their phase functions; 0 where b = 0.
    template <class F>
    [[nodiscard]] double mixture(double z, F&& f) const {
        std::array<double, max_components> w{};
        const double b = weights(z, w);
        double sum = 0.0;
        for (std::size_t i = 0; i < components(); ++i) sum = mul_add(w[i], f(i), sum);
        return b > 0.0 ? sum / b : 0.0;
    }

    /// Phase function of the mixture at depth z (1/sr).
    [[nodiscard]] double eval_phase(double z, double cos_psi) const {
        return mixture(z, [&](std::size_t i) {
            return visit_phase(i, [&](const auto& p) { return static_cast<double>(p.eval(cos_psi)); });
        });
    }

    /// The component choice of sample_phase: component `index` with probability b_i(z) / b(z)
    /// by u1, and u1 rescaled to v within that component's interval (u1 itself when there is
    /// one component): sample_direction(z, u1, u2) is component index's sample_direction(v, u2).
    struct ComponentChoice {
        std::size_t index;
        double v;
    };
    [[nodiscard]] ComponentChoice choose(double z, double u1) const {
        if (components() == 1) return {0, u1};
        std::array<double, max_components> w{};
        const double target = u1 * weights(z, w);
        double lo = 0.0;
        std::size_t i = 0;
        while (i + 1 < components() && target >= lo + w[i]) lo += w[i++];
        return {i, std::clamp((target - lo) / w[i], 0x1p-53, 1.0 - 0x1p-53)};
    }

    /// b_i(z) into w (unnormalised mixture weights); returns b(z) = sum_i b_i(z).
    double weights(double z, std::array<double, max_components>& w) const {
        const std::size_t j = cell(z);
        double b = 0.0;
        for (std::size_t i = 0; i < components(); ++i) b += (w[i] = interpolate_in(b_i_[i], j, z));
        return b;
    }

private:
    static constexpr double horizontal = 1e-6;

    /// f(p_i, v) for the component i and rescaled uniform v that choose(z, u1) gives, called on
    /// component i's own type.
    template <class F>
    [[nodiscard]] auto choose_component(double z, double u1, F&& f) const {
        const ComponentChoice c = choose(z, u1);
        return visit_phase(c.index, [&](const auto& p) { return f(p, c.v); });
    }

    static int index(Coefficient k) { return k == Coefficient::absorption ? 0 : k == Coefficient::scattering ? 1 : 2; }

    void validate(const std::vector<double>& a) const {
        require(!z_.empty() && z_.front() == 0.0, "depth profile: first depth (m)", z_.empty() ? NAN : z_.front(),
                "must be 0 (the surface)");
        require(a.size() == z_.size(), "depth profile: absorption values", a.size(), "must match the depth nodes");
        require(components() >= 1 && components() <= max_components, "scattering components", components(),
                "must be 1 to 8");
        require(b_i_.size() == components(), "depth profile: scattering components", b_i_.size(),
                "must match the phase functions");
        for (std::size_t j = 0; j < z_.size(); ++j) {
            require(std::isfinite(z_[j]) && (j == 0 || z_[j] >= z_[j - 1]), "depth profile: depth (m)", z_[j],
                    "must be finite and nondecreasing");
            require(std::isfinite(a[j]) && a[j] >= 0.0, "depth profile: absorption (1/m)", a[j], "must be >= 0");
            for (const auto& bi : b_i_) {
                require(bi.size() == z_.size(), "depth profile: scattering values", bi.size(), "must match the nodes");
                require(std::isfinite(bi[j]) && bi[j] >= 0.0, "depth profile: scattering (1/m)", bi[j], "must be >= 0");
            }
        }
    }

    /// K at each node (trapezoid = exact for linear k).
    std::vector<double> cumulate(const std::vector<double>& k) const {
        std::vector<double> cum(z_.size(), 0.0);
        for (std::size_t j = 1; j < z_.size(); ++j) cum[j] = cum[j - 1] + 0.5 * (k[j] + k[j - 1]) * (z_[j] - z_[j - 1]);
        return cum;
    }

    /// Equally spaced nodes (the usual case: iop::uniform_depths) are found by division.
    void detect_uniform_spacing() {
        const std::size_t n = z_.size();
        if (n < 2 || z_[1] <= 0.0) return;
        const double h = z_[1];
        for (std::size_t j = 0; j < n; ++j)
            if (std::abs(z_[j] - static_cast<double>(j) * h) > 1e-9 * h * static_cast<double>(j + 1)) return;
        inverse_spacing_ = 1.0 / h;
    }

    /// Node interval j with z_j <= z < z_{j+1} (the last node for z beyond it; 0 above the surface).
    [[nodiscard]] std::size_t cell(double z) const {
        if (inverse_spacing_ > 0.0) {
            if (!(z > 0.0)) return 0;
            const double x = z * inverse_spacing_;
            if (x >= static_cast<double>(z_.size() - 1)) return z_.size() - 1;
            std::size_t j = static_cast<std::size_t>(x);
            // Division may land one node off where z sits on a node: settle by comparison.
            if (z < z_[j]) --j;
            else if (j + 1 < z_.size() && z >= z_[j + 1]) ++j;
            return j;
        }
        const auto it = std::upper_bound(z_.begin(), z_.end(), z);
        return it == z_.begin() ? 0 : static_cast<std::size_t>(it - z_.begin()) - 1;
    }

    [[nodiscard]] double interpolate(const std::vector<double>& v, double z) const { return interpolate_in(v, cell(z), z); }

    /// int_0^z k dz' for the profile k at the nodes (linear between them) with cumulative cum.
    [[nodiscard]] double integral_to(const std::vector<double>& kk, const std::vector<double>& cum, double z) const {
        const std::size_t j = cell(z);
        const double x = z - z_[j];
        if (j + 1 == z_.size() || x <= 0.0) return cum[j] + kk[j] * x;
        const double slope = (kk[j + 1] - kk[j]) / (z_[j + 1] - z_[j]);
        return cum[j] + x * (kk[j] + 0.5 * slope * x);
    }
    /// The profile's optical path over a flight (a level one at its mid-depth value).
    [[nodiscard]] double path_of(const std::vector<double>& kk, const std::vector<double>& cum, double z, double uz,
                                 double s) const {
        const double z1 = z + uz * s;
        if (std::abs(uz) < horizontal) return interpolate(kk, 0.5 * (z + z1)) * s;
        return (integral_to(kk, cum, z1) - integral_to(kk, cum, z)) / uz;
    }

    [[nodiscard]] double interpolate_in(const std::vector<double>& v, std::size_t j, double z) const {
        if (j + 1 == z_.size() || z <= z_[j]) return v[j];
        return v[j] + (v[j + 1] - v[j]) * (z - z_[j]) / (z_[j + 1] - z_[j]);
    }

    /// A coarse index into the nondecreasing K_j: bins of equal width in K (four per node on
    /// average), each holding the last node j with K_j <= the bin's start, so that finding
    /// the node interval of a given K is a lookup and a short forward walk.
    void index_cumulative(int c) {
        const auto& cum = cumulative_[c];
        const std::size_t bins = 4 * cum.size();
        bin_width_[c] = cum.back() / static_cast<double>(bins);
        bin_node_[c].assign(bins + 1, 0);
        if (!(bin_width_[c] > 0.0)) return;
        std::size_t j = 0;
        for (std::size_t b = 0; b <= bins; ++b) {
            const double start = static_cast<double>(b) * bin_width_[c];
            while (j + 1 < cum.size() && cum[j + 1] <= start) ++j;
            bin_node_[c][b] = j;
        }
    }

    /// The last node j with K_j <= target (target >= 0).
    [[nodiscard]] std::size_t node_below(int c, double target) const {
        const auto& cum = cumulative_[c];
        std::size_t j = 0;
        if (bin_width_[c] > 0.0) {
            const double b = std::min(target / bin_width_[c], static_cast<double>(bin_node_[c].size() - 1));
            j = bin_node_[c][static_cast<std::size_t>(b)];
        }
        while (j + 1 < cum.size() && cum[j + 1] <= target) ++j;
        return j;
    }

    /// The depth where K(z) = target (target >= 0), by the quadratic of 3.3.4.
    [[nodiscard]] double depth_at_optical_depth(Coefficient k, double target) const {
        const auto& kk = k_[index(k)];
        const auto& cum = cumulative_[index(k)];
        const std::size_t j = node_below(index(k), target);
        const double dk = target - cum[j];
        if (j + 1 == z_.size()) return kk[j] > 0.0 ? z_[j] + dk / kk[j] : INFINITY;
        const double h = z_[j + 1] - z_[j];
        const double slope = (kk[j + 1] - kk[j]) / h;
        const double disc = std::max(0.0, kk[j] * kk[j] + 2.0 * slope * dk);
        const double denom = kk[j] + std::sqrt(disc);
        const double x = denom > 0.0 ? 2.0 * dk / denom : 0.0;
        return z_[j] + std::min(x, h);
    }

    std::vector<double> z_;
    std::array<std::vector<double>, 3> k_;           ///< a, b, c at the nodes
    std::array<std::vector<double>, 3> cumulative_;  ///< K at the nodes
    std::array<double, 3> bin_width_{};               ///< index_cumulative's bins
    std::array<std::vector<std::size_t>, 3> bin_node_;
    std::vector<std::vector<double>> b_i_;
    std::vector<std::vector<double>> component_cumulative_;  ///< int b_i at the nodes
    std::optional<double> refractive_index_;
    double inverse_spacing_ = 0.0;  ///< 1 / h for equally spaced nodes, else 0
};

}  // namespace secchi
