// GilRelease and the exit hook (see gil_release.h).
#include "gil_release.h"

#include <nanobind/nanobind.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace nb = nanobind;

namespace gw {
namespace {

std::mutex mu;
std::condition_variable returned;
bool ending = false;           // set by the exit hook, never cleared
std::thread::id ending_thread;  // the thread that runs finalisation: it always gets the GIL back
int returning = 0;             // threads past the check below, not yet holding the GIL

void on_exit() {
    std::unique_lock<std::mutex> lock(mu);
    ending = true;
    ending_thread = std::this_thread::get_id();
    if (returning == 0) return;
    // Threads already committed to taking the GIL back get it now, before
    // finalisation begins, and go on as ordinary daemon threads.
    PyThreadState* state = PyEval_SaveThread();
    returned.wait(lock, [] { return returning == 0; });
    lock.unlock();
    PyEval_RestoreThread(state);
}

}  // namespace

GilRelease::GilRelease() : state_(PyEval_SaveThread()) {}

GilRelease::~GilRelease() {
    bool stay_out;
    {
        std::lock_guard<std::mutex> lock(mu);
        stay_out = ending && std::this_thread::get_id() != ending_thread;
        if (!stay_out) ++returning;
    }
    // The interpreter is ending: taking the GIL back would end this thread by
    // a forced unwind through noexcept code. Sleep instead (holding no lock);
    // the process exits around it.
    while (stay_out) std::this_thread::sleep_for(std::chrono::hours(1));
    PyEval_RestoreThread(state_);
    std::lock_guard<std::mutex> lock(mu);
    if (--returning == 0) returned.notify_all();
}

void install_exit_hook() { nb::module_::import_("atexit").attr("register")(nb::cpp_function(&on_exit)); }

}  // namespace gw
