"""The viewport's session without a GUI: depsgraph updates drive it as
view_update does (a depsgraph_update_post handler passes the same
depsgraph.updates), a camera built from the scene camera's matrices stands
for the region's view.

usage: <python with bpy> viewport_session.py OUT_DIR
For each edit, OUT_DIR/viewport_session.json records: whether the render
restarted, how many meshes were read and instances transformed, whether the
incremental arrays equal a fresh export's, and whether the session's image
equals a RenderJob render of a fresh export (one pass, so both are the same
pure function of the seed). Then the session is stopped and its threads
counted.
"""
import json
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import native_threads  # noqa: E402


class Engine:
    """Stands for the RenderEngine: the session only calls tag_redraw."""
    redraws = 0

    def tag_redraw(self):
        Engine.redraws += 1


def build(bpy, scenes):
    scenes.reset(resolution=(80, 60))
    a = scenes.link(scenes.cube_object("Plain", 1.5))
    a.location = (-2.0, 0.0, 0.0)
    twin = scenes.link(bpy.data.objects.new("Twin", a.data))            # a linked duplicate
    twin.location = (0.0, 2.0, 1.0)
    smooth = scenes.link(scenes.uv_sphere_object("Smooth", 1.0, 16, 8))
    smooth.location = (2.0, 0.0, 0.0)
    mod = smooth.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = 1
    red = scenes.principled_material("Red", (0.8, 0.1, 0.1))
    # a glow of each object's Viewport Display colour (Object Info: one value per instance)
    nodes = red.node_tree.nodes
    red.node_tree.links.new(nodes.new("ShaderNodeObjectInfo").outputs["Color"],
                            nodes["Principled BSDF"].inputs["Emission Color" if bpy.app.version >= (4, 0, 0)
                                                            else "Emission"])
    nodes["Principled BSDF"].inputs["Emission Strength"].default_value = 0.2
    a.data.materials.append(red)
    # half the shared mesh's faces: a Checker at Generated coordinates into a Principled BSDF's
    # Base Color, which the instances' moves in the core carry along
    checkered = scenes.principled_material("Checkered", (0.8, 0.8, 0.8))
    nodes = checkered.node_tree.nodes
    checkered.node_tree.links.new(nodes.new("ShaderNodeTexChecker").outputs["Color"],
                                  nodes["Principled BSDF"].inputs["Base Color"])
    a.data.materials.append(checkered)
    for poly in a.data.polygons[:3]:
        poly.material_index = 1
    # Smooth: a Checker at the Object coordinates of an empty (the world point in its space),
    # which moves with the empty, not with Smooth
    frame = scenes.link(bpy.data.objects.new("Frame", None))
    frame.location, frame.scale = (1.0, 0.3, -0.2), (0.5, 0.5, 0.5)
    framed = scenes.principled_material("Framed", (0.8, 0.8, 0.8))
    nodes, coords = framed.node_tree.nodes, framed.node_tree.nodes.new("ShaderNodeTexCoord")
    coords.object = frame
    checker = nodes.new("ShaderNodeTexChecker")
    framed.node_tree.links.new(coords.outputs["Object"], checker.inputs["Vector"])
    framed.node_tree.links.new(checker.outputs["Color"], nodes["Principled BSDF"].inputs["Base Color"])
    smooth.data.materials.append(framed)
    scenes.add_light("Key", "POINT", (0, -6, 6), energy=800.0)
    bpy.context.scene.world = bpy.data.worlds.new("World")
    bpy.context.scene.gridwalk.viewport_samples = 1
    bpy.context.scene.gridwalk.viewport_start_pixels = 1
    bpy.context.view_layer.update()


