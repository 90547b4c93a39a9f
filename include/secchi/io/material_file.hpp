#pragma once
// Reader for the DIRSIG material-file syntax of the IOP model (manual chapter 5): a generic
// syntax layer of nested sections and NAME = value parameters, with source locations, that a
// later binding step turns into IOP models. Also the reader of the two-column data files
// (spectral coefficients, phase-function tables) that FILENAME parameters point to.
//
// Syntax (manual 5.3, 5.5):
//   NAME {            opens a section; the '{' must end the line ("NAME{" is fine too)
//   }                 closes the innermost open section, alone on its line
//   NAME = value      a parameter; the value runs to the end of the line and is trimmed
//   # ...             a comment to the end of the line (our choice: the manual shows none;
//                     DIRSIG's material files use '#'). A '#' therefore cannot be part of a value.
//   blank lines are ignored; names are letters, digits and '_', case-sensitive (the manual's
//   are upper case: TYPE, ID, ...), values are case-sensitive too ("morelconc").
// Value forms read by ParameterReader: numbers (finite, no trailing garbage), arrays of numbers
// separated by spaces and/or commas ("0.9, 0.5 0.1"), booleans as 0 or 1, text, and file names
// resolved relative to the material file's directory.
// Every error is a secchi::input_error naming the file:line, and where relevant the section and
// the parameter.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

namespace secchi::SECCHI_ISA::io {

/// Where a section or parameter was written: the file name as given and its 1-based line.
struct SourceLocation {
    std::string file;
    int line = 0;
    /// "file:line"
    [[nodiscard]] std::string where() const { return file + ":" + std::to_string(line); }
};

/// One NAME = value line.
struct MaterialParameter {
    std::string name, value;
    SourceLocation loc;
};

/// One NAME { ... } block. The root returned by parse_material has an empty name and line 0
/// and holds the top-level sections (and any top-level parameters).
struct MaterialSection {
    std::string name;
    SourceLocation loc;
    std::vector<MaterialParameter> parameters;
    std::vector<MaterialSection> sections;

    /// The first parameter with this name, or nullptr (names are unique within a section).
    [[nodiscard]] const MaterialParameter* find(std::string_view key) const {
        for (const auto& p : parameters)
            if (p.name == key) return &p;
        return nullptr;
    }
    /// All direct subsections with this name, in file order (e.g. every ADD_ABSORPTION_MODEL).
    [[nodiscard]] std::vector<const MaterialSection*> all(std::string_view key) const {
        std::vector<const MaterialSection*> out;
        for (const auto& s : sections)
            if (s.name == key) out.push_back(&s);
        return out;
    }
    /// "ADD_ABSORPTION_MODEL (TYPE = morelconc)" when the section has a TYPE, else its name.
    [[nodiscard]] std::string describe() const {
        const std::string label = name.empty() ? std::string("(top level)") : name;
        if (const auto* type = find("TYPE")) return label + " (TYPE = " + type->value + ")";
        return label;
    }
};

namespace detail {

inline bool is_space(char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; }

/// Trims spaces, tabs and a Windows '\r'.
inline std::string_view trim(std::string_view s) {
    while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
    while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
    return s;
}

/// Drops a '#' comment and trims.
inline std::string_view strip_comment(std::string_view line) {
    if (const auto hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    return trim(line);
}

/// Names are letters, digits and '_', not starting with a digit.
inline bool is_name(std::string_view s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s.front()))) return false;
    return std::all_of(s.begin(), s.end(),
                       [](char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; });
}

/// A finite double filling the whole token (an optional leading '+'), else nullopt.
inline std::optional<double> parse_double(std::string_view token) {
    if (token.size() > 1 && token.front() == '+' && token[1] != '-' && token[1] != '+') token.remove_prefix(1);
    double v = 0.0;
    const char* end = token.data() + token.size();
    const auto [ptr, ec] = std::from_chars(token.data(), end, v);
    if (token.empty() || ec != std::errc{} || ptr != end || !std::isfinite(v)) return std::nullopt;
    return v;
}

/// Splits "0.9, 0.5 0.1" into tokens: commas and/or whitespace separate; an empty item between
/// commas (",," or a leading/trailing comma) is reported by returning nullopt.
inline std::optional<std::vector<std::string>> split_numbers(std::string_view text) {
    std::vector<std::string> out;
    std::size_t start = 0;
    while (true) {
        const std::size_t comma = text.find(',', start);
        const std::string_view item = text.substr(start, comma == std::string_view::npos ? text.npos : comma - start);
        std::istringstream words{std::string(item)};
        const std::size_t before = out.size();
        for (std::string w; words >> w;) out.push_back(w);
        if (out.size() == before) return std::nullopt;  // empty item
        if (comma == std::string_view::npos) return out;
        start = comma + 1;
    }
}

