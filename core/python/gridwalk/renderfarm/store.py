"""Finished tiles and frames on disk, one file each, written atomically.

A folder holds the results and a manifest (.gridwalk-farm.json) that records,
for each result, the digest of the job it was rendered for (scene, settings,
tile layout). A re-run with the same digest finds them and renders only what
is missing; a result of another job (the scene or a setting changed) is
rendered again. A file is renamed into place only when complete, and entered
in the manifest after that, so an interrupted run never leaves a result that
looks finished but is not.
"""
from __future__ import annotations

import io
import json
import os
from pathlib import Path

import numpy as np

MANIFEST = ".gridwalk-farm.json"


def write_atomically(path: Path, data: bytes) -> None:
    """Write to a temporary name, then rename: a reader (or a re-run after the
    process was killed) sees the old file or the whole new one, never a part."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def npy_bytes(array: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, array)
    return buf.getvalue()


class ResultStore:
    """results = ResultStore(folder, digest); results.find("tile_0003") -> Path or None;
    results.put("tile_0003", ".npy", data)."""

    def __init__(self, folder, digest: str):
        self.folder = Path(folder)
        self.digest = digest
        self.folder.mkdir(parents=True, exist_ok=True)
        try:
            self.records = json.loads((self.folder / MANIFEST).read_text())
            if not isinstance(self.records, dict):
                self.records = {}
        except (OSError, ValueError):
            self.records = {}

    def find(self, stem: str) -> Path | None:
        """The finished result `stem` of this job, or None."""
        record = self.records.get(stem)
        if not isinstance(record, dict) or record.get("digest") != self.digest:
            return None
        path = self.folder / str(record.get("file", ""))
        return path if path.is_file() else None

    def put(self, stem: str, suffix: str, data: bytes) -> Path:
        path = self.folder / (stem + suffix)
        write_atomically(path, data)
        self.records[stem] = {"file": path.name, "digest": self.digest}
        write_atomically(self.folder / MANIFEST, json.dumps(self.records, separators=(",", ":")).encode())
        return path

    def remove(self) -> None:
        """Delete the stored results of every job, and the folder if that empties it."""
        for record in self.records.values():
            if isinstance(record, dict) and record.get("file"):
                (self.folder / record["file"]).unlink(missing_ok=True)
        (self.folder / MANIFEST).unlink(missing_ok=True)
        try:
            self.folder.rmdir()
        except OSError:
            pass
