"""A script may end while its daemon threads are inside Gridwalk calls that
release the GIL (intersect, RenderJob.wait). CPython ends such a thread with
pthread_exit when it asks for the GIL back during finalisation; through
nanobind's own GIL guard that aborted the whole process (SIGABRT, "terminate
called without an active exception") after the script had finished. The
bindings' GilRelease (core/src/gil_release.h) parks those threads instead, and only those: a
thread Python joins, and a child process forked while such threads ran, must still end."""
import subprocess
import sys

HEAD = """
import atexit, threading, time
import numpy as np
"""

SCENE = """
import gridwalk as gw
from gridwalk import scenes
scene = gw.Scene(**scenes.balls(2))
o = np.zeros((256, 3), np.float32)
d = np.tile(np.float32([0, 0, 1]), (256, 1))
"""

# Two daemon threads calling intersect back to back: one is nearly always on
# its way back to the GIL.
LOOPING = """
def loop():
    while True:
        scene.intersect(o, d)
for _ in range(2):
    threading.Thread(target=loop, daemon=True).start()
time.sleep(0.1)
"""


def run(script):
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60)


def test_daemon_threads_looping_on_intersect_do_not_abort_the_exit():
    # Two threads call intersect back to back, so one is nearly always on its
    # way back to the GIL when finalisation starts (aborted 6 of 6 runs before).
    script = HEAD + SCENE + LOOPING + """
print("done")
"""
    for _ in range(3):
        out = run(script)
        assert out.returncode == 0 and out.stdout.strip() == "done", (out.returncode, out.stderr[-500:])


def test_exit_hooks_on_the_main_thread_still_call_into_gridwalk():
    # An atexit hook registered before gridwalk's own runs after it, on the
    # thread that finalises: it must get the GIL back, not be parked, while a
    # daemon thread is parked beside it.
    script = HEAD + """
results = []
def at_exit():
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1), camera=gw.Camera(eye=(0, -5, 1), target=(0, 0, 0),
                                                                            width=8, height=6))
    image = job.start().wait()
    print("hook", image.shape, int(np.isfinite(scene.intersect(o, d).t).sum()), flush=True)
atexit.register(at_exit)
""" + SCENE + """
threading.Thread(target=lambda: [scene.intersect(o, d) for _ in iter(int, 1)], daemon=True).start()
time.sleep(0.1)
print("done", flush=True)
"""
    out = run(script)
    assert out.returncode == 0, (out.returncode, out.stderr[-500:])
    assert out.stdout.split() == ["done", "hook", "(6,", "8,", "4)", "256"], out.stdout


def test_a_thread_that_an_exit_hook_starts_and_joins_comes_back():
    # Not a daemon thread: Python would wait for it, so it must take the GIL
    # back after gridwalk's hook has marked the interpreter as ending.
    script = HEAD + """
def late():
    t = threading.Thread(target=lambda: print("thread", int(np.isfinite(scene.intersect(o, d).t).sum()), flush=True))
    t.start()
    t.join()
    print("joined", flush=True)
atexit.register(late)
""" + SCENE + """
print("done", flush=True)
"""
    out = run(script)
    assert out.returncode == 0, (out.returncode, out.stderr[-500:])
    assert out.stdout.split() == ["done", "thread", "256", "joined"], out.stdout


def test_forked_children_end_while_the_parent_has_threads_in_native_calls():
    # A child forked while a parent thread was on its way back to the GIL
    # must not wait for that thread (which it does not have) when it ends.
    script = HEAD + SCENE + LOOPING + """
import os, sys
hung = 0
for _ in range(8):
    pid = os.fork()
    if pid == 0:
        sys.exit(0)   # (through the interpreter's own exit: the hooks run)
    t0 = time.time()
    while time.time() - t0 < 5 and os.waitpid(pid, os.WNOHANG)[0] == 0:
        time.sleep(0.02)
    if time.time() - t0 >= 5:
        hung += 1
        os.kill(pid, 9)
        os.waitpid(pid, 0)
print("hung", hung, flush=True)
"""
    out = run(script)
    assert out.returncode == 0, (out.returncode, out.stderr[-500:])
    assert out.stdout.split() == ["hung", "0"], out.stdout
