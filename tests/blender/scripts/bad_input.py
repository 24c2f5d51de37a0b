"""Render every bad-input case with GRIDWALK in one Blender session.

usage: <python with bpy> bad_input.py OUT_DIR
For each case: OUT_DIR/<case>.exr when the render succeeded, and in
OUT_DIR/bad_input.json the error Blender raised (RuntimeError from the
operator, i.e. the engine's ERROR report), everything written to stdout and
stderr during the render (Blender prints the WARNING and ERROR reports there)
and the time taken. The session surviving all cases is part of the test.
"""
import ctypes
import json
import os
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

NAN, INF = float("nan"), float("inf")
LIBC = ctypes.CDLL(None)


def captured(fn):
    """(fn(), text that fn wrote to file descriptors 1 and 2, C stdio included)."""
    sys.stdout.flush()
    sys.stderr.flush()
    LIBC.fflush(None)
    saved = os.dup(1), os.dup(2)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 1)
        os.dup2(tmp.fileno(), 2)
        try:
            result = fn()
        finally:
            sys.stdout.flush()
            sys.stderr.flush()
            LIBC.fflush(None)
            os.dup2(saved[0], 1)
            os.dup2(saved[1], 2)
            for fd in saved:
                os.close(fd)
        tmp.seek(0)
        text = tmp.read().decode("utf-8", "replace")
    sys.stdout.write(text)
    return result, text


def mesh_object(bpy, name, verts, edges=(), faces=()):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(list(verts), list(edges), list(faces))
    mesh.update()
    return bpy.data.objects.new(name, mesh)


# -- the cases: each builds its scene (from scenes.reset) and may return options --

def case_empty(bpy, s):
    s.reset()
    s.add_light("Key", "POINT", (0, -5, 5), energy=100.0)


def case_no_camera(bpy, s):
    s.no_camera_scene()


def case_camera_deleted(bpy, s):
    """An animation whose camera is deleted at frame 2: Blender calls the engine anyway."""
    s.cube_scene()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 2

    def delete_camera(scene, *args):
        if scene.frame_current == 2 and scene.camera is not None:
            camera = scene.camera
            scene.camera = None
            bpy.data.objects.remove(camera)
    bpy.app.handlers.frame_change_pre.append(delete_camera)
    return {"animation": True}


def case_empty_frame(bpy, s):
    """An animation of three frames whose only object is keyed Disable in Renders at frame 2
    (a cut): Cycles renders that frame's world and goes on."""
    s.cube_scene()
    scene = bpy.context.scene
    scene.frame_start, scene.frame_end = 1, 3
    cube = bpy.data.objects["Cube"]
    for frame, hidden in ((1, False), (2, True), (3, False)):
        cube.hide_render = hidden
        cube.keyframe_insert("hide_render", frame=frame)
    scene.frame_set(1)
    return {"animation": True}


def case_not_a_camera(bpy, s):
    s.cube_scene()
    empty = s.link(bpy.data.objects.new("NotACamera", None))
    camera = bpy.context.scene.camera
    empty.location, empty.rotation_euler = camera.location, camera.rotation_euler
    bpy.context.scene.camera = empty


def case_nan_camera(bpy, s):
    s.cube_scene()
    bpy.context.scene.camera.location = (NAN, -10.0, 0.0)


def case_zero_scale_camera(bpy, s):
    s.cube_scene()
    bpy.context.scene.camera.scale = (1.0, 0.0, 1.0)


def case_empty_panorama(bpy, s):
    """An equirectangular panorama whose latitude range is empty."""
    s.cube_scene()
    cam = bpy.context.scene.camera.data
    cam.type = "PANO"
    pano = cam if hasattr(cam, "panorama_type") else cam.cycles
    pano.panorama_type = "EQUIRECTANGULAR"
    pano.latitude_min = pano.latitude_max = 0.3


def case_custom_camera(bpy, s):
    """Blender 4.5's Custom camera (an OSL shader); before 4.5 an orthographic one stands in."""
    s.cube_scene()
    cam = bpy.context.scene.camera.data
    kinds = {item.identifier for item in cam.bl_rna.properties["type"].enum_items}
    cam.type = "CUSTOM" if "CUSTOM" in kinds else "ORTHO"


