// Acceleration structures: brute force ("none") and the uniform grid. Both
// answer closest-hit and any-hit (occlusion) queries for one ray.
#pragma once
#include <memory>
#include <string>

#include "empty_space.h"
#include "mailbox.h"
#include "scene.h"
#include "stats.h"

namespace gw {

class Accel;

// Per-thread state for traversal: the mailbox (enabled when sized to the
// primitive count) and the statistics counters.
struct TraceContext {
    TraceContext() = default;
    // Mailboxes are sized only where the acceleration structure uses them.
    TraceContext(const Accel& accel, bool mailboxes, bool skip_empty);
    Mailbox mailbox;
    Stats stats;
    bool skip_empty = true;   // grid: jump across blocks of empty cells (empty_space.h)
};

struct GridInfo {
    int n[3] = {0, 0, 0};
    uint64_t cells = 0, refs = 0, bytes = 0;
    double build_seconds = 0, density_requested = 0, density_used = 0;
    bool reduced = false;   // density lowered to respect the cell / reference caps
    std::string note;
};

class Accel {
public:
    virtual ~Accel() = default;
    // Closest hit in (ray.tmin, hit.t); returns true if hit was updated.
    virtual bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const = 0;
    // True if anything is hit in (ray.tmin, ray.tmax).
    virtual bool occluded(const RayPre& r, TraceContext& ctx) const = 0;
    virtual GridInfo info() const { return {}; }
    virtual bool uses_mailboxes() const { return false; }
    const Scene& scene() const { return *scene_; }

protected:
    explicit Accel(std::shared_ptr<const Scene> s) : scene_(std::move(s)) {}
    std::shared_ptr<const Scene> scene_;
};

// Tests every primitive: the seed's "no grid" column.
class BruteForce final : public Accel {
public:
    explicit BruteForce(std::shared_ptr<const Scene> s) : Accel(std::move(s)) {}
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

struct GridParams {
    double density = 2.0;              // the seed's M
    uint64_t max_cells = 1ull << 24;   // cap on nx*ny*nz
    uint64_t max_refs = 1ull << 27;    // cap on primitive references (4 bytes each)
};

class Grid final : public Accel {
public:
    Grid(std::shared_ptr<const Scene> s, const GridParams& p);
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override;
    bool occluded(const RayPre& r, TraceContext& ctx) const override;
    GridInfo info() const override { return info_; }
    bool uses_mailboxes() const override { return true; }

private:
    template <class F>
    void for_cells(const int c0[3], const int c1[3], F&& f) const {   // f(linear cell index)
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) f((uint64_t(z) * n_[1] + y) * n_[0] + x);
    }
    template <bool AnyHit>
    bool traverse(const RayPre& r, Hit& hit, TraceContext& ctx) const;
    void cell_range(const Bounds& b, int lo[3], int hi[3]) const;
    int cell_at(const Ray& ray, float t, int axis) const;

    Vec3 lo_, hi_, cell_, inv_cell_;
    int n_[3] = {1, 1, 1};
    std::vector<uint32_t> offsets_;   // per cell: start in prims_ (size cells + 1)
    std::vector<uint32_t> prims_;     // flat primitive index list
    std::vector<uint8_t> empty_;      // per cell: Chebyshev distance to the nearest non-empty cell
    GridInfo info_;
};

inline TraceContext::TraceContext(const Accel& accel, bool mailboxes, bool skip)
    : skip_empty(skip) {
    if (mailboxes && accel.uses_mailboxes()) mailbox.resize(accel.scene().num_prims());
}

}  // namespace gw
