#pragma once
// Run-time choice of a phase function by name, for command lines: the edge where the
// configuration becomes a compile-time type (std::visit instantiates the whole simulation per
// phase type, so no virtual call reaches the photon loop). The names, their parameters and
// what each builds are the registry's (optics/phase/phase_names.hpp): "name" or "name:X",
//   isotropic | rayleigh | petzold | petzold-trapezoid | petzold-linear | pure-water | hg:G
//   | schlick:K | ff:BB   (and the aliases uniform, hgpf:G, fournierforand:BB).
// AnyPhase, the variant of every phase type, is defined in optics/phase/any_phase.hpp.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/optics/phase/phase_names.hpp"
#include <algorithm>
#include <charconv>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>

namespace secchi::SECCHI_ISA {

/// "isotropic|rayleigh|...|ff:BB": the --phase choices of a usage text.
inline std::string phase_usage() { return join_names(cli_phase_spellings()); }

/// One line per model, "  hg:G (also hgpf)  Henyey-Greenstein ...": its command-line spelling
/// (the name alone for a model of material files only, so marked), aliases and description.
inline std::string phase_help() {
    std::string out;
    for (const PhaseModel& m : phase_models()) {
        std::string names = m.on_command_line ? cli_spelling(m) : std::string(m.naming.name);
        for (const auto alias : m.naming.aliases) names.append(" (also ").append(alias).append(")");
        if (!m.on_command_line) names += " (files)";
        out.append("  ").append(names).append(std::max<std::size_t>(names.size() + 2, 28) - names.size(), ' ');
        out.append(m.naming.description).append("\n");
    }
    return out;
}

namespace detail {
/// The number after "name:" in spec, or input_error naming the model's spelling ("phase hg:G").
inline double phase_parameter(const std::string& spec, std::size_t colon, const PhaseModel& model) {
    const std::string text = spec.substr(colon + 1);
    double x = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), x);
    if (ec != std::errc{} || end != text.data() + text.size())
        reject(std::string("phase ").append(cli_spelling(model)), spec, "the parameter must be a number");
    return x;
}
}  // namespace detail

/// The phase function a command line names: "name" or "name:X" (the registry's spellings, or
/// an alias in place of the name); input_error naming the value and the valid spellings.
inline AnyPhase parse_phase(const std::string& spec) {
    const std::size_t colon = spec.find(':');
    const PhaseModel* model = find_named(phase_models(), std::string_view(spec).substr(0, colon));
    if (!model || !model->on_command_line) reject("phase", spec, must_be_one_of(phase_models(), cli_phase_spellings()));
    const bool has_parameter = colon != std::string::npos;
    if (has_parameter != !model->cli_parameter.empty())
        reject("phase", spec, has_parameter ? std::string(model->naming.name).append(" takes no parameter")
                                            : std::string("needs its parameter: ").append(cli_spelling(*model)));
    return model->on_command_line(has_parameter ? detail::phase_parameter(spec, colon, *model) : 0.0);
}

/// parse_phase(spec) as one of Phases only: a program that simulates a few phase types visits
/// this narrower variant, so that its simulation is instantiated for those types alone (each
/// alternative of AnyPhase instantiates the whole first and second pass). input_error naming
/// `parameter`, spec and `allowed` when spec names another model.
template <class... Phases>
std::variant<Phases...> parse_phase_among(std::string_view parameter, const std::string& spec, std::string_view allowed) {
    AnyPhase any = parse_phase(spec);
    std::optional<std::variant<Phases...>> chosen;
    std::visit(
        [&]<class P>(P& phase) {
            if constexpr ((std::is_same_v<P, Phases> || ...)) chosen.emplace(std::in_place_type<P>, std::move(phase));
        },
        any);
    if (!chosen) reject(parameter, spec, std::string("must be ").append(allowed));
    return std::move(*chosen);
}

}  // namespace secchi
