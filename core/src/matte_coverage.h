// Matte coverage: what Cryptomatte's passes are made of (RenderSettings.
// matte_ranks, Scene::set_matte_keys). A camera ray's first surfaces are kept
// as matte classes (Scene::matte_class: one per distinct row of keys, say an
// object and material pair) with their shares of the ray (FirstHit::mattes:
// the surface, and where it is partly transparent (alpha) what lies behind
// it, with the rest); a camera sample's lens rays add theirs (SampleMattes);
// a pixel sums its samples' classes into each key layer's keys
// (MatteCoverage), so that every layer (objects, materials, ...) is merged by
// key before its ranks are cut. Entries beyond a list's capacity are dropped:
// it takes more classes than that in one sample or ray, not more triangles.
#pragma once
#include <algorithm>
#include <cstdint>

namespace gw {

// Up to N distinct ids, each with its summed weight.
template <int N>
struct IdWeights {
    int32_t id[N];
    float weight[N];
    int n = 0;

    void clear() { n = 0; }
    void add(int32_t k, float w) {
        if (k < 0 || !(w > 0)) return;
        for (int i = 0; i < n; ++i)
            if (id[i] == k) {
                weight[i] += w;
                return;
            }
        if (n < N) {
            id[n] = k;
            weight[n] = w;
            ++n;
        }
    }
    template <int M>
    void add(const IdWeights<M>& other, float scale) {
        for (int i = 0; i < other.n; ++i) add(other.id[i], other.weight[i] * scale);
    }
    // The `ranks` ids of most weight, most first (equal weights: the smaller
    // id first, so that the order does not depend on the samples' order);
    // ranks beyond the ids met get -1 and weight 0.
    void top(int ranks, int32_t* ids, float* weights) const {
        int order[N];
        for (int i = 0; i < n; ++i) order[i] = i;
        std::sort(order, order + n, [&](int a, int b) { return weight[a] != weight[b] ? weight[a] > weight[b] : id[a] < id[b]; });
        for (int r = 0; r < ranks; ++r) {
            ids[r] = r < n ? id[order[r]] : -1;
            weights[r] = r < n ? weight[order[r]] : 0.0f;
        }
    }
};

using RayMattes = IdWeights<4>;       // matte classes a camera ray sees, with their shares (FirstHit)
using SampleMattes = IdWeights<16>;   // a camera sample's: its lens rays' together

constexpr int kMaxMatteLayers = 4;

// A pixel's keys, per layer of keys (Scene::matte_key(prim, layer)).
struct MatteCoverage {
    IdWeights<24> layer[kMaxMatteLayers];
};

}  // namespace gw
