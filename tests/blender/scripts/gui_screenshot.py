"""Inside Blender's GUI (under Xvfb): build the demo scene, select GRIDWALK in
Render Properties, render (F12, shown in the main area), take a screenshot.
The steps after the render call operators where Blender allows it: a
render of our (Python) engine on the render job's thread can leave Python's
writes refused (write_permission.py).

Run by tests/blender/gui.py; SHOT (env) is the PNG to write.
"""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "blender_addon"))
import demo  # noqa: E402
from blender_addon.scripting import leave  # noqa: E402  (demo put the checkout on sys.path)

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import write_permission  # noqa: E402

OUT = os.environ["SHOT"]


def log(*args):
    print("gui_screenshot:", *args)
    sys.stdout.flush()


def window_area(kind):
    win = bpy.context.window_manager.windows[0]
    return win, next(a for a in win.screen.areas if a.type == kind)


def start_render():
    demo.build_demo_scene(480, 270, fresh=False)
    for area in bpy.context.window.screen.areas:
        if area.type == "PROPERTIES":
            area.spaces.active.context = "RENDER"
    bpy.context.preferences.view.render_display_type = "AREA"
    bpy.app.handlers.render_complete.append(lambda *args: bpy.app.timers.register(
        lambda: write_permission.run(fit), first_interval=1.0))
    win, area = window_area("VIEW_3D")
    with bpy.context.temp_override(window=win, area=area):
        bpy.ops.render.render("INVOKE_DEFAULT")
    log("render started")


def fit():
    win, area = window_area("IMAGE_EDITOR")
    region = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.image.view_all(fit_view=True)
    bpy.app.timers.register(lambda: write_permission.run(shoot), first_interval=1.5)


def shoot():
    win = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
        bpy.ops.screen.screenshot(filepath=OUT)
    log("saved", OUT)
    leave(0)


bpy.app.timers.register(start_render, first_interval=1.0)
