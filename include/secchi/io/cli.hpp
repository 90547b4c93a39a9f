#pragma once
// A small command-line reader for the example programs: --name value options, typed
// getters with defaults, and a usage error (exit status 2) naming the option and value.
// Every program also takes --quiet (no progress display: io/progress.hpp); output files are
// checked before the work and written whole or not at all (OutputFile).
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include "secchi/io/progress.hpp"
#include <charconv>
#include <cmath>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iostream>
#include <limits>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA {

/// The most worker threads a --threads option accepts.
inline constexpr std::uint64_t max_threads = 1024;

class CommandLine {
public:
    /// `known`: option names without dashes; `flags`: options that take no value (--quiet is
    /// one in every program); `max_positional`: how many arguments not starting with "--" the
    /// program takes (positional()). An unknown, repeated or valueless option is an input_error.
    CommandLine(int argc, char** argv, std::set<std::string> known, std::set<std::string> flags = {},
                std::size_t max_positional = 0) {
        flags.insert("quiet");
        for (int i = 1; i < argc; ++i) {
            std::string arg = argv[i];
            if (arg.rfind("--", 0) != 0) {
                if (positional_.size() >= max_positional)
                    reject("argument", arg, max_positional == 0 ? "expected --option" : "one argument too many");
                positional_.push_back(arg);
                continue;
            }
            const std::string name = arg.substr(2);
            if (!known.count(name) && !flags.count(name)) reject("option", arg, "unknown option");
            if (values_.count(name)) reject("option", arg, "is given more than once");
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
    /// True if `flag` (without dashes) is among the arguments, before any parsing.
    static bool has_flag(int argc, char** argv, std::string_view flag) {
        for (int i = 1; i < argc; ++i) {
            const std::string_view arg = argv[i];
            if (arg.size() == flag.size() + 2 && arg.substr(0, 2) == "--" && arg.substr(2) == flag) return true;
        }
        return false;
    }
    /// The arguments not starting with "--", in order.
    [[nodiscard]] const std::vector<std::string>& positional() const { return positional_; }
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
    /// A count that must lie in [lo, hi].
    [[nodiscard]] std::uint64_t count(const std::string& name, std::uint64_t fallback, std::uint64_t lo,
                                      std::uint64_t hi) const {
        const std::uint64_t v = count(name, fallback);
        if (v < lo || v > hi) {
            std::string reason("must be a whole number in [");
            reason.append(std::to_string(lo)).append(", ").append(std::to_string(hi)).append("]");
            reject("--" + name, has(name) ? text(name) : std::to_string(v), reason);
        }
        return v;
    }
    /// A count kept in an unsigned (--batches, --steps, ...): one above its range is an
    /// input_error naming the option, not a value wrapped modulo 2^32.
    [[nodiscard]] unsigned unsigned_count(const std::string& name, unsigned fallback) const {
        return static_cast<unsigned>(count(name, fallback, 0, std::numeric_limits<unsigned>::max()));
    }
    /// --threads: 1 to max_threads worker threads.
    [[nodiscard]] unsigned threads(unsigned fallback) const {
        return static_cast<unsigned>(count("threads", fallback, 1, max_threads));
    }
    [[nodiscard]] std::vector<double> numbers(const std::string& name, std::vector<double> fallback) const {
        if (!has(name)) return fallback;
        std::vector<double> out;
        std::stringstream ss(text(name));
        for (std::string item; std::getline(ss, item, ',');) out.push_back(parse<double>(name, item));
        if (out.empty()) reject("--" + name, text(name), "needs at least one number");
        return out;
    }

    /// A range option, START:STOP:STEP (STOP included when the steps land on it) or one number;
    /// every value must be >= `lowest`.
    [[nodiscard]] std::vector<double> range(const std::string& name, const std::string& fallback,
                                            double lowest = -INFINITY) const {
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
        if (parts.size() != 1 && parts.size() != 3) reject("--" + name, t, "expected START:STOP:STEP or one number");
        const double start = number(parts[0]);
        if (!(start >= lowest)) {
            std::string reason("must not go below ");
            reason.append(std::to_string(lowest));
            reject("--" + name, t, reason);
        }
        if (parts.size() == 1) return {start};
        const double stop = number(parts[1]), step = number(parts[2]);
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
    std::vector<std::string> positional_;
};

/// An output file written whole or not at all. The constructor checks the path before any work
/// (input_error naming `option` and the path if it is empty, a folder, in a folder that does
/// not exist, or cannot be created) and opens PATH.partial.<token>; the content goes there (stream(),
/// or any writer given partial_path()) and commit() renames it onto PATH. Without commit()
/// (an error on the way) the partial file is removed and PATH is left as it was.
class OutputFile {
public:
    OutputFile(std::string option, std::string path) : option_(std::move(option)), path_(std::move(path)) {
        namespace fs = std::filesystem;
        std::error_code ec;
        if (path_.empty()) reject(option_, "\"\"", "must name a file");
        if (fs::is_directory(path_, ec)) reject(option_, path_, "is a folder, not a file");
        const fs::path folder = fs::path(path_).parent_path();
        if (!folder.empty() && !fs::is_directory(folder, ec)) reject(option_, path_, "names a folder that does not exist");
        partial_ = path_;  // PATH.partial.<token>: unique per writer, so runs writing one PATH do not collide
        partial_ += ".partial.";
        partial_ += std::to_string(std::random_device{}());
        stream_.open(partial_, std::ios::binary | std::ios::trunc);
        if (!stream_) reject(option_, path_, "cannot be opened for writing");
    }
    OutputFile(const OutputFile&) = delete;
    OutputFile& operator=(const OutputFile&) = delete;
    ~OutputFile() {
        if (committed_) return;
        stream_.close();
        std::error_code ec;
        std::filesystem::remove(partial_, ec);
    }
    [[nodiscard]] const std::string& path() const { return path_; }
    /// Where a writer that takes a path writes the content (closes stream()).
    [[nodiscard]] const std::string& partial_path() {
        stream_.close();
        return partial_;
    }
    [[nodiscard]] std::ostream& stream() { return stream_; }
    /// Moves the finished content onto path() (input_error naming the option if it fails).
    void commit() {
        if (stream_.is_open()) {
            stream_.close();
            if (!stream_) reject(option_, path_, "could not be written");
        }
        std::error_code ec;
        std::filesystem::rename(partial_, path_, ec);
        if (ec) reject(option_, path_, std::string("could not be written: ") + ec.message());
        committed_ = true;
    }

private:
    std::string option_, path_, partial_;
    std::ofstream stream_;
    bool committed_ = false;
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

/// A program's main around body() (which returns the exit status): --help prints the usage
/// and exits 0; an input_error prints the one line "<name>: <message> (<name> --help: usage)"
/// on stderr and exits 2 (the programs' command-line contract); any other exception prints
/// "<name>: error: <what>" and exits 1. While body() runs, the loops of parallel_for show a
/// progress display on stderr (io/progress.hpp) unless --quiet is given.
template <class Body>
int run_program(int argc, char** argv, std::string_view name, std::string_view usage, Body&& body) {
    if (CommandLine::wants_help(argc, argv)) {
        std::cout << usage << "  --quiet   no progress display (shown on stderr when it is a terminal and the run lasts over 2 s)\n";
        return 0;
    }
    try {
        const ProgressDisplay progress(name, !CommandLine::has_flag(argc, argv, "quiet"));
        return body();
    } catch (const input_error& e) {
        std::cerr << name << ": " << e.what() << " (" << name << " --help: usage)" << std::endl;
        return 2;
    } catch (const std::exception& e) {
        std::cerr << name << ": error: " << e.what() << std::endl;
        return 1;
    }
}

}  // namespace secchi
