// The seed's uniform grid: one resolution for the whole scene box (the
// seed's formula in M), compact CSR storage, Amanatides & Woo 3D-DDA
// traversal with per-thread mailboxes and empty-space jumps.
#pragma once
#include <memory>
#include <vector>

#include "accel.h"

namespace gw {

struct GridParams {
    double density = RenderSettings{}.grid_density;   // the seed's M
    uint64_t max_cells = RenderSettings{}.max_cells;  // cap on nx*ny*nz
    uint64_t max_refs = 1ull << 27;    // cap on primitive references (4 bytes each)
    // Empty cells added on each side of the scene's box, as a fraction of the
    // cells along that axis, rounded down (the viewport's grids: room for
    // objects to move without leaving the box, so that update() applies).
    double margin = 0.0;
};

// What a uniform grid of `prims` primitives at density M may hold; its build
// lowers M until it fits, and gridwalk.memory's estimate reads these same
// figures, so the estimate holds for every distribution of primitives.
//  - cells: 2 (M cbrt(prims) + 1)^3 + 64, at most max_cells. The seed's
//    formula gives (M cbrt(prims) + 1)^3 in a cube and up to 1.6 times that
//    in the SPD scenes' boxes; a box thin along one axis would give many times
//    more (the +1 per axis), and is held to the budget instead.
//  - refs: prims (M + 1)^3 (a primitive one mean cell-side across overlaps
//    at most that many cells; the SPD scenes take 1.8 - 4.2 per primitive at
//    M = 1 - 2 and up to 49 at M = 8), plus four slabs of cells,
//    4 (M cbrt(prims) + 1)^2 (a floor of two triangles spanning the box),
//    plus 64; never below prims, at most max_refs. Primitives far larger
//    than their cells everywhere (long thin triangles across the scene)
//    would exceed it.
struct GridBudget {
    uint64_t cells, refs;
};
GridBudget uniform_grid_budget(uint64_t prims, double density, uint64_t max_cells, uint64_t max_refs);

class UniformGrid final : public Accel {
public:
    UniformGrid(std::shared_ptr<const Scene> s, const GridParams& p, const CancelToken* cancel = nullptr);
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override;
    bool occluded(const RayPre& r, TraceContext& ctx) const override;
    AccelInfo info() const override { return info_; }
    bool uses_mailboxes() const override { return true; }
    // Adds a sentence to info().note (why this grid was built).
    void add_note(const std::string& text) { info_.note = info_.note.empty() ? text : info_.note + "; " + text; }

    // The grid of `s` (a later version of previous's scene) over previous's
    // box and resolution, reusing its lists: only the primitives whose cells
    // differ are moved, and the lists come out as a fresh build over that box
    // would leave them. Null when that does not apply: other primitive counts,
    // a primitive outside the box, more than a quarter of them changed, more
    // cell moves than the grid has references, or more references than the
    // build's budget (a fresh build lowers the density instead).
    static std::shared_ptr<const UniformGrid> update(const UniformGrid& previous, std::shared_ptr<const Scene> s,
                                                     const CancelToken* cancel = nullptr);

    // Walks that test only some triangles: those inside one of `count`
    // triangle ranges (inside = true), or those inside none (inside = false);
    // other primitives are tested by the second kind only. moved_grid.h walks
    // the grid of an earlier scene version so.
    struct PrimFilter {
        const InstanceDelta* ranges;   // (only their triangle ranges are read)
        size_t count;
        bool inside;
        bool skip(uint32_t prim) const {
            bool in = false;
            for (size_t i = 0; i < count; ++i) in |= prim >= ranges[i].triangle_start && prim < ranges[i].triangle_end;
            return in != inside;
        }
    };
    bool closest_filtered(const RayPre& r, Hit& hit, TraceContext& ctx, const PrimFilter& f) const;
    bool occluded_filtered(const RayPre& r, TraceContext& ctx, const PrimFilter& f) const;

private:
    struct CellChange {   // a primitive that leaves cells a0..a1 for cells b0..b1
        uint32_t prim;
        int a0[3], a1[3], b0[3], b1[3];
    };
    UniformGrid(const UniformGrid& previous, std::shared_ptr<const Scene> s, const std::vector<CellChange>& moves,
                const CancelToken* cancel);
    template <class F>
    void for_cells(const int c0[3], const int c1[3], F&& f) const {   // f(linear cell index)
        for (int z = c0[2]; z <= c1[2]; ++z)
            for (int y = c0[1]; y <= c1[1]; ++y)
                for (int x = c0[0]; x <= c1[0]; ++x) f((uint64_t(z) * n_[1] + y) * n_[0] + x);
    }
    template <bool AnyHit, bool Filtered>
    bool traverse(const RayPre& r, Hit& hit, TraceContext& ctx, const PrimFilter* filter) const;
    void cell_range(const Bounds& b, int lo[3], int hi[3]) const;
    int cell_at(const Ray& ray, double t, int axis) const;

    Vec3 lo_, hi_, cell_, inv_cell_;
    int n_[3] = {1, 1, 1};
    uint64_t max_refs_ = 0;           // the reference budget of the build
    std::vector<uint32_t> offsets_;   // per cell: start in prims_ (size cells + 1)
    std::vector<uint32_t> prims_;     // flat primitive index list
    std::vector<uint8_t> empty_;      // per cell: Chebyshev distance to the nearest non-empty cell
    AccelInfo info_;
};

}  // namespace gw