/// Reads a whole file; input_error naming the path when missing or unreadable.
inline std::string slurp(const std::filesystem::path& path, std::string_view what) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec))
        reject(what, path.string(), "file does not exist or is not a regular file", path.string());
    std::ifstream in(path, std::ios::binary);
    if (!in.is_open()) reject(what, path.string(), "cannot open file", path.string());
    std::ostringstream buf;
    buf << in.rdbuf();
    if (in.bad()) reject(what, path.string(), "cannot read file", path.string());
    std::string text = buf.str();
    // A binary file is refused at its first control byte (tab, CR, LF and form feed are text).
    for (std::size_t i = 0; i < text.size(); ++i) {
        const auto c = static_cast<unsigned char>(text[i]);
        if (c >= 0x20 || c == '\t' || c == '\r' || c == '\n' || c == '\f') continue;
        std::string where = path.string();
        where.append(":").append(std::to_string(1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(i), '\n')));
        char byte[8];
        std::snprintf(byte, sizeof byte, "0x%02x", c);
        std::string reason("is not a text file (control byte ");
        reason.append(byte).append(")");
        reject(what, path.string(), reason, where);
    }
    return text;
}

/// Calls fn(line_number, line) for every line of text (1-based; '\n' or "\r\n" endings; a
/// leading UTF-8 byte-order mark is skipped).
template <class Fn>
void for_each_line(std::string_view text, Fn&& fn) {
    if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    int number = 0;
    while (!text.empty()) {
        const std::size_t nl = text.find('\n');
        fn(++number, text.substr(0, nl));
        if (nl == std::string_view::npos) break;
        text.remove_prefix(nl + 1);
    }
}

/// The section-stack parser behind parse_material.
class MaterialParser {
public:
    explicit MaterialParser(std::string file) { root_.loc = {std::move(file), 0}; }

    void line(int number, std::string_view raw) {
        const std::string_view text = strip_comment(raw);
        const SourceLocation loc{root_.loc.file, number};
        if (text.empty()) return;
        if (text == "}") return close(loc);
        if (text.back() == '{') return open(trim(text.substr(0, text.size() - 1)), text, loc);
        if (const auto eq = text.find('='); eq != std::string_view::npos)
            return parameter(trim(text.substr(0, eq)), trim(text.substr(eq + 1)), text, loc);
        malformed(text, loc, "expected 'NAME {', '}' or 'NAME = value'");
    }

    MaterialSection finish() {
        if (!open_.empty()) {
            const MaterialSection& s = open_.back();
            reject("section", s.name, "not closed: missing '}' before the end of the file (section opened here)",
                   s.loc.where());
        }
        return std::move(root_);
    }

private:
    MaterialSection& current() { return open_.empty() ? root_ : open_.back(); }

    [[noreturn]] void malformed(std::string_view text, const SourceLocation& loc, std::string_view why) {
        reject("line", "'" + std::string(text) + "'", "malformed in section " + current().describe() + ": " + std::string(why),
               loc.where());
    }

    void open(std::string_view name, std::string_view text, const SourceLocation& loc) {
        if (!is_name(name)) malformed(text, loc, "a section is 'NAME {' with NAME of letters, digits and '_'");
        MaterialSection s;
        s.name = std::string(name);
        s.loc = loc;
        open_.push_back(std::move(s));
    }

    void close(const SourceLocation& loc) {
        if (open_.empty()) reject("line", "'}'", "stray '}' with no open section", loc.where());
        MaterialSection done = std::move(open_.back());
        open_.pop_back();
        current().sections.push_back(std::move(done));
    }

    void parameter(std::string_view name, std::string_view value, std::string_view text, const SourceLocation& loc) {
        if (!is_name(name)) malformed(text, loc, "a parameter is 'NAME = value' with NAME of letters, digits and '_'");
        MaterialSection& s = current();
        if (value.empty()) reject(name, "(empty)", "empty value in section " + s.describe(), loc.where());
        if (const auto* first = s.find(name))
            reject(name, value,
                   "duplicate parameter in section " + s.describe() + ", first given at " + first->loc.where(),
                   loc.where());
        s.parameters.push_back({std::string(name), std::string(value), loc});
    }

    MaterialSection root_;
    std::vector<MaterialSection> open_;  // the stack of sections still open, innermost last
};

}  // namespace detail

/// Parses material-file text; `file_name` labels the locations (and is the base directory of
/// relative FILENAMEs read through ParameterReader::file). Returns the root section.
inline MaterialSection parse_material(std::string_view text, std::string file_name) {
    detail::MaterialParser parser(std::move(file_name));
    detail::for_each_line(text, [&](int n, std::string_view line) { parser.line(n, line); });
    return parser.finish();
}

/// Reads and parses a material file; input_error naming the path if it cannot be read.
inline MaterialSection read_material_file(const std::filesystem::path& path) {
    return parse_material(detail::slurp(path, "material file"), path.string());
}

