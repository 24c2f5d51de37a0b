// How many worker threads a request means.
#pragma once
#include <thread>

namespace gw {

// requested > 0: that many; 0: one per hardware thread (at least 1).
inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    const unsigned hc = std::thread::hardware_concurrency();
    return hc ? int(hc) : 1;
}

}  // namespace gw
