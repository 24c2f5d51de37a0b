// Empty-space skipping for the uniform grid ("proximity clouds", Cohen &
// Sheffer 1994): every empty cell stores its Chebyshev (L-infinity) distance,
// in cells, to the nearest non-empty cell. A cell at distance k sits at the
// centre of a (2k - 1)^3 block of empty cells, which a ray can cross in one
// jump instead of k - 1 DDA steps or more.
#pragma once
#include <cstdint>
#include <vector>

#include "cancel.h"

namespace gw {

// offsets: the grid's CSR offsets (cells + 1). Returns one byte per cell: 0
// for non-empty cells, else the exact distance up to `cap`, and cap + 1 for
// cells farther away (a safe lower bound).
// `cancel` (may be null) stops the work with BuildCancelled.
std::vector<uint8_t> empty_distance(const std::vector<uint32_t>& offsets, const int n[3], int cap,
                                    const CancelToken* cancel = nullptr);

// The same from an occupancy mask (1 = non-empty), one byte per cell, on up
// to `threads` threads (the same result on any number).
std::vector<uint8_t> chebyshev_distance(const std::vector<uint8_t>& occupied, const int n[3], int cap,
                                        const CancelToken* cancel = nullptr, int threads = 1);

}  // namespace gw
