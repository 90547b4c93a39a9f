#pragma once
// A progress display on stderr for the programs (run_program in io/cli.hpp installs one):
// once the run has lasted 2 s, each long loop shows one line, rewritten in place at most four
// times a second, "<program>: loop K, P% (E s, ETA R s)", with R extrapolated from the loop's
// own rate so far; the line is cleared when the loop ends and when the display goes. Shown only
// when stderr is a terminal and the program is not --quiet; SECCHI_PROGRESS=always (for tests)
// shows it from the start whatever stderr is. It observes the loops only (core/progress.hpp).
#include "secchi/core/config.hpp"
#include "secchi/core/progress.hpp"
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#if __has_include(<unistd.h>)
#include <unistd.h>
#endif

namespace secchi::SECCHI_ISA {

class ProgressDisplay final : public ProgressSink {
public:
    using clock = std::chrono::steady_clock;

    /// `wanted`: false for --quiet. The display is installed only if it would show.
    ProgressDisplay(std::string_view program, bool wanted) : program_(program) {
        const char* force = std::getenv("SECCHI_PROGRESS");
        const bool forced = force != nullptr && std::string_view(force) == "always";
        if (forced) delay_ = clock::duration::zero();
        if (wanted && (forced || stderr_is_terminal())) scope_.emplace(this);
    }
    ProgressDisplay(const ProgressDisplay&) = delete;
    ProgressDisplay& operator=(const ProgressDisplay&) = delete;
    ~ProgressDisplay() override {
        scope_.reset();
        clear_line();
    }

    void loop_started(std::size_t total) override {
        std::lock_guard lock(mutex_);
        total_.store(total, std::memory_order_relaxed);
        done_.store(0, std::memory_order_relaxed);
        loop_start_ = clock::now();
        ++loop_;
    }
    void advanced() override {
        const std::size_t done = done_.fetch_add(1, std::memory_order_relaxed) + 1;
        const auto now = clock::now();
        if (now.time_since_epoch().count() < next_print_.load(std::memory_order_relaxed)) return;
        std::unique_lock lock(mutex_, std::try_to_lock);
        if (!lock.owns_lock() || now - start_ < delay_) return;
        next_print_.store((now + std::chrono::milliseconds(250)).time_since_epoch().count(), std::memory_order_relaxed);
        const std::size_t total = total_.load(std::memory_order_relaxed);
        const double elapsed = std::chrono::duration<double>(now - loop_start_).count();
        const double eta = elapsed * static_cast<double>(total - std::min(done, total)) / static_cast<double>(done);
        std::fprintf(stderr, "\r%.*s: loop %u, %3.0f%% (%.1f s, ETA %.1f s)\x1b[K", static_cast<int>(program_.size()),
                     program_.data(), loop_, 100.0 * static_cast<double>(done) / static_cast<double>(total), elapsed, eta);
        std::fflush(stderr);
        shown_ = true;
    }
    void loop_finished() override { clear_line(); }

private:
    static bool stderr_is_terminal() {
#if __has_include(<unistd.h>)
        return isatty(STDERR_FILENO) != 0;
#else
        return false;
#endif
    }
    void clear_line() {
        std::lock_guard lock(mutex_);
        if (!shown_) return;
        std::fputs("\r\x1b[K", stderr);
        std::fflush(stderr);
        shown_ = false;
    }

    std::string program_;
    clock::time_point start_ = clock::now(), loop_start_ = start_;
    clock::duration delay_ = std::chrono::seconds(2);
    std::mutex mutex_;
    std::atomic<std::size_t> total_{0}, done_{0};
    std::atomic<clock::rep> next_print_{0};
    unsigned loop_ = 0;
    bool shown_ = false;
    std::optional<ProgressScope> scope_;  ///< engaged while this display is the process's sink
};

}  // namespace secchi
