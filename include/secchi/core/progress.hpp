#pragma once
// Progress of the library's long loops (first-pass photon blocks, radiance estimates over rays,
// image rows): parallel_for (core/parallel.hpp) reports each finished index of its
// outermost loop to the ProgressSink installed for the process, if any. Reporting observes
// only: it never changes what a loop computes, and with no sink installed it costs one atomic
// load per loop. A display of it is io/progress.hpp's ProgressDisplay.
#include "secchi/core/config.hpp"
#include <atomic>
#include <cstddef>

namespace secchi::SECCHI_ISA {

/// Receives loop progress. loop_started and loop_finished come from the thread running the
/// loop, before its workers start and after they have joined; advanced() from any worker, once
/// per finished index (thread-safe, and cheap: an index is a block of photons, a ray or a row).
class ProgressSink {
public:
    virtual ~ProgressSink() = default;
    virtual void loop_started(std::size_t total) = 0;
    virtual void advanced() = 0;
    virtual void loop_finished() = 0;
};

namespace detail {
inline std::atomic<ProgressSink*> progress_sink{nullptr};
/// True on a thread while it runs a parallel_for body: loops nested in it are not reported.
inline thread_local bool inside_parallel_loop = false;
}  // namespace detail

/// Installs `sink` for the process while it lives (the previous one is restored after).
class ProgressScope {
public:
    explicit ProgressScope(ProgressSink* sink) : previous_(detail::progress_sink.exchange(sink)) {}
    ProgressScope(const ProgressScope&) = delete;
    ProgressScope& operator=(const ProgressScope&) = delete;
    ~ProgressScope() { detail::progress_sink.store(previous_); }

private:
    ProgressSink* previous_;
};

/// One loop of `total` indices as seen by the installed sink (none for a nested loop, or for
/// one not `reported`).
class ProgressLoop {
public:
    explicit ProgressLoop(std::size_t total, bool reported = true)
        : sink_(!reported || detail::inside_parallel_loop ? nullptr
                                                          : detail::progress_sink.load(std::memory_order_acquire)) {
        if (sink_) sink_->loop_started(total);
    }
    ProgressLoop(const ProgressLoop&) = delete;
    ProgressLoop& operator=(const ProgressLoop&) = delete;
    ~ProgressLoop() {
        if (sink_) sink_->loop_finished();
    }
    void advanced() const {
        if (sink_) sink_->advanced();
    }

private:
    ProgressSink* sink_;
};

}  // namespace secchi
