// Empty boxes (empty_box.h): every empty cell's box holds only empty cells,
// holds the cell's Chebyshev cube, and cannot grow on any face; grids past
// the size limit get the cubes.
#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "empty_box.h"
#include "empty_space.h"
#include "ordered_tasks.h"

using namespace gw;

namespace {

struct Grid {
    int n[3];
    std::vector<uint8_t> occupied;
    bool full(int x, int y, int z) const { return occupied[(size_t(z) * n[1] + y) * n[0] + x] != 0; }
    // Whether any cell of lo..hi (clipped to the grid) is occupied.
    bool any(const int lo[3], const int hi[3]) const {
        for (int z = std::max(lo[2], 0); z <= std::min(hi[2], n[2] - 1); ++z)
            for (int y = std::max(lo[1], 0); y <= std::min(hi[1], n[1] - 1); ++y)
                for (int x = std::max(lo[0], 0); x <= std::min(hi[0], n[0] - 1); ++x)
                    if (full(x, y, z)) return true;
        return false;
    }
};

// Checks every cell's box; returns the number of empty cells whose box is
// larger than their cube on some face.
int check_boxes(const Grid& g, const std::vector<uint32_t>& boxes, bool grown) {
    const std::vector<uint8_t> dist = chebyshev_distance(g.occupied, g.n, 16);
    int larger = 0;
    size_t c = 0;
    for (int z = 0; z < g.n[2]; ++z)
        for (int y = 0; y < g.n[1]; ++y)
            for (int x = 0; x < g.n[0]; ++x, ++c) {
                if (g.occupied[c]) {
                    CHECK(boxes[c] == 0u);
                    continue;
                }
                const int at[3] = {x, y, z}, r = int(dist[c]) - 1;
                int lo[3], hi[3];
                bool bigger = false;
                for (int a = 0; a < 3; ++a) {
                    lo[a] = at[a] - box_extent(boxes[c], a, false);
                    hi[a] = at[a] + box_extent(boxes[c], a, true);
                    // The cube, clipped to the grid, lies inside (the grid's side is stored as 31).
                    CHECK(lo[a] <= std::max(at[a] - r, 0));
                    CHECK(hi[a] >= std::min(at[a] + r, g.n[a] - 1));
                    bigger = bigger || (lo[a] > 0 && lo[a] < at[a] - r) || (hi[a] < g.n[a] - 1 && hi[a] > at[a] + r);
                }
                larger += bigger;
                // A face short of the largest extent is short of the grid's side too (the side stores 31).
                for (int a = 0; a < 3; ++a) {
                    if (box_extent(boxes[c], a, false) < int(kBoxExtentMax)) CHECK(lo[a] > 0);
                    if (box_extent(boxes[c], a, true) < int(kBoxExtentMax)) CHECK(hi[a] < g.n[a] - 1);
                }
                REQUIRE_FALSE(g.any(lo, hi));   // only empty cells
                if (!grown) {
                    for (int a = 0; a < 3; ++a) {
                        CHECK((lo[a] <= 0 || lo[a] == at[a] - r));
                        CHECK((hi[a] >= g.n[a] - 1 || hi[a] == at[a] + r));
                    }
                    continue;
                }
                // No face can grow by one layer: it is at the grid's side, at
                // the largest extent, or the layer beyond holds an occupied cell.
                for (int face = 0; face < 6; ++face) {
                    const int a = face >> 1;
                    const bool up = face & 1;
                    if (box_extent(boxes[c], a, up) == int(kBoxExtentMax)) continue;
                    if (up ? hi[a] >= g.n[a] - 1 : lo[a] <= 0) continue;
                    int l0[3] = {lo[0], lo[1], lo[2]}, l1[3] = {hi[0], hi[1], hi[2]};
                    l0[a] = l1[a] = up ? hi[a] + 1 : lo[a] - 1;
                    CHECK(g.any(l0, l1));
                }
            }
    return larger;
}

}  // namespace