def case_camera_inside_cube(bpy, s):
    s.reset()
    s.link(s.cube_object("Room", size=6.0))
    s.add_light("Inside", "POINT", (1.0, 1.0, 1.0), energy=50.0)
    bpy.context.scene.camera.location = (0.0, 0.0, 0.0)


def case_camera_inside_sphere(bpy, s):
    s.reset()
    bpy.ops.mesh.primitive_uv_sphere_add(radius=3.0, location=(0.0, 0.0, 0.0))
    bpy.context.object.gridwalk.render_as_sphere = True
    s.add_light("Outside", "POINT", (0, -10, 5), energy=100.0)
    bpy.context.scene.camera.location = (0.5, 0.0, 0.0)


def _lit_cube_scene(bpy, s, resolution=(64, 48)):
    s.reset(resolution=resolution)
    cube = s.link(s.cube_object())
    cube.rotation_euler = (0.4, 0.3, 0.2)
    s.add_light("Key", "POINT", (2, -6, 4), energy=400.0)


def case_tiny_1x1(bpy, s):
    _lit_cube_scene(bpy, s, resolution=(100, 100))
    bpy.context.scene.render.resolution_percentage = 1     # Blender's smallest size is 4 x 4 at 100%
    bpy.context.scene.gridwalk.aa = "CENTER"               # the pixel centre looks at the cube


def case_full_frame(bpy, s):
    _lit_cube_scene(bpy, s)


def _border(bpy, s, x0, x1, y0, y1, crop=False):
    _lit_cube_scene(bpy, s)
    render = bpy.context.scene.render
    render.use_border, render.use_crop_to_border = True, crop
    render.border_min_x, render.border_max_x, render.border_min_y, render.border_max_y = x0, x1, y0, y1


def case_border(bpy, s):
    _border(bpy, s, 0.25, 0.6, 0.1, 0.55)


def case_border_crop(bpy, s):
    _border(bpy, s, 0.25, 0.6, 0.1, 0.55, crop=True)


def case_border_1px(bpy, s):
    _border(bpy, s, 0.5, 0.52, 0.5, 0.53)          # 64 x 48: pixel (32, 24) from the bottom left


def case_nan_transforms(bpy, s):
    _lit_cube_scene(bpy, s)
    bad = {"NaNLocation": ("location", (NAN, 0.0, 0.0)), "NaNRotation": ("rotation_euler", (NAN, 0.0, 0.0)),
           "InfScale": ("scale", (INF, 1.0, 1.0))}
    for name, (attr, value) in bad.items():
        setattr(s.link(s.cube_object(name)), attr, value)
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0)
    ball = bpy.context.object
    ball.name, ball.location = "NaNSphere", (0.0, NAN, 0.0)
    ball.gridwalk.render_as_sphere = True
    s.add_light("NaNLight", "POINT", (NAN, 0.0, 3.0), energy=100.0)
    nan_vertex = s.link(s.cube_object("NaNVertex"))
    nan_vertex.data.vertices[0].co = (NAN, 0.0, 0.0)


def _vertex_instances(bpy, s, points):
    """The lit cube, and a small cube instanced on each of `points` (a carrier mesh's vertices)."""
    _lit_cube_scene(bpy, s)
    carrier = s.link(mesh_object(bpy, "Carrier", points))
    carrier.instance_type = "VERTS"
    stone = s.link(s.cube_object("NaNInstanced"))
    stone.scale, stone.parent = (0.3, 0.3, 0.3), carrier


def case_nan_instance(bpy, s):
    """Copies of one mesh whose second copy's transform is NaN: the export reads a copy after
    the first as its matrix alone and checks a block of them at once (MeshCollector)."""
    _vertex_instances(bpy, s, [(1.6, -1.0, 0.8), (NAN, 0.0, 0.0), (-1.6, -1.0, 0.8)])


def case_nan_instance_removed(bpy, s):
    _vertex_instances(bpy, s, [(1.6, -1.0, 0.8), (-1.6, -1.0, 0.8)])


def case_zero_scale_lights(bpy, s):
    """Lights switched off as artists do, by scaling them to zero, and an area light of size 0."""
    _lit_cube_scene(bpy, s)
    for kind, energy in (("SUN", 3.0), ("SPOT", 1000.0), ("AREA", 1000.0)):
        s.add_light(f"Zero{kind.title()}", kind, (3, -6, 5), (0.7, 0.0, 0.4), energy=energy).scale = (0.0, 0.0, 0.0)
    s.add_light("SizeZero", "AREA", (3, -6, 5), (0.7, 0.0, 0.4), energy=1000.0, size=0.0)


