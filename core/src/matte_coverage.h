// The matte keys a pixel's camera samples meet, with their summed weights:
// what Cryptomatte's passes are made of (RenderSettings.matte_ranks,
// Scene::set_matte_keys). Each camera sample adds its first surface's key
// (FirstHit::matte) with the sample's weight times that surface's coverage,
// and, where the surface is partly transparent, the key behind it with the
// rest. A pixel keeps up to kMax distinct keys; later ones are dropped.
#pragma once
#include <algorithm>
#include <cstdint>

#include "integrator.h"

namespace gw {

struct MatteCoverage {
    static constexpr int kMax = 32;
    int32_t key[kMax];
    float weight[kMax];
    int n = 0;

    void add(int32_t k, float w) {
        if (k < 0 || !(w > 0)) return;
        for (int i = 0; i < n; ++i)
            if (key[i] == k) {
                weight[i] += w;
                return;
            }
        if (n < kMax) {
            key[n] = k;
            weight[n] = w;
            ++n;
        }
    }
    void add(const FirstHit& fh, float w) {
        add(fh.matte, w * fh.matte_weight);
        add(fh.matte_behind, w * fh.matte_behind_weight);
    }
    // The `ranks` keys of most weight, most first (equal weights: the smaller
    // key first, so that the order does not depend on the samples' order);
    // ranks beyond the keys met get key -1 and weight 0.
    void top(int ranks, int32_t* keys, float* weights) const {
        int order[kMax];
        for (int i = 0; i < n; ++i) order[i] = i;
        std::sort(order, order + n, [&](int a, int b) {
            return weight[a] != weight[b] ? weight[a] > weight[b] : key[a] < key[b];
        });
        for (int r = 0; r < ranks; ++r) {
            keys[r] = r < n ? key[order[r]] : -1;
            weights[r] = r < n ? weight[order[r]] : 0.0f;
        }
    }
};

}  // namespace gw
