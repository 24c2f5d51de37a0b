// Anisotropic empty regions for the adaptive grid's walk: every empty cell
// stores a box of empty cells around it, grown face by face as far as the
// empty space reaches (in the spirit of the cell expansion of Perard-Gayot,
// Kalojanov & Slusallek's irregular grids), instead of the largest empty
// cube centred on it (empty_space.h). Beside a floor or a wall the cube is one
// cell wide, while the box stretches along the surface and away from it, so
// a ray crosses the empty space in fewer jumps.
//
// A box is stored as six extents, the number of further empty cells on each
// side of the cell: bits [10a, 10a + 5) hold the extent towards -a, bits
// [10a + 5, 10a + 10) towards +a (a = 0, 1, 2 for x, y, z), each 0..31. A box
// that reaches the grid's side on one face stores 31 there: cells beyond the
// grid do not exist, so the walk, leaving the box there, leaves the grid.
#pragma once
#include <cstdint>
#include <vector>

#include "cancel.h"

namespace gw {

constexpr uint32_t kBoxExtentMax = 31;

// Where a packed box keeps its extent towards -axis (positive false) or +axis.
inline int box_shift(int axis, bool positive) { return 10 * axis + (positive ? 5 : 0); }

// The extent of a packed box towards -axis (positive false) or +axis.
inline int box_extent(uint32_t box, int axis, bool positive) {
    return int((box >> box_shift(axis, positive)) & kBoxExtentMax);
}

// occupied: one byte per cell (1 = not empty), x fastest. Returns one packed
// box per cell (0 for occupied cells; 0 too for an empty cell whose six
// neighbours are all occupied, while one on the grid's side has 31 there). Grids of more than `max_cells` cells get the
// Chebyshev cubes (empty_space.h) as their boxes, without growing them, to
// bound the build's memory (a 32-bit prefix sum per cell) and time.
// `cancel` (may be null) stops the work with BuildCancelled. Up to `threads`
// threads share the work (the same boxes on any number).
std::vector<uint32_t> empty_boxes(const std::vector<uint8_t>& occupied, const int n[3],
                                  uint64_t max_cells = uint64_t(1) << 23, const CancelToken* cancel = nullptr,
                                  int threads = 1);

}  // namespace gw
