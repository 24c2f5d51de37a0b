// Chebyshev distance to the nearest non-empty cell by repeated dilation. See empty_space.h.
#include "empty_space.h"

#include <algorithm>

namespace gw {

// One dilation by a 3x3x3 cube, done as three separable 1D dilations along x, y, z.
static void dilate(std::vector<uint8_t>& mask, std::vector<uint8_t>& tmp, const int n[3]) {
    const int64_t stride[3] = {1, n[0], int64_t(n[0]) * n[1]};
    const int64_t cells = int64_t(n[0]) * n[1] * n[2];
    for (int a = 0; a < 3; ++a) {
        if (n[a] == 1) continue;
        for (int64_t c = 0; c < cells; ++c) {
            const int64_t i = (c / stride[a]) % n[a];   // coordinate along axis a
            uint8_t v = mask[c];
            if (i > 0) v |= mask[c - stride[a]];
            if (i + 1 < n[a]) v |= mask[c + stride[a]];
            tmp[c] = v;
        }
        mask.swap(tmp);
    }
}

std::vector<uint8_t> chebyshev_distance(const std::vector<uint8_t>& occupied, const int n[3], int cap) {
    const int64_t cells = int64_t(n[0]) * n[1] * n[2];
    std::vector<uint8_t> dist(size_t(cells), uint8_t(cap + 1)), mask(size_t(cells), 0), tmp(size_t(cells), 0);
    bool any_empty = false;
    for (int64_t c = 0; c < cells; ++c) {
        if (occupied[c]) { mask[c] = 1; dist[c] = 0; }
        else any_empty = true;
    }
    for (int r = 1; r <= cap && any_empty; ++r) {
        dilate(mask, tmp, n);
        any_empty = false;
        for (int64_t c = 0; c < cells; ++c) {
            if (mask[c] && dist[c] > r) dist[c] = uint8_t(r);
            any_empty |= !mask[c];
        }
    }
    return dist;
}

std::vector<uint8_t> empty_distance(const std::vector<uint32_t>& offsets, const int n[3], int cap) {
    const int64_t cells = int64_t(n[0]) * n[1] * n[2];
    std::vector<uint8_t> occupied(static_cast<size_t>(cells), 0);
    for (int64_t c = 0; c < cells; ++c) occupied[c] = offsets[c + 1] != offsets[c];
    return chebyshev_distance(occupied, n, cap);
}

}  // namespace gw
