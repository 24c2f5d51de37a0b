// See moved_grid.h.
#include "moved_grid.h"

#include <algorithm>
#include <cmath>

namespace gw {

std::shared_ptr<const Accel> MovedGrid::follow(std::shared_ptr<const UniformGrid> grid,
                                               std::shared_ptr<const Scene> scene) {
    if (!grid || !scene || grid->scene().num_prims() != scene->num_prims()) return nullptr;
    const uint64_t id = grid->scene().id();
    const auto& ancestors = scene->ancestors();
    const auto a = std::find_if(ancestors.begin(), ancestors.end(), [&](const SceneAncestor& x) { return x.id == id; });
    if (a == ancestors.end()) return nullptr;
    std::shared_ptr<MovedGrid> g(new MovedGrid(std::move(grid), std::move(scene)));
    g->moved_ = a->moved;
    for (const InstanceDelta& d : g->moved_) {
        const Affine there = Affine::from_rows(d.from_ancestor);
        Affine back;
        if (!there.inverse(back)) return nullptr;
        // Maps that scale by more than 2^20 either way are left to a rebuild: the
        // walks assume directions within 2^+-64 and the mapped rays' rounding
        // grows with the scale.
        const double grow = there.norm(), shrink = back.norm();
        if (!(grow <= 0x1p20 && shrink <= 0x1p20)) return nullptr;
        g->to_grid_.push_back(back);
        g->scale_.push_back(shrink);
    }
    return g;
}

MovedGrid::MovedGrid(std::shared_ptr<const UniformGrid> grid, std::shared_ptr<const Scene> scene)
    : Accel(std::move(scene)), grid_(std::move(grid)) {}

RayPre MovedGrid::to_grid(const RayPre& r, size_t instance) const {
    const Affine& m = to_grid_[instance];
    Ray ray = r.ray;
    const Vec3d o = m.point(Vec3d(ray.o)), d = m.vector(Vec3d(ray.d));
    ray.o = Vec3(float(o.x), float(o.y), float(o.z));
    ray.d = Vec3(float(d.x), float(d.y), float(d.z));
    if (ray.spawned) {
        // A ray leaving a surface starts just off it, by a few ulps of this
        // scene's coordinates; mapped and rounded again, and tested against the
        // ancestor's copy of its triangle (rounded at the ancestor's
        // coordinates), the start may fall on the other side. Skip 64 ulps of
        // both magnitudes along the ray: the own surface is then passed by rays
        // down to about 0.01 of a right angle from it (test35; 8 ulps left 26
        // of 20000 such rays re-hitting it).
        const double big = std::max(std::max(std::abs(o.x), std::abs(o.y)), std::abs(o.z));
        const double here = std::max(std::max(std::abs(double(r.ray.o.x)), std::abs(double(r.ray.o.y))),
                                     std::abs(double(r.ray.o.z)));
        const double err = 64.0 * 0x1p-23 * (big + scale_[instance] * here);
        const double len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        if (len > 0) ray.tmin = std::max(ray.tmin, float(err / len));
    }
    return RayPre(ray);
}

bool MovedGrid::closest(const RayPre& r, Hit& hit, TraceContext& ctx) const {
    bool found = grid_->closest_filtered(r, hit, ctx, {moved_.data(), moved_.size(), false});
    for (size_t i = 0; i < moved_.size(); ++i)
        found |= grid_->closest_filtered(to_grid(r, i), hit, ctx, {&moved_[i], 1, true});
    return found;
}

bool MovedGrid::occluded(const RayPre& r, TraceContext& ctx) const {
    if (grid_->occluded_filtered(r, ctx, {moved_.data(), moved_.size(), false})) return true;
    for (size_t i = 0; i < moved_.size(); ++i)
        if (grid_->occluded_filtered(to_grid(r, i), ctx, {&moved_[i], 1, true})) return true;
    return false;
}

AccelInfo MovedGrid::info() const {
    AccelInfo i = grid_->info();
    i.build_seconds = 0;
    i.note = "the grid of an earlier version, walked once more for each of the " + std::to_string(moved_.size()) +
             " instances moved since";
    return i;
}

}  // namespace gw
