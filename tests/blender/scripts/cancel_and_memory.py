"""Cancel GRIDWALK renders at random moments, and render a long animation, in one session.

usage: <python with bpy> cancel_and_memory.py MODE OUT_DIR [key=json ...]
MODE cancel: a complete render (the reference), then `cancels` renders each
    cancelled after a random delay in [0, 1.2 x the reference time), then one
    more complete render. Cancelling goes through the engine's one cancel
    check, streaming.break_requested (RenderEngine.test_break cannot be
    overridden from Python and nothing in the bpy module raises Blender's break
    flag), which this script replaces with "the deadline has passed, or
    test_break()". Threads are counted from /proc/self/task before, during
    (at every cancel check) and after each render. Then one render gets a
    SIGINT while its workers run (Blender's break flag in `blender -b`,
    KeyboardInterrupt in the bpy module).
MODE animation: `frames` frames of an animation (a subdivided monkey and a
    cube moving) rendered by bpy.ops.render.render(animation=True); the
    resident memory (/proc/self/statm) and the thread count are read after
    every frame (render_post).
MODE export: a scene of `objects` separate mesh objects (slow to export);
    the cancel deadline is set when the export has read `at` of them, and the
    time from the deadline to the end of the render is measured.
Writes OUT_DIR/<mode>.json and the EXR files of the renders.
"""
import ctypes
import gc
import json
import os
import random
import re
import signal
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from bad_input import captured  # noqa: E402
import native_threads  # noqa: E402

PAGE = os.sysconf("SC_PAGE_SIZE")
LIBC = ctypes.CDLL(None)


def tasks() -> int:
    """Threads of this process, less jemalloc's background threads (Debian's
    Blender 3.4 links jemalloc, which starts one per arena as arenas come into
    use: 3 to 4 over an animation, not a leak of ours)."""
    return sum(1 for name in native_threads.names() if name != "jemalloc_bg_thd")


def rss(trim=True) -> int:
    """Resident bytes; with trim, after handing freed heap pages back (glibc's
    malloc_trim, jemalloc's purge), so that what is measured is memory still in
    use rather than the allocator's high-water mark."""
    if trim:
        gc.collect()
        mallctl = getattr(LIBC, "mallctl", None)     # jemalloc (Debian's blender links it)
        if mallctl is not None:
            mallctl(b"thread.tcache.flush", None, None, None, 0)
            mallctl(b"arena.4096.purge", None, None, None, 0)     # 4096: MALLCTL_ARENAS_ALL
        LIBC.malloc_trim(0)
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * PAGE


def build(bpy, scenes, resolution, levels):
    scenes.reset(resolution=tuple(resolution))
    bpy.ops.mesh.primitive_monkey_add(location=(-1.0, 0.0, 0.0))
    monkey = bpy.context.object
    modifier = monkey.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = levels
    cube = scenes.link(scenes.cube_object())
    cube.location = (1.5, 0.0, 0.0)
    scenes.add_light("Key", "POINT", (2, -6, 4), energy=400.0)
    return monkey, cube


def configure(bpy, out_dir, name, opts):
    import render_scene
    render_scene.configure(bpy.context.scene, "GRIDWALK", {"settings": opts.get("settings", {})})
    bpy.context.scene.render.filepath = os.path.join(out_dir, name)


def render():
    """Render the current frame; (log, seconds)."""
    import bpy
    t0 = time.perf_counter()
    _, log = captured(lambda: bpy.ops.render.render(write_still=True))
    return log, time.perf_counter() - t0


def stage(log: str) -> str:
    for line in log.splitlines():
        if line.startswith("Gridwalk: cancelled (KeyboardInterrupt)"):
            return "interrupted"
        if line.startswith("Gridwalk: cancel stopped all workers"):
            return "while rendering"
        if line.startswith("Gridwalk: cancelled "):
            return line[len("Gridwalk: cancelled "):].split(",")[0].strip()
        if line.startswith("Gridwalk: finished"):
            return "finished"
    return "unknown"


