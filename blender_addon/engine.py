"""The GRIDWALK RenderEngine: export the depsgraph, render with the core, stream tiles.

render() never touches bpy.context: the scene, view layer and objects all come
from the depsgraph Blender passes in. Every failure (no camera, empty scene,
invalid geometry, a scene too large for memory, a core error) becomes a
message in Blender's report and error_set; nothing propagates into Blender.

Before anything large is built, the triangles are counted from the evaluated
meshes and gridwalk.memory estimates the render's memory; past the limit
(memory_limit() below) the render is refused with the estimate and the limit.
Blender's render border becomes RenderSettings.region. A cancel (test_break)
is honoured between the stages and, through streaming.run, while rendering.
"""
import os
import sys
import threading
import time

import bpy

from . import cryptomatte, dependencies, passes, streaming
from .settings import render_settings

MEMORY_LIMIT_ENV = "GRIDWALK_MEMORY_LIMIT_MB"
AROUND = [(x, y, z) for x in (-1, 0, 1) for y in (-1, 0, 1) for z in (-1, 0, 1) if (x, y, z) != (0, 0, 0)]


def camera_enclosed(gw_scene, camera, settings) -> bool:
    """Whether the camera sits inside a closed object: rays from the eye in 26
    directions (to the faces, edges and corners of a cube) all meet the back
    of a surface. Traced through the render's own acceleration structure."""
    import numpy as np

    directions = np.array(AROUND, dtype=np.float32)
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    origins = np.tile(np.asarray(camera.eye, dtype=np.float32), (len(directions), 1))
    hits = gw_scene.intersect(origins, directions, tmin=float(camera.hither), settings=settings.replace(threads=1))
    facing = np.sum(hits.normal * directions, axis=1)
    return bool(np.all(np.isfinite(hits.t)) and np.all(facing > 0))


def unsupported_render_settings(scene) -> list[str]:
    """Warnings for render and camera settings that the final render does not model."""
    out = []
    if scene.render.use_motion_blur:
        out.append("Motion blur is not supported: each object renders where it is at the current frame")
    linked = sorted(obj.name for obj in scene.objects if getattr(obj, "light_linking", None) is not None
                    and (obj.light_linking.receiver_collection or obj.light_linking.blocker_collection))
    if linked:                             # (Blender 4.0+)
        out.append("Light and shadow linking are not supported (every light reaches every object, every "
                   "object casts shadows): " + ", ".join(repr(n) for n in linked))
    return out


def memory_limit(props, memory) -> tuple[int | None, str]:
    """(limit in bytes or None, where it comes from).

    The scene's Memory Limit (MiB, 0 = automatic) and the environment variable
    GRIDWALK_MEMORY_LIMIT_MB each set a limit; when both are set the lower
    wins. Otherwise the limit is memory.DEFAULT_FRACTION of physical memory.
    """
    limits = []
    if getattr(props, "memory_limit", 0) > 0:
        limits.append((int(props.memory_limit) << 20, "Render Properties > Performance > Memory Limit"))
    env = os.environ.get(MEMORY_LIMIT_ENV, "").strip()
    if env:
        try:
            value = float(env)
        except ValueError:
            raise ValueError(f"{MEMORY_LIMIT_ENV}={env!r} is not a number of MiB") from None
        if value > 0:
            limits.append((int(value * (1 << 20)), f"set by {MEMORY_LIMIT_ENV}"))
    if limits:
        return min(limits)
    limit = memory.default_limit()
    return limit, f"{memory.DEFAULT_FRACTION:.0%} of physical memory"


