// Brute force: every ray tests every primitive (the seed's "no grid" column).
#pragma once
#include "accel.h"

namespace gw {

class BruteForce final : public Accel {
public:
    explicit BruteForce(std::shared_ptr<const Scene> s) : Accel(std::move(s)) {}
    bool clips_to_box() const override { return false; }
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override {
        if (!r.valid) return false;
        bool any = false;
        const size_t n = scene_->num_prims();
        for (size_t i = 0; i < n; ++i) any |= scene_->intersect(i, r, hit);
        ctx.stats.prim_tests += n;
        return any;
    }
    bool occluded(const RayPre& r, TraceContext& ctx) const override {
        if (!r.valid) return false;
        Hit hit;
        hit.t = r.ray.tmax;
        const size_t n = scene_->num_prims();
        for (size_t i = 0; i < n; ++i) {
            ++ctx.stats.prim_tests;
            if (scene_->intersect(i, r, hit)) return true;
        }
        return false;
    }
};

}  // namespace gw
