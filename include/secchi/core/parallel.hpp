#pragma once
// A minimal parallel loop: `threads` workers take indices 0..n-1 from an atomic counter.
// Callers write results into per-index slots and merge them in index order, so the result
// never depends on which thread ran which index. The outermost loop's finished indices are
// reported to the installed progress sink (core/progress.hpp), which only observes, unless
// the loop is LoopProgress::unreported (a short set-up loop, such as a table's values, that
// would otherwise count as one of a program's long loops).
#include "secchi/core/config.hpp"
#include "secchi/core/progress.hpp"
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace secchi::SECCHI_ISA {

/// Whether a loop's progress goes to the installed progress sink.
enum class LoopProgress { reported, unreported };

template <class F>
void parallel_for(std::size_t n, unsigned threads, F&& body, LoopProgress report = LoopProgress::reported) {
    std::atomic<std::size_t> next{0};
    std::exception_ptr error;
    std::mutex error_mutex;
    const ProgressLoop progress(n, report == LoopProgress::reported);
    auto worker = [&] {
        const bool nested = detail::inside_parallel_loop;
        detail::inside_parallel_loop = true;
        for (std::size_t i; (i = next.fetch_add(1)) < n;) {
            try {
                body(i);
                progress.advanced();
            } catch (...) {
                std::lock_guard lock(error_mutex);
                if (!error) error = std::current_exception();
                next = n;
            }
        }
        detail::inside_parallel_loop = nested;
    };
    const unsigned extra = threads > 1 ? std::min<std::size_t>(threads, n) - 1 : 0;
    std::vector<std::jthread> pool;
    for (unsigned t = 0; t < extra; ++t) pool.emplace_back(worker);
    worker();
    pool.clear();  // joins
    if (error) std::rethrow_exception(error);
}

}  // namespace secchi