def cancel_mode(bpy, scenes, streaming, out_dir, opts):
    build(bpy, scenes, opts.get("resolution", (160, 120)), opts.get("levels", 2))
    configure(bpy, out_dir, "first.exr", opts)
    log, reference = render()
    out = {"reference_seconds": reference, "first": stage(log), "tasks_idle": tasks(), "renders": []}
    real = streaming.break_requested
    state = {"deadline": None, "peak": 0}

    def break_requested(engine):
        state["peak"] = max(state["peak"], tasks())
        return time.monotonic() >= state["deadline"] or real(engine)

    streaming.break_requested = break_requested
    rng = random.Random(opts.get("seed", 7))
    try:
        for _ in range(opts.get("cancels", 50)):
            delay = rng.uniform(0.0, 1.2 * reference)
            state["peak"] = 0
            state["deadline"] = time.monotonic() + delay
            configure(bpy, out_dir, "cancelled.exr", opts)
            log, seconds = render()
            joined = re.search(r"cancel stopped all workers in ([\d.]+) ms", log)
            out["renders"].append({"delay": delay, "seconds": seconds, "stage": stage(log),
                                   "join_ms": float(joined.group(1)) if joined else None,
                                   "peak_tasks": state["peak"], "tasks_after": tasks(),
                                   "traceback": "Traceback" in log})
    finally:
        streaming.break_requested = real
    # Ctrl-C (SIGINT) at the render loop's first cancel check, the workers running:
    # Blender's own break flag in `blender -b`, KeyboardInterrupt in the bpy module
    configure(bpy, out_dir, "interrupted.exr", opts)
    real_run, armed = streaming.run, []

    def run(engine, job, writer):
        armed.append(True)
        return real_run(engine, job, writer)

    def interrupt(engine):
        if armed and len(armed) == 1:
            armed.append(True)
            os.kill(os.getpid(), signal.SIGINT)
        return real(engine)

    streaming.run, streaming.break_requested = run, interrupt
    try:
        log, seconds = render()
    finally:
        streaming.run, streaming.break_requested = real_run, real
    out["interrupted"] = {"stage": stage(log), "seconds": seconds, "tasks_after": tasks(),
                          "keyboard_interrupt": "cancelled (KeyboardInterrupt)" in log,
                          "traceback": "Traceback" in log}
    configure(bpy, out_dir, "last.exr", opts)
    log, seconds = render()
    out.update(last=stage(log), last_seconds=seconds, tasks_end=tasks())
    return out


def export_mode(bpy, scenes, streaming, out_dir, opts):
    from blender_addon import engine, export
    scenes.reset(resolution=(32, 24))
    count = opts.get("objects", 3000)
    for i in range(count):       # separate meshes: each is read on its own
        obj = scenes.link(scenes.cube_object(f"Cube{i}", 0.6))
        obj.location = (i % 60 - 30, (i // 60) % 60 - 30, 0.0)
    scenes.add_light("Key", "POINT", (2, -6, 4), energy=400.0)
    configure(bpy, out_dir, "full.exr", opts)
    log, full = render()
    out = {"full": stage(log), "full_seconds": full}
    real_break, real_add = streaming.break_requested, export.MeshCollector.add_instance
    real_render = engine.GridwalkRenderEngine._render
    state = {"added": 0, "deadline": None, "returned": None}

    def _render(self, depsgraph):          # the engine's work, without Blender's saving of the image
        try:
            return real_render(self, depsgraph)
        finally:
            state["returned"] = time.perf_counter()

    def add_instance(self, inst, *rest):
        state["added"] += 1
        if state["added"] == opts.get("at", 1000):
            state["deadline"] = time.perf_counter()
        return real_add(self, inst, *rest)

    def break_requested(engine):
        return (state["deadline"] is not None) or real_break(engine)

    streaming.break_requested, export.MeshCollector.add_instance = break_requested, add_instance
    engine.GridwalkRenderEngine._render = _render
    try:
        configure(bpy, out_dir, "cancelled.exr", opts)
        log, _ = render()
    finally:
        streaming.break_requested, export.MeshCollector.add_instance = real_break, real_add
        engine.GridwalkRenderEngine._render = real_render
    out.update(stage=stage(log), latency_ms=1e3 * (state["returned"] - state["deadline"]), added=state["added"],
               traceback="Traceback" in log, log=log[-2000:])
    return out


def animation_mode(bpy, scenes, out_dir, opts):
    frames = opts.get("frames", 100)
    monkey, cube = build(bpy, scenes, opts.get("resolution", (32, 24)), opts.get("levels", 2))
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, frames
    for obj, start, end in ((monkey, (-2.0, 0.0, -0.5), (1.0, 0.0, 0.5)), (cube, (2.0, 1.0, 0.0), (0.0, -1.0, 1.0))):
        for frame, location in ((1, start), (frames, end)):
            obj.location = location
            obj.keyframe_insert("location", frame=frame)
    configure(bpy, out_dir, "frame_", opts)
    samples, threads = {}, {}

    def after_frame(scene, *args):
        samples[scene.frame_current] = rss(trim=scene.frame_current % 10 == 0)
        threads[scene.frame_current] = tasks()
    bpy.app.handlers.render_post.append(after_frame)
    t0 = time.perf_counter()
    _, log = captured(lambda: bpy.ops.render.render(animation=True))
    return {"seconds": time.perf_counter() - t0, "rss": samples, "tasks": threads,
            "finished": log.count("Gridwalk: finished"), "traceback": "Traceback" in log,
            "tasks_after": tasks()}


def main(mode, out_dir, *options):
    import bpy

    import blender_addon
    import scenes
    from blender_addon import streaming
    opts = {k: json.loads(v) for k, v in (o.split("=", 1) for o in options)}
    blender_addon.register()
    if mode == "cancel":
        out = cancel_mode(bpy, scenes, streaming, out_dir, opts)
    elif mode == "export":
        out = export_mode(bpy, scenes, streaming, out_dir, opts)
    else:
        out = animation_mode(bpy, scenes, out_dir, opts)
    out["blender"] = list(bpy.app.version)
    with open(os.path.join(out_dir, f"{mode}.json"), "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main, spread=True)
