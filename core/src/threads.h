// How many worker threads a request means, and their name.
#pragma once
#include <thread>
#ifdef __linux__
#include <pthread.h>
#endif

namespace gw {

// Names the calling thread "gridwalk" (Linux: /proc/<pid>/task/*/comm), so
// hosts and tests can tell the core's render threads from their own.
inline void name_this_thread() {
#ifdef __linux__
    pthread_setname_np(pthread_self(), "gridwalk");
#endif
}

// requested > 0: that many; 0: one per hardware thread (at least 1).
inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    const unsigned hc = std::thread::hardware_concurrency();
    return hc ? int(hc) : 1;
}

}  // namespace gw
