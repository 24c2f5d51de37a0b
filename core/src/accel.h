// Acceleration structures: the interface every structure implements, and
// build_accel, which builds the one a RenderSettings asks for. Each answers
// closest-hit and any-hit (occlusion) queries for one ray.
#pragma once
#include <memory>
#include <string>

#include "cancel.h"
#include "scene.h"
#include "settings.h"
#include "trace_context.h"

namespace gw {

// What a structure reports about itself (resolution, memory, build time).
struct AccelInfo {
    std::string kind;       // "uniform grid", "adaptive grid"
    int n[3] = {0, 0, 0};   // resolution (of the root grid)
    uint64_t grids = 0;     // uniform grids in the structure (1 for the uniform grid)
    uint64_t cells = 0, refs = 0, bytes = 0;
    double build_seconds = 0, density_requested = 0, density_used = 0;
    bool reduced = false;   // density lowered to respect the cell / reference caps
    int build_threads = 1;  // threads the build ran on
    std::string note;
};

class Accel {
public:
    virtual ~Accel() = default;
    // Closest hit in (ray.tmin, hit.t); returns true if hit was updated.
    virtual bool closest(const RayPre& r, Hit& hit, TraceContext& ctx) const = 0;
    // True if anything is hit in (ray.tmin, ray.tmax).
    virtual bool occluded(const RayPre& r, TraceContext& ctx) const = 0;
    virtual AccelInfo info() const { return {}; }
    virtual bool uses_mailboxes() const { return false; }
    // Whether a ray that misses the scene's box is a miss before any primitive
    // test (the grids clip every ray to their box; brute force does not).
    virtual bool clips_to_box() const { return true; }
    const Scene& scene() const { return *scene_; }

protected:
    explicit Accel(std::shared_ptr<const Scene> s) : scene_(std::move(s)) {}
    std::shared_ptr<const Scene> scene_;
};

// The structure s.accel names, built over `scene` (validates s first). A
// cancelled `cancel` token (may be null) stops the build with BuildCancelled.
// grid_margin: a uniform grid's GridParams::margin (the viewport's, so that
// its grids can be updated as objects move).
std::shared_ptr<const Accel> build_accel(std::shared_ptr<const Scene> scene, const RenderSettings& s,
                                         const CancelToken* cancel = nullptr, double grid_margin = 0.0);

// Per-thread state for tracing with `accel` under settings `s`: mailboxes are
// sized only where the structure uses them and s.mailboxes asks for them.
TraceContext make_trace_context(const Accel& accel, const RenderSettings& s);

}  // namespace gw
