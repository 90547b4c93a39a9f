#pragma once
// Run-time choice of a phase function by name, for command lines and files: the edge where
// the configuration becomes a compile-time type (std::visit instantiates the whole
// simulation per phase type, so no virtual call reaches the photon loop).
//   isotropic | rayleigh | petzold | petzold-linear | petzold-linear-flat | hg:G
#include "secchi/core/error.hpp"
#include "secchi/optics/phase/henyey_greenstein.hpp"
#include "secchi/optics/phase/isotropic.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/rayleigh.hpp"
#include <charconv>
#include <string>
#include <variant>

namespace secchi {

using AnyPhase = std::variant<IsotropicPhase, RayleighPhase, HenyeyGreensteinPhase, TabulatedPhase>;

inline AnyPhase parse_phase(const std::string& spec) {
    if (spec == "isotropic") return IsotropicPhase{};
    if (spec == "rayleigh") return RayleighPhase{};
    if (spec == "petzold") return petzold_m93(TabulatedConvention::trapezoid);
    if (spec == "petzold-linear") return petzold_m93(TabulatedConvention::linear_p);
    if (spec == "petzold-linear-flat") return petzold_m93_flat_forward();
    if (spec.rfind("hg:", 0) == 0) {
        const std::string g_text = spec.substr(3);
        double g = 0;
        const auto [end, ec] = std::from_chars(g_text.data(), g_text.data() + g_text.size(), g);
        if (ec != std::errc{} || end != g_text.data() + g_text.size()) reject("phase hg:G", spec, "G must be a number");
        return HenyeyGreensteinPhase(g);
    }
    reject("phase", spec, "must be isotropic, rayleigh, petzold, petzold-linear, petzold-linear-flat or hg:G");
}

}  // namespace secchi
