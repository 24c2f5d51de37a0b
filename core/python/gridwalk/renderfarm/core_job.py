"""An NFF or PLY scene (or gridwalk.Scene keywords) split into tiles, rendered
by the core on the workers.

Each tile is a render of the whole scene with RenderSettings.region set to
the tile. Every sample is seeded by its pixel (and, for adaptive
anti-aliasing, lattice points by their global position), never by the tile
or the thread, so the tiles put together are the single-machine image bit
for bit.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from .. import __version__, io
from ..cli import check_output, write_image
from ..image import Image
from ..render import RenderJob
from ..scene import Scene
from ..settings import RenderSettings
from . import plan
from .jobplugin import JobPlugin, TaskStopped

# Settings that change how a render is run, not the image it makes.
NOT_IN_IMAGE = ("threads", "tile_size")


class CoreTiles(JobPlugin):
    """On the workers: the scene keywords, the settings and the tile rectangles."""
    what = "tile"

    def __init__(self, run_id: str, threads: int, scene_kwargs: dict, settings: RenderSettings, rects: list):
        super().__init__(run_id, threads)
        self.scene_kwargs, self.settings, self.rects = scene_kwargs, settings, rects

    def setup(self, worker):
        super().setup(worker)
        self._scene = None

    def scene(self) -> Scene:
        """The scene with its grid, built by the first task on this worker."""
        with self.lock:
            if self._scene is None:
                scene = Scene(**self.scene_kwargs)
                scene.accel(self.settings)
                self._scene = scene
                self.scene_loads += 1
        return self._scene

    def label(self, index) -> str:
        x, y, w, h = self.rects[index]
        return f"tile {index} ({w} x {h} pixels at x={x}, y={y})"

    def run(self, index, key) -> dict:
        x, y, w, h = self.rects[index]
        settings = self.settings.replace(region=(x, y, w, h), threads=self.render_threads())
        job = RenderJob(self.scene(), settings).start()
        with self.stoppable(key, job.cancel):
            job.wait()                           # the GIL is released while the core renders
        if self.stop_requested(key):
            raise TaskStopped(f"{self.label(index)} cancelled")
        stats = job.stats
        return {"rgba": job.area_image, "rays": stats["rays"], "seconds": stats["seconds"]}


def _scene_digest(kwargs: dict) -> str:
    """What the tiles were rendered from: every array's bytes, every image's
    pixels, every record's fields, however deeply nested (a repr would
    shorten long arrays with "..." and names only an Image's size)."""
    parts = []

    def add(value):
        if isinstance(value, np.ndarray):
            parts.extend([value.dtype.str, value.shape, np.ascontiguousarray(value).tobytes()])
        elif isinstance(value, Image):
            parts.extend(["Image", value.colorspace])
            add(value.pixels())
        elif isinstance(value, dict):
            parts.append(("dict", len(value)))
            for key in sorted(value, key=repr):
                parts.append(key)
                add(value[key])
        elif isinstance(value, (list, tuple)):
            parts.append((type(value).__name__, len(value)))
            for item in value:
                add(item)
        elif dataclasses.is_dataclass(value) and not isinstance(value, type):
            parts.append(type(value).__name__)
            add(dataclasses.asdict(value))
        else:
            parts.append(value)

    add(kwargs)
    return plan.digest(*parts)


def load_scene(scene, width=None, height=None) -> tuple[dict, str]:
    """(Scene keywords, a name for messages) from a .nff / .ply path or a dict
    of keywords, with the camera's image size replaced where given."""
    if not isinstance(scene, dict):
        return io.load_scene(scene, width, height), Path(scene).name
    kwargs = dict(scene)
    cam = kwargs.get("camera")
    if cam is not None and (width is not None or height is not None):
        kwargs["camera"] = cam.resized(cam.width if width is None else width,
                                       cam.height if height is None else height)
    return kwargs, "scene"


class CoreJob:
    """On the client: what to render, where the tiles are kept, how they are put together."""
    what = "tile"

    def __init__(self, scene, output, settings: RenderSettings | None = None, tiles: int = 16,
                 width=None, height=None):
        self.settings = settings or RenderSettings()
        if self.settings.region not in (None, (0, 0, 0, 0)):
            raise ValueError("the farm renders the whole image (in tiles): leave RenderSettings.region unset")
        self.settings.to_core()
        self.output = check_output(output)
        self.scene_kwargs, self.name = load_scene(scene, width, height)
        camera = Scene(**self.scene_kwargs).camera         # checks the scene here, before any worker sees it
        self.width, self.height = camera.width, camera.height
        self.rects = plan.tiles(self.width, self.height, tiles)
        self.items = list(range(len(self.rects)))
        self.folder = self.output.with_name(self.output.name + ".parts")
        image_settings = {k: v for k, v in dataclasses.asdict(self.settings).items() if k not in NOT_IN_IMAGE}
        self.digest = plan.digest(__version__, _scene_digest(self.scene_kwargs), sorted(image_settings.items()),
                                  self.rects)

    def describe(self) -> str:
        cols, rows = plan.tile_grid(self.width, self.height, len(self.rects))
        return f"{self.name}, {self.width} x {self.height} pixels in {len(self.rects)} tiles ({cols} x {rows})"

    def stem(self, index) -> str:
        return f"tile_{index:04d}"

    def plugin(self, run_id: str, threads: int) -> CoreTiles:
        return CoreTiles(run_id, threads, self.scene_kwargs, self.settings, self.rects)

    def keep(self, store, index, result: dict) -> None:
        store.put(self.stem(index), ".npy", result["rgba"])

    def finish(self, store) -> Path:
        """Put the tiles together, write the output, delete the tiles."""
        image = np.zeros((self.height, self.width, 4), np.float32)
        for index, (x, y, w, h) in enumerate(self.rects):
            image[y:y + h, x:x + w] = np.load(store.find(self.stem(index)))
        write_image(self.output, image)
        store.remove()
        return self.output