def case_ignored_settings(bpy, s):
    """Settings Cycles honours and the Whitted core does not model: each is named in a warning
    (and some it does model, not named: Holdout on an object and on a collection, Visibility > Camera off)."""
    _lit_cube_scene(bpy, s)
    hidden = s.link(s.cube_object("CameraInvisible"))
    hidden.location, hidden.visible_camera = (-3.0, 0.0, 0.0), False
    s.link(s.cube_object("Holdout")).is_holdout = True
    layer = bpy.data.collections.new("Mask")
    bpy.context.scene.collection.children.link(layer)
    s.link(s.cube_object("InMask"), layer).location = (3.0, 0.0, 0.0)
    bpy.context.view_layer.layer_collection.children["Mask"].holdout = True
    s.add_light("Narrow", "AREA", (0, -4, 4), (0.8, 0.0, 0.0), energy=100.0, spread=0.5)
    s.add_light("Negative", "POINT", (0, -4, 4), energy=-50.0)
    s.add_light("Stretched", "SPOT", (0, -4, 4), (0.8, 0.0, 0.0), energy=100.0).scale = (1.0, 3.0, 1.0)
    s.add_light("NoShadow", "POINT", (0, -4, 4), energy=10.0).data.use_shadow = False
    bpy.context.scene.render.use_motion_blur = True
    key = bpy.data.objects["Key"]
    if hasattr(key, "light_linking"):                              # Blender 4.0+
        key.light_linking.receiver_collection = bpy.data.collections.new("OnlyTheCube")
    dof = bpy.context.scene.camera.data.dof
    dof.use_dof, dof.focus_distance, dof.aperture_fstop, dof.aperture_blades = True, 10.0, 64.0, 6
    furry = s.link(s.cube_object("Furry"))                          # particle hair: rendered as cones
    furry.location = (0.0, 3.0, 0.0)
    hair = furry.modifiers.new("Hair", "PARTICLE_SYSTEM").particle_system.settings
    hair.type, hair.count = "HAIR", 20
    view_layer = bpy.context.view_layer
    view_layer.use_pass_mist = True   # a pass GRIDWALK does not write
    view_layer.use_pass_object_index = True   # one it writes (not in the warning)
    view_layer.aovs.add().name = "mask"                                   # a Shader AOV: a pass of its own
    if hasattr(view_layer, "lightgroups"):                                # (light groups: Blender 3.2+)
        view_layer.lightgroups.add(name="key_group")


def case_nan_only(bpy, s):
    s.reset()
    cube = s.link(s.cube_object("NaNCube"))
    cube.location = (0.0, NAN, 0.0)
    # (a shader the export would warn about: a skipped object's materials are not read)
    cube.data.materials.append(s.shader_material("SkippedTranslucent", "ShaderNodeBsdfTranslucent"))
    s.add_light("Key", "POINT", (0, -5, 5), energy=100.0)


def _faceless(bpy, s):
    s.link(mesh_object(bpy, "Points", [(0, 0, 0), (1, 0, 0), (0, 0, 1)]))
    s.link(mesh_object(bpy, "Edges", [(0, 0, 0), (1, 0, 0), (0, 0, 1)], edges=[(0, 1), (1, 2)]))


def case_no_faces(bpy, s):
    _lit_cube_scene(bpy, s)
    _faceless(bpy, s)
    # A cube whose Mask modifier keeps an empty vertex group: its modifiers leave
    # nothing, which is what they are for (Cycles renders nothing either).
    masked = s.link(s.cube_object("Masked"))
    masked.vertex_groups.new(name="Nothing")
    mask = masked.modifiers.new("Mask", "MASK")
    mask.vertex_group = "Nothing"


def case_no_faces_only(bpy, s):
    s.reset()
    s.add_light("Key", "POINT", (0, -5, 5), energy=100.0)
    _faceless(bpy, s)


