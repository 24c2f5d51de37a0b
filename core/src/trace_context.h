// Per-thread state for traversal: the mailbox (enabled when sized to the
// primitive count) and the statistics counters.
#pragma once
#include <atomic>

#include "mailbox.h"
#include "stats.h"

namespace gw {

struct TraceContext {
    Mailbox mailbox;
    Mailbox copies;   // the instanced grid's: copies this ray already walked (instanced_grid.h)
    Stats stats;
    bool skip_empty = true;   // grid: jump across blocks of empty cells (empty_space.h)
    bool unshadowed = false;  // Integrator::visible sees every light unblocked (a shadow catcher's light without shadows)
    // The render's cancel flag (nullptr: none), asked between samples and lattice rows so that
    // one costly pixel or an adaptive tile's corners do not hold a cancel up.
    const std::atomic<bool>* cancel = nullptr;
    bool cancelled() const { return cancel && cancel->load(std::memory_order_relaxed); }
};

}  // namespace gw
