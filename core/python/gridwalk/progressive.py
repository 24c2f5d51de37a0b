"""ProgressiveRenderer: a sequence of passes refining one image, run by a
native controller thread (gridwalk._core.ViewportRenderer), for interactive
viewers such as Blender's viewport.

    r = ProgressiveRenderer()
    rid, _ = r.submit(scene, [(4, coarse_settings, small_camera), (1, settings, camera, 16)],
                      camera.width, camera.height)
    r.status        # request, finished, pass, passes_done, rendering, error, version, timings
    version, rgba = r.image()      # (H, W, 4) float32, rows bottom-up
    r.stop()

A pass of block b renders a camera of 1/b the resolution and paints each
pixel over a b x b square; passes of block 1 are averaged. A pass with a
repeat count n renders n times, with seeds settings.seed + 0 ... n - 1. Each distinct
acceleration structure the passes' settings need is built once per scene
(in the controller thread; a newer request cancels the build) and kept
while the scene stays the same. When a new scene differs from the last only
in where some primitives are (objects moved), a uniform grid of the last
one is updated instead of rebuilt: only the moved primitives are re-listed
(its box has a margin of empty cells so that they stay inside). While a
renderer exists, a new Scene reuses the large buffers of freed ones of the
same size (the pages are already mapped). A submit replaces the waiting request and
cancels the running one without waiting for it. No Python runs off the
caller's thread.
"""
from __future__ import annotations

from . import _core
from .model import Camera
from .scene import Scene, structure_key
from .settings import RenderSettings


class ProgressiveRenderer:
    def __init__(self):
        self._native = _core.ViewportRenderer()
        self._id = 0

    def submit(self, scene: Scene | None, passes, width: int, height: int, opaque: bool = True,
               limit: float = _core.HALF_FLOAT_SAFE_LIMIT, delay: float = 0.0) -> tuple[int, list[int]]:
        """Render `passes`, a list of (block, RenderSettings, Camera[, repeat]), into a
        width x height image; scene None clears the image. opaque: alpha 1
        everywhere; values are clamped to +-limit (NaN shows as 0; the default
        stays below the largest half float, which a GPU's RGBA16F texture holds); the
        request waits `delay` seconds first unless a newer one arrives.
        Returns (request id, the structure index of each pass)."""
        if scene is not None and not isinstance(scene, Scene):
            raise ValueError(f"scene must be a gridwalk.Scene or None, got {type(scene).__name__}")
        structures, keys, native, indexes = [], {}, [], []
        for item in passes:
            block, settings, camera, repeat = (tuple(item) + (1,))[:4]
            if not isinstance(settings, RenderSettings) or not isinstance(camera, Camera):
                raise ValueError("each pass is (block, gridwalk.RenderSettings, gridwalk.Camera[, repeat])")
            key = repr(structure_key(settings))
            if key not in keys:
                keys[key] = len(structures)
                structures.append((key, settings.to_core()))
            indexes.append(keys[key])
            native.append((int(block), keys[key], settings.to_core(), camera.to_core(), int(repeat)))
        self._id += 1
        self._native.submit(self._id, scene._native if scene is not None else None, structures, native,
                            int(width), int(height), bool(opaque), float(limit), float(delay))
        return self._id, indexes

    @property
    def status(self) -> dict:
        """request: the request worked on; finished: the last one completed;
        pass (-1: none), its repetition, and passes_done (renders completed); rendering: past its delay and not
        done; error: why it failed; version: of the image. Seconds after the
        submit (-1: not yet): first_pass_started, first_pixels, and
        structure_ready (one per structure); structure_updated (one per
        structure): whether it was updated from the previous scene's uniform
        grid (only moved primitives re-listed) instead of built."""
        return self._native.status

    def image(self):
        """(version, (H, W, 4) float32 copy of the image, rows bottom-up)."""
        return self._native.image()

    def stop(self) -> None:
        """Cancel and join the controller and its render threads."""
        self._native.stop()
