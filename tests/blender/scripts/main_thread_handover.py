"""How export/main_thread.py hands work from a job thread to the main thread, in Blender:
with the add-on registered, a worker thread asks for a function to run on the main thread;
the main thread drains the queue (the persistent timer's function, called here as the event
loop calls it); a worker that cancels gets MainThreadTimeout at once, and its abandoned
request does not run later.

usage: <python with bpy> main_thread_handover.py OUT_DIR   (writes OUT_DIR/handover.json)
"""
import json
import os
import sys
import threading
import time


def main(out_dir):
    import bpy

    import blender_addon
    from blender_addon.export import main_thread

    blender_addon.register()
    info = {"timer_registered": bpy.app.timers.is_registered(main_thread._drain)}
    ran_on = []

    def job():
        ran_on.append(threading.current_thread() is threading.main_thread())
        return 42

    result = {}

    def worker(cancel_after=None):
        start = time.monotonic()
        try:
            result["value"] = main_thread.on_main_thread(
                job, timeout=30, cancelled=lambda: cancel_after is not None and time.monotonic() - start > cancel_after)
        except main_thread.MainThreadTimeout as exc:
            result["timeout"] = str(exc)
        result["seconds"] = time.monotonic() - start

    thread = threading.Thread(target=worker)
    thread.start()
    time.sleep(0.3)                       # (the worker waits: nothing drains yet)
    info["waiting"] = thread.is_alive()
    main_thread._drain()                  # what the timer does on the main thread
    thread.join(10)
    info["value"], info["ran_on_main"] = result.get("value"), list(ran_on)
    result.clear()
    ran_on.clear()
    thread = threading.Thread(target=worker, kwargs={"cancel_after": 0.2})
    thread.start()
    thread.join(10)
    info["cancelled"], info["cancel_seconds"] = result.get("timeout"), result.get("seconds")
    main_thread._drain()                  # the abandoned request: dropped, not run
    info["abandoned_ran"] = bool(ran_on)
    info["on_main_directly"] = main_thread.on_main_thread(lambda: threading.current_thread() is threading.main_thread())
    blender_addon.unregister()
    info["timer_after_unregister"] = bpy.app.timers.is_registered(main_thread._drain)
    with open(os.path.join(out_dir, "handover.json"), "w") as f:
        json.dump(info, f)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main, spread=True)
