// Per-thread ray statistics, the measures Havran & Sixta report for SPD grids.
#pragma once
#include <cstdint>

namespace gw {

enum class RayType : int { Primary = 0, Shadow = 1, Secondary = 2 };

struct Stats {
    uint64_t rays[3] = {0, 0, 0};   // by RayType
    uint64_t prim_tests = 0;        // ray/primitive intersection tests actually run
    uint64_t mailbox_skips = 0;     // tests avoided because the primitive was already tested by this ray
    uint64_t cells = 0;             // grid cells visited
    void add(const Stats& o) {
        for (int i = 0; i < 3; ++i) rays[i] += o.rays[i];
        prim_tests += o.prim_tests;
        mailbox_skips += o.mailbox_skips;
        cells += o.cells;
    }
    uint64_t total_rays() const { return rays[0] + rays[1] + rays[2]; }
};

}  // namespace gw
