// build_accel and make_trace_context. See accel.h.
#include "accel.h"

#include "adaptive_grid.h"
#include "brute_force.h"
#include "instanced_grid.h"
#include "threads.h"
#include "uniform_grid.h"

#include <algorithm>
#include <string>

namespace gw {

namespace {

std::shared_ptr<UniformGrid> build_uniform(std::shared_ptr<const Scene> scene, const RenderSettings& s,
                                           const CancelToken* cancel, double grid_margin) {
    GridParams p;
    p.density = s.grid_density;
    p.max_cells = s.max_cells;
    p.margin = grid_margin;
    return std::make_shared<UniformGrid>(std::move(scene), p, cancel);
}

}  // namespace

std::shared_ptr<const Accel> build_accel(std::shared_ptr<const Scene> scene, const RenderSettings& s,
                                         const CancelToken* cancel, double grid_margin) {
    validate_settings(s);
    switch (s.accel) {
    case AccelKind::None: return std::make_shared<BruteForce>(std::move(scene));
    case AccelKind::Adaptive: {
        AdaptiveParams ap;
        ap.leaf_size = s.leaf_size;
        ap.max_depth = s.grid_levels;
        ap.threads = std::min(resolve_threads(s.threads), resolve_threads(0));   // (no more than the cores)
        if (s.instancing != Instancing::Off) {
            if (auto instanced = InstancedGrid::build(scene, ap, cancel, s.instancing == Instancing::On)) return instanced;
        }
        auto adaptive = std::make_shared<AdaptiveGrid>(scene, ap, cancel);
        if (!adaptive->too_few_spacings()) return adaptive;
        // A 0.2-wide sphere 1e5 from the origin (floats 0.0078 apart there):
        // the adaptive root stayed one cell of its 36,864 triangles, tested by
        // every ray; the uniform grid tests 34 a ray (adaptive_grid.h).
        adaptive.reset();   // (not both in memory at once)
        auto uniform = build_uniform(std::move(scene), s, cancel, grid_margin);
        uniform->add_note("the scene spans only a few float spacings at its distance from the origin, too few "
                          "for the adaptive grid's padded cells, so the uniform grid is used");
        return uniform;
    }
    case AccelKind::Grid: break;
    }
    return build_uniform(std::move(scene), s, cancel, grid_margin);
}

TraceContext make_trace_context(const Accel& accel, const RenderSettings& s) {
    TraceContext ctx;
    ctx.skip_empty = s.skip_empty;
    if (s.mailboxes && accel.uses_mailboxes()) ctx.mailbox.resize(accel.scene().num_prims());
    return ctx;
}

}  // namespace gw
