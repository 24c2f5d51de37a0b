// The viewport's native controller thread. See viewport_renderer.h.
#include "viewport_renderer.h"

#include <algorithm>
#include <chrono>
#include <new>
#include <cmath>
#include <string>

#include "threads.h"
#include "moved_grid.h"
#include "uniform_grid.h"

namespace gw {

namespace {
double now_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
constexpr auto kPoll = std::chrono::milliseconds(4);   // tiles are collected this often
// The viewport's uniform grids extend this fraction of their cells beyond the
// scene on each side, so that an object moved a little stays inside and the
// grid is updated instead of rebuilt (UniformGrid::update).
constexpr double kGridMargin = 0.1;
constexpr auto kIdleTrim = std::chrono::seconds(5);
}  // namespace

ViewportRenderer::ViewportRenderer() {
    thread_ = std::thread([this] { run(); });
    name_thread(thread_, "gridwalk-view");
}

ViewportRenderer::~ViewportRenderer() { stop(); }

void ViewportRenderer::submit(ViewportRequest r) {
    if (r.width < 1 || r.height < 1) throw std::invalid_argument("viewport image must be at least 1 x 1");
    // (An infinite or huge delay overflowed the wait's deadline: the
    // controller spun and stop() never returned.)
    if (!(r.delay >= 0 && r.delay <= kMaxViewportDelay))
        throw std::invalid_argument("viewport delay must be between 0 and " + std::to_string(int(kMaxViewportDelay)) +
                                    " seconds, got " + std::to_string(r.delay));
    if (!(r.limit > 0)) throw std::invalid_argument("viewport limit must be a positive number (+inf: no clamp)");
    for (const ViewportPass& p : r.passes) {
        if (p.structure < 0 || size_t(p.structure) >= r.structures.size())
            throw std::invalid_argument("viewport pass names a structure it does not list");
        if (p.block < 1) throw std::invalid_argument("viewport pass block must be at least 1");
        if (p.repeat < 1) throw std::invalid_argument("viewport pass repeat must be at least 1");
        const int64_t w = (int64_t(r.width) + p.block - 1) / p.block, h = (int64_t(r.height) + p.block - 1) / p.block;
        if (int64_t(p.camera.width) != w || int64_t(p.camera.height) != h)
            throw std::invalid_argument("a viewport pass of block " + std::to_string(p.block) + " over a " +
                                        std::to_string(r.width) + " x " + std::to_string(r.height) +
                                        " image needs a " + std::to_string(w) + " x " + std::to_string(h) +
                                        " camera, got " + std::to_string(p.camera.width) + " x " +
                                        std::to_string(p.camera.height));
        validate_settings(p.settings);
        validate_camera(p.camera);
    }
    std::lock_guard<std::mutex> lock(mu_);
    if (stopping_) throw std::runtime_error("the viewport renderer is stopped");
    latest_id_ = r.id;
    next_ = std::move(r);
    next_submitted_ = now_seconds();
    has_request_ = true;
    if (build_cancel_) build_cancel_->cancel();   // a running build stops at its next check
    cv_.notify_all();                             // a running pass is cancelled by the controller
}

void ViewportRenderer::stop() {
    {
        std::lock_guard<std::mutex> lock(mu_);
        stopping_ = true;
        if (build_cancel_) build_cancel_->cancel();
        cv_.notify_all();
    }
    if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

ViewportStatus ViewportRenderer::status() const {
    std::lock_guard<std::mutex> lock(mu_);
    return status_;
}

std::vector<float> ViewportRenderer::image(int& width, int& height, uint64_t& version) const {
    std::lock_guard<std::mutex> lock(mu_);
    width = width_;
    height = height_;
    version = status_.version;
    if (rgba_.empty()) return std::vector<float>(size_t(width_) * size_t(height_) * 4, 0.0f);
    return rgba_;
}

bool ViewportRenderer::superseded(uint64_t id) const { return stopping_ || latest_id_ != id; }

void ViewportRenderer::run() {
    for (;;) {
        ViewportRequest r;
        double submitted;
        {
            std::unique_lock<std::mutex> lock(mu_);
            // Idle, the pool is trimmed now and then (its buffers have an age limit).
            while (!cv_.wait_for(lock, kIdleTrim, [this] { return stopping_ || has_request_; })) {
                lock.unlock();
                pool_trim();
                lock.lock();
            }
            if (stopping_) break;
            r = std::move(next_);
            submitted = next_submitted_;
            has_request_ = false;
            status_.request = r.id;
            status_.pass = -1;
            status_.repetition = 0;
            status_.passes_done = 0;
            status_.rendering = false;
            status_.error.clear();
            status_.first_pixels = status_.first_pass_started = -1;
            status_.structure_ready.assign(r.structures.size(), -1.0);
            status_.structure_updated.assign(r.structures.size(), false);
            // A resize settles first: a newer request (or stop) ends the wait.
            const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(std::max(0.0, r.delay));
            if (cv_.wait_until(lock, until, [this] { return stopping_ || has_request_; })) continue;
            status_.rendering = true;
        }
        try {
            render(r, submitted);
        } catch (const BuildCancelled&) {
            // a newer request or stop: the loop takes it
        } catch (const std::bad_alloc&) {
            std::lock_guard<std::mutex> lock(mu_);
            if (status_.request == r.id)
                status_.error = "out of memory for a " + std::to_string(r.width) + " x " + std::to_string(r.height) +
                                " image of this scene (its structure, its passes' images and their threads' buffers)";
        } catch (const std::exception& e) {
            std::lock_guard<std::mutex> lock(mu_);
            if (status_.request == r.id) status_.error = e.what();
        }
        std::lock_guard<std::mutex> lock(mu_);
        build_cancel_ = nullptr;
        if (status_.request == r.id) {
            status_.rendering = false;
            status_.pass = -1;
        }
    }
}

void ViewportRenderer::render(const ViewportRequest& r, double submitted) {
    {
        std::lock_guard<std::mutex> lock(mu_);
        reset_display(r.width, r.height);
        if (!r.scene) std::fill(rgba_.begin(), rgba_.end(), 0.0f);
        ++status_.version;
    }
    if (!r.scene) {
        std::lock_guard<std::mutex> lock(mu_);
        if (!superseded(r.id)) status_.finished = r.id;
        return;
    }
    if (cached_scene_ != r.scene) {
        // An older scene's uniform grids are kept to be updated (objects moved),
        // each replacing the one of its key from an even older scene (which
        // stays while no newer one was built: a drag's requests cancel each
        // other); its other structures are rebuilt.
        // (A moved scene's grid keeps the ancestor's grid it walks: moved_grid.h.)
        for (auto& [key, accel] : cache_) {
            if (const auto moved = std::dynamic_pointer_cast<const MovedGrid>(accel)) previous_[key] = moved->grid();
            else if (std::dynamic_pointer_cast<const UniformGrid>(accel)) previous_[key] = std::move(accel);
        }
        cache_.clear();
        cached_scene_ = r.scene;
    }
    int done = 0;
    for (size_t i = 0; i < r.passes.size(); ++i) {
        for (int rep = 0; rep < r.passes[i].repeat; ++rep) {
            if (!render_pass(r, submitted, i, rep)) return;
            std::lock_guard<std::mutex> lock(mu_);
            status_.passes_done = ++done;
        }
    }
    std::lock_guard<std::mutex> lock(mu_);
    if (!superseded(r.id)) status_.finished = r.id;
}

std::shared_ptr<const Accel> ViewportRenderer::structure(const ViewportRequest& r, int index) {
    const ViewportStructure& wanted = r.structures[size_t(index)];
    std::shared_ptr<const Accel>& accel = cache_[wanted.key];
    if (accel) return accel;
    CancelToken token;
    {
        std::lock_guard<std::mutex> lock(mu_);
        if (superseded(r.id)) return nullptr;
        build_cancel_ = &token;
    }
    bool updated = false;
    try {
        const auto prev = previous_.find(wanted.key);
        if (prev != previous_.end()) {
            // Instances moved since that grid's scene (Scene::moved): walk it
            // with the rays mapped back, no build. Otherwise update it.
            // (A cancelled update leaves it there for the next request.)
            const auto grid = std::static_pointer_cast<const UniformGrid>(prev->second);
            accel = MovedGrid::follow(grid, r.scene);
            if (!accel) accel = UniformGrid::update(*grid, r.scene, &token);
            updated = accel != nullptr;
            previous_.erase(prev);   // its scene (and that scene's pooled buffers) can go, unless followed
        }
        if (!accel) accel = build_accel(r.scene, wanted.settings, &token, kGridMargin);
    } catch (...) {
        std::lock_guard<std::mutex> lock(mu_);
        build_cancel_ = nullptr;
        throw;
    }
    // Once every structure of the request is at hand, older scenes' grids of
    // keys it does not use are no use either.
    if (std::all_of(r.structures.begin(), r.structures.end(), [&](const ViewportStructure& st) {
            const auto built = cache_.find(st.key);
            return built != cache_.end() && built->second;
        }))
        previous_.clear();
    std::lock_guard<std::mutex> lock(mu_);
    build_cancel_ = nullptr;
    if (status_.request == r.id) status_.structure_updated[size_t(index)] = updated;
    return accel;
}

bool ViewportRenderer::render_pass(const ViewportRequest& r, double submitted, size_t index, int rep) {
    const ViewportPass& p = r.passes[index];
    const std::shared_ptr<const Accel> accel = structure(r, p.structure);
    if (!accel) return false;
    RenderSettings settings = p.settings;
    settings.seed = uint32_t(uint64_t(p.settings.seed) + uint64_t(rep));   // wraps, as the library's seeds do
    RenderJob job(accel, settings, p.camera);
    {
        std::lock_guard<std::mutex> lock(mu_);
        if (superseded(r.id)) return false;
        double& ready = status_.structure_ready[size_t(p.structure)];
        if (ready < 0) ready = now_seconds() - submitted;
        if (status_.first_pass_started < 0) status_.first_pass_started = now_seconds() - submitted;
        status_.pass = int(index);
        status_.repetition = rep;
    }
    job.start();
    for (;;) {
        const bool finished = job.finished();
        const std::vector<Tile> tiles = job.poll();
        std::unique_lock<std::mutex> lock(mu_);
        for (const Tile& t : tiles) add_tile(job, t, p.block, r.opaque, r.limit);
        if (!tiles.empty()) {
            ++status_.version;
            if (status_.first_pixels < 0) status_.first_pixels = now_seconds() - submitted;
        }
        if (superseded(r.id)) {
            lock.unlock();
            job.cancel();
            return false;
        }
        if (finished) break;
        cv_.wait_for(lock, kPoll);
    }
    job.wait();   // rethrows a worker's error
    return true;
}

void ViewportRenderer::reset_display(int width, int height) {
    // Keep the last image on show (resized, nearest pixel) until new tiles arrive.
    if (width != width_ || height != height_ || rgba_.empty()) {
        std::vector<float> resized(size_t(width) * size_t(height) * 4, 0.0f);
        if (!rgba_.empty()) {
            for (int y = 0; y < height; ++y) {
                const int sy = std::min(int(int64_t(y) * height_ / height), height_ - 1);
                for (int x = 0; x < width; ++x) {
                    const int sx = std::min(int(int64_t(x) * width_ / width), width_ - 1);
                    std::copy_n(&rgba_[(size_t(sy) * width_ + sx) * 4], 4, &resized[(size_t(y) * width + x) * 4]);
                }
            }
        }
        rgba_.swap(resized);
        width_ = width;
        height_ = height;
    }
    accum_.assign(size_t(width) * size_t(height) * 4, 0.0f);
    count_.assign(size_t(width) * size_t(height), 0.0f);
}

void ViewportRenderer::add_tile(const RenderJob& job, const Tile& t, int block, bool opaque, float limit) {
    auto clean = [limit](float v) { return std::isnan(v) ? 0.0f : std::min(std::max(v, -limit), limit); };
    for (int ty = 0; ty < t.h; ++ty) {
        const float* src_row = &job.rgba[job.at(t.x, t.y + ty) * 4];
        // An opaque film is clear only where a holdout takes the pixel (RenderJob::holdout).
        const float* held_row = job.holdout.empty() ? nullptr : &job.holdout[job.at(t.x, t.y + ty)];
        auto opaque_alpha = [&](int tx) { return held_row ? 1.0f - held_row[tx] : 1.0f; };
        if (block == 1) {
            const int row = height_ - 1 - (t.y + ty);          // the display is bottom-up
            if (row < 0) continue;
            for (int tx = 0; tx < t.w && t.x + tx < width_; ++tx) {
                const size_t k = size_t(row) * width_ + size_t(t.x + tx);
                count_[k] += 1.0f;
                for (int c = 0; c < 4; ++c) {
                    const float v = c == 3 && opaque ? opaque_alpha(tx) : clean(src_row[4 * tx + c]);
                    accum_[4 * k + c] += v;
                    rgba_[4 * k + c] = accum_[4 * k + c] / count_[k];
                }
            }
            continue;
        }
        // A coarse pass: each pixel covers a block x block square of the display.
        const int y0 = (t.y + ty) * block, y1 = std::min(y0 + block, height_);
        for (int tx = 0; tx < t.w; ++tx) {
            const int x0 = (t.x + tx) * block, x1 = std::min(x0 + block, width_);
            float v[4];
            for (int c = 0; c < 4; ++c) v[c] = c == 3 && opaque ? opaque_alpha(tx) : clean(src_row[4 * tx + c]);
            for (int y = y0; y < y1; ++y)
                for (int x = x0; x < x1; ++x) std::copy_n(v, 4, &rgba_[(size_t(height_ - 1 - y) * width_ + x) * 4]);
        }
    }
}

}  // namespace gw