def case_degenerate(bpy, s):
    _lit_cube_scene(bpy, s)
    verts = [(0, 0, 0), (1, 0, 0), (2, 0, 0), (0, 0, 1), (0, 0, 1)]
    faces = [(0, 1, 2), (0, 3, 4), (1, 3, 4)]      # collinear, and two with coincident corners
    s.link(mesh_object(bpy, "ZeroArea", verts, faces=faces)).location = (-2.5, 0.0, 0.0)
    flat = s.cube_object("Squashed")
    flat.scale = (1.0, 0.0, 1.0)                   # zero depth: four faces of zero area, two facing us
    s.link(flat).location = (2.5, 0.0, 0.0)


def _dense_monkey(bpy, s, levels=3):
    _lit_cube_scene(bpy, s)
    bpy.ops.mesh.primitive_monkey_add(location=(0.0, 0.0, 0.0))
    modifier = bpy.context.object.modifiers.new("Subdivision", "SUBSURF")
    modifier.levels = modifier.render_levels = levels


def case_too_large_property(bpy, s):
    _dense_monkey(bpy, s)
    bpy.context.scene.gridwalk.memory_limit = 4                  # MiB


def case_too_large_env(bpy, s):
    _dense_monkey(bpy, s)
    return {"env": {"GRIDWALK_MEMORY_LIMIT_MB": "2.5"}}


def case_fits_default_limit(bpy, s):
    _dense_monkey(bpy, s)


def _large_frame(bpy, s, border):
    _lit_cube_scene(bpy, s, resolution=(3000, 3000))
    render = bpy.context.scene.render
    render.use_border, render.use_crop_to_border = border, True
    render.border_min_x, render.border_max_x = 0.45, 0.5        # 150 x 150 pixels about the cube
    render.border_min_y, render.border_max_y = 0.45, 0.5
    bpy.context.scene.gridwalk.memory_limit = 24                 # MiB: the region fits, the frame does not


def case_large_frame(bpy, s):
    _large_frame(bpy, s, border=False)


def case_large_frame_border(bpy, s):
    _large_frame(bpy, s, border=True)


def case_direct_no_camera(bpy, s):
    """The engine's render() called directly (no Blender check first) on a scene without camera."""
    s.no_camera_scene()
    return {"direct": True}


CASES = {name[5:]: fn for name, fn in globals().items() if name.startswith("case_")}


class DirectEngine:
    """Stands in for Blender when the engine's methods are called directly: records reports."""

    def __init__(self):
        self.reports, self.errors, self.writer = [], [], None

    def report(self, kind, message):
        self.reports.append([sorted(kind)[0], message])

    def error_set(self, message):
        self.errors.append(message)

    def update_stats(self, *args):
        pass

    def update_progress(self, *args):
        pass

    def test_break(self):
        return False


def render_case(bpy, name, opts, out_dir):
    scene = bpy.context.scene
    import render_scene
    render_scene.configure(scene, "GRIDWALK", {"transparent": True})
    scene.render.filepath = os.path.join(out_dir, name + ("_" if opts.get("animation") else ".exr"))
    info = {"error": None}
    if opts.get("direct"):
        from blender_addon.engine import GridwalkRenderEngine
        engine = DirectEngine()
        for attr, value in vars(GridwalkRenderEngine).items():
            if callable(value) and not attr.startswith("__"):
                setattr(DirectEngine, attr, value)
        _, info["log"] = captured(lambda: engine.render(bpy.context.evaluated_depsgraph_get()))
        info.update(reports=engine.reports, errors=engine.errors)
        return info
    saved_env = {k: os.environ.get(k) for k in opts.get("env", {})}
    os.environ.update(opts.get("env", {}))

    def render():
        try:
            if opts.get("animation"):
                bpy.ops.render.render(animation=True)
            else:
                bpy.ops.render.render(write_still=True)
        except RuntimeError as exc:
            info["error"] = str(exc)
    try:
        _, info["log"] = captured(render)
    finally:
        for key, value in saved_env.items():
            os.environ.pop(key) if value is None else os.environ.__setitem__(key, value)
        bpy.app.handlers.frame_change_pre.clear()
    return info


def main(out_dir):
    import bpy

    import blender_addon
    import scenes
    blender_addon.register()
    results = {"blender": list(bpy.app.version)}
    for name, build in CASES.items():
        t0 = time.perf_counter()
        opts = build(bpy, scenes) or {}
        results[name] = render_case(bpy, name, opts, out_dir)
        results[name]["seconds"] = time.perf_counter() - t0
    with open(os.path.join(out_dir, "bad_input.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main, spread=True)