def main(out_dir):
    import bpy
    import gridwalk
    import numpy as np

    import blender_addon
    import scenes
    from blender_addon.export import export_scene
    from blender_addon.export._matrix import to_numpy
    from blender_addon.export.viewport_camera import view_camera
    from blender_addon.viewport import ViewportSession, tick

    blender_addon.register()
    build(bpy, scenes)
    scene = bpy.context.scene
    engine = Engine()
    session = ViewportSession(engine)
    results = {"threads_before": native_threads.count(native_threads.RENDER)}
    state = {}

    def handler(scene_, depsgraph):
        session.cache.reset_stats()
        before = session._versions()
        session.update(depsgraph)
        state["restarted"] = session._versions() != before      # the scene or the settings changed
        state["reads"], state["transforms"] = session.cache.reads, session.cache.transforms
        state["moved_in_core"] = session.moved
    bpy.app.handlers.depsgraph_update_post.append(handler)

    depsgraph = bpy.context.evaluated_depsgraph_get()
    session.update(depsgraph)
    results["initial_reads"] = session.cache.reads
    cam = scene.camera.evaluated_get(depsgraph)
    projection = cam.calc_matrix_camera(depsgraph, x=80, y=60)
    camera = view_camera(np.linalg.inv(to_numpy(cam.matrix_world)), projection, 80, 60,
                         clip=(cam.data.clip_start, cam.data.clip_end))
    session.set_view((80, 60, "view"), camera, 1)

    def wait_done():
        # this process runs no event loop: call the main-thread timer Blender would call
        deadline = time.monotonic() + 60
        while tick() is not None and not session.idle():
            if time.monotonic() > deadline:
                raise RuntimeError(f"the viewport render did not finish: {session.message}")
            time.sleep(0.02)

    def check(name):
        wait_done()
        fresh, _ = export_scene(bpy.context.evaluated_depsgraph_get(), camera=False)
        ours = session.gw_scene.geometry()               # the arrays the core holds (moved there, or copied in)
        same = all(np.array_equal(ours[k], fresh[k]) for k in ("vertices", "triangles", "triangle_materials"))
        same = same and (ours["normals"] is None) == (fresh["normals"] is None)
        same = same and (ours["normals"] is None or np.array_equal(ours["normals"], fresh["normals"]))
        settings = session.settings.replace(aa="random", aa_samples=1, threads=1)
        image = gridwalk.RenderJob(gridwalk.Scene(**fresh), settings, camera=camera).start().wait()
        image[..., 3] = 1.0                                  # film not transparent
        with session.lock:
            shown = session.display.rgba[::-1].copy()
        results[name] = dict(state, arrays_equal_fresh_export=bool(same),
                             image_equals_fresh_render=bool(np.array_equal(shown, image)),
                             coverage=float((shown[..., :3].sum(axis=2) > 0).mean()))
        print("viewport_session:", name, results[name], flush=True)
        state.clear()

    check("initial")
    bpy.data.objects["Plain"].location.x += 0.5
    bpy.context.view_layer.update()
    check("move_object")
    bpy.data.objects["Twin"].rotation_euler.z += 0.3
    bpy.context.view_layer.update()
    check("rotate_linked_duplicate")
    mesh = bpy.data.objects["Plain"].data
    mesh.vertices[0].co.z -= 0.4
    mesh.update()
    bpy.context.view_layer.update()
    check("edit_shared_mesh")
    bpy.data.objects["Smooth"].modifiers["Subdivision"].levels = 2
    bpy.context.view_layer.update()
    check("change_modifier")
    bpy.data.materials["Red"].node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.1, 0.1, 0.9, 1)
    bpy.context.view_layer.update()
    check("change_material")
    bpy.data.objects["Twin"].color = (0.2, 0.9, 0.3, 1.0)     # (what its Object Info gives it)
    bpy.context.view_layer.update()
    check("change_object_colour")
    # (after a full export: a move in the core, the edits before, leaves its chunk to transform again)
    bpy.data.objects["Frame"].location.x += 0.3
    bpy.context.view_layer.update()
    check("move_texture_empty")
    bpy.data.lights["Key"].energy = 300.0
    bpy.context.view_layer.update()
    check("change_light")
    tree = scene.world.node_tree if getattr(scene.world, "use_nodes", True) else None    # 5.0: always nodes
    if tree is not None:
        tree.nodes["Background"].inputs["Color"].default_value = (0.3, 0.1, 0.05, 1.0)
    else:
        scene.world.color = (0.3, 0.1, 0.05)
    bpy.context.view_layer.update()
    check("change_world")
    if tree is None:                                     # (a world without nodes: give it its nodes)
        scene.world.use_nodes = True
        tree = scene.world.node_tree
    sky = tree.nodes.new("ShaderNodeTexSky")
    tree.links.new(sky.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    tree.nodes["Background"].inputs["Strength"].default_value = 0.05
    bpy.context.view_layer.update()
    check("sky_world")
    sky.sun_elevation = 0.6
    bpy.context.view_layer.update()
    check("change_sky")
    scene.gridwalk.max_depth = 1
    bpy.context.view_layer.update()
    check("change_render_setting")
    scene.view_settings.exposure = 1.5
    bpy.context.view_layer.update()
    results["colour_management"] = dict(state)
    bpy.data.objects.remove(bpy.data.objects["Twin"])
    bpy.context.view_layer.update()
    check("delete_object")

    # a large mesh, a coarse pass: its first pixels come from the quick structure, before the
    # render settings' structure is built
    bpy.ops.mesh.primitive_monkey_add(size=1.0, location=(0.0, -3.0, 0.0))   # Suzanne, 250k triangles
    big = bpy.context.object
    big.modifiers.new("Subdivision", "SUBSURF").levels = 4
    scene.gridwalk.viewport_start_pixels = 4
    bpy.context.view_layer.update()
    wait_done()
    big.location.x += 0.2
    bpy.context.view_layer.update()
    wait_done()
    results["large_edit"] = {k: session.timings.get(k) for k in ("edit_to_pixels", "edit_to_full_grid", "grid",
                                                                  "full_grid")}
    results["large_edit"]["triangles"] = session.gw_scene.num_triangles
    results["large_edit"]["moved_in_core"] = session.moved
    print("viewport_session: large_edit", results["large_edit"], flush=True)

    # a resize (only the region's size changes) waits until it settles
    import dataclasses
    wait_done()
    shown_before = session.display.version
    t_resize = time.monotonic()
    session.set_view((100, 60, "view"), dataclasses.replace(camera, width=100, pixel_aspect=0.8), 1)
    time.sleep(0.15)
    session.poll()
    results["resize_waits"] = session.display.version == shown_before and session.job is None
    wait_done()
    results["resize_rendered_after"] = time.monotonic() - t_resize
    results["resized_shape"] = list(session.display.rgba.shape)
    results["threads_rendering_session"] = native_threads.count(native_threads.VIEWPORT)
    session.stop()
    results["threads_after_stop"] = {"render": native_threads.count(native_threads.RENDER),
                                     "viewport": native_threads.count(native_threads.VIEWPORT)}
    results["redraws"] = Engine.redraws
    with open(os.path.join(out_dir, "viewport_session.json"), "w") as f:
        json.dump(results, f, indent=1)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main, spread=True)
