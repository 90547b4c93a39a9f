#pragma once
// A small command-line reader for the example programs: --name value options, typed
// getters with defaults, and a usage error (exit status 2) naming the option and value.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <charconv>
#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

class CommandLine {
public:
    /// `known`: option names without dashes; `flags`: options that take no value.
    CommandLine(int argc, char** argv, std::set<std::string> known, std::set<std::string> flags = {}) {
        for (int i = 1; i < argc; ++i) {
            std::string arg = argv[i];
            if (arg.rfind("--", 0) != 0) reject("argument", arg, "expected --option");
            const std::string name = arg.substr(2);
            if (!known.count(name) && !flags.count(name)) reject("option", arg, "unknown option");
            // insert_or_assign of a whole string (not assignment from a char pointer, where
            // GCC 12 -O3 inlines a memcpy it then wrongly reports under -Wrestrict).
            if (flags.count(name)) {
                values_.insert_or_assign(name, std::string(1, '1'));
                continue;
            }
            if (i + 1 >= argc) reject("option", arg, "needs a value");
            values_.insert_or_assign(name, std::string(argv[++i]));
        }
    }
    /// True if --help is among the arguments (checked before parsing, so it always works).
    static bool wants_help(int argc, char** argv) {
        for (int i = 1; i < argc; ++i)
            if (std::string(argv[i]) == "--help") return true;
        return false;
    }
    [[nodiscard]] bool has(const std::string& name) const { return values_.count(name) != 0; }
    [[nodiscard]] std::string text(const std::string& name, const std::string& fallback = "") const {
        auto it = values_.find(name);
        return it == values_.end() ? fallback : it->second;
    }
    [[nodiscard]] std::string required_text(const std::string& name) const {
        if (!has(name)) reject("option --" + name, "(missing)", "is required");
        return text(name);
    }
    [[nodiscard]] double number(const std::string& name, double fallback) const {
        return has(name) ? parse<double>(name, text(name)) : fallback;
    }
    [[nodiscard]] std::uint64_t count(const std::string& name, std::uint64_t fallback) const {
        if (!has(name)) return fallback;
        const std::string t = text(name);
        // accept 1e6-style counts
        const double v = parse<double>(name, t);
        if (v < 0 || v != std::floor(v) || v > 1e18) reject("--" + name, t, "must be a non-negative whole number");
        return static_cast<std::uint64_t>(v);
    }
    [[nodiscard]] std::vector<double> numbers(const std::string& name, std::vector<double> fallback) const {
        if (!has(name)) return fallback;
        std::vector<double> out;
        std::stringstream ss(text(name));
        for (std::string item; std::getline(ss, item, ',');) out.push_back(parse<double>(name, item));
        if (out.empty()) reject("--" + name, text(name), "needs at least one number");
        return out;
    }

    /// A range option, START:STOP:STEP (STOP included when the steps land on it) or one number.
    [[nodiscard]] std::vector<double> range(const std::string& name, const std::string& fallback) const {
        const std::string t = has(name) ? text(name) : fallback;
        std::vector<std::string> parts(1);
        for (char ch : t) {
            if (ch == ':') parts.emplace_back();
            else parts.back().push_back(ch);
        }
        const auto number = [&](const std::string& part) {
            double v = 0.0;
            const auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
            if (part.empty() || ec != std::errc{} || end != part.data() + part.size() || !std::isfinite(v))
                reject("--" + name, t, "is not a number (expected START:STOP:STEP or one number)");
            return v;
        };
        if (parts.size() == 1) return {number(parts[0])};
        if (parts.size() != 3) reject("--" + name, t, "expected START:STOP:STEP or one number");
        const double start = number(parts[0]), stop = number(parts[1]), step = number(parts[2]);
        if (!(step > 0.0) || stop < start) reject("--" + name, t, "needs STEP > 0 and STOP >= START");
        const double n = std::floor((stop - start) / step + 1e-9);
        if (n > 1e6) reject("--" + name, t, "has more than a million values");
        std::vector<double> out;
        for (int k = 0; k <= static_cast<int>(n); ++k) out.push_back(start + k * step);
        return out;
    }

private:
    template <class T>
    static T parse(const std::string& name, const std::string& t) {
        T v{};
        const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
        if (ec != std::errc{} || end != t.data() + t.size() || !std::isfinite(static_cast<double>(v)))
            reject("--" + name, t, "is not a number");
        return v;
    }
    std::map<std::string, std::string> values_;
};

/// `text` with every "{key}" replaced by its value: a usage text whose lists of names come
/// from the registries (e.g. {"phases", phase_usage()}), so that it lists what the parsers accept.
inline std::string fill_usage(std::string text, std::initializer_list<std::pair<std::string_view, std::string>> lists) {
    for (const auto& [key, value] : lists) {
        std::string placeholder("{");
        placeholder.append(key).append("}");
        for (auto at = text.find(placeholder); at != std::string::npos; at = text.find(placeholder, at + value.size()))
            text.replace(at, placeholder.size(), value);
    }
    return text;
}

/// A program's main around body() (which returns the exit status): --help / -h prints the
/// usage and exits 0; an input_error prints "<name>: <message>" and the usage on stderr and
/// exits 2 (the programs' command-line contract).
template <class Body>
int run_program(int argc, char** argv, std::string_view name, std::string_view usage, Body&& body) {
    if (CommandLine::wants_help(argc, argv)) {
        std::cout << usage;
        return 0;
    }
    try {
        return body();
    } catch (const input_error& e) {
        std::cerr << name << ": " << e.what() << "\n" << usage;
        return 2;
    }
}

}  // namespace secchi
