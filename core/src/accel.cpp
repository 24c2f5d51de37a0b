// build_accel and make_trace_context. See accel.h.
#include "accel.h"

#include "adaptive_grid.h"
#include "brute_force.h"
#include "uniform_grid.h"

namespace gw {

std::shared_ptr<const Accel> build_accel(std::shared_ptr<const Scene> scene, const RenderSettings& s,
                                         const CancelToken* cancel, double grid_margin) {
    validate_settings(s);
    switch (s.accel) {
    case AccelKind::None: return std::make_shared<BruteForce>(std::move(scene));
    case AccelKind::Adaptive: {
        AdaptiveParams ap;
        ap.leaf_size = s.leaf_size;
        ap.max_depth = s.grid_levels;
        return std::make_shared<AdaptiveGrid>(std::move(scene), ap, cancel);
    }
    case AccelKind::Grid: break;
    }
    GridParams p;
    p.density = s.grid_density;
    p.max_cells = s.max_cells;
    p.margin = grid_margin;
    return std::make_shared<UniformGrid>(std::move(scene), p, cancel);
}

TraceContext make_trace_context(const Accel& accel, const RenderSettings& s) {
    TraceContext ctx;
    ctx.skip_empty = s.skip_empty;
    if (s.mailboxes && accel.uses_mailboxes()) ctx.mailbox.resize(accel.scene().num_prims());
    return ctx;
}

}  // namespace gw
