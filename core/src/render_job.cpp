// Tile scheduling, polling and cancellation. See render_job.h.
#include "render_job.h"

#include <algorithm>
#include <chrono>
#include <new>
#include <stdexcept>

#include "pixel_estimator.h"
#include "threads.h"

namespace gw {

namespace {
double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

RenderJob::RenderJob(std::shared_ptr<const Accel> accel, const RenderSettings& s, const CameraDesc& camera)
    : accel_(std::move(accel)), s_(s), camera_(camera) {
    validate_settings(s_);
    validate_camera(camera_);
    width = camera_.width;
    height = camera_.height;
    int x0 = 0, y0 = 0, x1 = width, y1 = height;
    if (s_.region.w > 0) {   // render only a region (border render, farm tile, sparse timing)
        x0 = s_.region.x;
        y0 = s_.region.y;
        x1 = int(std::min<int64_t>(width, int64_t(s_.region.x) + s_.region.w));
        y1 = int(std::min<int64_t>(height, int64_t(s_.region.y) + s_.region.h));
        if (x0 >= x1 || y0 >= y1) throw std::invalid_argument("region lies outside the image");
    }
    area = {x0, y0, x1 - x0, y1 - y0};
    const size_t n = size_t(area.w) * size_t(area.h);
    rgba.assign(n * 4, 0.0f);
    depth.assign(n, kInf);
    normal.assign(n * 3, 0.0f);
    albedo.assign(n * 3, 0.0f);
    const std::vector<Material>& mats = accel_->scene().materials();
    if (std::any_of(mats.begin(), mats.end(), [](const Material& m) { return m.holdout || m.holdout_camera; })) holdout.assign(n, 0.0f);
    matte_layers = accel_->scene().matte_layers();
    matte_keys.assign(n * size_t(matte_layers) * size_t(s_.matte_ranks), -1);
    matte_coverage.assign(n * size_t(matte_layers) * size_t(s_.matte_ranks), 0.0f);
    for (int y = y0; y < y1; y += s_.tile_size)
        for (int x = x0; x < x1; x += s_.tile_size)
            tiles_.push_back({x, y, std::min(s_.tile_size, x1 - x), std::min(s_.tile_size, y1 - y)});
}

RenderJob::~RenderJob() {
    cancel_.store(true);
    join_all();
}

void RenderJob::start() {
    if (started_.load()) throw std::runtime_error("render job already started");
    t_start_ = now_seconds();
    const int wanted = std::min(resolve_threads(s_.threads), std::max(1, int(tiles_.size())));
    nthreads_.store(wanted);   // (before started_: finished() must not read started with no workers counted)
    started_.store(true);
    threads_.reserve(size_t(wanted));
    try {
        for (int i = 0; i < wanted; ++i) {
            threads_.emplace_back([this] { worker(); });
            name_thread(threads_.back(), "gridwalk");   // it would carry its creator's name until it runs
        }
    } catch (const std::system_error& e) {   // could not start every thread: stop the ones that did
        const int started = int(threads_.size());
        nthreads_.store(started);
        cancel_.store(true);
        join_all();
        throw thread_start_error(started, wanted, e);
    }
}

void RenderJob::worker() {
    try {
        PixelEstimator est(*accel_, s_, camera_);
        TraceContext ctx = make_trace_context(*accel_, s_);
        ctx.cancel = &cancel_;
        PixelScratch scratch;
        for (;;) {
            if (cancel_.load(std::memory_order_relaxed)) break;
            const int t = next_tile_.fetch_add(1);
            if (t >= int(tiles_.size())) break;
            const Tile tile = tiles_[size_t(t)];
            est.begin_tile(tile.x, tile.y, tile.w, tile.h, ctx, scratch);
            bool complete = true;
            for (int y = tile.y; y < tile.y + tile.h && complete; ++y) {
                for (int x = tile.x; x < tile.x + tile.w; ++x) {
                    if (cancel_.load(std::memory_order_relaxed)) { complete = false; break; }
                    const PixelValue pv = est.pixel(x, y, ctx, scratch);
                    // (a pixel cut short by a cancel, its tile's last one too, is not kept)
                    if (cancel_.load(std::memory_order_relaxed)) { complete = false; break; }
                    const size_t k = at(x, y);
                    rgba[4 * k + 0] = pv.rgb.x;
                    rgba[4 * k + 1] = pv.rgb.y;
                    rgba[4 * k + 2] = pv.rgb.z;
                    rgba[4 * k + 3] = pv.alpha;
                    depth[k] = pv.first.hit ? pv.first.depth : kInf;
                    normal[3 * k + 0] = pv.first.normal.x;
                    normal[3 * k + 1] = pv.first.normal.y;
                    normal[3 * k + 2] = pv.first.normal.z;
                    albedo[3 * k + 0] = pv.first.albedo.x;
                    albedo[3 * k + 1] = pv.first.albedo.y;
                    albedo[3 * k + 2] = pv.first.albedo.z;
                    if (!holdout.empty()) holdout[k] = pv.holdout;
                    if (const int r = s_.matte_ranks)
                        for (int l = 0; l < matte_layers; ++l) {
                            const size_t at = (k * size_t(matte_layers) + size_t(l)) * size_t(r);
                            pv.matte.layer[l].top(r, &matte_keys[at], &matte_coverage[at]);
                        }
                }
            }
            std::lock_guard<std::mutex> lock(mu_);
            stats_.add(ctx.stats);
            ctx.stats = Stats();
            if (complete) {
                ready_.push_back(tile);
                tiles_done_.fetch_add(1);
                ready_cv_.notify_all();
            }
        }
    } catch (const std::bad_alloc&) {
        std::lock_guard<std::mutex> lock(mu_);
        if (error_.empty()) error_ = "out of memory in a render thread (its tile's buffers)";
        cancel_.store(true);
    } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mu_);
        if (error_.empty()) error_ = e.what();
        cancel_.store(true);
    } catch (...) {
        std::lock_guard<std::mutex> lock(mu_);
        if (error_.empty()) error_ = "unknown error in render worker";
        cancel_.store(true);
    }
    std::lock_guard<std::mutex> lock(mu_);
    if (finished_workers_.fetch_add(1) + 1 == nthreads_.load()) t_end_ = now_seconds();
    ready_cv_.notify_all();
}

