#pragma once
// The registry of phase-function names: the one table that both the command lines
// (solver/phase_choice.hpp, parse_phase: "name" or "name:X") and the material files
// (io/material_medium.hpp, ADD_PHASE_FUNCTION_MODEL { TYPE = name ... }, DIRSIG manual 5.8)
// look names up in, and from which their usage texts and error messages list the names.
//
//   name               aliases         command line        material file (defaults)   source
//   isotropic          uniform         isotropic           -                          eq. 5.26
//   rayleigh                           rayleigh (k2 = 1)   K2 (1), K1 (checked)       eq. 5.29
//   petzold                            petzold             -                          M93 Table 2
//   petzold-trapezoid                  petzold-trapezoid   -                          (petzold.hpp)
//   petzold-linear                     petzold-linear      -
//   pure-water                         pure-water          -                          eq. 5.2
//   hg                 hgpf            hg:G                G (0), W (1): lists        eq. 5.28
//   schlick                            schlick:K           G (0), W (1): lists        eq. 5.28
//   ff                 fournierforand  ff:BB (N = 1.10)    BB (0.0183), N (1.10)      fournier_forand.hpp
//   data                               (files only)        FILENAME, MUSAMPLES (0)    5.8.2
// (equations: the DIRSIG manual's chapter 5.)
// The canonical names are the command line's; the manual's TYPE names (uniform, hgpf, and
// secchi's fournierforand) are aliases, accepted in both places. Each form builds what it
// always built: on a command line "rayleigh" is RayleighPhase (k2 = 1 exactly, M93 problem 1)
// and "hg:G" / "schlick:K" one function; in a file "rayleigh" is RayleighLikePhase(K2)
// (K2 = 1: the same function) and hgpf / schlick the mixture of eq. 5.28 (one component: the
// same function). pure-water (eq. 5.2, otherwise the phase function of a purewater base
// medium, 5.3) is accepted in files too; data reads a file, so it is for files only.
#include "secchi/core/config.hpp"
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "secchi/core/names.hpp"
#include "secchi/optics/phase/any_phase.hpp"
#include "secchi/optics/phase/petzold.hpp"
#include "secchi/optics/phase/tabulated_samples.hpp"

