// How many worker threads a request means, and their name.
#pragma once
#include <stdexcept>
#include <string>
#include <system_error>
#include <thread>
#ifdef __linux__
#include <pthread.h>
#endif

namespace gw {

// Names a thread from its creator, so the name is in place before the
// constructor that started it returns (no race with a caller reading it).
// Linux: /proc/<pid>/task/*/comm, so hosts and tests can tell the core's
// threads ("gridwalk", "gridwalk-build", "gridwalk-view", "gridwalk-rays" for
// batched ray queries) from their own.
inline void name_thread(std::thread& t, const char* name) {
#ifdef __linux__
    pthread_setname_np(t.native_handle(), name);
#else
    (void)t;
    (void)name;
#endif
}

// requested > 0: that many; 0: one per hardware thread (at least 1).
inline int resolve_threads(int requested) {
    if (requested > 0) return requested;
    const unsigned hc = std::thread::hardware_concurrency();
    return hc ? int(hc) : 1;
}

// The error to raise when the system refuses to start worker thread number
// `started` + 1 of `wanted` (std::thread reports only "Resource temporarily
// unavailable"): says what was asked and what to change.
inline std::runtime_error thread_start_error(int started, int wanted, const std::system_error& e) {
    return std::runtime_error("could not start worker thread " + std::to_string(started + 1) + " of " +
                              std::to_string(wanted) + " (" + e.what() +
                              "): the system limits threads or memory; set fewer threads (RenderSettings.threads)");
}

}  // namespace gw
