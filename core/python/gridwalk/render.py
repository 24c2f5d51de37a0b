"""Rendering: the asynchronous RenderJob and the blocking render()."""
from __future__ import annotations

import threading
import time
from dataclasses import dataclass

import numpy as np

from . import _core
from .model import Camera
from .scene import Scene
from .settings import RenderSettings


@dataclass
class TileResult:
    x: int
    y: int            # row of the tile's top edge (row 0 is the top of the image)
    width: int
    height: int
    rgba: np.ndarray  # (height, width, 4) float32 copy of the finished pixels
    passes: dict = None   # "depth", "normal", "albedo" (and "matte_keys", "matte_coverage" with
                          # RenderSettings.matte_ranks > 0, "holdout" where a material is one):
                          # copies of the tile's pixels in those passes


class RenderJob:
    """A render running in native worker threads (the GIL is released).

    job = RenderJob(scene, settings); job.start()
    while not job.finished: tiles = job.poll(); ...; job.cancel() to stop

    camera: another view of the same scene (the viewport's); None renders
    through the scene's own camera. The scene's acceleration structure is
    built once and shared by every job on it.
    """

    def __init__(self, scene: Scene, settings: RenderSettings | None = None, camera: Camera | None = None,
                 should_stop=None):
        """Builds (or reuses) the scene's acceleration structure before the
        clock starts; should_stop() can cancel that build (see Scene.accel)."""
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a gridwalk.Scene, got {type(scene).__name__}")
        if camera is not None and not isinstance(camera, Camera):
            raise ValueError(f"camera must be a gridwalk.Camera, got {type(camera).__name__}")
        if settings is not None and not isinstance(settings, RenderSettings):
            raise ValueError(f"settings must be a gridwalk.RenderSettings, got {type(settings).__name__}")
        self.settings = settings or RenderSettings()
        core = self.settings.to_core()
        self.scene = scene
        self.camera = camera or scene.camera
        t0 = time.perf_counter()
        self.accel = scene.accel(self.settings, should_stop)
        self.build_seconds = time.perf_counter() - t0
        if camera is None:
            self._job = _core.RenderJob(self.accel, core)
        else:
            self._job = _core.RenderJob(self.accel, core, camera.to_core())

    def start(self) -> "RenderJob":
        self._job.start()
        return self

    def poll(self) -> list[TileResult]:
        """Tiles finished since the previous poll, with copies of their pixels
        (rgba, and depth, normal and albedo in TileResult.passes)."""
        job = self._job
        ax, ay = job.area[:2]               # the buffers hold only the rendered area
        arrays = {"depth": job.depth, "normal": job.normal, "albedo": job.albedo}
        if self.settings.matte_ranks > 0:
            arrays.update(matte_keys=job.matte_keys, matte_coverage=job.matte_coverage)
        if job.holdout.size:
            arrays["holdout"] = job.holdout
        tiles = []
        for x, y, w, h in job.poll():
            part = (slice(y - ay, y - ay + h), slice(x - ax, x - ax + w))
            tiles.append(TileResult(x, y, w, h, job.rgba[part].copy(), {k: v[part].copy() for k, v in arrays.items()}))
        return tiles

    def cancel(self) -> None:
        """Stop the workers; returns when no worker thread is left running."""
        self._job.cancel()

    def wait(self) -> np.ndarray:
        """Block until the job ends; returns the image. On the main thread the
        wait comes back to Python every 0.1 s, so that Ctrl-C
        (KeyboardInterrupt) and other signals land while it renders; an
        exception raised there cancels the job before it propagates. (Python
        runs signal handlers on the main thread only; another thread waits in
        native code throughout, so that a daemon thread still waiting when the
        interpreter exits is never woken into its shutdown.)"""
        if self._job.started and threading.current_thread() is threading.main_thread():
            try:
                while not self._job.wait_for(0.1):
                    pass
            except BaseException:
                self._job.cancel()
                raise
        self._job.wait()          # (joins the workers; raises what a worker raised)
        return self.image

    def wait_for(self, seconds: float) -> bool:
        """Block until another tile is finished, the job ends, or `seconds`
        pass; True once it has finished. A loop showing progress or
        streaming tiles sees them as they are done, and the end at once."""
        return self._job.wait_for(float(seconds))

    @property
    def finished(self) -> bool:
        return self._job.finished

    @property
    def cancelled(self) -> bool:
        return self._job.cancelled

    @property
    def progress(self) -> float:
        return self._job.tiles_done / max(1, self._job.tiles_total)

    @property
    def tiles_done(self) -> int:
        return self._job.tiles_done

    @property
    def tiles_total(self) -> int:
        return self._job.tiles_total

    def _whole(self, part: np.ndarray, outside: float) -> np.ndarray:
        """A pass of the whole image from the rendered area's buffer; pixels
        outside a region hold `outside` (nothing was rendered there)."""
        x, y, w, h = self._job.area
        height, width = self._job.height, self._job.width
        if (w, h) == (width, height):
            return part.copy()
        whole = np.full((height, width) + part.shape[2:], outside, part.dtype)
        whole[y:y + h, x:x + w] = part
        return whole

    @property
    def area(self) -> tuple[int, int, int, int]:
        """(x, y, w, h): the rectangle rendered (RenderSettings.region, clipped
        to the image), or the whole image."""
        return tuple(self._job.area)

    @property
    def area_image(self) -> np.ndarray:
        """(h, w, 4) float32 linear RGBA of just the rendered rectangle (a
        farm's tile): no image-sized copy."""
        return self._job.rgba.copy()

    @property
    def image(self) -> np.ndarray:
        """(H, W, 4) float32 linear RGBA; alpha is the fraction of samples that hit."""
        return self._whole(self._job.rgba, 0.0)

    @property
    def depth(self) -> np.ndarray:
        """(H, W) distance along the view axis to the first hit (inf on a miss)."""
        return self._whole(self._job.depth, np.inf)

    @property
    def normal(self) -> np.ndarray:
        """(H, W, 3) world-space shading normal at the first hit (0 on a miss)."""
        return self._whole(self._job.normal, 0.0)

    @property
    def albedo(self) -> np.ndarray:
        """(H, W, 3) base colour at the first hit, textures applied (0 on a miss):
        Blender's Denoising Albedo pass."""
        return self._whole(self._job.albedo, 0.0)

    @property
    def holdout(self) -> np.ndarray | None:
        """(H, W) float32: the share of each pixel's camera samples that met a
        holdout (Material(holdout=True)), where the film is clear; None when
        no material is one."""
        return self._whole(self._job.holdout, 0.0) if self._job.holdout.size else None

    @property
    def matte_keys(self) -> np.ndarray:
        """(H, W, L, RenderSettings.matte_ranks) int32: per layer of the
        scene's matte keys (Scene(matte_keys=...)), the keys covering most of
        each pixel, most first; -1 beyond the keys the pixel's samples met."""
        return self._whole(self._job.matte_keys, -1)

    @property
    def matte_coverage(self) -> np.ndarray:
        """(H, W, L, RenderSettings.matte_ranks) float32: the share of each
        pixel that each of matte_keys covers (its samples' weights times the
        surfaces' alpha; the ranks of a pixel whose samples all hit keyed
        surfaces sum to 1)."""
        return self._whole(self._job.matte_coverage, 0.0)

    @property
    def stats(self) -> dict:
        """Ray counts by kind, tests and cells per ray, time, and the grid's figures."""
        s = dict(self._job.stats)
        rays = max(1, s["rays"])
        s["tests_per_ray"] = s["prim_tests"] / rays
        s["cells_per_ray"] = s["cells"] / rays
        s["seconds"] = self._job.elapsed
        s["mrays_per_second"] = s["rays"] / max(s["seconds"], 1e-9) / 1e6
        s["grid"] = dict(self.accel.grid) if self.settings.accel != "none" else None
        return s


def render(scene: Scene, settings: RenderSettings | None = None, progress=None) -> np.ndarray:
    """Render to a (H, W, 4) float32 array. progress(fraction) is called as tiles finish."""
    job = RenderJob(scene, settings).start()
    try:
        if progress is not None:
            while not job.finished:
                job.wait_for(0.05)
                job.poll()
                progress(job.progress)
        return job.wait()
    except BaseException:
        job.cancel()
        raise