class GridwalkRenderEngine(bpy.types.RenderEngine):
    bl_idname = "GRIDWALK"
    bl_label = "Gridwalk"
    bl_use_preview = True                   # material and world previews (see docs/blender.md)
    bl_use_shading_nodes_custom = False     # edit materials with Blender's standard nodes
    bl_use_eevee_viewport = True            # Material Preview in the viewport uses EEVEE

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)   # required since Blender 4.4
        self.writer = None                  # the current render's ResultWriter
        self.viewport = None                # viewport.ViewportSession, for Rendered shading

    def __del__(self):
        # The viewport closed, shading or engine switched, file loaded, Blender quits:
        # Blender frees the engine; the session's threads stop and are joined.
        session = self.__dict__.get("viewport")
        if session is not None:
            session.stop()
        # Should Blender free the engine off the main thread, a GPU texture
        # freed there would crash it (seen in Blender 3.4 when a quad view
        # ended, while a Python worker could hold the engine): the texture
        # waits for the main thread.
        texture = self.__dict__.pop("viewport_texture", None)
        if texture is not None and threading.current_thread() is not threading.main_thread():
            from .viewport_draw import free_on_main_thread
            free_on_main_thread(texture)

    # -- Rendered viewport shading (viewport.py; never called in `blender -b`) --
    def _viewport(self):
        if self.viewport is None:
            from .viewport import ViewportSession
            self.viewport = ViewportSession(self)
        return self.viewport

    def view_update(self, context, depsgraph):
        t0 = time.perf_counter()
        try:
            from . import viewport_draw
            viewport_draw.free_kept()          # main thread: textures of engines freed on a worker
            self._viewport().update(depsgraph)
        except Exception as exc:           # shown in the viewport, never raised into Blender
            print(f"Gridwalk viewport: {exc}")
            self._viewport().message = f"Gridwalk: {exc}"
        self._viewport().main_thread.append(("view_update", time.perf_counter() - t0))

    def view_draw(self, context, depsgraph):
        t0 = time.perf_counter()
        try:
            from . import viewport_draw
            viewport_draw.free_kept()
            viewport_draw.draw(self, self._viewport(), context, depsgraph)
        except Exception as exc:
            print(f"Gridwalk viewport: {exc}")
        self._viewport().main_thread.append(("view_draw", time.perf_counter() - t0))

    def update_render_passes(self, scene=None, renderlayer=None):
        for p in passes.enabled(renderlayer, scene):
            self.register_pass(scene, renderlayer, p.name, p.channels, p.chanid, p.kind)
        for name in cryptomatte.pass_names(renderlayer):
            self.register_pass(scene, renderlayer, name, 4, "rgba", "COLOR")   # (lower case, as Cycles' are saved)

    def render(self, depsgraph):
        try:
            self._render(depsgraph)
        except KeyboardInterrupt:   # Ctrl-C in a script using the bpy module: a cancel
            if self.writer is not None:
                self.writer.ensure_written()
            print("Gridwalk: cancelled (KeyboardInterrupt); no worker thread is left")
            self.report({"WARNING"}, "Gridwalk: render interrupted (Ctrl-C)")
        except Exception as exc:   # report, never raise into Blender
            for warning in getattr(exc, "warnings", ()):
                self._warn(warning)
            message = f"Gridwalk: {exc}"
            print(message)
            self.report({"ERROR"}, message)
            if hasattr(self, "error_set"):
                self.error_set(message)
        finally:
            self.writer = None

    def _warn(self, warning: str):
        if self.is_preview:                # a thumbnail: nobody reads its report
            return
        print("Gridwalk warning:", warning)
        self.report({"WARNING"}, f"Gridwalk: {warning}")

    def _cancelled(self, stage: str, writer) -> bool:
        """Honour a cancel between stages; the (empty) result is still written
        (see ResultWriter.ensure_written)."""
        if not streaming.break_requested(self):
            return False
        writer.ensure_written()
        print(f"Gridwalk: cancelled {stage}")
        return True

    def _check_memory(self, gridwalk, depsgraph, settings):
        """Refuse (gridwalk.memory.SceneTooLarge) a scene whose estimate exceeds the limit."""
        from gridwalk import memory

        from .export import count_geometry, resolution
        from .export.textures import corner_arrays_read, corner_point_arrays, scene_texture_bytes, uses_normal_maps
        scene = depsgraph.scene
        counts = count_geometry(depsgraph)
        # (a border render's buffers hold its region only: 1% of a 16000 x 16000 frame was refused)
        width, height = settings.region[2:] if settings.region is not None else resolution(scene.render)
        texture_bytes = scene_texture_bytes(depsgraph)
        corners = corner_arrays_read(depsgraph)
        estimate = memory.estimate(counts["triangles"], counts["vertices"], counts["spheres"], counts["cylinders"],
                                   width=width, height=height, settings=settings, normals=counts["normals"],
                                   texture_bytes=texture_bytes, uvs=corners["uvs"], colors=corners["colors"],
                                   tangents=corners["uvs"] and uses_normal_maps(depsgraph),
                                   corner_points=corner_point_arrays(depsgraph),
                                   matte_layers=len(cryptomatte.key_layers(depsgraph.view_layer)),
                                   copies=counts["copies"], copied_triangles=counts["copied_triangles"])
        limit, source = memory_limit(scene.gridwalk, memory)
        print(f"Gridwalk: memory estimate {memory.format_bytes(estimate.total)} ({estimate.breakdown()}), "
              f"limit {memory.format_bytes(limit) if limit else 'none'} ({source})")
        hair = f"{counts['cylinders']:,} hair segments, " if counts["cylinders"] else ""
        what = (f"This scene ({counts['triangles']:,} triangles, {counts['spheres']:,} spheres, {hair}"
                f"{width} x {height} pixels)")
        memory.check(estimate, limit, what, source)

    def _render(self, depsgraph):
        gridwalk = dependencies.import_gridwalk()
        import numpy as np

        from .export import Export, ExportCancelled, ExportError, render_region, resolution

        scene = depsgraph.scene
        settings = render_settings(gridwalk, scene.gridwalk)
        if settings.threads == 0:
            # Gridwalk's Threads at 0 (all cores): Blender's own count, which `blender -t N` and
            # Performance > Threads > Fixed set (it is every core otherwise).
            settings = settings.replace(threads=max(1, int(scene.render.threads)))
        region = render_region(scene.render)
        if region is not None:
            settings = settings.replace(region=region)
        ranks = cryptomatte.ranks(depsgraph.view_layer)
        if ranks:
            settings = settings.replace(matte_ranks=ranks)
        writer = self.writer = streaming.ResultWriter(self, *resolution(scene.render), depsgraph.view_layer.name,
                                                      opaque=not scene.render.film_transparent, region=region)
        self.update_stats("", "Gridwalk: estimating memory")
        t0 = time.perf_counter()
        self._check_memory(gridwalk, depsgraph, settings)
        if self._cancelled("before the export", writer):
            return
        self.update_stats("", "Gridwalk: exporting scene")
        try:                               # Esc is honoured between objects
            export = Export(depsgraph, should_stop=lambda: streaming.break_requested(self))
        except ExportCancelled:
            writer.ensure_written()
            print(f"Gridwalk: cancelled during the export, after {time.perf_counter() - t0:.3f} s")
            return
        try:
            # A render with nothing visible (a cut in an animation, a farm's frame, an empty scene)
            # shows the world, as Cycles renders it, and says why in a warning.
            kwargs, warnings = export.kwargs(world_only=not self.is_preview,
                                             mattes=cryptomatte.key_layers(depsgraph.view_layer) if ranks else ())
        except ExportError:
            if not self.is_preview:
                raise
            # A world's thumbnail has no geometry: it shows the world, a constant background
            image = np.empty((writer.region[3], writer.region[2], 4), np.float32)
            image[...] = (*export.background, 1.0)
            writer.write(writer.region[0], writer.region[1], {"rgba": image})
            print(f"Gridwalk: preview of the background in {time.perf_counter() - t0:.3f} s")
            return
        for warning in warnings:
            self._warn(warning)
        if ranks:
            writer.mattes = cryptomatte.Mattes(depsgraph.view_layer, export.matte_tables)
        if depsgraph.scene.render.use_multiview:
            self._warn("Stereoscopy is not supported: the first view is rendered, the others are left empty")
        for warning in unsupported_render_settings(depsgraph.scene):
            self._warn(warning)
        unwritten = passes.unwritten_passes(depsgraph.view_layer)
        if unwritten:
            self._warn("Render passes not written (only Combined, Depth, Normal, Object and Material Index, "
                       "the denoising data and Cryptomatte are): " + ", ".join(unwritten))
        t1 = time.perf_counter()
        if self._cancelled("after the export", writer):
            return
        self.update_stats("", "Gridwalk: building the grid")
        camera = kwargs["camera"]
        gw_scene = gridwalk.Scene(**kwargs)
        kwargs = None                      # the core holds its own copies
        try:                               # Esc stops the build too (within milliseconds)
            job = gridwalk.RenderJob(gw_scene, settings, should_stop=lambda: streaming.break_requested(self))
        except gridwalk.BuildCancelled:
            writer.ensure_written()
            print(f"Gridwalk: cancelled while building the grid; export {t1 - t0:.3f} s")
            return
        if camera_enclosed(gw_scene, camera, settings):
            self._warn("The camera is inside a closed object (every direction from it meets the back "
                       "of a surface): the image shows that object's inside")
        if self._cancelled("after building the grid", writer):
            return
        completed = streaming.run(self, job, writer)
        what = ("finished" if completed else "cancelled") + (" preview" if self.is_preview else "")
        print(f"Gridwalk: {what}; export {t1 - t0:.3f} s, build {job.build_seconds:.3f} s, "
              f"render {job.stats['seconds']:.3f} s, total {time.perf_counter() - t0:.3f} s on "
              f"{settings.threads} thread{'s' if settings.threads != 1 else ''}, {streaming.stats_text(job)}")


@bpy.app.handlers.persistent
def stop_viewports(*_):
    """Before a file loads (and on unregister): stop every viewport render."""
    viewport = sys.modules.get(f"{__package__}.viewport")     # never imported in `blender -b`
    if viewport is not None:
        viewport.stop_all()


def register():
    bpy.utils.register_class(GridwalkRenderEngine)
    bpy.app.handlers.load_pre.append(stop_viewports)


def unregister():
    if stop_viewports in bpy.app.handlers.load_pre:
        bpy.app.handlers.load_pre.remove(stop_viewports)
    stop_viewports()
    bpy.utils.unregister_class(GridwalkRenderEngine)
