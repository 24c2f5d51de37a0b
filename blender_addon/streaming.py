"""The render loop: run a gridwalk.RenderJob and stream its tiles into Blender.

The core renders in its own threads with the GIL released. This loop polls
finished tiles every POLL_SECONDS and writes each into the render result
(begin_result / end_result per tile, so the image appears as it renders),
reports progress and statistics, and cancels the job as soon as Blender asks
to stop (test_break): cancel() returns only when no worker thread is left.
The Depth and Normal passes are written once, for the whole frame, at the end.
"""
from __future__ import annotations

import time

import numpy as np

POLL_SECONDS = 0.02
STATS_SECONDS = 0.25


def set_pass(render_pass, values: np.ndarray):
    """Copy (h, w, c) float32 values (row 0 = top) into a render pass (rows bottom-up)."""
    flat = np.ascontiguousarray(values[::-1], dtype=np.float32).reshape(-1)
    try:
        render_pass.rect.foreach_set(flat)                 # Blender 4.x, 5.x
    except TypeError:                                      # Blender 3.x: a sequence of pixels
        render_pass.rect = flat.reshape(-1, values.shape[2])


def stats_text(job) -> str:
    stats = job.stats
    return f"Tiles {job.tiles_done}/{job.tiles_total} | {stats['mrays_per_second']:.1f} Mrays/s"


class ResultWriter:
    """Writes rectangles of the image (row 0 = top, as the core stores it) into Blender."""

    def __init__(self, engine, height: int, layer_name: str, opaque: bool):
        self.engine, self.height, self.layer_name, self.opaque = engine, height, layer_name, opaque

    def write(self, x, y, rgba, depth=None, normal=None):
        h, w = rgba.shape[:2]
        rgba = np.array(rgba, dtype=np.float32)
        if self.opaque:
            rgba[..., 3] = 1.0
        result = self.engine.begin_result(x, self.height - y - h, w, h, layer=self.layer_name)
        try:
            passes = result.layers[0].passes
            set_pass(passes["Combined"], rgba)
            if depth is not None and "Depth" in passes:
                set_pass(passes["Depth"], depth[..., None])
            if normal is not None and "Normal" in passes:
                set_pass(passes["Normal"], normal)
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
                writer.write(tile.x, tile.y, tile.rgba)
            engine.update_progress(job.progress)
            now = time.monotonic()
            if finished or now - last_stats > STATS_SECONDS:
                engine.update_stats("", stats_text(job))
                last_stats = now
            if finished:
                break
            if engine.test_break():
                t_break = time.perf_counter()
                job.cancel()
                print(f"Gridwalk: cancel stopped all workers in "
                      f"{(time.perf_counter() - t_break) * 1e3:.1f} ms")
                return False
            time.sleep(POLL_SECONDS)
        image = job.wait()          # rethrows a worker's error
        writer.write(0, 0, image, np.nan_to_num(job.depth, posinf=1e10), job.normal)
        return True
    except BaseException:
        job.cancel()
        raise
