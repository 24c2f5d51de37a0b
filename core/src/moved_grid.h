// The grid of a scene whose instances moved (Scene::moved), without a build:
// the uniform grid of an ancestor of the scene (Scene::ancestors) walked
// once for the triangles that stayed, and once per moved instance with the
// ray mapped back into the root's space, where that grid lists the
// instance's triangles. An affine map keeps the ray's parameter t and the
// triangles' barycentric coordinates, so each walk's hit is a hit of this
// scene. This is the viewport's coarse pass's structure after a transform
// edit: moving a 1M-triangle object costs no grid build at all.
#pragma once
#include <memory>
#include <vector>

#include "affine.h"
#include "uniform_grid.h"

namespace gw {

class MovedGrid final : public Accel {
public:
    // The grid of `scene` made from `grid`, the uniform grid of one of its
    // ancestors (Scene::ancestors); null when the grid's scene is none of them.
    static std::shared_ptr<const Accel> follow(std::shared_ptr<const UniformGrid> grid,
                                               std::shared_ptr<const Scene> scene);
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override;
    bool occluded(const RayPre& r, TraceContext& ctx) const override;
    AccelInfo info() const override;
    bool uses_mailboxes() const override { return true; }
    // The ancestor's grid it walks.
    const std::shared_ptr<const UniformGrid>& grid() const { return grid_; }

private:
    MovedGrid(std::shared_ptr<const UniformGrid> grid, std::shared_ptr<const Scene> scene);
    RayPre to_grid(const RayPre& r, size_t instance) const;

    std::shared_ptr<const UniformGrid> grid_;
    std::vector<InstanceDelta> moved_;   // the instances moved since the grid's scene
    std::vector<Affine> to_grid_;        // per moved instance: this scene's world -> the grid scene's
    std::vector<double> scale_;          // ... and the largest row sum of its linear part
};

}  // namespace gw
