"""Blender-side half of the benchmarks: run inside a Python that has `bpy`.

    <python with bpy> bench_bpy.py suzanne OUT_DIR LEVEL...
        Suzanne with each Subdivision level, exported as binary PLY files.
    <python with bpy> bench_bpy.py cycles CONFIG.json
        SPD balls (from the NFF file in the config) built as a Blender scene,
        rendered with GRIDWALK and with Cycles for each job of the config;
        writes OUT_DIR/result.json (times) and OUT_DIR/<job name>.npy (linear RGBA).

Scripts end with os._exit: bpy can hang at interpreter exit after image I/O.
"""
from __future__ import annotations

import json
import math
import os
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def export_suzanne(out_dir, levels):
    """Suzanne with each Subdivision level, triangulated, to OUT_DIR/suzanne_L<level>.ply (binary)."""
    import bpy
    for level in levels:
        bpy.ops.wm.read_homefile(use_empty=True)
        bpy.ops.mesh.primitive_monkey_add()
        monkey = bpy.context.object
        mod = monkey.modifiers.new("Subdivision", "SUBSURF")
        mod.levels = mod.render_levels = level
        bpy.ops.wm.ply_export(filepath=os.path.join(out_dir, f"suzanne_L{level}.ply"), apply_modifiers=True,
                              export_selected_objects=False, export_normals=False, export_uv=False,
                              export_colors="NONE", export_triangulated_mesh=True, ascii_format=False)
    print(json.dumps({"blender": bpy.app.version_string}))


# -- the Cycles comparison scene -----------------------------------------------

def build_balls(scene_npz, width, height, fstop):
    """SPD balls from the arrays the driver wrote (gridwalk.io.load_nff's, see bench_cycles.py):
    floor mesh, one UV-sphere mesh shared by every ball object (flagged 'render as sphere' so
    GRIDWALK exports analytic spheres; Cycles renders the mesh), one area light, a camera with
    depth of field. (The NFF is read outside Blender: the bpy venvs lack plyfile, which
    gridwalk.io imports.)"""
    import bpy

    from blender_addon.scripting import principled_material
    import numpy as np
    from mathutils import Vector

    import blender_addon

    kw = dict(np.load(scene_npz))
    bpy.ops.wm.read_homefile(use_empty=True)
    blender_addon.register()
    scene = bpy.context.scene
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    floor_mat = principled_material("Floor", tuple(map(float, kw["floor_color"])), Roughness=1.0, Metallic=0.0)
    # NFF ball: kd 0.5, mirror 0.5 -> Principled metallic 0.5, roughness 0 (kd = 1 - m, mirror = m)
    ball_mat = principled_material("Ball", tuple(map(float, kw["ball_color"])), Roughness=0.0,
                           Metallic=float(kw["ball_mirror"]))

    floor = bpy.data.meshes.new("Floor")
    floor.from_pydata([tuple(map(float, v)) for v in kw["vertices"]], [],
                      [tuple(map(int, t)) for t in kw["triangles"]])
    floor.materials.append(floor_mat)
    scene.collection.objects.link(bpy.data.objects.new("Floor", floor))

    bpy.ops.mesh.primitive_uv_sphere_add(segments=32, ring_count=16, radius=1.0)
    proto = bpy.context.object
    for poly in proto.data.polygons:
        poly.use_smooth = True
    proto.data.materials.append(ball_mat)
    sphere_mesh = proto.data
    bpy.data.objects.remove(proto)
    for i, (c, r) in enumerate(zip(kw["sphere_centers"], kw["sphere_radii"])):
        obj = bpy.data.objects.new(f"Ball{i}", sphere_mesh)
        obj.location, obj.scale = tuple(map(float, c)), (float(r),) * 3
        obj.gridwalk.render_as_sphere = True
        scene.collection.objects.link(obj)

    light = bpy.data.lights.new("Area", "AREA")
    light.shape, light.size, light.energy = "SQUARE", 1.5, 400.0
    lobj = bpy.data.objects.new("Area", light)
    scene.collection.objects.link(lobj)
    lobj.location = (1.0, -4.0, 4.0)
    lobj.rotation_euler = (-Vector(lobj.location)).to_track_quat("-Z", "Y").to_euler()

    cam = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
    scene.collection.objects.link(cam)
    eye, target = Vector(kw["eye"].tolist()), Vector(kw["target"].tolist())
    cam.location = eye
    cam.rotation_euler = (target - eye).to_track_quat("-Z", "Y").to_euler()
    cam.data.sensor_fit = "VERTICAL"
    cam.data.angle_y = math.radians(float(kw["fov"]))
    cam.data.dof.use_dof = True
    cam.data.dof.focus_distance = float(kw["focus_distance"])
    cam.data.dof.aperture_fstop = fstop
    scene.camera = cam

    world = bpy.data.worlds.new("World")
    background = tuple(map(float, kw["background"]))
    world.color = background
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (*background, 1.0)
    # Whitted: the sky is seen by camera, mirror and refraction rays, but does not light diffuse
    # surfaces; so Cycles' diffuse rays (and light sampling at diffuse hits) do not see it either.
    scene.world = world
    world.cycles_visibility.diffuse = False
    scene.render.film_transparent = False
    return scene, len(kw["sphere_radii"])


