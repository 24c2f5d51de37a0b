"""Interactive rendering in the 3D viewport (Rendered shading).

One ViewportSession per engine instance (a quad view has four). On the main
thread, view_update exports the depsgraph into a MeshCache kept between
updates (only changed meshes are read, only moved instances transformed)
and compares the export's signature with the last one: geometry,
transforms, materials, lights, world or render settings restart the render;
anything else (colour management, selection) only redraws. view_draw turns
the region's matrices into a camera (export/viewport_camera.py) and
restarts the render when the view, projection or region size changes
(resizes are debounced).

A Python worker thread builds the gridwalk.Scene and its grid (the grid
build releases the GIL) and runs the passes as gridwalk.RenderJobs (native
threads, GIL released): a coarse pass (blocks of start_pixels x the pixel
size), then full-resolution passes of one random camera sample per pixel,
averaged, up to the viewport sample count. Until the render settings'
acceleration structure is built for the latest scene, the coarse pass traces a quick structure (a coarse uniform grid, QUICK_GRID: it builds
in a fraction of the render settings' structure's time, about 0.09 s
against 1 - 3 s for 1M triangles), so the first new pixels do not wait for
the full build; the full-resolution passes use the render settings' own
structure, whose build a new request cancels. With Threads = 0 it renders on
all cores but one, which Blender's main loop keeps. A new request cancels the
running job, which returns once its threads have stopped; stop() joins the
worker. It calls the engine's tag_redraw (through a weak reference, so the
engine can still be freed) when new tiles arrive.

Nothing here imports gpu: drawing lives in viewport_draw.py.
"""
from __future__ import annotations

import atexit
import collections
import os
import threading
import time
import weakref

import numpy as np

POLL_SECONDS = 0.01
REDRAW_SECONDS = 0.25          # at most 4 redraws a second from the worker (and one per pass)
RESIZE_DEBOUNCE_SECONDS = 0.3
QUICK_GRID = dict(accel="grid", grid_density=0.3)   # ~0.03 cells per primitive: the coarse pass's structure
SESSIONS = weakref.WeakSet()   # every live session, stopped on file load and at exit


def stop_all():
    for session in list(SESSIONS):
        session.stop()


atexit.register(stop_all)


HALF_LIMIT = 65000.0            # below the half-float maximum (65504): beyond it the view turns black


