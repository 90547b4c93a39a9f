#pragma once
// Invalid input is an exception naming the parameter, the value and where it came from
// (a file:line of the user's input, or the source location of the check). Never a silent NaN.
#include "secchi/core/config.hpp"
#include <sstream>
#include <version>
#if defined(__cpp_lib_source_location)
#include <source_location>
#endif
#include <stdexcept>
#include <string>
#include <string_view>

namespace secchi::SECCHI_ISA {

/// Thrown for every invalid input: bad coefficient, |g| >= 1, malformed table or file, ...
class input_error : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

#if defined(__cpp_lib_source_location)
using source_location = std::source_location;
#else
/// Where a check is, for compilers whose standard library lacks std::source_location (clang 14
/// with libstdc++ 12): the file and line of the call, by the builtins std::source_location uses.
struct source_location {
    static constexpr source_location current(const char* file = __builtin_FILE(), unsigned line = __builtin_LINE()) noexcept {
        return {file, line};
    }
    [[nodiscard]] constexpr const char* file_name() const noexcept { return file_; }
    [[nodiscard]] constexpr unsigned line() const noexcept { return line_; }
    const char* file_ = "";
    unsigned line_ = 0;
};
#endif

namespace detail {
inline std::string location_string(const source_location& loc) {
    std::string file = loc.file_name();
    if (auto slash = file.find_last_of('/'); slash != std::string::npos) file = file.substr(slash + 1);
    return file + ":" + std::to_string(loc.line());
}
}  // namespace detail

/// Throws input_error "invalid <parameter> = <value>: <reason> (at <where>)".
/// `where` is the user's file:line when the value came from a file, else the checking code.
template <class Value>
[[noreturn]] void reject(std::string_view parameter, const Value& value, std::string_view reason,
                         std::string_view where = {},
                         source_location loc = source_location::current()) {
    std::ostringstream msg;
    msg << "invalid " << parameter << " = " << value << ": " << reason << " (at "
        << (where.empty() ? detail::location_string(loc) : std::string(where)) << ")";
    throw input_error(msg.str());
}

/// "name[i]", the name of an array element in messages (built by appending: g++ 12 at -O3
/// flags "literal" + std::string with a false -Wrestrict).
inline std::string indexed_name(std::string_view name, std::size_t i) {
    std::string s(name);
    s += '[';
    s += std::to_string(i);
    s += ']';
    return s;
}

/// Checks a condition on an input value; throws input_error naming it otherwise.
template <class Value>
void require(bool ok, std::string_view parameter, const Value& value, std::string_view reason,
             source_location loc = source_location::current()) {
    if (!ok) reject(parameter, value, reason, {}, loc);
}

}  // namespace secchi
