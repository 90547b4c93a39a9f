#pragma once
// A budget that cannot fit in memory is invalid input: refused before anything is allocated,
// with a message naming the parameter and its value, rather than ended by the OOM killer.
#include "secchi/core/config.hpp"
#include "secchi/core/error.hpp"
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#if __has_include(<unistd.h>)
#include <unistd.h>
#endif

namespace secchi::SECCHI_ISA {

/// The machine's physical memory in bytes (the largest std::uint64_t where it is unknown).
inline std::uint64_t physical_memory_bytes() {
#if __has_include(<unistd.h>) && defined(_SC_PHYS_PAGES) && defined(_SC_PAGESIZE)
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGESIZE);
    if (pages > 0 && page > 0) return static_cast<std::uint64_t>(pages) * static_cast<std::uint64_t>(page);
#endif
    return std::numeric_limits<std::uint64_t>::max();
}

/// Throws input_error naming `parameter` = `value` when `bytes` (at the least what the value
/// asks for) exceed the physical memory.
template <class Value>
void require_fits_in_memory(double bytes, std::string_view parameter, const Value& value,
                            source_location loc = source_location::current()) {
    const double available = static_cast<double>(physical_memory_bytes());
    if (bytes <= available) return;
    std::string reason("needs at least ");
    reason.append(std::to_string(static_cast<unsigned long long>(bytes / 1e9))).append(" GB of memory, more than the ");
    reason.append(std::to_string(static_cast<unsigned long long>(available / 1e9))).append(" GB here");
    reject(parameter, value, reason, {}, loc);
}

}  // namespace secchi