def configure(scene, engine, spp, seed, threads, max_depth):
    scene.render.engine = engine
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    if engine == "CYCLES":
        c = scene.cycles
        c.device, c.samples, c.seed = "CPU", spp, seed
        c.use_adaptive_sampling = c.use_denoising = False
        c.max_bounces = max_depth - 1          # bounces after the primary ray
        c.diffuse_bounces = 0                  # Whitted: direct light only at diffuse surfaces
        c.glossy_bounces = c.transmission_bounces = max_depth - 1
        c.volume_bounces = c.transparent_max_bounces = 0
        c.caustics_reflective = c.caustics_refractive = True
        c.blur_glossy = 0.0
        c.pixel_filter_type, c.filter_width = "BOX", 1.0
        return
    n = int(round(math.sqrt(spp)))
    assert n * n == spp, "GRIDWALK takes n x n samples per pixel"
    g = scene.gridwalk
    g.aa, g.aa_samples, g.seed, g.threads, g.max_depth = "JITTERED", n, seed, threads, max_depth
    # one shadow ray per light and hit, and one lens point, per pixel sample: the
    # light's n x n strata and the lens points each cover the pixel's samples
    g.shadow, g.shadow_samples, g.dof_samples, g.glossy_samples = "AREA", n, 1, 1
    g.filter = "BOX"


def render(scene, path):
    """Render and time it (not the file write): ((H, W, 4) float32 linear, row 0 at the top,
    wall seconds, CPU seconds of the whole process, all its threads)."""
    import bpy
    import numpy as np
    t0, c0 = time.perf_counter(), time.process_time()
    bpy.ops.render.render()
    seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):
        settings.media_type = "IMAGE"
    settings.file_format, settings.exr_codec, settings.color_depth = "OPEN_EXR", "NONE", "32"
    bpy.data.images["Render Result"].save_render(path)
    img = bpy.data.images.load(path)
    w, h = img.size
    px = np.empty(w * h * 4, np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    os.remove(path)
    return px.reshape(h, w, 4)[::-1].copy(), seconds, cpu


def blender_floor(scene, threads, reps=5):
    """Wall seconds (best of reps) of bpy.ops.render.render() with a render engine that only
    opens and closes its result: what Blender itself spends on a render call of this scene
    (its render depsgraph, the result), which every engine pays before its own work."""
    import bpy

    class FloorEngine(bpy.types.RenderEngine):
        bl_idname, bl_label = "GRIDWALK_BENCH_FLOOR", "Floor"

        def render(self, depsgraph):
            r = depsgraph.scene.render
            scale = r.resolution_percentage / 100.0
            self.end_result(self.begin_result(0, 0, int(r.resolution_x * scale), int(r.resolution_y * scale)))

    bpy.utils.register_class(FloorEngine)
    engine, scene.render.engine = scene.render.engine, FloorEngine.bl_idname
    scene.render.threads_mode, scene.render.threads = "FIXED", threads
    times = []
    for _ in range(reps + 1):                  # (the first call, untimed: first-render set-up)
        t0 = time.perf_counter()
        bpy.ops.render.render()
        times.append(time.perf_counter() - t0)
    scene.render.engine = engine
    bpy.utils.unregister_class(FloorEngine)
    return min(times[1:])


def cycles_vs_gridwalk(config_path):
    """Render every job of the config ({engine, spp, seed, reps, name}) and record its best time."""
    import bpy
    import numpy as np
    with open(config_path) as f:
        cfg = json.load(f)
    out = cfg["out_dir"]
    scene, spheres = build_balls(cfg["scene"], cfg["width"], cfg["height"], cfg["fstop"])
    result = {"blender": bpy.app.version_string, "spheres": spheres, "runs": [],
              "floor_seconds": blender_floor(scene, cfg["threads"])}
    warm = set()
    for job in cfg["jobs"]:
        engine = job["engine"]
        if engine not in warm:                  # first-render set-up (kernels, caches), not timed
            configure(scene, engine, 1, 0, cfg["threads"], cfg["max_depth"])
            render(scene, os.path.join(out, "warmup.exr"))
            warm.add(engine)
        configure(scene, engine, job["spp"], job["seed"], cfg["threads"], cfg["max_depth"])
        times, cpus = [], []
        for _ in range(job["reps"]):
            image, seconds, cpu = render(scene, os.path.join(out, "tmp.exr"))
            times.append(seconds)
            cpus.append(cpu)
        np.save(os.path.join(out, job["name"] + ".npy"), image)
        result["runs"].append({**job, "seconds": min(times), "cpu_seconds": min(cpus), "all_seconds": times})
        print(engine, job["spp"], f"{min(times):.2f}s", flush=True)
    with open(os.path.join(out, "result.json"), "w") as f:
        json.dump(result, f, indent=1)


def main(argv):
    sys.path[:0] = [ROOT]
    command, arg = argv[0], argv[1]
    if command == "suzanne":
        export_suzanne(arg, [int(a) for a in argv[2:]])
    elif command == "cycles":
        cycles_vs_gridwalk(arg)
    else:
        raise SystemExit(f"unknown command {command!r}")


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
