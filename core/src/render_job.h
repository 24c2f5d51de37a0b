// An asynchronous render: worker threads take tiles from a shared counter and
// publish finished tiles; the caller polls them, reads progress and can
// cancel at any time. Pixels are pure functions of (seed, pixel, sample), so
// the image is bit-identical for any thread count, tile size or tile order.
#pragma once
#include <atomic>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "accel.h"
#include "settings.h"

namespace gw {

struct Tile { int x, y, w, h; };

class RenderJob {
public:
    // Renders the accel's scene through `camera` (validated here); without
    // one, through the scene's own camera.
    RenderJob(std::shared_ptr<const Accel> accel, const RenderSettings& s, const CameraDesc& camera);
    RenderJob(std::shared_ptr<const Accel> accel, const RenderSettings& s)
        : RenderJob(accel, s, accel->scene().camera()) {}
    ~RenderJob();
    RenderJob(const RenderJob&) = delete;
    RenderJob& operator=(const RenderJob&) = delete;

    void start();
    std::vector<Tile> poll();            // tiles finished since the last poll
    void cancel();                       // returns once every worker has stopped
    void wait();                         // joins; rethrows a worker's error
    // Blocks until another tile is finished, every worker has stopped, or
    // `seconds` have passed (at most 1e6; NaN or negative: 0); returns
    // finished(). For a host that shows progress or streams tiles: it sees
    // them as they are done, and the end at once, without a timer's delay.
    bool wait_for(double seconds);
    bool finished() const { return started_.load() && finished_workers_.load() == nthreads_.load(); }
    bool started() const { return started_.load(); }
    // cancel() stopped the render before every tile was done (a cancel after
    // the end leaves a finished job, not a cancelled one).
    bool cancelled() const { return cancel_.load() && tiles_done_.load() < tiles_total(); }
    int tiles_done() const { return tiles_done_.load(); }
    int tiles_total() const { return int(tiles_.size()); }
    double elapsed() const;
    Stats stats() const;

    int width, height;
    // The rectangle rendered: RenderSettings::region, or the whole image.
    // The buffers hold only it (a farm's tile of a large image allocates and
    // zeroes its own pixels, not the image's: 11 floats a pixel).
    Tile area;
    // (area.h, area.w, 4), (area.h, area.w), (area.h, area.w, 3); row 0 is
    // the area's top row. Complete after wait(); before that, only tiles
    // returned by poll() (in image coordinates) are final.
    std::vector<float> rgba, depth, normal, albedo;
    // (area.h, area.w, matte_layers, matte_ranks) with RenderSettings.matte_ranks
    // > 0, else empty: per layer of the scene's matte keys, the keys covering
    // most of each pixel, most first (-1 beyond those met), and the share of
    // the pixel each covers (matte_coverage.h).
    // (area.h, area.w) where a material is a holdout, else empty: the share of
    // each pixel's camera samples that met one (the film is clear there).
    std::vector<float> holdout;
    std::vector<int32_t> matte_keys;
    std::vector<float> matte_coverage;
    int matte_layers = 1;
    size_t at(int x, int y) const { return size_t(y - area.y) * size_t(area.w) + size_t(x - area.x); }

private:
    void worker();
    void join_all();

    std::shared_ptr<const Accel> accel_;
    RenderSettings s_;
    CameraDesc camera_;
    std::vector<Tile> tiles_;
    std::vector<std::thread> threads_;
    std::atomic<int> next_tile_{0}, tiles_done_{0}, finished_workers_{0};
    std::atomic<bool> cancel_{false};
    std::atomic<bool> started_{false};
    std::atomic<int> nthreads_{0};
    std::mutex join_mu_;   // wait() and cancel() may be called from two Python threads at once
    mutable std::mutex mu_;
    std::condition_variable ready_cv_;   // (with mu_) a tile was finished or a worker stopped
    std::vector<Tile> ready_;
    Stats stats_;
    std::string error_;
    double t_start_ = 0, t_end_ = -1;
};

}  // namespace gw
