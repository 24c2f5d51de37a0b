// GilRelease and the exit hook (see gil_release.h).
#include "gil_release.h"

#include <nanobind/nanobind.h>

#include <pthread.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace nb = nanobind;

namespace gw {
namespace {

std::mutex mu;
std::condition_variable returned;
bool ending = false;            // set by the exit hook (cleared where the module is set up again)
std::thread::id ending_thread;  // the thread that runs finalisation: it always gets the GIL back
int returning = 0;              // threads past the check below, not yet holding the GIL
thread_local int daemon = -1;   // whether this thread is a daemon thread (-1: not asked yet)

// Whether the calling thread (holding the GIL) is one Python does not join
// at exit: threading's daemon threads, and threads it did not start (its
// _DummyThread); where that cannot be told, yes. Only those may be parked: a
// thread that an exit hook starts and joins must come back.
int is_daemon() {
    PyObject* threading = PyImport_ImportModule("threading");
    PyObject* thread = threading ? PyObject_CallMethod(threading, "current_thread", nullptr) : nullptr;
    PyObject* flag = thread ? PyObject_GetAttrString(thread, "daemon") : nullptr;
    const int out = flag ? PyObject_IsTrue(flag) : 1;
    Py_XDECREF(flag);
    Py_XDECREF(thread);
    Py_XDECREF(threading);
    if (PyErr_Occurred()) PyErr_Clear();
    return out != 0;
}

// fork(): the child has only the thread that forked, so no thread is on its
// way back to the GIL there (a parent's thread counted in `returning` would
// make the child's exit hook wait forever), and `mu` is held across the
// fork so that the child never inherits it locked by a thread it lacks.
void before_fork() { mu.lock(); }
void after_fork_parent() { mu.unlock(); }
void after_fork_child() {
    returning = 0;
    mu.unlock();
}

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

GilRelease::GilRelease() {
    if (daemon < 0) daemon = is_daemon();
    state_ = PyEval_SaveThread();
}

GilRelease::~GilRelease() {
    bool stay_out;
    {
        std::lock_guard<std::mutex> lock(mu);
        stay_out = ending && daemon == 1 && std::this_thread::get_id() != ending_thread;
        if (!stay_out) ++returning;
    }
    // The interpreter is ending and will not wait for this daemon thread:
    // taking the GIL back would end it by a forced unwind through noexcept
    // code. Sleep instead (holding no lock); the process exits around it.
    while (stay_out) std::this_thread::sleep_for(std::chrono::hours(1));
    PyEval_RestoreThread(state_);
    std::lock_guard<std::mutex> lock(mu);
    if (--returning == 0) returned.notify_all();
}

void install_exit_hook() {
    static const bool at_fork = pthread_atfork(before_fork, after_fork_parent, after_fork_child) == 0;
    (void)at_fork;
    {
        std::lock_guard<std::mutex> lock(mu);
        ending = false;   // (an interpreter started again in this process)
    }
    nb::module_::import_("atexit").attr("register")(nb::cpp_function(&on_exit));
}

}  // namespace gw
