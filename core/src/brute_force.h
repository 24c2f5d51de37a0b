// Brute force: every ray tests every primitive (the seed's "no grid" column).
#pragma once
#include "accel.h"

namespace gw {

// Every primitive tested, in index order: the closest hit (returns whether
// hit was updated), or whether any is hit in (tmin, tmax).
inline bool closest_of_all(const Scene& sc, const RayPre& r, Hit& hit, TraceContext& ctx) {
    if (!r.valid) return false;
    bool any = false;
    const size_t n = sc.num_prims();
    for (size_t i = 0; i < n; ++i) any |= sc.intersect(i, r, hit);
    ctx.stats.prim_tests += n;
    return any;
}

inline bool occluded_by_any(const Scene& sc, const RayPre& r, TraceContext& ctx) {
    if (!r.valid) return false;
    Hit hit;
    hit.t = r.ray.tmax;
    const size_t n = sc.num_prims();
    for (size_t i = 0; i < n; ++i) {
        ++ctx.stats.prim_tests;
        if (sc.intersect(i, r, hit)) return true;
    }
    return false;
}

class BruteForce final : public Accel {
public:
    explicit BruteForce(std::shared_ptr<const Scene> s) : Accel(std::move(s)) {}
    bool clips_to_box() const override { return false; }
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override {
        return closest_of_all(*scene_, r, hit, ctx);
    }
    bool occluded(const RayPre& r, TraceContext& ctx) const override { return occluded_by_any(*scene_, r, ctx); }
};

}  // namespace gw
