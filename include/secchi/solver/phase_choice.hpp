#pragma once
// Run-time choice of a phase function by name, for command lines and files: the edge where
// the configuration becomes a compile-time type (std::visit instantiates the whole
// simulation per phase type, so no virtual call reaches the photon loop).
//   isotropic | rayleigh | petzold | petzold-trapezoid | petzold-linear | hg:G
//   | schlick:K | pure-water | ff:BB (Fournier-Forand with b_b/b = BB, n = 1.10)
// (petzold: the canonical reading of M93 Table 2; the other two: optics/phase/petzold.hpp.)
// AnyPhase, the variant of every phase type, is defined in optics/phase/any_phase.hpp.
#include "secchi/core/error.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include <charconv>
#include <string>
#include <variant>

namespace secchi {

namespace detail {
/// The number after "prefix:" in spec, or input_error.
inline double phase_parameter(const std::string& spec, std::size_t prefix_length, const char* what) {
    const std::string text = spec.substr(prefix_length);
    double x = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (ec != std::errc{} || end != text.data() + text.size()) reject(what, spec, "the parameter must be a number");
    return x;
}
}  // namespace detail

inline AnyPhase parse_phase(const std::string& spec) {
    if (spec == "isotropic") return IsotropicPhase{};
    if (spec == "rayleigh") return RayleighPhase{};
    if (const auto reading = petzold_reading(spec)) return petzold_m93(*reading);
    if (spec == "pure-water") return pure_water_phase();
    if (spec.rfind("hg:", 0) == 0) return HenyeyGreensteinPhase(detail::phase_parameter(spec, 3, "phase hg:G"));
    if (spec.rfind("schlick:", 0) == 0) return SchlickPhase(detail::phase_parameter(spec, 8, "phase schlick:K"));
    if (spec.rfind("ff:", 0) == 0)
        return FournierForandPhase::from_backscatter_fraction(detail::phase_parameter(spec, 3, "phase ff:BB"));
    reject("phase", spec,
           "must be isotropic, rayleigh, petzold, petzold-trapezoid, petzold-linear, pure-water, hg:G, schlick:K "
           "or ff:BB");
}

}  // namespace secchi
