// Cancelling a long build from another thread: the caller keeps a
// CancelToken, the builder calls check() now and then (every few tens of
// thousands of primitives or cells, well under a millisecond apart) and
// stops with BuildCancelled once the token is cancelled.
#pragma once
#include <atomic>
#include <stdexcept>

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
// to call every few thousand items: `step` counts calls, the token is read
// every 4096th.
inline void check_cancel(const CancelToken* token, uint64_t& step) {
    if (token && (++step & 4095u) == 0 && token->cancelled()) throw BuildCancelled();
}

}  // namespace gw
