// Releasing the GIL around native work, safely when the interpreter ends.
//
// A daemon thread can be inside a native call (RenderJob.wait, intersect)
// when the script ends. CPython ends such a thread with pthread_exit as soon
// as it asks for the GIL back after finalisation has begun; the forced unwind
// then meets nanobind's noexcept GIL guard and the whole process aborts
// ("terminate called without an active exception", a SIGABRT at the end of an
// otherwise finished script). GilRelease is the guard every binding uses
// instead: an atexit hook (install_exit_hook, run before finalisation starts)
// marks the interpreter as ending and lets any thread already on its way back
// take the GIL; a daemon thread that comes back later sleeps until the process
// ends, as CPython 3.14 itself does with such threads (other threads, which
// Python joins, and the thread that finalises always take it back).
#pragma once
#include <Python.h>

namespace gw {

class GilRelease {
public:
    GilRelease();
    ~GilRelease();
    GilRelease(const GilRelease&) = delete;
    GilRelease& operator=(const GilRelease&) = delete;

private:
    PyThreadState* state_;
};

// Registers the hook with Python's atexit (once, at module import).
void install_exit_hook();

}  // namespace gw
