// Chebyshev distance to the nearest non-empty cell. See empty_space.h.
#include "empty_space.h"

#include <algorithm>

#include "ordered_tasks.h"

namespace gw {

// The exact Chebyshev distance transform, capped, in three separable passes
// (the L-infinity distance to the nearest occupied cell is the min over them
// of the max of the per-axis distances):
//   pass x: g(x) = distance along x to the nearest occupied cell of the row;
//   pass y: g(x, y) = min over y' of max(|y - y'|, g(x, y'));
//   pass z: the same along z.
// Values are capped at cap + 1, so each min looks at most cap cells away.
namespace {

// One pass along axis a over every line of the grid: in/out hold one value per cell.
// A cell k of a line takes the least max(o, in[k +- o]) over the cells o
// away. A cell holding the cap's cap + 1 never lowers that (nothing is above
// cap + 1), so the search starts at the nearest cell of the line below it
// (nearest[k], from two sweeps): a line far from everything (most of them) costs
// two sweeps, not up to 2 cap reads per cell.
// Lines are independent: `threads` threads take ranges of them.
void pass(const std::vector<uint8_t>& in, std::vector<uint8_t>& out, const int n[3], int a, int cap,
          const CancelToken* cancel, int threads) {
    const int64_t stride[3] = {1, n[0], int64_t(n[0]) * n[1]};
    const int b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;   // the other two axes
    const int len = n[a];
    const int far = cap + 1;
    const uint8_t* src = in.data();
    uint8_t* dst = out.data();
    const int64_t sa = stride[a], sb = stride[b], sc = stride[c];
    const size_t nb = size_t(n[b]);
    for_each_range(size_t(n[b]) * size_t(n[c]), threads, kCellsPerRange / size_t(len) + 1, [=](size_t l0, size_t l1) {
        // (Locals, not the closure's members: a byte store may alias anything
        // it can reach, and would make the loop reload them.)
        const uint8_t* const from = src;
        uint8_t* const to = dst;
        const int64_t step_a = sa, step_b = sb, step_c = sc;
        const size_t lines_b = nb;
        const int length = len, beyond = far;
        uint64_t step = 0;
        std::vector<int> line_buf(static_cast<size_t>(length)), nearest_buf(static_cast<size_t>(length));
        int* line = line_buf.data();
        int* nearest = nearest_buf.data();
        for (size_t l = l0; l < l1; ++l) {
            check_cancel(cancel, step, uint64_t(length));
            const int64_t base = int64_t(l % lines_b) * step_b + int64_t(l / lines_b) * step_c;
            for (int k = 0, last = -(1 << 30); k < length; ++k) {
                line[k] = from[base + k * step_a];
                if (line[k] < beyond) last = k;
                nearest[k] = k - last;
            }
            for (int k = length - 1, next = 1 << 30; k >= 0; --k) {
                if (line[k] < beyond) next = k;
                nearest[k] = std::min(nearest[k], next - k);
            }
            for (int k = 0; k < length; ++k) {
                int best = line[k];
                for (int o = std::max(1, nearest[k]); o < best; ++o) {   // a cell o away helps only if o < best
                    if (k - o >= 0) best = std::min(best, std::max(o, line[k - o]));
                    if (k + o < length) best = std::min(best, std::max(o, line[k + o]));
                }
                to[base + k * step_a] = uint8_t(best);
            }
        }
    }, "gridwalk-build");
}

}  // namespace

std::vector<uint8_t> chebyshev_distance(const std::vector<uint8_t>& occupied, const int n[3], int cap,
                                        const CancelToken* cancel, int threads) {
    const size_t cells = size_t(n[0]) * size_t(n[1]) * size_t(n[2]);
    if (cells == 0) return {};
    uint64_t step = 0;
    std::vector<uint8_t> a, b;
    assign_checked(a, cells, uint8_t(0), cancel, step);
    assign_checked(b, cells, uint8_t(0), cancel, step);
    for (size_t c = 0; c < cells; ++c) {
        check_cancel(cancel, step);
        a[c] = occupied[c] ? 0 : uint8_t(cap + 1);
    }
    // Axis x starts from "occupied here": max(|x - x'|, 0) is the 1D distance.
    pass(a, b, n, 0, cap, cancel, threads);
    pass(b, a, n, 1, cap, cancel, threads);
    pass(a, b, n, 2, cap, cancel, threads);
    return b;
}

std::vector<uint8_t> empty_distance(const std::vector<uint32_t>& offsets, const int n[3], int cap,
                                    const CancelToken* cancel) {
    const int64_t cells = int64_t(n[0]) * n[1] * n[2];
    uint64_t step = 0;
    std::vector<uint8_t> occupied;
    assign_checked(occupied, size_t(cells), uint8_t(0), cancel, step);
    for (int64_t c = 0; c < cells; ++c) {
        check_cancel(cancel, step);
        occupied[c] = offsets[c + 1] != offsets[c];
    }
    return chebyshev_distance(occupied, n, cap, cancel);
}

}  // namespace gw
