// The render behind one Blender viewport, entirely in native threads.
//
// Blender's Python threads are not safe beside its operators: Blender 3.4 -
// 5.0 (Python 3.11) decide whether the main thread holds the GIL by asking
// whether *any* thread holds it, so a Python thread that runs while the main
// thread is inside an operator called from Python with a context override
// (bpy.ops... under temp_override) makes Blender touch Python objects without
// the GIL and crash. The viewport therefore runs no Python off the main
// thread: one native controller thread per viewport (named "gridwalk-view")
// takes the latest request, waits out a resize's debounce, builds the
// structures it needs (cancellable), runs the passes as RenderJobs and
// accumulates their tiles into the display image. The main thread submits
// requests and reads the status and the image; neither call waits for a
// render or a build.
#pragma once
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "accel.h"
#include "buffer_pool.h"
#include "cancel.h"
#include "render_job.h"
#include "settings.h"

namespace gw {

struct ViewportPass {
    int block = 1;           // pixel block: the pass renders 1/block of the resolution, stretched back
    int structure = 0;       // index into ViewportRequest::structures
    RenderSettings settings;
    CameraDesc camera;       // at the pass's resolution
    int repeat = 1;          // rendered this many times, with seeds settings.seed + 0, 1, ...
};

struct ViewportStructure {
    std::string key;          // the settings that shape it: built once per scene and key
    RenderSettings settings;
};

// The largest |value| a viewport image holds by default: below the largest
// half float (65504), which the viewport's RGBA16F texture would turn to inf.
constexpr float kHalfFloatSafeLimit = 65000.0f;
constexpr double kMaxViewportDelay = 3600.0;   // seconds: a debounce, not a schedule

struct ViewportRequest {
    uint64_t id = 0;
    std::shared_ptr<const Scene> scene;   // null: nothing to render (the image is cleared)
    std::vector<ViewportStructure> structures;
    std::vector<ViewportPass> passes;
    int width = 1, height = 1;            // the display image
    bool opaque = true;                   // alpha 1 everywhere (no Film Transparent)
    float limit = kHalfFloatSafeLimit;    // |values| are clamped to it
    double delay = 0.0;                   // seconds to wait first (a resize settles); a newer request ends the wait
};

struct ViewportStatus {
    uint64_t request = 0;        // the request being (or last) worked on
    uint64_t finished = 0;       // the last request whose passes all completed
    int pass = -1;               // the pass running (-1: none)
    int repetition = 0;          // ... and which of its repeats
    int passes_done = 0;         // renders completed (each repeat counts)
    bool rendering = false;      // a request is past its delay and not finished
    std::string error;           // of the request `request`, if it failed
    uint64_t version = 0;        // of the display image
    // Seconds after the request was submitted (-1: not yet): its first tile
    // shown, and each structure ready (built, or found built).
    double first_pixels = -1;
    double first_pass_started = -1;
    std::vector<double> structure_ready;
    // Per structure: whether it was updated from the previous scene's (a
    // uniform grid whose moved primitives were moved) rather than built.
    std::vector<bool> structure_updated;
};

class ViewportRenderer {
public:
    ViewportRenderer();
    ~ViewportRenderer();
    ViewportRenderer(const ViewportRenderer&) = delete;
    ViewportRenderer& operator=(const ViewportRenderer&) = delete;

    void submit(ViewportRequest r);     // replaces any waiting request and cancels the running one; never blocks long
    void stop();                        // cancels and joins the controller (and its render threads)
    ViewportStatus status() const;
    // The display image, (height, width, 4) scene-linear float RGBA, rows
    // bottom-up; with its version.
    std::vector<float> image(int& width, int& height, uint64_t& version) const;

private:
    void run();
    void render(const ViewportRequest& r, double submitted);
    // false: superseded (a newer request or stop)
    bool render_pass(const ViewportRequest& r, double submitted, size_t index, int rep);
    std::shared_ptr<const Accel> structure(const ViewportRequest& r, int index);   // null: superseded
    void reset_display(int width, int height);
    void add_tile(const RenderJob& job, const Tile& t, int block, bool opaque, float limit);
    bool superseded(uint64_t id) const;

    mutable std::mutex mu_;
    std::condition_variable cv_;
    bool stopping_ = false;
    bool has_request_ = false;
    ViewportRequest next_;
    double next_submitted_ = 0;
    uint64_t latest_id_ = 0;
    ViewportStatus status_;
    CancelToken* build_cancel_ = nullptr;   // the running build's token (under mu_)

    // Display image (under mu_): shown, and the running sums of full-resolution passes.
    int width_ = 1, height_ = 1;
    std::vector<float> rgba_, accum_, count_;

    // Built structures of the latest scene (controller thread only).
    std::shared_ptr<const Scene> cached_scene_;
    std::map<std::string, std::shared_ptr<const Accel>> cache_;
    // The previous scene's uniform grids, by key: UniformGrid::update starts from them.
    std::map<std::string, std::shared_ptr<const Accel>> previous_;

    BufferPoolUse pool_use_;   // while the viewport is open, a new scene version reuses the last one's buffers
    std::thread thread_;
};

}  // namespace gw
