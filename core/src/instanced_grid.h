// The instanced grid: the adaptive grid for scenes of many copies of a few
// meshes (a forest scattered by Geometry Nodes, particles). Instead of one
// grid over every copy's triangles, it builds one adaptive grid per mesh (over
// the triangles of its first copy) and a uniform grid over the boxes of the
// other copies, walked with Amanatides & Woo's 3D-DDA; a ray that reaches a
// copy is mapped into the first copy's place by the affine map between the
// two and walks the mesh's grid there (t and the barycentrics are the same
// under an affine map), and its hit is reported as the copy's own triangle.
// Everything else (the first copies, meshes seen once, spheres, cones) is in
// one more adaptive grid, "the rest", whose answers are the flat grid's.
//
// The copies come from Scene::set_instances, and each is checked corner by
// corner against its mesh's first copy before it is trusted: one that does
// not match stays in the rest. A copy's hits are the first copy's triangles
// moved into its place, so they may differ from those of its own triangles
// (rounded where the host placed them) by float rounding: answers are not
// bit-identical to brute force there, as they are everywhere else.
#pragma once
#include <memory>
#include <vector>

#include "adaptive_grid.h"
#include "affine.h"
#include "dda.h"

namespace gw {

class InstancedGrid final : public Accel {
public:
    // The structure for `scene`, or null where it has no copy that checks
    // out, a part's adaptive grid could not be built finely
    // (too_few_spacings), or the copies crowd into a few cells of the grid
    // over them (kCrowdedCell); unless `always`, also where it would not pay:
    // copies that check out make less than half of the primitives, or fewer
    // than kAutoTriangles triangles (Instancing::Auto).
    static std::shared_ptr<const Accel> build(std::shared_ptr<const Scene> scene, const AdaptiveParams& p,
                                              const CancelToken* cancel, bool always = false);
    // Below this many copied triangles the flat adaptive grid builds in under
    // a few tenths of a second and traces faster: a ray pays each copy's
    // entry (the ray mapped, its watertight set-up, the mesh grid's entry)
    // for every copy it reaches (docs/architecture.md).
    static constexpr size_t kAutoTriangles = size_t(1) << 20;
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override;
    bool occluded(const RayPre& r, TraceContext& ctx) const override;
    AccelInfo info() const override { return info_; }

    // A copy traced through its mesh's grid.
    struct Copy {
        uint32_t start = 0, count = 0;   // its triangles in the scene
        uint32_t mesh = 0;               // meshes_[mesh]: the grid it walks
        Affine to_mesh;                  // this copy's place -> the first copy's
        double scale = 0;                // to_mesh.norm()
        Vec3 lo, hi;                     // its box (padded by the map's rounding)
    };
    size_t copies() const { return copies_.size(); }

private:
    explicit InstancedGrid(std::shared_ptr<const Scene> scene) : Accel(std::move(scene)) {}
    template <bool kAny>
    bool walk(const RayPre& r, Hit& hit, TraceContext& ctx) const;
    template <bool kAny>
    bool test_copy(uint32_t c, const RayPre& r, Hit& hit, TraceContext& ctx) const;   // its box met
    RayPre to_mesh(const RayPre& r, const Copy& c) const;
    RayPre to_rest(const RayPre& r) const;   // a resumed ray (Ray::after) in the rest's numbering
    void cell_range(const Copy& c, int c0[3], int c1[3]) const;   // the top grid's cells c's box meets

    std::shared_ptr<const AdaptiveGrid> rest_;   // null: nothing outside the copies
    std::vector<uint32_t> rest_ids_;             // the rest's primitive i is rest_ids_[i]
    std::vector<std::shared_ptr<const AdaptiveGrid>> meshes_;
    std::vector<Copy> copies_;
    // The uniform grid over the copies' boxes: cell c lists
    // ids_[first_[c] .. first_[c + 1]), in copy order.
    Vec3 lo_, hi_;
    double cell_[3] = {1, 1, 1}, inv_cell_[3] = {1, 1, 1};
    int n_[3] = {1, 1, 1};
    std::vector<uint32_t> first_, ids_;
    AccelInfo info_;
};

}  // namespace gw
