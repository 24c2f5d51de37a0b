"""A .blend file's frames, or one frame split into border tiles, rendered by
Blender with the GRIDWALK engine on the workers.

The .blend travels once per worker, inside the job plugin, and is written to
the worker's local folder; each task runs `blender -b` on that copy (see
blender.py and in_blender.py). Frames come back as the files Blender wrote
(the .blend's output format); tiles come back as float32 pixels and are put
together into a linear float image (.exr or .npy).
"""
from __future__ import annotations

import io
import shutil
import tempfile
from pathlib import Path

import numpy as np

from .. import __version__
from . import plan
from .blender import BlenderSetup, run_blender
from .exr import write_exr
from .jobplugin import JobPlugin, plugin_name
from .store import write_atomically

TILE_OUTPUTS = (".exr", ".npy")
PROBE = "probe"
BLEND_MAGICS = (b"BLENDER", b"\x1f\x8b", b"\x28\xb5\x2f\xfd")   # a .blend: plain, gzip- or zstd-compressed


class BlendOnWorker(JobPlugin):
    """On the workers: the .blend file, how to run Blender, and what to render."""

    def __init__(self, run_id, threads, blend_name, blend_bytes, blender: BlenderSetup, frame, tiles):
        super().__init__(run_id, threads)
        self.what = "tile" if tiles else "frame"
        self.blend_name, self.blend_bytes, self.blender = blend_name, blend_bytes, blender
        self.frame, self.tiles = frame, tiles

    def setup(self, worker):
        super().setup(worker)
        self.folder = Path(worker.local_directory) / plugin_name(self.run_id)
        self.folder.mkdir(parents=True, exist_ok=True)
        self.blend = self.folder / self.blend_name
        self.blend.write_bytes(self.blend_bytes)
        self.blend_bytes = None
        self.scene_loads += 1

    def teardown(self, worker):
        super().teardown(worker)
        shutil.rmtree(self.folder, ignore_errors=True)

    def label(self, item) -> str:
        if item == PROBE:
            return f"reading {self.blend_name} in Blender"
        if self.tiles:
            return f"tile {item} of frame {'(current)' if self.frame is None else self.frame}"
        return f"frame {item}"

    def run(self, item, key) -> dict:
        work = Path(tempfile.mkdtemp(dir=self.folder))
        try:
            if item == PROBE:
                task = {"action": "probe", "frame": None}
            elif self.tiles:
                task = {"action": "tile", "frame": self.frame, "tile": item, "tiles": self.tiles}
            else:
                task = {"action": "frame", "frame": item}
            task.update(output=str(work / self.what), threads=self.render_threads())
            result, _ = run_blender(self.blender, self.blend, task, lambda: self.stop_requested(key))
            if item == PROBE:
                return result
            if self.tiles:
                result["rgba"] = np.load(work / "tile.npy")
            else:
                if result.get("frame") != item:   # (Blender clamps frame_set to its frame range)
                    raise RuntimeError(f"Blender rendered frame {result.get('frame')} for frame {item}")
                written = sorted(p for p in work.iterdir() if p.name.startswith("frame"))
                if len(written) != 1:
                    raise RuntimeError(f"Blender wrote {len(written)} files for one frame: "
                                       f"{[p.name for p in written]}")
                result.update(data=written[0].read_bytes(), suffix="".join(written[0].suffixes))
            return result
        finally:
            shutil.rmtree(work, ignore_errors=True)


class BlendJob:
    """On the client: frames (output: a folder) or the tiles of one frame (output: .exr or .npy)."""

    def __init__(self, blend, output, frames=None, tiles=None, blender: BlenderSetup | None = None):
        self.blend = Path(blend)
        self.data = self.blend.read_bytes()
        if not self.data.startswith(BLEND_MAGICS):
            # (found out only once a cluster had started and Blender had failed on every worker)
            raise ValueError(f"{self.blend}: not a .blend file (it starts with {self.data[:8]!r}; a .blend starts "
                             "with BLENDER, or is gzip or zstd compressed)")
        self.output = Path(output)
        self.blender = blender or BlenderSetup()
        if tiles is not None and (isinstance(tiles, bool) or not isinstance(tiles, int) or tiles < 1):
            raise ValueError(f"--tiles must be at least 1, got {tiles!r}")
        self.tiles = tiles
        self.frames = plan.parse_frames(frames) if frames is not None else None
        self.frame = None
        self._size_known = not tiles     # (a tiled frame's size comes from Blender: use_probe checks the tiles)
        if tiles:
            if self.frames is not None and len(self.frames) != 1:
                raise ValueError(f"--tiles splits one frame: give --frames N, not {frames!r}")
            self.frame = self.frames[0] if self.frames else None
            self.items = list(range(tiles))
            if self.output.suffix.lower() not in TILE_OUTPUTS:
                raise ValueError(f"{self.output}: a tiled frame is written as linear float: "
                                 f"the output must end in {' or '.join(TILE_OUTPUTS)}")
            self.folder = self.output.with_name(self.output.name + ".parts")
        else:
            self.items = self.frames
            if self.output.exists() and not self.output.is_dir():
                raise ValueError(f"{self.output}: frames are written into a folder, and this is a file")
            self.folder = self.output
        if not self.output.parent.is_dir():
            raise ValueError(f"{self.output}: the folder {str(self.output.parent)!r} does not exist")
        self.what = "tile" if tiles else "frame"
        self.digest = plan.digest(__version__, plan.digest(self.data), self.what, self.frame, tiles)

    @property
    def needs_probe(self) -> bool:
        """Frames to render are not known before Blender reads the .blend."""
        return self.items is None or not self._size_known

    def use_probe(self, result: dict) -> None:
        """The .blend's frame range (frames not given) and image size (tiles: ValueError where
        they do not fit it, before a task starts Blender for a tile that cannot be)."""
        if self.items is None:
            self.items = list(range(result["frame_start"], result["frame_end"] + 1))
        if self.tiles:
            plan.tile_grid(int(result["width"]), int(result["height"]), self.tiles)
            self._size_known = True

    def describe(self) -> str:
        if self.tiles:
            frame = "the current frame" if self.frame is None else f"frame {self.frame}"
            return f"{self.blend.name}, {frame} in {self.tiles} tiles, through Blender"
        first, last = self.items[0], self.items[-1]
        return f"{self.blend.name}, {len(self.items)} frames ({first}-{last}), through Blender"

    def stem(self, item) -> str:
        return f"{self.what}_{item:04d}"

    def plugin(self, run_id: str, threads: int) -> BlendOnWorker:
        return BlendOnWorker(run_id, threads, self.blend.name, self.data, self.blender, self.frame, self.tiles)

    def keep(self, store, item, result: dict) -> None:
        if self.tiles:
            buf = io.BytesIO()
            np.savez(buf, rgba=result["rgba"], rect=result["rect"], size=result["size"])
            store.put(self.stem(item), ".npz", buf.getvalue())
        else:
            store.put(self.stem(item), result["suffix"], result["data"])

    def finish(self, store) -> Path:
        if not self.tiles:
            return self.output
        image = None
        for item in self.items:
            with np.load(store.find(self.stem(item))) as tile:
                if image is None:
                    width, height = (int(v) for v in tile["size"])
                    image = np.zeros((height, width, 4), np.float32)
                x, y, w, h = (int(v) for v in tile["rect"])
                image[y:y + h, x:x + w] = tile["rgba"]
        if self.output.suffix.lower() == ".npy":
            write_atomically(self.output, image)
        else:
            write_exr(self.output, image)
        store.remove()
        return self.output
