// The adaptive grid: a hierarchy of uniform grids. The root is a uniform grid
// over the scene box; each of its cells that holds more than a leaf's worth
// of primitives is refined by its own uniform grid, sized from that cell's
// primitive count and fitted to the part of the cell they occupy; and so on,
// a few levels deep. Every level is walked with Amanatides & Woo's 3D-DDA and
// jumps across blocks of empty cells; a leaf's triangles are tested several
// at a time (triangle_simd.h), 8 with AVX2 or 4 with SSE / NEON, chosen at
// run time. See docs/architecture.md for the measurements behind the design.
#pragma once
#include <vector>

#include "accel.h"

namespace gw {

constexpr int kMaxGridDepth = 7;   // refining levels the traversal's stack holds

struct AdaptiveParams {
    double root_density = 1.0;   // root grid: cells per primitive ...
    uint64_t root_cells = 1ull << 16;   // ... up to this many cells (a root that stays in cache; its cells refine)
    double sub_density = 2.0;    // refining grids: cells per primitive of their cell
    int leaf_size = RenderSettings{}.leaf_size;     // a cell with more primitives than this is refined (deeper: x 4 per level)
    int max_depth = RenderSettings{}.grid_levels;   // refining levels below the root
    double max_refs_per_prim = 3.0;   // a grid's references per primitive (its resolution is lowered past it)
    // A crowded root (its cells still averaging over 4 leaves' worth) may list up to
    // this many per primitive, within crowded_refs in all:
    double crowded_refs_per_prim = 32.0;
    uint64_t crowded_refs = 1ull << 18;
    int big_cells = 64;          // a primitive covering more cells of a grid than this is "large" there ...
    int big_max = 16;            // ... and up to this many large ones per grid are tested once per ray
    uint64_t max_cells = 1ull << 26;   // cap on cells of all levels (densities are lowered past it)
    uint64_t max_refs = 1ull << 28;    // cap on primitive references of all levels
    uint64_t max_box_cells = 1ull << 23;   // grids beyond this keep cubic empty regions (empty_box.h)
    int threads = 1;             // threads building the root's refined cells (the same structure for any number)
};

// The structure, flat. Public so that the per-ISA traversal code
// (adaptive_walk.inc) can read it.
struct AdaptiveGridData {
    struct Node {
        Vec3 lo, hi;          // the node's box
        Vec3 cell, inv_cell;  // cell size and its reciprocal (float, as the DDA uses them)
        int n[3];             // resolution
        // What the walk reads of these in double, converted once: lo, cell and
        // inv_cell, and each axis's last cell index, n - 1 (random rays 1.035x
        // as fast, primary and shadow rays alike; docs/architecture.md).
        double lo_d[3], cell_d[3], inv_cell_d[3], last_d[3];
        int64_t stride[3];    // how far apart neighbouring cells along each axis lie in cells: 1, n[0], n[0] n[1]
        uint32_t first;       // index of the node's cell (0, 0, 0) in cells
        // The node's large primitives (refs[big] = number of triangles, then
        // the ids; big_count == 0: none): primitives that would cover many of
        // its cells are tested once, when a ray enters the node, instead, if
        // the ray's part in the node meets their box [big_lo, big_hi] (a floor
        // is a thin slab, which rays leaving it upwards do not meet).
        uint32_t big, big_count;
        Vec3 big_lo, big_hi;
        // The box the rays are clipped to: [big_lo, big_hi] grown by 1e-4 of the node's
        // longest cell on every side, rounded outwards (as a child's box is padded: a floor's
        // box is flat, and near a ray's origin the float test's t lies outside a flat box by
        // more than the clip's relative margin). The skip of rays leaving a surface reads
        // the box itself.
        Vec3 big_clip_lo, big_clip_hi;
        bool big_boxed;   // closest-hit rays check the box too (see adaptive_walk.inc's meets_big)
    };
    // b == 0: empty, a = the box of empty cells around it in the same node,
    // packed as in empty_box.h; b == kChild: refined by node a; otherwise a
    // leaf of b primitives whose list is refs[a] = number of triangles, then
    // refs[a + 1 ..] the triangles' and then the quadrics' global indices.
    struct Cell { uint32_t a, b; };
    static constexpr uint32_t kChild = 0xFFFFFFFFu;
    std::vector<Node> nodes;
    std::vector<Cell> cells;
    std::vector<uint32_t> refs;
    // Whether the walk, at a leaf, asks for the next cell's list before
    // testing the leaf (adaptive_walk.inc): set where cells and lists
    // outgrow the caches (kPrefetchBytes), where it hides part of the next
    // cell's memory latency; in a small grid it only adds instructions.
    bool prefetch = false;
    static constexpr size_t kPrefetchBytes = size_t(8) << 20;
};

class AdaptiveGrid final : public Accel {
public:
    AdaptiveGrid(std::shared_ptr<const Scene> s, const AdaptiveParams& p, const CancelToken* cancel = nullptr);
    bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const override;
    bool occluded(const RayPre& r, TraceContext& ctx) const override;
    AccelInfo info() const override { return info_; }
    const AdaptiveGridData& data() const { return g_; }
    int simd_width() const { return width_; }
    // Whether the root stayed one cell of many primitives because the scene
    // spans only a few float spacings at its distance from the origin (cells
    // are padded by a few, so every resolution listed each primitive in most
    // cells): build_accel then builds the uniform grid, which needs no such
    // padding.
    bool too_few_spacings() const { return too_few_spacings_; }

private:
    AdaptiveGridData g_;
    AccelInfo info_;
    bool too_few_spacings_ = false;
    // The root is one leaf listing every primitive (a scene of a few, such as
    // the seed's Distant): rays test them in index order as brute force does,
    // without the walk (the same answers; 9-12% of Distant's render time,
    // at 2% of its instructions).
    bool one_leaf_ = false;
    int width_ = 4;   // triangles per SIMD test: 8 (AVX2) or 4
};

}  // namespace gw
