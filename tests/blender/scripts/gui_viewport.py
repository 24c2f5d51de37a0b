"""Inside Blender's GUI (Debian's blender 3.4 under Xvfb): Rendered viewport
shading with GRIDWALK, step by step (run by tests/blender/test_b23_gui_viewport.py).

 1. scenes.viewport_scene, seen through the camera at zoom 1:1 (the camera's
    frame is the render's size in pixels): screenshot shot_camera.png once the
    viewport render is done; a final render of the same camera, final.png.
 2. "Sphere" moved from this script: screenshot shot_moved.png. The
    camera's scale set to (1, 0, 1), the message shown recorded; scale restored.
    The camera made an equirectangular panorama: screenshot shot_panorama.png
    and a final render of it, final_panorama.png; then an equisolid fisheye:
    shot_fisheye.png and final_fisheye.png; the camera made perspective again.
    Everything moved 1e7 from the origin: screenshot shot_far.png and a final
    render, final_far.png; moved back.
 3. The front numpad view (orthographic): screenshot shot_front.png.
 4. Rendering with many samples for 5 s: the time the engine spends in each
    call on Blender's main thread (view_update, view_draw) is recorded; the
    engine is switched to Workbench mid-render; back to GRIDWALK, then Solid
    shading mid-render; Rendered again, then Toggle Quad View (four views,
    four renders); 400 operators called under temp_override while the sphere
    moves (operator_storm), and back; the 3D view's area switched to the Image Editor
    (the view closes); back to a Rendered 3D view, then File > New while rendering;
    Rendered again, then quit while rendering.
    Render threads (named "gridwalk") and the viewport's controller threads ("gridwalk-view") are
    counted after each event.
OUT (env) is the output folder; results go to OUT/gui_viewport.json.
"""
import json
import os
import sys
import time
import traceback

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import native_threads  # noqa: E402
import write_permission  # noqa: E402
from gridwalk_blender.scripting import leave  # noqa: E402  (the add-on, as gui.py installs it)
OUT = os.environ["OUT"]
DEADLINE = time.monotonic() + 240
RESULTS = {"log": []}


def log(*args):
    line = " ".join(str(a) for a in args)
    RESULTS["log"].append(line)
    print("gui_viewport:", line, flush=True)


def save():
    with open(os.path.join(OUT, "gui_viewport.json"), "w") as f:
        json.dump(RESULTS, f, indent=1)


def fail(message):
    log("FAILED:", message)
    save()
    leave(1)


def record_refused(fn):
    """Notes a step that runs in a property update because writes were refused."""
    RESULTS.setdefault("write_refused", []).append(
        [fn.__name__, round(time.monotonic(), 2), bpy.app.is_job_running("RENDER_PREVIEW")])
    log("writes refused, running the step in a property update:", RESULTS["write_refused"][-1])


def step(fn):
    """A timer callback: any error ends Blender with exit code 1 and the
    traceback. While Blender refuses a script's writes to ID data (after a
    preview render of our engine, sometimes), the step runs where writes are
    allowed (write_permission.py)."""
    def wrapped():
        try:
            return write_permission.run(fn, record_refused)
        except Exception:
            traceback.print_exc()
            fail(traceback.format_exc())
    return wrapped


def after(seconds, fn):
    bpy.app.timers.register(step(fn), first_interval=seconds, persistent=True)


