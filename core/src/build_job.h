// BuildJob: one acceleration-structure build on its own native thread, so a
// host can wait for it in short slices, cancel it, and stay responsive
// (Python's Ctrl-C, Blender's Esc) without starting a thread of its own.
// Inside Blender a Python thread is a hazard (docs/blender.md); a native one
// never touches the interpreter.
#pragma once
#include <chrono>
#include <condition_variable>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>

#include "accel.h"
#include "cancel.h"
#include "threads.h"

namespace gw {

class BuildJob {
public:
    BuildJob(std::shared_ptr<const Scene> scene, const RenderSettings& s) : scene_(std::move(scene)), settings_(s) {
        validate_settings(s);   // a bad setting raises here, in the caller's thread
        // The thread only borrows scene_: the job holds it until it is
        // destroyed, in its owner's thread, so the thread never drops the
        // last reference (which may be a Python object's: dropping it needs the GIL).
        thread_ = std::thread([this] {
            std::shared_ptr<const Accel> built;
            std::exception_ptr error;
            try {
                built = build_accel(scene_, settings_, &token_);
            } catch (...) {
                error = std::current_exception();
            }
            std::lock_guard<std::mutex> lock(mu_);
            result_ = std::move(built);
            error_ = error;
            done_ = true;
            cv_.notify_all();
        });
        name_thread(thread_, "gridwalk-build");
    }
    BuildJob(const BuildJob&) = delete;
    BuildJob& operator=(const BuildJob&) = delete;
    ~BuildJob() {
        token_.cancel();
        if (thread_.joinable()) thread_.join();
    }

    void cancel() { token_.cancel(); }
    bool cancelled() const { return token_.cancelled(); }

    // Waits up to `seconds` (negative: until done); true once the build has
    // ended and its thread is joined. Called from the owner's thread only.
    bool wait(double seconds) {
        {
            std::unique_lock<std::mutex> lock(mu_);
            if (seconds < 0) {
                cv_.wait(lock, [this] { return done_; });
            } else {
                cv_.wait_for(lock, std::chrono::duration<double>(seconds), [this] { return done_; });
            }
            if (!done_) return false;
        }
        if (thread_.joinable()) thread_.join();
        return true;
    }

    // The structure, once done; rethrows the build's error (BuildCancelled after a cancel).
    std::shared_ptr<const Accel> result() {
        wait(-1);
        if (error_) std::rethrow_exception(error_);
        return result_;
    }

private:
    std::shared_ptr<const Scene> scene_;
    RenderSettings settings_;
    CancelToken token_;
    std::mutex mu_;
    std::condition_variable cv_;
    bool done_ = false;
    std::shared_ptr<const Accel> result_;
    std::exception_ptr error_;
    std::thread thread_;
};

}  // namespace gw
