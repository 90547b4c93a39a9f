#pragma once
// A family of names that users type (phase functions, photon stores, tracers, ...): per entry
// its canonical name, the other spellings accepted for it and a one-line description. Lookup,
// the usage texts' "a|b|c" and the error messages' "a, b or c" all read the family's one table,
// so the command lines, the material files, the usage texts and the errors cannot drift apart.
// A family is a range of entries, each with a member `naming` (a Naming).
#include "secchi/core/config.hpp"
#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

#include "secchi/core/error.hpp"

namespace secchi::SECCHI_ISA {

struct Naming {
    std::string_view name;                  ///< the canonical spelling
    std::vector<std::string_view> aliases;  ///< other spellings accepted for it
    std::string_view description;           ///< one line, for usage texts and docs

    /// True if s is the name or one of the aliases (exact, case-sensitive).
    [[nodiscard]] bool spelled_by(std::string_view s) const {
        return s == name || std::find(aliases.begin(), aliases.end(), s) != aliases.end();
    }
};

/// The entry of `family` that `spelling` names (canonically or by an alias), or nullptr.
template <class Family>
[[nodiscard]] const auto* find_named(const Family& family, std::string_view spelling) {
    const auto it = std::find_if(std::begin(family), std::end(family),
                                 [&](const auto& entry) { return entry.naming.spelled_by(spelling); });
    return it == std::end(family) ? nullptr : &*it;
}

/// spell(entry) for the entries of `family` that `keep` accepts, in the family's order.
template <class Family, class Spell, class Keep>
[[nodiscard]] std::vector<std::string> spellings(const Family& family, Spell spell, Keep keep) {
    std::vector<std::string> out;
    for (const auto& entry : family)
        if (keep(entry)) out.emplace_back(spell(entry));
    return out;
}

/// The canonical names of a family's entries.
template <class Family>
[[nodiscard]] std::vector<std::string> canonical_names(const Family& family) {
    return spellings(family, [](const auto& e) { return std::string(e.naming.name); }, [](const auto&) { return true; });
}

/// "a|b|c", as usage texts list the choices of an option.
inline std::string join_names(const std::vector<std::string>& names, std::string_view separator = "|") {
    std::string out;
    for (const auto& n : names) {
        if (!out.empty()) out += separator;
        out += n;
    }
    return out;
}

/// "a", "a or b", "a, b or c", as error messages list the choices.
inline std::string or_list(const std::vector<std::string>& names) {
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i) {
        if (i > 0) out += i + 1 == names.size() ? " or " : ", ";
        out += names[i];
    }
    return out;
}

/// "uniform = isotropic, hgpf = hg" (every alias of `family`'s entries with its canonical
/// name), or empty when the family has none.
template <class Family>
[[nodiscard]] std::string alias_list(const Family& family) {
    std::string out;
    for (const auto& entry : family)
        for (const auto alias : entry.naming.aliases) {
            if (!out.empty()) out += ", ";
            out += alias;
            out += " = ";
            out += entry.naming.name;
        }
    return out;
}

/// "must be a, b or c" and, where the family has aliases, " (also: uniform = isotropic, ...)":
/// the reason of an error for a name that is none of `names` (spellings of `family`'s entries).
template <class Family>
[[nodiscard]] std::string must_be_one_of(const Family& family, const std::vector<std::string>& names) {
    std::string reason = "must be ";
    reason += or_list(names);
    if (const std::string aliases = alias_list(family); !aliases.empty()) {
        reason += " (also: ";
        reason += aliases;
        reason += ')';
    }
    return reason;
}

/// An entry of a family of plain choices: a name for one value (of an enum).
template <class Value>
struct NamedValue {
    Naming naming;
    Value value;
};

/// "a|b|c": the canonical names, as a usage text lists an option's choices.
template <class Family>
[[nodiscard]] std::string usage_names(const Family& family) {
    return join_names(canonical_names(family));
}

/// The value `spelling` names in `family`; input_error naming `parameter`, the spelling and
/// the valid names otherwise.
template <class Value>
[[nodiscard]] Value parse_named(const std::vector<NamedValue<Value>>& family, std::string_view parameter,
                                const std::string& spelling) {
    const auto* entry = find_named(family, spelling);
    if (!entry) reject(parameter, spelling, must_be_one_of(family, canonical_names(family)));
    return entry->value;
}

/// The canonical name of `value` in `family` ("?" for a value the family lacks).
template <class Value>
[[nodiscard]] std::string name_of(const std::vector<NamedValue<Value>>& family, Value value) {
    for (const auto& entry : family)
        if (entry.value == value) return std::string(entry.naming.name);
    return "?";
}

}  // namespace secchi
