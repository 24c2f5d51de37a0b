// Empty-space distances: every cell's stored value is the exact Chebyshev
// distance to the nearest non-empty cell, up to the cap (then cap + 1).
#include <doctest/doctest.h>

#include <random>
#include <vector>

#include "empty_space.h"

using namespace gw;

namespace {

// Brute force: minimum over non-empty cells of max(|dx|, |dy|, |dz|).
std::vector<int> chebyshev(const std::vector<uint32_t>& offsets, const int n[3]) {
    const int cells = n[0] * n[1] * n[2];
    std::vector<int> d(size_t(cells), 1 << 20);
    for (int c = 0; c < cells; ++c) {
        if (offsets[c + 1] == offsets[c]) continue;
        const int cx = c % n[0], cy = (c / n[0]) % n[1], cz = c / (n[0] * n[1]);
        for (int e = 0; e < cells; ++e) {
            const int ex = e % n[0], ey = (e / n[0]) % n[1], ez = e / (n[0] * n[1]);
            const int dist = std::max(std::abs(ex - cx), std::max(std::abs(ey - cy), std::abs(ez - cz)));
            d[e] = std::min(d[e], dist);
        }
    }
    return d;
}

}  // namespace

TEST_CASE("distances match brute-force Chebyshev distances, capped") {
    std::mt19937 rng(1);
    const int shapes[][3] = {{7, 5, 3}, {16, 1, 9}, {1, 1, 40}, {12, 12, 12}, {30, 20, 12}};
    for (const auto& shape : shapes) {
      for (const int cap : {3, 16}) {
        for (double fill : {0.0, 0.0005, 0.002, 0.02, 0.3}) {
            const int cells = shape[0] * shape[1] * shape[2];
            std::vector<uint32_t> offsets(size_t(cells) + 1, 0);
            std::bernoulli_distribution full(fill);
            for (int c = 0; c < cells; ++c) offsets[c + 1] = offsets[c] + (full(rng) ? 1 : 0);
            const std::vector<uint8_t> got = empty_distance(offsets, shape, cap);
            const std::vector<int> want = chebyshev(offsets, shape);
            for (int c = 0; c < cells; ++c) {
                const int expect = want[c] <= cap ? want[c] : cap + 1;
                CHECK(int(got[c]) == expect);
            }
        }
      }
    }
}