namespace secchi::SECCHI_ISA {

/// The named parameters of a phase model in a material file's ADD_PHASE_FUNCTION_MODEL
/// section, as io/material_medium.hpp reads them (each accessor marks the parameter as read;
/// errors name the file, line and parameter).
class PhaseFileParameters {
public:
    virtual double number(const std::string& name, double fallback) = 0;
    virtual std::optional<double> optional_number(const std::string& name) = 0;
    virtual std::vector<double> numbers(const std::string& name, std::vector<double> fallback) = 0;
    virtual bool flag(const std::string& name, bool fallback) = 0;
    /// The first two columns (x, value) of the data file the parameter names.
    virtual std::pair<std::vector<double>, std::vector<double>> columns(const std::string& name) = 0;

protected:
    ~PhaseFileParameters() = default;
};

/// One phase-function model: its names, its parameters in each form and how each form builds it.
struct PhaseModel {
    Naming naming;
    std::string_view cli_parameter;  ///< the X of "name:X" on a command line; empty: the name alone
    AnyPhase (*on_command_line)(double x);           ///< nullptr: not on command lines
    AnyPhase (*in_file)(PhaseFileParameters& file);  ///< nullptr: not in material files
};

namespace detail {
template <PetzoldReading reading>
PhaseModel petzold_model(std::string_view name, std::string_view description) {
    return {{name, {}, description}, {},
            [](double) -> AnyPhase { return petzold_m93(reading); },
            [](PhaseFileParameters&) -> AnyPhase { return petzold_m93(reading); }};
}
}  // namespace detail

/// Every phase-function model, in the order the usage texts list them.
inline const std::vector<PhaseModel>& phase_models() {
    static const std::vector<PhaseModel> models{
        {{"isotropic", {"uniform"}, "the same in every direction, p = 1/(4 pi) (manual eq. 5.26)"}, {},
         [](double) -> AnyPhase { return IsotropicPhase{}; },
         [](PhaseFileParameters&) -> AnyPhase { return IsotropicPhase{}; }},
        {{"rayleigh", {}, "k1 (1 + k2 cos^2) (eq. 5.29): command line k2 = 1 (M93 problem 1); files K2 (1), K1"}, {},
         [](double) -> AnyPhase { return RayleighPhase{}; },
         [](PhaseFileParameters& f) -> AnyPhase {
             const double k2 = f.number("K2", 1.0);
             const auto k1 = f.optional_number("K1");
             return k1 ? RayleighLikePhase::from_k1_k2(*k1, k2) : RayleighLikePhase(k2);
         }},
        detail::petzold_model<PetzoldReading::canonical>(
            "petzold", "Petzold's average particle, M93 Table 2: all 55 nodes, p linear in angle"),
        detail::petzold_model<PetzoldReading::trapezoid>(
            "petzold-trapezoid", "Petzold by M93's stated rule: trapezoids from 0.126 deg, a power law below"),
        detail::petzold_model<PetzoldReading::linear>(
            "petzold-linear", "Petzold, p linear in angle from 0.126 deg, the same power law below"),
        {{"pure-water", {}, "pure water, k1 (1 + k2 cos^2) with k1 = 0.06225, k2 = 0.835 (manual eq. 5.2)"}, {},
         [](double) -> AnyPhase { return pure_water_phase(); },
         [](PhaseFileParameters&) -> AnyPhase { return pure_water_phase(); }},
        {{"hg", {"hgpf"}, "Henyey-Greenstein of mean cosine G; files: sum w_i HG(g_i), lists G (0), W (1), eq. 5.28"},
         "G", [](double g) -> AnyPhase { return HenyeyGreensteinPhase(g); },
         [](PhaseFileParameters& f) -> AnyPhase { return hg_mixture(f.numbers("G", {0.0}), f.numbers("W", {1.0})); }},
        {{"schlick", {}, "Schlick of parameter K; files: sum w_i S(k_i), lists G (0: the k), W (1), eq. 5.28"}, "K",
         [](double k) -> AnyPhase { return SchlickPhase(k); },
         [](PhaseFileParameters& f) -> AnyPhase {
             return schlick_mixture(f.numbers("G", {0.0}), f.numbers("W", {1.0}));
         }},
        {{"ff", {"fournierforand"}, "Fournier-Forand of b_b/b = BB and n = 1.10; files: BB (0.0183), N (1.10)"}, "BB",
         [](double bb) -> AnyPhase { return FournierForandPhase::from_backscatter_fraction(bb); },
         [](PhaseFileParameters& f) -> AnyPhase {
             return FournierForandPhase::from_backscatter_fraction(f.number("BB", 0.0183), f.number("N", 1.10));
         }},
        {{"data", {}, "a table of p on angles (deg), or on cosines with MUSAMPLES = 1; FILENAME (5.8.2)"}, {}, nullptr,
         [](PhaseFileParameters& f) -> AnyPhase {
             const auto [x, p] = f.columns("FILENAME");
             if (f.flag("MUSAMPLES", false)) return tabulated_from_mu_samples(x, p);
             return tabulated_from_theta_samples(x, p);
         }},
    };
    return models;
}

/// How a command line writes the model: "hg:G", or the name alone.
inline std::string cli_spelling(const PhaseModel& m) {
    std::string s(m.naming.name);
    if (!m.cli_parameter.empty()) s.append(":").append(m.cli_parameter);
    return s;
}

/// The command line's spellings ("isotropic", ..., "hg:G", ...), for usage texts and errors.
inline std::vector<std::string> cli_phase_spellings() {
    return spellings(phase_models(), cli_spelling, [](const PhaseModel& m) { return m.on_command_line != nullptr; });
}

/// The TYPE names a material file accepts (canonical; the aliases too are accepted).
inline std::vector<std::string> file_phase_types() {
    return spellings(
        phase_models(), [](const PhaseModel& m) { return std::string(m.naming.name); },
        [](const PhaseModel& m) { return m.in_file != nullptr; });
}

}  // namespace secchi
