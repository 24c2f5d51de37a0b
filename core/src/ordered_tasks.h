// OrderedTasks: tasks 0 .. n-1 run on several threads, taken in index order,
// while the caller consumes their results in index order. wait(k) returns
// once task k has run; while it has not, the caller runs the next unclaimed
// task itself (k or a later one), so the caller's thread works too, and a
// pool of one thread (no worker started) runs every task in order on the
// caller's thread.
//
// Used by the adaptive grid's build (adaptive_grid.cpp): each refined cell of
// the first node worth splitting (the root, mostly) is built as a structure of
// its own, then copied into the whole in cell order, so the result does not
// depend on the number of threads; and by for_each_range (below) for the
// top nodes' passes over independent cells, lines and primitives.
//
// A task that throws (BuildCancelled after a cancel, bad_alloc) stops the
// claiming of further tasks; wait() rethrows its exception. The destructor
// stops the claiming and joins the workers (each finishes the task it holds:
// tasks should poll the build's cancel token, as the builds do).
#pragma once
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "threads.h"

namespace gw {

class OrderedTasks {
public:
    // Starts up to threads - 1 workers named `name` (fewer when the system
    // refuses one: the caller's thread does the rest).
    OrderedTasks(size_t n, int threads, std::function<void(size_t)> task, const char* name)
        : n_(n), task_(std::move(task)), done_(n, 0), errors_(n) {
        const size_t workers = std::min<size_t>(threads > 1 ? size_t(threads - 1) : 0, n > 0 ? n - 1 : 0);
        threads_.reserve(workers);   // (emplace_back then cannot throw after starting a thread)
        for (size_t i = 0; i < workers; ++i) {
            try {
                threads_.emplace_back([this] { while (!stop_.load() && run_next()) {} });
            } catch (...) {   // (std::system_error, or bad_alloc for the thread's state)
                break;
            }
            name_thread(threads_.back(), name);
        }
    }
    OrderedTasks(const OrderedTasks&) = delete;
    OrderedTasks& operator=(const OrderedTasks&) = delete;
    ~OrderedTasks() {
        stop_.store(true);
        for (std::thread& t : threads_) t.join();
    }

    // Threads the tasks run on, the caller's included.
    int threads() const { return int(threads_.size()) + 1; }

    // Returns once task k has run; rethrows its exception. After a task has
    // failed, tasks claimed before the failure still run and deliver, and
    // waiting for one never claimed rethrows the first failure's exception.
    void wait(size_t k) {
        for (;;) {
            {
                std::unique_lock<std::mutex> lock(mu_);
                if (done_[k]) {
                    if (errors_[k]) std::rethrow_exception(errors_[k]);
                    return;
                }
                const bool claimed = k < next_.load();   // (then it runs, or is running, on another thread)
                if (!claimed && first_error_) std::rethrow_exception(first_error_);
                if (first_error_ || next_.load() >= n_) {   // nothing to help with: wait for it
                    cv_.wait(lock, [&] { return done_[k] != 0; });
                    continue;
                }
            }
            run_next();   // a task not claimed yet (k, or one before or after it)
        }
    }

private:
    // Claims and runs the next task; false when none is left.
    bool run_next() {
        const size_t j = next_.fetch_add(1);
        if (j >= n_) return false;
        std::exception_ptr error;
        try {
            task_(j);
        } catch (...) {
            error = std::current_exception();
        }
        std::lock_guard<std::mutex> lock(mu_);
        done_[j] = 1;
        if (error) {
            errors_[j] = error;
            if (!first_error_) first_error_ = error;
            stop_.store(true);
        }
        cv_.notify_all();
        return true;
    }

    const size_t n_;
    const std::function<void(size_t)> task_;
    std::atomic<size_t> next_{0};
    std::atomic<bool> stop_{false};
    std::mutex mu_;
    std::condition_variable cv_;
    std::vector<uint8_t> done_;                 // guarded by mu_
    std::vector<std::exception_ptr> errors_;    // guarded by mu_
    std::exception_ptr first_error_;            // guarded by mu_
    std::vector<std::thread> threads_;
};

// The fewest grid cells worth a range of their own in the build's per-cell
// passes (for_each_range): below that, starting a thread costs more than it saves.
constexpr size_t kCellsPerRange = size_t(1) << 15;

// Calls f(begin, end) on consecutive ranges covering 0 .. n-1, on up to
// `threads` threads (the caller's among them), and returns once all have
// run; rethrows the first range's exception. Ranges hold at least `least`
// items each (at most 4 per thread), so fewer than 2 x least items, or one
// thread, make a single call on the caller's thread. For passes whose items
// are independent, so the result does not depend on the split.
inline void for_each_range(size_t n, int threads, size_t least, const std::function<void(size_t, size_t)>& f,
                           const char* name) {
    const size_t ranges = threads > 1 && n >= 2 * least ? std::min(size_t(threads) * 4, n / least) : 1;
    if (ranges <= 1) {
        if (n) f(0, n);
        return;
    }
    OrderedTasks tasks(ranges, threads, [&](size_t k) { f(n * k / ranges, n * (k + 1) / ranges); }, name);
    for (size_t k = 0; k < ranges; ++k) tasks.wait(k);
}

}  // namespace gw
