"""The render loop: run a gridwalk.RenderJob and stream its tiles into Blender.

The core renders in its own threads with the GIL released. This loop polls
finished tiles every POLL_SECONDS and writes each into the render result
(begin_result / end_result per tile, so the image appears as it renders),
reports progress and statistics, and cancels the job as soon as Blender asks
to stop (test_break): cancel() returns only when no worker thread is left.
Every pass (Depth, Normal, Denoising Albedo / Normal, Object and Material Index, Cryptomatte) is
written with its tile.

A border render (RenderSettings.region) gets a render result the size of the
border from Blender, so tiles are written relative to the region's corner.
"""
from __future__ import annotations

import time

import numpy as np

from .passes import PASSES

POLL_SECONDS = 0.02
STATS_SECONDS = 0.25


def set_pass(render_pass, values: np.ndarray):
    """Copy (h, w, c) float32 values (row 0 = top) into a render pass (rows bottom-up)."""
    flat = np.ascontiguousarray(values[::-1], dtype=np.float32).reshape(-1)
    try:
        render_pass.rect.foreach_set(flat)                 # Blender 4.x, 5.x
    except TypeError:                                      # Blender 3.x: a sequence of pixels
        render_pass.rect = flat.reshape(-1, values.shape[2])


def break_requested(engine) -> bool:
    """Whether Blender asks the render to stop (Esc; Ctrl-C in `blender -b`).

    Every cancel check of the engine goes through here. Tests replace this
    function to cancel at chosen moments: RenderEngine.test_break itself cannot
    be overridden from Python (Blender's RNA function shadows a subclass
    attribute), and in the bpy module nothing else can raise Blender's break flag.
    """
    return engine.test_break()


def stats_text(job) -> str:
    stats = job.stats
    return f"Tiles {job.tiles_done}/{job.tiles_total} | {stats['mrays_per_second']:.1f} Mrays/s"


class ResultWriter:
    """Writes rectangles of the image (row 0 = top, as the core stores it) into Blender.

    region = (x, y, w, h) of a border render (row 0 = top) or None: Blender's
    render result then covers only the region, with its rows bottom-up.
    """

    def __init__(self, engine, width: int, height: int, layer_name: str, opaque: bool, region=None):
        self.engine, self.layer_name, self.opaque = engine, layer_name, opaque
        self.region = tuple(region) if region is not None else (0, 0, width, height)
        self.written = False
        self.mattes = None          # a cryptomatte.Mattes: the tiles' matte ranks become its passes
        self.stamped = False        # its metadata added to the render result

    def ensure_written(self):
        """After a cancel: if no tile was written, write the (empty) result for the
        whole frame. Blender 4.5 crashes saving a multilayer EXR of a render
        result that the engine never wrote (seen with write_still)."""
        if self.written:
            return
        _, _, w, h = self.region
        result = self.engine.begin_result(0, 0, w, h, layer=self.layer_name)
        if result is not None:
            self.engine.end_result(result)
        self.written = True

    def write(self, x, y, arrays: dict):
        """Write the rectangle whose top-left pixel is (x, y) in the full image;
        `arrays` maps a pass source ("rgba", "depth", ...) to its pixels."""
        h, w = arrays["rgba"].shape[:2]
        rx, ry, _, rh = self.region
        if self.opaque:   # (the film is opaque but where a holdout clears it)
            arrays = dict(arrays, rgba=np.array(arrays["rgba"], dtype=np.float32))
            arrays["rgba"][..., 3] = 1.0 - arrays["holdout"] if "holdout" in arrays else 1.0
        result = self.engine.begin_result(x - rx, ry + rh - y - h, w, h, layer=self.layer_name)
        if result is None:
            raise RuntimeError(f"Blender refused the result rectangle {x - rx}, {ry + rh - y - h}, {w} x {h}")
        self.written = True
        try:
            layer_passes = result.layers[0].passes
            mattes = {}
            if self.mattes is not None and "matte_keys" in arrays:
                mattes = self.mattes.passes(arrays["matte_keys"], arrays["matte_coverage"])
                arrays = dict(arrays, **mattes)
            for p in PASSES:
                if p.source in arrays and p.name in layer_passes:
                    set_pass(layer_passes[p.name], p.values(arrays))
            for name, values in mattes.items():
                if name.startswith("Crypto") and name in layer_passes:
                    set_pass(layer_passes[name], values)
            if self.mattes is not None and "matte_keys" in arrays:
                if not self.stamped and self.mattes.layers:   # (on the whole render's result, as Cycles adds them)
                    whole = self.engine.get_result()
                    for key, value in self.mattes.metadata().items():
                        whole.stamp_data_add_field(key, value)
                    self.stamped = True
        finally:
            self.engine.end_result(result)


def run(engine, job, writer: ResultWriter) -> bool:
    """Run `job` to completion (True) or until Blender cancels it (False)."""
    job.start()
    try:
        last_stats = 0.0
        while True:
            finished = job.finished
            for tile in job.poll():
                writer.write(tile.x, tile.y, {"rgba": tile.rgba, **(tile.passes or {})})
            engine.update_progress(job.progress)
            now = time.monotonic()
            if finished or now - last_stats > STATS_SECONDS:
                engine.update_stats("", stats_text(job))
                last_stats = now
            if finished:
                break
            if break_requested(engine):
                t_break = time.perf_counter()
                job.cancel()
                print(f"Gridwalk: cancel stopped all workers in "
                      f"{(time.perf_counter() - t_break) * 1e3:.1f} ms")
                for tile in job.poll():         # tiles finished before the workers stopped
                    writer.write(tile.x, tile.y, {"rgba": tile.rgba, **(tile.passes or {})})
                writer.ensure_written()
                return False
            job.wait_for(POLL_SECONDS)   # returns as soon as a tile is done or the job ends
        job.wait()                  # rethrows a worker's error
        for tile in job.poll():     # the last tiles, if any finished after the final poll
            writer.write(tile.x, tile.y, {"rgba": tile.rgba, **(tile.passes or {})})
        return True
    except BaseException:
        job.cancel()
        try:
            writer.ensure_written()
        except Exception:           # keep the original error
            pass
        raise
