#pragma once
// Invalid input is an exception naming the parameter, the value and where it came from
// (a file:line of the user's input, or the source location of the check). Never a silent NaN.
#include "secchi/core/config.hpp"
#include <source_location>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace secchi::SECCHI_ISA {

/// Thrown for every invalid input: bad coefficient, |g| >= 1, malformed table or file, ...
class input_error : public std::invalid_argument {
public:
    using std::invalid_argument::invalid_argument;
};

namespace detail {
inline std::string location_string(const std::source_location& loc) {
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
                         std::source_location loc = std::source_location::current()) {
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
             std::source_location loc = std::source_location::current()) {
    if (!ok) reject(parameter, value, reason, {}, loc);
}

}  // namespace secchi