std::vector<Tile> RenderJob::poll() {
    std::lock_guard<std::mutex> lock(mu_);
    std::vector<Tile> out;
    out.swap(ready_);
    return out;
}

void RenderJob::join_all() {
    std::lock_guard<std::mutex> lock(join_mu_);
    for (auto& t : threads_)
        if (t.joinable()) t.join();
}

void RenderJob::cancel() {
    cancel_.store(true);
    join_all();
}

void RenderJob::wait() {
    if (!started_.load()) throw std::logic_error("RenderJob.wait() called before start(): nothing was rendered");
    join_all();
    std::lock_guard<std::mutex> lock(mu_);
    if (!error_.empty()) throw std::runtime_error("render failed: " + error_);
}

bool RenderJob::wait_for(double seconds) {
    if (!started_.load()) throw std::logic_error("RenderJob.wait_for() called before start(): nothing is rendering");
    seconds = seconds > 0 ? std::min(seconds, 1e6) : 0.0;   // (NaN: 0)
    std::unique_lock<std::mutex> lock(mu_);
    const int seen = tiles_done_.load();   // (tiles_done_ grows under mu_)
    ready_cv_.wait_for(lock, std::chrono::duration<double>(seconds),
                       [&] { return tiles_done_.load() != seen || finished(); });
    return finished();
}

double RenderJob::elapsed() const {
    if (!started_.load()) return 0.0;
    std::lock_guard<std::mutex> lock(mu_);
    return (t_end_ >= 0 ? t_end_ : now_seconds()) - t_start_;
}

Stats RenderJob::stats() const {
    std::lock_guard<std::mutex> lock(mu_);
    return stats_;
}

}  // namespace gw
