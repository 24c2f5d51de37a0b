"""Runs inside Blender on a worker: `blender -b FILE.blend --python in_blender.py`.

The task is described by the environment variable GRIDWALK_FARM_TASK (JSON):
    action   "probe" (print the frame range and image size), "frame" (render
             one frame to `output`, in the .blend's file format) or "tile"
             (render tile `tile` of `tiles` of the frame as a border render
             and save its float32 RGBA pixels, row 0 at the top, to `output`.npy)
    frame    the frame number (None: the .blend's current frame)
    addon    a Gridwalk add-on folder to register first (None: the add-on
             must be enabled in this Blender's preferences)
    threads  Gridwalk render threads (0: the .blend's setting)

The render engine is set to GRIDWALK here, which fails when the add-on is
not registered: Blender would otherwise render with another engine without
a word. A result is printed as one line `GRIDWALK-FARM-RESULT {json}`, a
failure as `GRIDWALK-FARM-ERROR message` with exit status 1.
"""
import importlib
import json
import os
import sys

import bpy

# This folder's own modules (blender_exit, plan), whatever gridwalk that Blender has.
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_exit import exit_now  # noqa: E402


def leave(code: int, tag: str, text: str):
    print(f"{tag} {text}")
    exit_now(code)


def fail(message: str):
    leave(1, "GRIDWALK-FARM-ERROR", " ".join(str(message).split()))


def register_addon(folder: str):
    folder = os.path.abspath(folder.rstrip("/\\"))
    if not os.path.isfile(os.path.join(folder, "__init__.py")):
        fail(f"the add-on folder {folder} has no __init__.py (GRIDWALK_ADDON or --addon must name "
             "the Gridwalk add-on folder)")
    parent, name = os.path.split(folder)
    sys.path.insert(0, parent)
    module = importlib.import_module(name)
    try:
        module.register()
    except ValueError:          # already registered: the add-on is enabled in the preferences too
        pass


def use_gridwalk(scene):
    try:
        scene.render.engine = "GRIDWALK"
    except TypeError:
        fail(f"the GRIDWALK render engine is not registered in Blender {bpy.app.version_string} on this "
             "worker: enable the Gridwalk add-on in this Blender's preferences, or set GRIDWALK_ADDON "
             "(--addon) to the add-on folder (Blender would silently render with another engine)")


def resolution(render):
    pct = render.resolution_percentage
    return max(1, render.resolution_x * pct // 100), max(1, render.resolution_y * pct // 100)


def render_still(scene, path: str):
    scene.render.filepath = path
    try:
        bpy.ops.render.render(write_still=True)
    except RuntimeError as exc:     # the engine reported an error
        fail(str(exc).replace("Error: ", "", 1))


def set_border(render, rect, width, height):
    """A border render of exactly the pixels `rect` (x, y, w, h; row 0 at the top).
    Blender truncates border * size (in float32) to pixels, so each edge is
    put half a pixel past its pixel boundary."""
    x, y, w, h = rect
    render.use_border = True
    render.use_crop_to_border = True
    render.border_min_x = (x + 0.5) / width if x > 0 else 0.0
    render.border_max_x = (x + w + 0.5) / width if x + w < width else 1.0
    bottom, top = height - y - h, height - y           # Blender counts rows from the bottom
    render.border_min_y = (bottom + 0.5) / height if bottom > 0 else 0.0
    render.border_max_y = (top + 0.5) / height if top < height else 1.0


def render_tile(scene, task):
    import numpy as np

    from plan import tiles          # this worker's own plan.py (sys.path above)

    width, height = resolution(scene.render)
    rect = tiles(width, height, task["tiles"])[task["tile"]]
    set_border(scene.render, rect, width, height)
    image = scene.render.image_settings
    image.file_format, image.color_mode, image.color_depth, image.exr_codec = "OPEN_EXR", "RGBA", "32", "NONE"
    exr = task["output"] + ".exr"
    render_still(scene, exr)
    loaded = bpy.data.images.load(exr)
    w, h = loaded.size
    if (w, h) != tuple(rect[2:]) or loaded.channels != 4:
        fail(f"Blender wrote a {w} x {h} image with {loaded.channels} channels for a tile of "
             f"{rect[2]} x {rect[3]} RGBA pixels")
    pixels = np.empty(w * h * 4, np.float32)
    loaded.pixels.foreach_get(pixels)
    np.save(task["output"] + ".npy", pixels.reshape(h, w, 4)[::-1])
    return {"rect": list(rect), "size": [width, height]}


def main():
    task = json.loads(os.environ["GRIDWALK_FARM_TASK"])
    if task.get("addon"):
        register_addon(task["addon"])
    scene = bpy.context.scene
    use_gridwalk(scene)
    if task.get("threads"):
        scene.gridwalk.threads = task["threads"]
    if task.get("frame") is not None:
        scene.frame_set(task["frame"])
    if task["action"] == "probe":
        width, height = resolution(scene.render)
        result = {"blender": bpy.app.version_string, "frame_start": scene.frame_start,
                  "frame_end": scene.frame_end, "frame_current": scene.frame_current,
                  "width": width, "height": height}
    elif task["action"] == "frame":
        render_still(scene, task["output"])
        result = {"frame": scene.frame_current}
    else:
        result = render_tile(scene, task)
    leave(0, "GRIDWALK-FARM-RESULT", json.dumps(result))


try:
    main()
except Exception as exc:        # anything unforeseen: one line, and a failing exit status
    fail(f"{type(exc).__name__}: {exc}")