/// Typed access to one section's parameters for the binding step. Every accessor marks the
/// parameter as read; finish() then rejects any parameter never read (a misspelt or
/// unsupported name). Errors name file:line, the section and the parameter.
class ParameterReader {
public:
    /// Keeps its own copy of the section.
    explicit ParameterReader(MaterialSection section)
        : section_(std::move(section)), read_(section_.parameters.size(), false) {}

    [[nodiscard]] const MaterialSection& section() const { return section_; }
    /// "ADD_ABSORPTION_MODEL (TYPE = morelconc)"
    [[nodiscard]] std::string context() const { return section_.describe(); }

    /// True if the parameter is given. Does not count as reading it (finish() still rejects it
    /// if nothing reads it), but makes the name known to finish()'s hint.
    [[nodiscard]] bool has(const std::string& name) {
        known_.insert(name);
        return section_.find(name) != nullptr;
    }
    /// The parameter's location, or the section's when it is absent.
    [[nodiscard]] SourceLocation location(const std::string& name) const {
        const auto* p = section_.find(name);
        return p ? p->loc : section_.loc;
    }

    // ---- text
    [[nodiscard]] std::optional<std::string> optional_text(const std::string& name) {
        const auto* p = take(name);
        return p ? std::optional<std::string>(p->value) : std::nullopt;
    }
    [[nodiscard]] std::string text(const std::string& name, const std::string& fallback) {
        return optional_text(name).value_or(fallback);
    }
    [[nodiscard]] std::string text(const std::string& name) { return required(name).value; }

    // ---- numbers
    [[nodiscard]] std::optional<double> optional_number(const std::string& name) {
        const auto* p = take(name);
        return p ? std::optional<double>(to_number(*p)) : std::nullopt;
    }
    [[nodiscard]] double number(const std::string& name, double fallback) {
        return optional_number(name).value_or(fallback);
    }
    [[nodiscard]] double number(const std::string& name) { return to_number(required(name)); }
    /// A number within [lo, hi] (inclusive); the default is not checked.
    [[nodiscard]] double number_in(const std::string& name, double fallback, double lo, double hi) {
        const auto* p = take(name);
        if (!p) return fallback;
        const double v = to_number(*p);
        if (!(v >= lo && v <= hi)) {
            std::ostringstream range;
            range << "must be within [" << lo << ", " << hi << "] in section " << context();
            fail(*p, range.str());
        }
        return v;
    }

    // ---- booleans: exactly 0 or 1 (manual 5.5)
    [[nodiscard]] std::optional<bool> optional_flag(const std::string& name) {
        const auto* p = take(name);
        if (!p) return std::nullopt;
        if (p->value != "0" && p->value != "1") fail(*p, "a flag must be 0 or 1 in section " + context());
        return p->value == "1";
    }
    [[nodiscard]] bool flag(const std::string& name, bool fallback) { return optional_flag(name).value_or(fallback); }

    // ---- arrays of numbers separated by spaces and/or commas
    [[nodiscard]] std::optional<std::vector<double>> optional_numbers(const std::string& name) {
        const auto* p = take(name);
        return p ? std::optional<std::vector<double>>(to_numbers(*p)) : std::nullopt;
    }
    [[nodiscard]] std::vector<double> numbers(const std::string& name, std::vector<double> fallback) {
        auto v = optional_numbers(name);
        return v ? std::move(*v) : std::move(fallback);
    }
    [[nodiscard]] std::vector<double> numbers(const std::string& name) { return to_numbers(required(name)); }

    // ---- file names, relative to the material file's directory; the file must exist
    [[nodiscard]] std::optional<std::filesystem::path> optional_file(const std::string& name) {
        const auto* p = take(name);
        return p ? std::optional<std::filesystem::path>(to_file(*p)) : std::nullopt;
    }
    [[nodiscard]] std::filesystem::path file(const std::string& name) { return to_file(required(name)); }

    /// Throws input_error for a parameter whose value the binding rejects (e.g. an unknown
    /// TYPE), naming file:line, the section, the parameter and its value.
    [[noreturn]] void reject_value(const std::string& name, std::string_view reason) const {
        const auto* p = section_.find(name);
        if (!p) reject(name, "(missing)", std::string(reason) + " in section " + context(), section_.loc.where());
        fail(*p, std::string(reason) + " in section " + context());
    }