class Display:
    """The image the viewport shows: (h, w, 4) float32, scene-linear, rows
    bottom-up (as the GPU texture wants them), values finite and within
    +-HALF_LIMIT (tiles are cleaned as they arrive, off the main thread).
    Coarse tiles are stretched over their block of pixels until
    full-resolution tiles arrive; full-resolution passes are averaged."""

    def __init__(self):
        self.rgba = np.zeros((1, 1, 4), np.float32)
        self.accum = np.zeros((1, 1, 4), np.float32)
        self.count = np.zeros((1, 1, 1), np.float32)
        self.version = 0

    def reset(self, width: int, height: int):
        """A new render of width x height: keep the last image (resized) on show."""
        if self.rgba.shape[:2] != (height, width):
            rows = np.minimum(np.arange(height) * self.rgba.shape[0] // height, self.rgba.shape[0] - 1)
            cols = np.minimum(np.arange(width) * self.rgba.shape[1] // width, self.rgba.shape[1] - 1)
            self.rgba = np.ascontiguousarray(self.rgba[rows][:, cols])
        self.accum = np.zeros((height, width, 4), np.float32)
        self.count = np.zeros((height, width, 1), np.float32)
        self.version += 1

    def add_tile(self, x: int, y: int, rgba: np.ndarray, block: int):
        """A finished tile whose top-left pixel is (x, y), row 0 at the top, of a
        pass rendered at 1/block of the resolution."""
        rgba = np.clip(np.nan_to_num(rgba[::-1], nan=0.0), -HALF_LIMIT, HALF_LIMIT)
        height = self.rgba.shape[0]
        if block == 1:
            h, w = rgba.shape[:2]
            rows = slice(height - y - h, height - y)
            self.accum[rows, x:x + w] += rgba
            self.count[rows, x:x + w] += 1.0
            self.rgba[rows, x:x + w] = self.accum[rows, x:x + w] / self.count[rows, x:x + w]
        else:
            big = np.repeat(np.repeat(rgba, block, axis=0), block, axis=1)
            y1, x0 = height - y * block, x * block                 # the block's bottom edge, bottom-up
            h, w = min(big.shape[0], y1), min(big.shape[1], self.rgba.shape[1] - x0)
            if h > 0 and w > 0:
                self.rgba[y1 - h:y1, x0:x0 + w] = big[big.shape[0] - h:, :w]
        self.version += 1


class Pass:
    def __init__(self, block: int, settings, camera, index: int):
        self.block, self.settings, self.camera, self.index = block, settings, camera, index


class ViewportSession:
    """The render behind one viewport; see the module docstring."""

    def __init__(self, engine):
        from .export import MeshCache
        self._engine = weakref.ref(engine)
        self.cache = MeshCache()
        self.lock = threading.Condition()
        self.display = Display()
        self.signature = None
        self.scene_kwargs = None       # the latest export (None: nothing to render)
        self.scene_version = 0
        self.settings = None           # gridwalk.RenderSettings for the viewport
        self.samples, self.start_pixels, self.opaque = 1, 1, True
        self.view = None               # (key, Camera at full resolution, pixel size)
        self.view_version = 0
        self.settings_version = 0
        self.not_before = 0.0          # a debounced resize waits until then
        self.message = ""              # status for the viewport's header
        self.timings = {}              # of the latest scene: export, scene, grid, first pixels
        self.main_thread = collections.deque(maxlen=256)   # (call, seconds) of view_update / view_draw
        self.job = None
        self.finished = None           # the (scene, view) versions whose render completed
        self.full_built = None         # the (scene, settings) versions whose full structure is built
        self.stopping = False
        self.thread = threading.Thread(target=self._run, name="gridwalk-viewport", daemon=True)
        self.thread.start()
        SESSIONS.add(self)

    # -- main thread ----------------------------------------------------------
    def update(self, depsgraph):
        """From view_update: export what changed; restart if the scene did."""
        from .export import Export, ExportError
        t0 = time.perf_counter()
        self.cache.invalidate(depsgraph.updates)
        self.follow_settings(depsgraph.scene)
        try:
            export = Export(depsgraph, self.cache, camera=False)
            signature = export.signature()
            if signature == self.signature:
                return False
            kwargs, _ = export.kwargs()
            self._check_memory(kwargs, depsgraph.scene)
            message = ""
        except (ExportError, MemoryError) as exc:
            kwargs, signature, message = None, None, f"Gridwalk: {exc}"
        t1 = time.perf_counter()
        with self.lock:
            self.signature = signature
            self.scene_kwargs, self.message = kwargs, message
            self.scene_version += 1
            self.timings = {"edit": t0, "export": t1 - t0}
            self.lock.notify_all()
        return True

    def _check_memory(self, kwargs, scene):
        """Refuse (gridwalk.memory.SceneTooLarge, shown in the view) a scene over
        the memory limit, as a final render does; the image is the region's."""
        from gridwalk import memory

        from .engine import memory_limit
        with self.lock:
            view, settings = self.view, self.settings
        width, height = (view[1].width, view[1].height) if view is not None else (1, 1)
        images = kwargs.get("images") or []
        estimate = memory.estimate(len(kwargs["triangles"]), len(kwargs["vertices"]), len(kwargs["sphere_radii"]),
                                   width=width, height=height, settings=settings,
                                   normals=kwargs["normals"] is not None,
                                   texture_bytes=sum(image.memory_bytes for image in images),
                                   uvs=kwargs.get("uvs") is not None, colors=kwargs.get("colors") is not None)
        limit, source = memory_limit(scene.gridwalk, memory)
        memory.check(estimate, limit, f"This scene ({len(kwargs['triangles']):,} triangles)", source)

    def follow_settings(self, scene):
        """From view_update and view_draw: restart when the render settings or
        the viewport's options changed (a property edit redraws the view but
        does not always reach view_update)."""
        import gridwalk

        from .properties import viewport_options
        from .settings import render_settings
        settings, options = render_settings(gridwalk, scene.gridwalk), viewport_options(scene)
        with self.lock:
            if (settings, options) == (self.settings, (self.samples, self.start_pixels, self.opaque)):
                return
            self.settings = settings
            self.samples, self.start_pixels, self.opaque = options
            self.settings_version += 1
            self.lock.notify_all()

    def set_view(self, key, camera, pixel_size: int):
        """From view_draw: the region's view (`key` tells views apart; its first
        two items are the region's size: a change of size alone is debounced)."""
        with self.lock:
            if self.view is not None and self.view[0] == key:
                return
            resized = self.view is not None and self.view[0][2:] == key[2:]
            self.view = (key, camera, pixel_size)
            self.not_before = time.monotonic() + (RESIZE_DEBOUNCE_SECONDS if resized else 0.0)
            self.view_version += 1
            self.lock.notify_all()

    def idle(self) -> bool:
        """Whether the latest scene and view are rendered completely."""
        with self.lock:
            return self.finished == self._versions()

    def stop(self):
        """Cancel the running job and join the worker. Safe to call twice and
        from any thread (from the worker itself it only asks it to stop)."""
        with self.lock:
            self.stopping = True
            job = self.job
            self.lock.notify_all()
        if job is not None:
            job.cancel()                       # returns once its threads have stopped
        if threading.current_thread() is not self.thread and self.thread.is_alive():
            self.thread.join()
            print("Gridwalk: viewport render stopped")
        SESSIONS.discard(self)

    # -- worker thread --------------------------------------------------------
    def _versions(self):
        return self.scene_version, self.view_version, self.settings_version

    def _restart_requested(self, versions) -> bool:
        return self.stopping or self._versions() != versions

    def _run(self):
        import gridwalk
        built, gw_scene, done = None, None, None
        while True:
            with self.lock:
                while True:
                    if self.stopping:
                        return
                    if self.view is None or self.scene_version == 0 or self._versions() == done:
                        self.lock.wait()
                        continue
                    delay = self.not_before - time.monotonic()      # a resize settles first
                    if delay <= 0:
                        break
                    self.lock.wait(delay)
                versions = done = self._versions()
                kwargs, settings, view = self.scene_kwargs, self.settings, self.view
                samples, start, opaque = self.samples, self.start_pixels, self.opaque
            try:
                if kwargs is None:
                    self._show_background(view)
                    continue
                if built != versions[0]:
                    t0 = time.perf_counter()
                    gw_scene = gridwalk.Scene(**kwargs)
                    built = versions[0]
                    self.timings["scene"] = time.perf_counter() - t0
                self._render(gridwalk, gw_scene, settings, view, samples, start, opaque, versions)
            except gridwalk.BuildCancelled:   # a newer request: start over with it
                continue
            except Exception as exc:      # shown in the viewport, never raised into Blender
                with self.lock:
                    self.message = f"Gridwalk: {exc}"
                self._redraw()

    def _passes(self, settings, view, samples: int, start: int, quick: bool = False):
        _, camera, pixel = view
        full_w, full_h = camera.width, camera.height
        if settings.threads == 0:      # all cores but one: Blender's main loop keeps one
            settings = settings.replace(threads=max(1, (os.cpu_count() or 2) - 1))
        out = []
        if start > 1 and max(full_w, full_h) > start:
            w, h = -(-full_w // start), -(-full_h // start)
            coarse = settings.replace(aa="center", tile_size=16, region=None, **(QUICK_GRID if quick else {}))
            out.append(Pass(start, coarse, _resized(camera, w, h), 0))
        for i in range(samples):
            out.append(Pass(1, settings.replace(aa="random", aa_samples=1, seed=(settings.seed + i) % 2**32,
                                                region=None), camera, i + 1))
        return out

    def _render(self, gridwalk, gw_scene, settings, view, samples, start, opaque, versions):
        """Run the passes of one request. Until the render settings' structure
        is built for this scene and settings, the coarse pass traces the quick one."""
        camera = view[1]
        with self.lock:
            self.display.reset(camera.width, camera.height)
        first = True
        full_built = (versions[0], versions[2])
        for p in self._passes(settings, view, samples, start, quick=self.full_built != full_built):
            t0 = time.perf_counter()
            # each structure is built once per scene (and cached by it); a new request cancels a build
            job = gridwalk.RenderJob(gw_scene, p.settings, camera=p.camera,
                                     should_stop=lambda: self._restart_requested(versions))
            with self.lock:
                if self._restart_requested(versions):
                    return
                self.job = job
                if first:
                    self.timings["grid"] = time.perf_counter() - t0
                if p.block == 1 and self.full_built != full_built:
                    self.full_built = full_built
                    now = time.perf_counter()
                    self.timings["full_grid"] = now - t0
                    self.timings["edit_to_full_grid"] = now - self.timings.get("edit", now)
            job.start()
            t_start = time.perf_counter()
            last_redraw = 0.0
            try:
                while True:
                    finished = job.finished
                    tiles = job.poll()
                    if tiles:
                        with self.lock:
                            for tile in tiles:
                                rgba = tile.rgba
                                if opaque:
                                    rgba[..., 3] = 1.0
                                self.display.add_tile(tile.x, tile.y, rgba, p.block)
                            if first and "first_pixels" not in self.timings:
                                now = time.perf_counter()
                                self.timings["first_pixels"] = now - t_start
                                self.timings["edit_to_pixels"] = now - self.timings.get("edit", now)
                            self.message = f"Pass {p.index}/{samples}" if p.block == 1 else "Coarse pass"
                        first = False
                        if time.monotonic() - last_redraw > REDRAW_SECONDS or finished:
                            self._redraw()
                            last_redraw = time.monotonic()
                    if finished or self._restart_requested(versions):
                        break
                    time.sleep(POLL_SECONDS)
            finally:
                job.cancel()
                with self.lock:
                    self.job = None
            if self._restart_requested(versions):
                return
            job.wait()                       # rethrows a worker's error
        with self.lock:
            self.message = f"Done: {samples} samples"
            self.finished = versions
        self._redraw()

    def _show_background(self, view):
        with self.lock:
            camera = view[1]
            self.display.reset(camera.width, camera.height)
            self.display.rgba[...] = 0.0
            self.display.version += 1
        self._redraw()

    def _redraw(self):
        engine = self._engine()
        if engine is None:
            return
        try:
            engine.tag_redraw()
        except ReferenceError:          # the engine was freed: nobody to draw for
            pass
        finally:
            del engine


def view_from_context(engine, context, depsgraph):
    """(key, Camera, pixel size) of the region being drawn. The camera renders
    the region at 1 / pixel size of its resolution. Looking through the scene
    camera, its clipping and lens come from it, and a panorama is stretched
    from the camera's frame over the region; a camera with a zero scale or a
    non-finite transform raises CameraError naming it."""
    from .export.camera import CameraError, camera_frame, convert_camera
    from .export._matrix import to_numpy
    from .export.viewport_camera import frame_in_region, stretch_panorama, view_camera
    region, rv3d, space = context.region, context.region_data, context.space_data
    scene = depsgraph.scene
    pixel = max(1, int(engine.get_preview_pixel_size(scene)))
    width, height = max(1, region.width), max(1, region.height)
    view, window = to_numpy(rv3d.view_matrix), to_numpy(rv3d.window_matrix)
    clip, extra, lens = (space.clip_start, space.clip_end), {}, None
    if rv3d.view_perspective == "CAMERA" and scene.camera is not None:
        cam_obj = scene.camera.evaluated_get(depsgraph)
        camera_frame(cam_obj)          # a camera without a view (zero scale, NaN) raises CameraError, named
        try:
            lens = convert_camera(cam_obj, scene.render, scene.unit_settings.scale_length)
        except CameraError:            # (an unsupported panorama: its frame, in perspective)
            lens = None
        if lens is not None:
            clip = (lens.hither, lens.yon)
            extra = dict(aperture=lens.aperture, focus_distance=lens.focus_distance)
            if lens.projection == "equirectangular":
                render = scene.render
                frame = frame_in_region(cam_obj.calc_matrix_camera(
                    depsgraph, x=lens.width, y=lens.height, scale_x=render.pixel_aspect_x,
                    scale_y=render.pixel_aspect_y), window, width, height)
                extra.update(projection="equirectangular", **stretch_panorama(lens, frame, width, height))
    key = (width, height, pixel, view.tobytes(), window.tobytes(), tuple(clip), repr(extra))
    camera = view_camera(view, window, -(-width // pixel), -(-height // pixel), clip=clip, **extra)
    return key, camera, pixel


def _resized(camera, width: int, height: int):
    """The same view at another resolution (pixel aspect adjusted: the image is
    stretched back over the region)."""
    import dataclasses
    aspect = camera.pixel_aspect * (camera.width / width) / (camera.height / height)
    return dataclasses.replace(camera, width=width, height=height, pixel_aspect=aspect)
