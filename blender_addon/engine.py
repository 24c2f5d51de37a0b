"""The GRIDWALK RenderEngine: export the depsgraph, render with the core, stream tiles.

render() never touches bpy.context: the scene, view layer and objects all come
from the depsgraph Blender passes in. Every failure (no camera, empty scene,
invalid geometry, a core error) becomes a message in Blender's report and
error_set; nothing propagates into Blender.
"""
import time

import bpy

from . import dependencies, streaming
from .settings import render_settings


class GridwalkRenderEngine(bpy.types.RenderEngine):
    bl_idname = "GRIDWALK"
    bl_label = "Gridwalk"
    bl_use_preview = False
    bl_use_shading_nodes_custom = False     # edit materials with Blender's standard nodes
    bl_use_eevee_viewport = True            # Material Preview in the viewport uses EEVEE

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)   # required since Blender 4.4

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if renderlayer.use_pass_z:
            self.register_pass(scene, renderlayer, "Depth", 1, "Z", "VALUE")
        if renderlayer.use_pass_normal:
            self.register_pass(scene, renderlayer, "Normal", 3, "XYZ", "VECTOR")

    def render(self, depsgraph):
        try:
            self._render(depsgraph)
        except Exception as exc:   # report, never raise into Blender
            message = f"Gridwalk: {exc}"
            print(message)
            self.report({"ERROR"}, message)
            if hasattr(self, "error_set"):
                self.error_set(message)

    def _render(self, depsgraph):
        gridwalk = dependencies.import_gridwalk()
        from .export import export_scene

        scene = depsgraph.scene
        self.update_stats("", "Gridwalk: exporting scene")
        t0 = time.perf_counter()
        kwargs, warnings = export_scene(depsgraph)
        for warning in warnings:
            print("Gridwalk warning:", warning)
            self.report({"WARNING"}, warning)
        t1 = time.perf_counter()
        self.update_stats("", "Gridwalk: building the grid")
        gw_scene = gridwalk.Scene(**kwargs)
        job = gridwalk.RenderJob(gw_scene, render_settings(gridwalk, scene.gridwalk))
        writer = streaming.ResultWriter(self, kwargs["camera"].height, depsgraph.view_layer.name,
                                        opaque=not scene.render.film_transparent)
        completed = streaming.run(self, job, writer)
        print(f"Gridwalk: {'finished' if completed else 'cancelled'}; export {t1 - t0:.3f} s, "
              f"render {job.stats['seconds']:.3f} s, {streaming.stats_text(job)}")


def register():
    bpy.utils.register_class(GridwalkRenderEngine)


def unregister():
    bpy.utils.unregister_class(GridwalkRenderEngine)
