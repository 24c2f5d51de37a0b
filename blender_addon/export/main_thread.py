"""Run a function on Blender's main thread and wait for its result.

A final render from the GUI (F12) runs the engine's render() on a job thread,
while Blender's main thread keeps drawing the interface. Adding an ID to
bpy.data (loading an image) from the job thread would race with the main
thread's own walks over bpy.data, so such work is handed to the main thread
through bpy.app.timers and the job thread waits for it. On the main thread
(the viewport's view_update, a render from `blender -b` or from the bpy
module) the function simply runs.
"""
from __future__ import annotations

import threading
import time

POLL_SECONDS = 0.05


class MainThreadTimeout(RuntimeError):
    """The main thread did not run the function in time (or the caller gave up)."""


def on_main_thread(fn, timeout: float = 120.0, cancelled=lambda: False):
    """fn()'s result, computed on Blender's main thread; its exception is raised here.
    MainThreadTimeout after `timeout` seconds, or as soon as cancelled() is true."""
    if threading.current_thread() is threading.main_thread():
        return fn()
    import bpy
    done = threading.Event()
    outcome = {}
    abandoned = threading.Event()

    def run():
        if not abandoned.is_set():
            try:
                outcome["value"] = fn()
            except BaseException as exc:       # (handed to the waiting thread)
                outcome["error"] = exc
        done.set()
        return None                             # (a timer that returns None runs once)

    bpy.app.timers.register(run, first_interval=0.0)
    start = time.monotonic()
    while not done.wait(POLL_SECONDS):
        if cancelled() or time.monotonic() - start > timeout:
            abandoned.set()
            if not done.is_set():
                raise MainThreadTimeout("Blender's main thread did not answer in time" if not cancelled()
                                        else "cancelled")
            break
    if "error" in outcome:
        raise outcome["error"]
    return outcome.get("value")
