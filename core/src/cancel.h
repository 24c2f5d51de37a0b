// Cancelling a long build from another thread: the caller keeps a
// CancelToken, the builder calls check() now and then (every few tens of
// thousands of primitives or cells, well under a millisecond apart) and
// stops with BuildCancelled once the token is cancelled.
#pragma once
#include <atomic>
#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace gw {

struct BuildCancelled : std::runtime_error {
    BuildCancelled() : std::runtime_error("the build was cancelled") {}
};

class CancelToken {
public:
    void cancel() { cancelled_.store(true, std::memory_order_relaxed); }
    bool cancelled() const { return cancelled_.load(std::memory_order_relaxed); }

private:
    std::atomic<bool> cancelled_{false};
};

// Throws BuildCancelled when `token` (may be null) is cancelled; cheap enough
// to call per item. `step` counts work done: pass `work` = the item's cost in
// elementary steps (cells touched, say) so that loops whose items are big still
// read the token every 4096 steps, i.e. every few microseconds.
__attribute__((always_inline)) inline void check_cancel(const CancelToken* token, uint64_t& step, uint64_t work = 1) {
    const uint64_t before = step;
    step += work;
    if (token && (before >> 12) != (step >> 12) && token->cancelled()) throw BuildCancelled();
}

// Grows v to n elements, the new ones equal to `value`, in slices of 64Ki
// elements with a token read between them: filling hundreds of megabytes
// (page faults included) takes longer than a cancel may wait. Capacity grows
// at least twofold, so repeated calls stay amortised.
template <class T>
void grow_checked(std::vector<T>& v, size_t n, const T& value, const CancelToken* token, uint64_t& step) {
    if (n <= v.size()) return;
    if (n > v.capacity()) {
        check_cancel(token, step, 4096);
        v.reserve(std::max(n, 2 * v.capacity()));
    }
    constexpr size_t kSlice = size_t(1) << 16;
    while (v.size() < n) {
        check_cancel(token, step, 4096);
        v.insert(v.end(), std::min(kSlice, n - v.size()), value);
    }
}

// v.assign(n, value), checked as grow_checked is.
template <class T>
void assign_checked(std::vector<T>& v, size_t n, const T& value, const CancelToken* token, uint64_t& step) {
    v.clear();
    grow_checked(v, n, value, token, step);
}

}  // namespace gw
