"""Interactive rendering in the 3D viewport (Rendered shading).

One ViewportSession per engine instance (a quad view has four). On the main
thread, view_update exports the depsgraph into a MeshCache kept between
updates (only changed meshes are read, only moved instances transformed),
compares the export's signature with the last one and builds the
gridwalk.Scene: geometry, transforms, materials, lights, world or render
settings restart the render; anything else (colour management, selection)
only redraws. view_draw turns the region's matrices into a camera
(export/viewport_camera.py) and restarts the render when the view,
projection or region size changes (a resize waits RESIZE_DEBOUNCE_SECONDS
for the size to settle).

The render runs in a gridwalk.ProgressiveRenderer (one native controller
thread per session, named "gridwalk-view", plus the render threads): it
builds the structures, runs the passes and accumulates their tiles into the
display image, and never runs Python. No Python thread is started here:
Blender (3.4 - 5.0, on Python 3.11) crashes when a Python thread runs while
the main thread is inside an operator called from Python with a context
override, because it then touches Python objects without the GIL (seen when
a script generated a material preview while the viewport rendered).

The passes: a coarse one (blocks of start_pixels x the pixel size), then
full-resolution passes of one random camera sample per pixel, averaged, up
to the viewport sample count. Until the render settings' acceleration
structure is built for the latest scene, the coarse pass traces a quick
structure (a coarse uniform grid, QUICK_GRID: it builds in a fraction of
the render settings' structure's time, about 0.09 s against 1 - 3 s for 1M
triangles), so the first new pixels do not wait for the full build. With
Threads = 0 it renders on all cores but one, which Blender's main loop keeps.
A new request cancels the running one without waiting for it.

A timer on Blender's main thread (tick) collects the progress: it copies the
image when it changed (at most every REDRAW_SECONDS, and at once for the
first pixels of a request or its end) and tags the engine's redraw.

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

TICK_SECONDS = 0.02            # the main-thread timer, while a session renders
IDLE_TICK_SECONDS = 0.25       # ... while every session is done
REDRAW_SECONDS = 0.25          # at most 4 image copies and redraws a second (and one per request's start and end)
RESIZE_DEBOUNCE_SECONDS = 0.3
QUICK_GRID = dict(accel="grid", grid_density=0.3)   # ~0.03 cells per primitive: the coarse pass's structure
SESSIONS = weakref.WeakSet()   # every live session, stopped on file load and at exit


def stop_all():
    for session in list(SESSIONS):
        session.stop()


atexit.register(stop_all)


def tick():
    """bpy.app.timers callback (main thread): every session collects its
    progress and redraws when its image changed."""
    live = list(SESSIONS)
    if not live:
        return None                    # unregistered; the next session registers it again
    busy = False
    for session in live:
        if session.poll():
            session._redraw()
        busy = busy or session.busy
    return TICK_SECONDS if busy else IDLE_TICK_SECONDS


def _ensure_timer():
    try:
        import bpy
    except ImportError:                # outside Blender (tests drive poll() themselves)
        return
    if not bpy.app.timers.is_registered(tick):
        bpy.app.timers.register(tick, first_interval=TICK_SECONDS, persistent=True)


class Display:
    """The image the viewport shows, as last copied from the renderer:
    (h, w, 4) float32, scene-linear, rows bottom-up (as the GPU texture wants
    them), values finite and below the largest half float (the renderer's limit). Coarse tiles are stretched
    over their block of pixels until full-resolution tiles arrive;
    full-resolution passes are averaged (in the core)."""

    def __init__(self):
        self.rgba = np.zeros((1, 1, 4), np.float32)
        self.version = 0


class Pass:
    """`repeat` renders of `camera` at 1/block of the view's resolution."""
    def __init__(self, block: int, settings, camera, repeat: int = 1):
        self.block, self.settings, self.camera, self.repeat = block, settings, camera, repeat


class ViewportSession:
    """The render behind one viewport; see the module docstring. Every method
    runs on Blender's main thread."""

    def __init__(self, engine):
        import gridwalk

        from .export import MeshCache
        self._engine = weakref.ref(engine)
        self.cache = MeshCache()
        self.lock = threading.RLock()
        self.display = Display()
        self.signature = None
        self.scene_kwargs = None       # the latest full export (None: nothing, or the scene was moved in the core)
        self.gw_scene = None           # the latest gridwalk.Scene
        self.layout = None             # its parts' Placements (export.meshes), for moving them
        self.moved = 0                 # instances the latest update moved in the core (0: a full export)
        self.scene_version = 0
        self.settings = None           # gridwalk.RenderSettings for the viewport
        self.samples, self.start_pixels, self.opaque = 1, 1, True
        self.view = None               # (key, Camera at full resolution, pixel size)
        self.view_version = 0
        self.settings_version = 0
        self.message = ""              # status for the viewport's header
        self.timings = {}              # of the latest scene: export, scene, grid, first pixels
        self.main_thread = collections.deque(maxlen=256)   # (call, seconds) of view_update / view_draw
        self.finished = None           # the (scene, view, settings) versions whose render completed
        self.full_built = None         # the (scene, settings) versions whose full structure is built
        self.stopping = False
        self.busy = False              # a request is submitted and not finished
        self.renderer = gridwalk.ProgressiveRenderer()
        self.request = None            # (id, versions, passes, full structure index, submit time)
        self.shown = (-1, -1, 0.0)     # (request id, image version, time) of the last copy
        self.reported = None           # (request id, pass, done, error) the message reflects
        SESSIONS.add(self)
        _ensure_timer()

    # -- the scene, settings and view -------------------------------------
    def update(self, depsgraph):
        """From view_update: export what changed; restart if the scene did."""
        import gridwalk

        from .export import Export, ExportError
        from .export.moves import instance_moves
        t0 = time.perf_counter()
        self.cache.invalidate(depsgraph.updates)
        self.follow_settings(depsgraph.scene)
        layout = None
        try:
            export = Export(depsgraph, self.cache, camera=False)
            signature = export.signature()
            if signature == self.signature:
                return False
            moves = None
            if self.gw_scene is not None and self.signature is not None:
                moves = instance_moves(self.signature, self.layout, signature, export, self.cache)
            gw_scene = None
            if moves is not None:      # only instances moved: the core moves them (same sizes: no memory check)
                kwargs, layout = None, self.layout
                t1 = time.perf_counter()
                try:
                    gw_scene, message = self.gw_scene.moved(moves), ""
                except ValueError:     # (not expected: the export checked the instances) a full export decides
                    moves = None
            if gw_scene is None:
                kwargs, _ = export.kwargs()
                layout = export.meshes.layout
                self._check_memory(kwargs, depsgraph.scene)
                t1 = time.perf_counter()
                gw_scene, message = gridwalk.Scene(**kwargs), ""
        except (ExportError, MemoryError, ValueError) as exc:
            t1 = time.perf_counter()
            kwargs, gw_scene, signature, message, moves = None, None, None, f"Gridwalk: {exc}", None
        t2 = time.perf_counter()
        with self.lock:
            self.signature, self.layout, self.moved = signature, layout, len(moves or ())
            self.scene_kwargs, self.gw_scene, self.message = kwargs, gw_scene, message
            self.scene_version += 1
            self.timings = {"edit": t0, "export": t1 - t0, "scene": t2 - t1}
        self._restart()
        return True

    def _check_memory(self, kwargs, scene):
        """Refuse (gridwalk.memory.SceneTooLarge, shown in the view) a scene over
        the memory limit, as a final render does; the image is the region's."""
        from gridwalk import memory

        from .engine import memory_limit
        from .export.assemble import CORNER_POINTS
        with self.lock:
            view, settings = self.view, self.settings
        width, height = (view[1].width, view[1].height) if view is not None else (1, 1)
        images = kwargs.get("images") or []
        estimate = memory.estimate(len(kwargs["triangles"]), len(kwargs["vertices"]), len(kwargs["sphere_radii"]),
                                   width=width, height=height, settings=settings,
                                   normals=kwargs["normals"] is not None,
                                   texture_bytes=sum(image.memory_bytes for image in images),
                                   uvs=kwargs.get("uvs") is not None, colors=kwargs.get("colors") is not None,
                                   corner_points=sum(kwargs.get(k) is not None for k in CORNER_POINTS),
                                   tangents=any(m.normal_texture >= 0 for m in kwargs["materials"]),
                                   **memory.declared_copies(kwargs))
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
        self._restart()

    def set_view(self, key, camera, pixel_size: int):
        """From view_draw: the region's view (`key` tells views apart; its first
        two items are the region's size: a change of size alone is debounced)."""
        with self.lock:
            if self.view is not None and self.view[0] == key:
                return
            resized = self.view is not None and self.view[0][2:] == key[2:]
            self.view = (key, camera, pixel_size)
            self.view_version += 1
        self._restart(delay=RESIZE_DEBOUNCE_SECONDS if resized else 0.0)

    # -- the render -------------------------------------------------------
    def _versions(self):
        return self.scene_version, self.view_version, self.settings_version

    def _restart(self, delay: float = 0.0):
        """Submit the latest scene, view and settings to the renderer (the
        running request is cancelled; this does not wait for it)."""
        with self.lock:
            if self.stopping or self.view is None or self.scene_version == 0 or self.settings is None:
                return
            versions = self._versions()
            if self.request is not None and self.request[1] == versions:
                return
            camera = self.view[1]
            passes = []
            if self.gw_scene is not None:
                quick = self.full_built != (self.scene_version, self.settings_version)
                passes = self._passes(self.settings, self.view, self.samples, self.start_pixels, quick)
            request_id, structures = self.renderer.submit(
                self.gw_scene, [(p.block, p.settings, p.camera, p.repeat) for p in passes], camera.width, camera.height,
                opaque=self.opaque, delay=delay)
            full = next((s for p, s in zip(passes, structures) if p.block == 1), None)
            self.request = (request_id, versions, passes, full, time.perf_counter())
            self.busy = True

    def _passes(self, settings, view, samples: int, start: int, quick: bool = False):
        _, camera, pixel = view
        full_w, full_h = camera.width, camera.height
        if settings.threads == 0:      # all cores but one: Blender's main loop keeps one
            settings = settings.replace(threads=max(1, (os.cpu_count() or 2) - 1))
        out = []
        if start > 1 and max(full_w, full_h) > start:
            w, h = -(-full_w // start), -(-full_h // start)
            coarse = settings.replace(aa="center", tile_size=16, region=None, **(QUICK_GRID if quick else {}))
            out.append(Pass(start, coarse, _resized(camera, w, h)))
        # one random camera sample per pixel and render, seeds settings.seed + 0 ... samples - 1, averaged
        out.append(Pass(1, settings.replace(aa="random", aa_samples=1, region=None), camera, samples))
        return out

    def poll(self) -> bool:
        """Collect the renderer's progress: status, timings and (when it
        changed) the image. Returns whether the image shown changed."""
        with self.lock:
            if self.request is None or self.stopping:
                return False
            request_id, versions, passes, full, submitted = self.request
            status = self.renderer.status
            if status["request"] != request_id:     # not started yet (a resize settling)
                return False
            done = status["finished"] == request_id
            state = (request_id, status["pass"], done, status["error"])
            if state != self.reported:          # the message follows changes only (view_draw sets its own)
                self.reported = state
                if status["error"]:
                    self.message = f"Gridwalk: {status['error']}"
                    self.busy = False
                elif done:
                    self.message = f"Done: {self.samples} samples" if passes else self.message
                elif status["pass"] >= 0:
                    p = passes[status["pass"]]
                    self.message = f"Pass {status['repetition'] + 1}/{p.repeat}" if p.block == 1 else "Coarse pass"
            self._note_timings(status, versions, full, submitted)
            changed = False
            last_request, last_version, last_time = self.shown
            if status["version"] != last_version and (
                    last_request != request_id or done or time.monotonic() - last_time > REDRAW_SECONDS):
                version, rgba = self.renderer.image()
                self.display.rgba = rgba
                self.display.version += 1
                self.shown = (request_id, version, time.monotonic())
                changed = True
            if done and self.shown[1] == status["version"]:
                self.finished = versions
                self.busy = False
            return changed

    def _note_timings(self, status, versions, full, submitted):
        t = self.timings
        before = submitted - t.get("edit", submitted)      # from the edit to the request
        if status["first_pass_started"] >= 0 and "grid" not in t:
            t["grid"] = status["first_pass_started"]
        if status["first_pixels"] >= 0 and "first_pixels" not in t:
            t["first_pixels"] = status["first_pixels"] - status["first_pass_started"]
            t["edit_to_pixels"] = before + status["first_pixels"]
        if full is not None and status["structure_ready"][full] >= 0:
            if "full_grid" not in t:
                t["full_grid"] = status["structure_ready"][full]
                t["edit_to_full_grid"] = before + status["structure_ready"][full]
            self.full_built = (versions[0], versions[2])

    def idle(self) -> bool:
        """Whether the latest scene and view are rendered completely (and shown)."""
        self.poll()
        with self.lock:
            return self.finished == self._versions()

    @property
    def job(self):
        """The running request's status (None while none renders: done, or a resize settling)."""
        status = self.renderer.status
        return status if status["rendering"] else None

    def stop(self):
        """Cancel the render and join its threads. Safe to call twice."""
        with self.lock:
            if self.stopping:
                return
            self.stopping = True
            self.busy = False
        self.renderer.stop()
        print("Gridwalk: viewport render stopped")
        SESSIONS.discard(self)

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
    from the camera's frame over the region; a camera the final render
    refuses (a zero scale, a non-finite transform, an empty panorama, Blender
    4.5's Custom type) raises CameraError naming it."""
    from .export.camera import convert_camera
    from .export._matrix import to_numpy
    from .export.viewport_camera import frame_in_region, stretch_panorama, view_camera
    region, rv3d, space = context.region, context.region_data, context.space_data
    scene = depsgraph.scene
    pixel = max(1, int(engine.get_preview_pixel_size(scene)))
    width, height = max(1, region.width), max(1, region.height)
    view, window = to_numpy(rv3d.view_matrix), to_numpy(rv3d.window_matrix)
    clip, extra = (space.clip_start, space.clip_end), {}
    if rv3d.view_perspective == "CAMERA" and scene.camera is not None:
        cam_obj = scene.camera.evaluated_get(depsgraph)
        # (a camera without a view, zero scale or NaN, or an empty panorama raises CameraError, named,
        # which the view shows, as the final render reports it)
        lens = convert_camera(cam_obj, scene.render, live=True)
        clip = (lens.hither, lens.yon)
        extra = dict(aperture=lens.aperture, focus_distance=lens.focus_distance)
        if lens.panoramic:
            render = scene.render
            frame = frame_in_region(cam_obj.calc_matrix_camera(
                depsgraph, x=lens.width, y=lens.height, scale_x=render.pixel_aspect_x,
                scale_y=render.pixel_aspect_y), window, width, height)
            extra.update(stretch_panorama(lens, frame, width, height))
    key = (width, height, pixel, view.tobytes(), window.tobytes(), tuple(clip), repr(extra))
    camera = view_camera(view, window, -(-width // pixel), -(-height // pixel), clip=clip, **extra)
    return key, camera, pixel


def _resized(camera, width: int, height: int):
    """The same view at another resolution (pixel aspect adjusted: the image is
    stretched back over the region)."""
    import dataclasses
    aspect = camera.pixel_aspect * (camera.width / width) / (camera.height / height)
    return dataclasses.replace(camera, width=width, height=height, pixel_aspect=aspect)