TEST_CASE("empty boxes hold only empty cells, hold the cube, and cannot grow") {
    std::mt19937 rng(7);
    const int shapes[][3] = {{7, 5, 3}, {16, 1, 9}, {1, 1, 80}, {12, 12, 12}, {70, 3, 4}};
    for (const auto& shape : shapes)
        for (double fill : {0.0, 0.002, 0.02, 0.3, 0.9}) {
            Grid g{{shape[0], shape[1], shape[2]}, {}};
            g.occupied.resize(size_t(shape[0]) * shape[1] * shape[2]);
            std::bernoulli_distribution full(fill);
            for (auto& o : g.occupied) o = full(rng) ? 1 : 0;
            check_boxes(g, empty_boxes(g.occupied, g.n), true);
        }
}

TEST_CASE("beside a floor the boxes stretch along it, where the cubes stay one cell thick") {
    Grid g{{40, 40, 10}, {}};
    g.occupied.assign(size_t(40) * 40 * 10, 0);
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) g.occupied[(size_t(2) * 40 + y) * 40 + x] = 1;   // the floor, z = 2
    g.occupied[(size_t(7) * 40 + 20) * 40 + 20] = 1;                                     // a speck above it
    const std::vector<uint32_t> boxes = empty_boxes(g.occupied, g.n);
    const int larger = check_boxes(g, boxes, true);
    CHECK(larger > 40 * 40 * 7 / 2);
    // A cell just above the floor: its cube is the cell alone, its box stretches along x and y.
    const uint32_t b = boxes[(size_t(3) * 40 + 5) * 40 + 5];
    CHECK(box_extent(b, 2, false) == 0);
    CHECK(box_extent(b, 0, false) == int(kBoxExtentMax));   // reaches the grid's side
    CHECK(box_extent(b, 0, true) >= 10);
    CHECK(box_extent(b, 1, true) >= 10);
}

TEST_CASE("a box cut to the largest extent towards -x can grow again in y and z") {
    // Along a row of 70 cells the boxes are carried from cell to cell; past
    // 31 cells they are cut at -x, and the cut may free the y and z faces
    // that a speck near the row's start had blocked.
    Grid g{{70, 3, 3}, {}};
    g.occupied.assign(size_t(70) * 9, 0);
    for (int x = 0; x < 70; ++x) g.occupied[(size_t(1) * 3 + 0) * 70 + x] = 1;   // the line y = 0, z = 1
    g.occupied[(size_t(1) * 3 + 2) * 70 + 5] = 1;                                // the speck (5, 2, 1)
    check_boxes(g, empty_boxes(g.occupied, g.n), true);
}

TEST_CASE("grids past the size limit keep the Chebyshev cubes") {
    std::mt19937 rng(3);
    Grid g{{20, 9, 14}, {}};
    g.occupied.resize(size_t(20) * 9 * 14);
    std::bernoulli_distribution full(0.01);
    for (auto& o : g.occupied) o = full(rng) ? 1 : 0;
    CHECK(check_boxes(g, empty_boxes(g.occupied, g.n, 100), false) == 0);
}

TEST_CASE("boxes and distances are the same on any number of threads") {
    // Grids large enough for the rows and lines to be split among threads
    // (for_each_range: at least 2 x kCellsPerRange cells), sparse and dense,
    // and one flat grid of many short rows.
    std::mt19937 rng(11);
    const int shapes[][3] = {{90, 40, 30}, {300, 300, 2}, {3, 200, 150}};
    for (const auto& shape : shapes)
        for (double fill : {0.0005, 0.01, 0.2}) {
            Grid g{{shape[0], shape[1], shape[2]}, {}};
            g.occupied.resize(size_t(shape[0]) * shape[1] * shape[2]);
            REQUIRE(g.occupied.size() >= 2 * kCellsPerRange);
            std::bernoulli_distribution full(fill);
            for (auto& o : g.occupied) o = full(rng) ? 1 : 0;
            const std::vector<uint8_t> dist = chebyshev_distance(g.occupied, g.n, 16);
            const std::vector<uint32_t> boxes = empty_boxes(g.occupied, g.n);
            for (int threads : {2, 3, 7}) {
                CHECK(chebyshev_distance(g.occupied, g.n, 16, nullptr, threads) == dist);
                CHECK(empty_boxes(g.occupied, g.n, uint64_t(1) << 23, nullptr, threads) == boxes);
            }
        }
}