def view3d():
    """(window, area, region, space) of the largest 3D view."""
    win = bpy.context.window_manager.windows[0]
    area = max((a for a in win.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return win, area, region, area.spaces.active


def threads() -> dict:
    """Render threads and viewport threads over 0.5 s: the most render threads
    seen (a pass may be between jobs at one instant), and the viewport's
    controller threads seen most often (a render thread a controller has
    just started carries the controller's name for an instant)."""
    log("sessions:", [(s.message, s.finished, s._versions()) for s in sessions()])
    render, viewport = 0, []
    for _ in range(10):
        render = max(render, native_threads.count(native_threads.RENDER))
        viewport.append(native_threads.count(native_threads.VIEWPORT))
        time.sleep(0.05)
    return {"render": render, "viewport": max(set(viewport), key=viewport.count)}


def sessions():
    module = sys.modules.get("gridwalk_blender.viewport")
    return list(module.SESSIONS) if module else []


def requests() -> int:
    """Requests submitted by every viewport session so far (each restart is one)."""
    return sum(s.request[0] for s in sessions() if s.request)


def when_done(then):
    """Call `then` once every viewport render has finished its latest scene and
    view (and has redrawn)."""
    def poll():
        if time.monotonic() > DEADLINE:
            fail(f"the viewport render did not finish: {[s.message for s in sessions()]}")
        live = sessions()
        if live and all(s.idle() for s in live):
            view3d()[1].tag_redraw()
            after(1.0, then)
            return None
        return 0.25
    bpy.app.timers.register(step(poll), first_interval=0.25, persistent=True)


def screenshot(name):
    win = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=win, area=win.screen.areas[0]):
        bpy.ops.screen.screenshot(filepath=os.path.join(OUT, name))
    _, area, region, space = view3d()
    RESULTS[name] = {"region": [region.x, region.y, region.width, region.height], "window_height": win.height,
                     "perspective": space.region_3d.is_perspective}
    log("screenshot", name, RESULTS[name])


def projected_box(obj):
    """The object's bounding box in region pixels (x0, y0, x1, y1, origin bottom left)."""
    from mathutils import Vector
    _, _, region, space = view3d()
    m = space.region_3d.perspective_matrix
    xs, ys = [], []
    for corner in obj.bound_box:
        p = m @ (obj.matrix_world @ Vector(corner)).to_4d()
        xs.append((p.x / p.w + 1) / 2 * region.width)
        ys.append((p.y / p.w + 1) / 2 * region.height)
    return [min(xs), min(ys), max(xs), max(ys)]


@step
def setup():
    import scenes
    scenes.viewport_scene(factory=False)
    scene = bpy.context.scene
    scene.render.engine = "GRIDWALK"
    scene.render.preview_pixel_size = "1"
    scene.gridwalk.viewport_samples = 4
    scene.camera.data.show_passepartout = False
    RESULTS["before"] = threads()
    for properties in bpy.context.window_manager.windows[0].screen.areas:
        if properties.type == "PROPERTIES":
            properties.spaces.active.context = "RENDER"         # the Gridwalk panels, for the docs' picture
    win, area, region, space = view3d()
    space.shading.type = "RENDERED"
    space.overlay.show_overlays = False
    space.show_gizmo = False
    space.show_region_toolbar = False
    space.show_region_tool_header = False
    space.region_3d.view_perspective = "CAMERA"
    space.region_3d.view_camera_offset = (0.0, 0.0)
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.view3d.zoom_camera_1_to_1()
    log("3D view", region.width, "x", region.height)
    when_done(camera_view)


def camera_frame():
    """The camera's frame in the 3D view's region (x0, y0, x1, y1, origin bottom left)."""
    from gridwalk_blender.export.viewport_camera import frame_in_region
    scene = bpy.context.scene
    depsgraph = bpy.context.evaluated_depsgraph_get()
    _, _, region, space = view3d()
    cam = scene.camera.evaluated_get(depsgraph)
    projection = cam.calc_matrix_camera(depsgraph, x=scene.render.resolution_x, y=scene.render.resolution_y)
    return list(frame_in_region(projection, space.region_3d.window_matrix, region.width, region.height))


def camera_view():
    screenshot("shot_camera.png")
    scene = bpy.context.scene
    RESULTS["frame"] = camera_frame()
    RESULTS["sphere_before"] = projected_box(bpy.data.objects["Sphere"])
    RESULTS["camera_boxes"] = {n: projected_box(bpy.data.objects[n]) for n in ("Near", "Far")}
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = os.path.join(OUT, "final.png")
    bpy.ops.render.render(write_still=True)
    log("final render written")
    RESULTS["world_color"] = list(scene.world.color)
    RESULTS["previews"] = {}
    preview("material", bpy.data.materials["Green"], lambda: preview("world", scene.world, move_sphere))


def preview(name, id_, then):
    """Render the thumbnail of `id_` (one at a time: a new preview job cancels
    the running one), record its mean colour, then call `then`."""
    import numpy as np
    if name == "world":
        id_.color = (0.2, 0.3, 0.8)
    id_.preview_ensure()
    with bpy.context.temp_override(id=id_):
        bpy.ops.ed.lib_id_generate_preview()
    deadline = time.monotonic() + 30

    def poll():
        w, h = id_.preview.image_size
        pixels = np.zeros(w * h * 4, np.float32)
        if w * h:
            id_.preview.image_pixels_float.foreach_get(pixels)
        rgb = pixels.reshape(-1, 4)[:, :3]
        if not w * h or rgb.max() == 0:
            if time.monotonic() > deadline:
                fail(f"no {name} preview")
            return 0.25
        RESULTS["previews"][name] = {"mean": rgb.mean(axis=0).tolist(), "std": rgb.std(axis=0).tolist()}
        log("preview", name, RESULTS["previews"][name])
        after(0.0, then)
        return None
    bpy.app.timers.register(step(poll), first_interval=0.25, persistent=True)


def move_sphere():
    bpy.context.scene.world.color = RESULTS["world_color"]
    bpy.data.objects["Sphere"].location.x += 0.6
    bpy.context.view_layer.update()
    RESULTS["sphere_after"] = projected_box(bpy.data.objects["Sphere"])
    RESULTS["camera_name"] = bpy.context.scene.camera.name
    RESULTS["edit_timings"] = None
    after(0.5, lambda: when_done(moved))


def moved():
    RESULTS["edit_timings"] = [dict(s.timings) for s in sessions()]
    screenshot("shot_moved.png")
    bpy.context.scene.camera.scale = (1.0, 0.0, 1.0)      # looking through a camera without a view
    view3d()[1].tag_redraw()
    after(1.5, zero_scale_camera)


def zero_scale_camera():
    RESULTS["zero_scale_camera_messages"] = [s.message for s in sessions()]
    log("zero scale camera:", RESULTS["zero_scale_camera_messages"])
    scene = bpy.context.scene
    scene.camera.scale = (1.0, 1.0, 1.0)
    cam = scene.camera.data
    cam.type = "PANO"
    pano = cam if hasattr(cam, "panorama_type") else cam.cycles        # Blender 4.x / 3.x (Cycles' settings)
    pano.panorama_type = "EQUIRECTANGULAR"
    pano.longitude_min, pano.longitude_max = -0.4, 0.4     # the frame's 16:9, about the perspective lens' angles
    pano.latitude_min, pano.latitude_max = -0.25, 0.2
    after(0.5, lambda: when_done(panorama_view))


def shot_and_render(name):
    """Screenshot shot_<name>.png, the camera's frame in it (frame_<name>) and a final render, final_<name>.png."""
    screenshot(f"shot_{name}.png")
    RESULTS[f"frame_{name}"] = camera_frame()
    bpy.context.scene.render.filepath = os.path.join(OUT, f"final_{name}.png")
    bpy.ops.render.render(write_still=True)


def panorama_view():
    shot_and_render("panorama")
    scene = bpy.context.scene
    cam = scene.camera.data
    pano = cam if hasattr(cam, "panorama_type") else cam.cycles
    pano.panorama_type = "FISHEYE_EQUISOLID"      # a 10.5 mm lens over 150 degrees: black corners
    pano.fisheye_lens, pano.fisheye_fov = 10.5, 2.6
    after(0.5, lambda: when_done(fisheye_view))


def fisheye_view():
    shot_and_render("fisheye")
    bpy.context.scene.camera.data.type = "PERSP"
    move_everything(FAR)
    after(0.5, lambda: when_done(far_view))


FAR = (1e7, 1e7, 0.0)        # whole numbers: the camera and the cubes' corners stay exact in float32


def move_everything(offset):
    """Every object moved by `offset`; the sphere (whose vertices float32 would
    snap to whole units 1e7 from the origin) hidden while away."""
    from mathutils import Vector
    for obj in bpy.context.scene.objects:
        obj.location += Vector(offset)
    sphere = bpy.data.objects["Sphere"]
    sphere.hide_viewport = sphere.hide_render = offset[0] > 0
    bpy.context.view_layer.update()


def far_view():
    shot_and_render("far")
    move_everything(tuple(-x for x in FAR))
    after(0.5, lambda: when_done(front_view))


def front_view():
    win, area, region, _ = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.view3d.view_axis(type="FRONT")
    after(0.5, lambda: when_done(front))


def front():
    screenshot("shot_front.png")
    RESULTS["front_boxes"] = {n: projected_box(bpy.data.objects[n]) for n in ("Near", "Far")}
    bpy.context.scene.gridwalk.viewport_samples = 4000          # keeps rendering
    for session in sessions():
        session.main_thread.clear()
    after(5.0, switch_engine)


def switch_engine():
    RESULTS["main_thread"] = [list(s.main_thread) for s in sessions()]
    RESULTS["rendering"] = threads()
    bpy.context.scene.render.engine = "BLENDER_WORKBENCH"
    view3d()[1].tag_redraw()
    after(2.0, switched)


def switched():
    RESULTS["after_engine_switch"] = threads()
    bpy.context.scene.render.engine = "GRIDWALK"
    view3d()[1].tag_redraw()
    after(2.0, solid_shading)


def solid_shading():
    RESULTS["rendering_again"] = threads()
    view3d()[3].shading.type = "SOLID"
    after(2.0, rendered_again)


def rendered_again():
    RESULTS["after_solid_shading"] = threads()
    view3d()[3].shading.type = "RENDERED"
    after(2.0, quad_view)


def toggle_quad_view():
    win, area, region, _ = view3d()
    with bpy.context.temp_override(window=win, area=area, region=region):
        bpy.ops.screen.region_quadview()
    area.tag_redraw()


def quad_view():
    RESULTS["rendering_before_quad_view"] = threads()
    toggle_quad_view()
    after(3.0, quad_view_rendering)


def quad_view_rendering():
    RESULTS["quad_view"] = threads()
    RESULTS["quad_view_regions"] = len(view3d()[3].region_quadviews)
    operator_storm(leave_quad_view)


STORM_TICKS, CALLS_PER_TICK = 40, 10


def operator_storm(then):
    """Operators called from Python under temp_override, ten per timer tick,
    while four views render and the sphere moves (each move restarts them).
    Blender 3.4-5.0 on Python 3.11 reads the override's dict without taking
    the GIL when another Python thread holds it, and crashed this way
    (docs/blender.md): the viewport runs no Python thread."""
    win, area, region, _ = view3d()
    sphere = bpy.data.objects["Sphere"]
    state = {"calls": 0, "requests_before": requests()}

    def tick():
        if state["calls"] >= STORM_TICKS * CALLS_PER_TICK:
            RESULTS["operator_storm"] = dict(state, requests_after=requests(), sessions=len(sessions()))
            log("operator storm:", RESULTS["operator_storm"])
            after(0.5, then)
            return None
        for _ in range(CALLS_PER_TICK):
            with bpy.context.temp_override(window=win, area=area, region=region):
                bpy.ops.object.select_all(action="TOGGLE")
            state["calls"] += 1
        sphere.location.z += 0.001 if state["calls"] % (2 * CALLS_PER_TICK) else -0.001
        return 0.01
    bpy.app.timers.register(step(tick), first_interval=0.01, persistent=True)


def leave_quad_view():
    toggle_quad_view()
    after(2.0, close_view)


def close_view():
    RESULTS["after_quad_view"] = threads()
    view3d()[1].type = "IMAGE_EDITOR"          # the 3D view closes (its area shows another editor)
    after(2.0, reopen_view)


def reopen_view():
    RESULTS["after_closing_the_view"] = threads()
    area = next(a for a in bpy.context.window_manager.windows[0].screen.areas if a.type == "IMAGE_EDITOR")
    area.type = "VIEW_3D"
    view3d()[3].shading.type = "RENDERED"
    after(2.0, new_file)


def new_file():
    RESULTS["rendering_before_new_file"] = threads()
    bpy.ops.wm.read_homefile()
    after(2.0, after_new_file)


def after_new_file():
    RESULTS["after_new_file"] = threads()
    scene = bpy.context.scene
    scene.render.engine = "GRIDWALK"
    scene.gridwalk.viewport_samples = 4000
    view3d()[3].shading.type = "RENDERED"
    after(2.0, quit_blender)


def quit_blender():
    RESULTS["rendering_before_quit"] = threads()
    RESULTS["completed"] = True
    save()
    log("quitting while rendering")
    bpy.ops.wm.quit_blender()


after(1.0, setup)
