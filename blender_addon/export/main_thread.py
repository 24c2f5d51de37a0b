"""Run a function on Blender's main thread and wait for its result.

A final render from the GUI (F12) runs the engine's render() on a job thread,
while Blender's main thread keeps drawing the interface. Adding an ID to
bpy.data (loading an image) from the job thread would race with the main
thread's own walks over bpy.data, so such work is handed to the main thread
and the job thread waits for it. The hand-over is a queue that a persistent
bpy.app.timers function drains on the main thread (register(), at the add-on's
registration, on the main thread: Blender's list of timers has no lock, so a
job thread must not register one itself). On the main thread (the viewport's
view_update, a render from `blender -b` or from the bpy module) the function
simply runs.
"""
from __future__ import annotations

import queue
import threading
import time

POLL_SECONDS = 0.05       # how often the waiting thread asks whether to give up
DRAIN_SECONDS = 0.1       # how often the main thread looks for work

_requests: queue.Queue = queue.Queue()
_draining = False         # register() ran (read by job threads instead of Blender's unlocked timer list)


class MainThreadTimeout(RuntimeError):
    """The main thread did not run the function in time (or the caller gave up)."""


class _Request:
    def __init__(self, fn):
        self.fn = fn
        self.done = threading.Event()
        self.lock = threading.Lock()
        self.started = self.abandoned = False
        self.outcome: dict = {}

    def run(self):
        with self.lock:             # (a request the caller gave up before it started is dropped)
            self.started = not self.abandoned
        if self.started:
            try:
                self.outcome["value"] = self.fn()
            except BaseException as exc:       # (handed to the waiting thread)
                self.outcome["error"] = exc
        self.done.set()

    def abandon(self) -> bool:
        """Gives the request up unless it has started (then it is waited for: it may use data the
        caller frees when it returns); whether it was given up."""
        with self.lock:
            self.abandoned = not self.started
            return self.abandoned


def _drain():
    """bpy.app.timers callback (main thread): runs every waiting request."""
    while True:
        try:
            request = _requests.get_nowait()
        except queue.Empty:
            return DRAIN_SECONDS
        request.run()


def register():
    global _draining
    import bpy
    if not bpy.app.timers.is_registered(_drain):
        bpy.app.timers.register(_drain, first_interval=DRAIN_SECONDS, persistent=True)
    _draining = True


def unregister():
    global _draining
    import bpy
    _draining = False
    if bpy.app.timers.is_registered(_drain):
        bpy.app.timers.unregister(_drain)


def on_main_thread(fn, timeout: float = 120.0, cancelled=lambda: False):
    """fn()'s result, computed on Blender's main thread; its exception is raised here.
    MainThreadTimeout when the main thread has not started it after `timeout` seconds, or when
    cancelled() is true before it starts; once started it is waited for to the end."""
    if threading.current_thread() is threading.main_thread():
        return fn()
    if not _draining:      # (the add-on is not registered: nothing drains the queue)
        raise MainThreadTimeout("the add-on's main-thread timer is not running")
    request = _Request(fn)
    _requests.put(request)
    start = time.monotonic()
    while not request.done.wait(POLL_SECONDS):
        if (cancelled() or time.monotonic() - start > timeout) and request.abandon():
            raise MainThreadTimeout("cancelled" if cancelled() else "Blender's main thread did not answer in time")
    if "error" in request.outcome:
        raise request.outcome["error"]
    return request.outcome.get("value")