    /// Rejects the first parameter never read: "unknown parameter X in section
    /// ADD_ABSORPTION_MODEL (TYPE = morelconc) at file:line; known parameters: ...".
    void finish() const {
        for (std::size_t i = 0; i < read_.size(); ++i) {
            if (read_[i]) continue;
            const auto& p = section_.parameters[i];
            std::string msg = "unknown parameter " + p.name + " = " + p.value + " in section " + context() + " at " +
                              p.loc.where();
            if (!known_.empty()) {
                msg += "; known parameters:";
                for (const auto& k : known_) msg += " " + k;
            }
            throw input_error(msg);
        }
    }

private:
    /// Finds a parameter and marks it read; nullptr if absent.
    const MaterialParameter* take(const std::string& name) {
        known_.insert(name);
        for (std::size_t i = 0; i < section_.parameters.size(); ++i)
            if (section_.parameters[i].name == name) {
                read_[i] = true;
                return &section_.parameters[i];
            }
        return nullptr;
    }
    const MaterialParameter& required(const std::string& name) {
        const auto* p = take(name);
        if (!p) reject(name, "(missing)", "required parameter missing in section " + context(), section_.loc.where());
        return *p;
    }
    [[noreturn]] static void fail(const MaterialParameter& p, const std::string& reason) {
        reject(p.name, p.value, reason, p.loc.where());
    }
    [[nodiscard]] double to_number(const MaterialParameter& p) const {
        const auto v = detail::parse_double(p.value);
        if (!v) fail(p, "not a finite number in section " + context());
        return *v;
    }
    [[nodiscard]] std::vector<double> to_numbers(const MaterialParameter& p) const {
        const auto tokens = detail::split_numbers(p.value);
        if (!tokens) fail(p, "empty item in the array (separate numbers by spaces or commas) in section " + context());
        std::vector<double> out;
        for (const auto& t : *tokens) {
            const auto v = detail::parse_double(t);
            if (!v) fail(p, "array item '" + t + "' is not a finite number in section " + context());
            out.push_back(*v);
        }
        return out;
    }
    [[nodiscard]] std::filesystem::path to_file(const MaterialParameter& p) const {
        std::filesystem::path path(p.value);
        if (path.is_relative()) path = std::filesystem::path(p.loc.file).parent_path() / path;
        std::error_code ec;
        if (!std::filesystem::is_regular_file(path, ec))
            fail(p, "file " + path.string() + " does not exist (relative names are taken from the material file's "
                    "directory) in section " + context());
        return path;
    }

    MaterialSection section_;
    std::vector<bool> read_;        // parallel to section_.parameters
    std::set<std::string> known_;   // every name asked for, for finish()'s hint
};

/// A two-column data file: wavelength (nm) or angle/mu, and a value.
struct SpectralData {
    std::vector<double> wavelength_nm, value;
    std::filesystem::path path;
};

namespace detail {
/// Parses one data row into its numbers; input_error naming path:line when malformed.
inline std::vector<double> data_row(std::string_view text, const std::string& where) {
    const auto tokens = split_numbers(text);
    if (!tokens) reject("data line", "'" + std::string(text) + "'", "empty item between commas", where);
    std::vector<double> row;
    for (const auto& t : *tokens) {
        const auto v = parse_double(t);
        if (!v) reject("data line", "'" + std::string(text) + "'", "'" + t + "' is not a finite number", where);
        row.push_back(*v);
    }
    if (row.size() < 2) reject("data line", "'" + std::string(text) + "'", "needs at least 2 columns", where);
    return row;
}
}  // namespace detail

/// Reads a data file of two (or more) numeric columns separated by whitespace and/or commas:
/// first column wavelength in nm (or angle or mu for phase-function tables), second the value;
/// further columns are allowed but ignored, and every row must have as many as the first.
/// '#' comments and blank lines are skipped. The first column must increase strictly, and at
/// least 2 rows are needed. Errors are input_error naming path:line.
inline SpectralData read_spectral_file(const std::filesystem::path& path) {
    const std::string text = detail::slurp(path, "data file");
    SpectralData out;
    out.path = path;
    std::size_t columns = 0;
    int previous_line = 0;
    detail::for_each_line(text, [&](int n, std::string_view raw) {
        const std::string_view line = detail::strip_comment(raw);
        if (line.empty()) return;
        const std::string where = path.string() + ":" + std::to_string(n);
        const auto row = detail::data_row(line, where);
        if (columns == 0) columns = row.size();
        if (row.size() != columns)
            reject("data line", "'" + std::string(line) + "'",
                   "has " + std::to_string(row.size()) + " columns, the first row has " + std::to_string(columns), where);
        if (!out.wavelength_nm.empty() && !(row[0] > out.wavelength_nm.back()))
            reject("first column", row[0],
                   "must increase strictly (previous row at line " + std::to_string(previous_line) + ")", where);
        out.wavelength_nm.push_back(row[0]);
        out.value.push_back(row[1]);
        previous_line = n;
    });
    if (out.wavelength_nm.size() < 2)
        reject("data file", path.string(), "needs at least 2 data rows, found " + std::to_string(out.wavelength_nm.size()),
               path.string());
    return out;
}

}  // namespace secchi::io
