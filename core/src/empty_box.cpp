// Empty boxes around empty cells. See empty_box.h.
#include "empty_box.h"

#include <algorithm>
#include <optional>

#include "empty_space.h"
#include "ordered_tasks.h"

namespace gw {

namespace {

constexpr int kCubeCap = 16;   // Chebyshev distances computed up to this (the boxes' starting cubes)

// Occupied cells per box of cells, in O(1): a 3D summed-area table.
class OccupiedCount {
public:
    OccupiedCount(const std::vector<uint8_t>& occupied, const int n[3], const CancelToken* cancel) {
        for (int a = 0; a < 3; ++a) m_[a] = n[a] + 1;
        uint64_t step = 0;
        assign_checked(s_, size_t(m_[0]) * m_[1] * m_[2], 0u, cancel, step);
        for (int z = 0; z < n[2]; ++z)
            for (int y = 0; y < n[1]; ++y) {
                check_cancel(cancel, step, uint64_t(n[0]));
                for (int x = 0; x < n[0]; ++x) {
                    const uint32_t here = occupied[(size_t(z) * n[1] + y) * n[0] + x];
                    at(x + 1, y + 1, z + 1) = here + at(x, y + 1, z + 1) + at(x + 1, y, z + 1) + at(x + 1, y + 1, z) -
                                              at(x, y, z + 1) - at(x, y + 1, z) - at(x + 1, y, z) + at(x, y, z);
                }
            }
    }
    // Occupied cells in lo..hi (inclusive, per axis).
    uint32_t count(const int lo[3], const int hi[3]) const {
        const int x0 = lo[0], y0 = lo[1], z0 = lo[2], x1 = hi[0] + 1, y1 = hi[1] + 1, z1 = hi[2] + 1;
        return get(x1, y1, z1) - get(x0, y1, z1) - get(x1, y0, z1) - get(x1, y1, z0) + get(x0, y0, z1) +
               get(x0, y1, z0) + get(x1, y0, z0) - get(x0, y0, z0);
    }

private:
    uint32_t& at(int x, int y, int z) { return s_[(size_t(z) * m_[1] + y) * m_[0] + x]; }
    uint32_t get(int x, int y, int z) const { return s_[(size_t(z) * m_[1] + y) * m_[0] + x]; }
    int m_[3];
    std::vector<uint32_t> s_;
};

// Grows the empty box lo..hi around cell `at`, each face in turn, while the
// slab beyond that face is empty: by `first` layers, twice as many after each
// success and half as many after a failure, until a failure at one layer
// marks the face blocked. Faces already blocked are not tried. Returns the
// number of slabs tested.
uint64_t grow_box(const OccupiedCount& occ, const int n[3], const int at[3], int lo[3], int hi[3], bool blocked[6],
                  int first) {
    uint64_t tests = 0;
    int by[6];
    for (int face = 0; face < 6; ++face) by[face] = blocked[face] ? 0 : first;
    for (bool again = true; again;) {
        again = false;
        for (int face = 0; face < 6; ++face) {
            const int a = face >> 1;
            const bool up = face & 1;
            const int room = up ? std::min(n[a] - 1 - hi[a], int(kBoxExtentMax) - (hi[a] - at[a]))
                                : std::min(lo[a], int(kBoxExtentMax) - (at[a] - lo[a]));
            by[face] = std::min(by[face], room);
            if (by[face] <= 0) continue;
            int l0[3] = {lo[0], lo[1], lo[2]}, l1[3] = {hi[0], hi[1], hi[2]};
            if (up) { l0[a] = hi[a] + 1; l1[a] = hi[a] + by[face]; }
            else { l1[a] = lo[a] - 1; l0[a] = lo[a] - by[face]; }
            ++tests;
            if (occ.count(l0, l1) == 0) {
                (up ? hi[a] : lo[a]) = up ? l1[a] : l0[a];
                by[face] *= 2;
            } else {
                blocked[face] = by[face] == 1;
                by[face] /= 2;
            }
            again = true;
        }
    }
    return tests;
}

// Packs the box lo..hi around cell c; a face on the grid's side gets the largest extent.
uint32_t pack(const int c[3], const int lo[3], const int hi[3], const int n[3]) {
    uint32_t out = 0;
    for (int a = 0; a < 3; ++a) {
        const uint32_t neg = lo[a] == 0 ? kBoxExtentMax : uint32_t(c[a] - lo[a]);
        const uint32_t pos = hi[a] == n[a] - 1 ? kBoxExtentMax : uint32_t(hi[a] - c[a]);
        out |= neg << box_shift(a, false) | pos << box_shift(a, true);
    }
    return out;
}

}  // namespace

std::vector<uint32_t> empty_boxes(const std::vector<uint8_t>& occupied, const int n[3], uint64_t max_cells,
                                  const CancelToken* cancel, int threads) {
    const uint64_t cells = uint64_t(n[0]) * n[1] * n[2];
    if (cells == 0) return {};
    uint64_t step = 0;
    const std::vector<uint8_t> dist = chebyshev_distance(occupied, n, kCubeCap, cancel, threads);
    std::vector<uint32_t> out;
    assign_checked(out, size_t(cells), 0u, cancel, step);
    const bool grow = cells <= max_cells;
    std::optional<OccupiedCount> occ;
    if (grow) occ.emplace(occupied, n, cancel);
    // Rows (lines along x) are independent: each starts afresh.
    const size_t rows = size_t(n[1]) * size_t(n[2]);
    const uint8_t* occupied_at = occupied.data();
    const uint8_t* dist_at = dist.data();
    uint32_t* out_at = out.data();
    const OccupiedCount* counts = occ ? &*occ : nullptr;
    for_each_range(rows, threads, kCellsPerRange / size_t(n[0]) + 1, [=](size_t row0, size_t row1) {
        const int m[3] = {n[0], n[1], n[2]};   // (a local: the stores below may alias the caller's n)
        uint64_t row_step = 0;
        for (size_t row = row0; row < row1; ++row) {
            const int y = int(row % size_t(m[1])), z = int(row / size_t(m[1]));
            uint64_t c = uint64_t(row) * uint64_t(m[0]);
            int lo[3], hi[3];
            bool blocked[6], carried = false;   // the previous cell's box holds this one
            for (int x = 0; x < m[0]; ++x, ++c) {
                if (occupied_at[c]) { carried = false; continue; }
                const int at[3] = {x, y, z};
                uint64_t tests = 1;
                // The empty cube centred on the cell (distance k: the cells within
                // k - 1), clipped to the grid.
                const int r = std::min(int(dist_at[c]) - 1, int(kBoxExtentMax));
                int cube_lo[3], cube_hi[3];
                bool inside = carried;   // the cube lies in the previous cell's box
                for (int a = 0; a < 3; ++a) {
                    cube_lo[a] = std::max(at[a] - r, 0);
                    cube_hi[a] = std::min(at[a] + r, m[a] - 1);
                    inside = inside && lo[a] <= cube_lo[a] && cube_hi[a] <= hi[a];
                }
                int first = 1;
                if (inside) {
                    // Start from the previous cell's box, cut to the largest extent
                    // towards -x. Its faces blocked before are blocked still, unless
                    // the cut narrowed the y and z faces.
                    if (x - lo[0] > int(kBoxExtentMax)) {
                        lo[0] = x - int(kBoxExtentMax);
                        for (int face = 2; face < 6; ++face) blocked[face] = false;
                    }
                } else {
                    std::copy(cube_lo, cube_lo + 3, lo);
                    std::copy(cube_hi, cube_hi + 3, hi);
                    std::fill(blocked, blocked + 6, false);
                    first = std::max(r, 1);   // first try: doubling the cube
                }
                if (counts) tests += grow_box(*counts, m, at, lo, hi, blocked, first);
                carried = counts != nullptr;
                check_cancel(cancel, row_step, tests);
                out_at[c] = pack(at, lo, hi, m);
            }
        }
    }, "gridwalk-build");
    return out;
}

}  // namespace gw
