"""Finished tiles and frames on disk, one file each, written atomically.

A folder holds the results and a journal (.gridwalk-farm.jsonl) with a line
per result: its name, its file and the digest of the job it was rendered for
(scene, settings, tile layout). A re-run with the same digest finds them and
renders only what is missing; a result of another job (the scene or a setting
changed) is rendered again. A file is renamed into place only when complete,
and its line is appended after that, in one write, so an interrupted run
never leaves a result that looks finished but is not (a line cut short by a
crash is not read; a later line for the same name wins). Appending a line,
instead of rewriting a whole manifest, keeps the cost of a result constant:
the client keeps every tile of a run, and on a 2-core machine its work takes
time from the workers.
"""
from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

try:
    import fcntl
except ImportError:                         # (not POSIX: no lock; one run per output is then the user's care)
    fcntl = None

JOURNAL = ".gridwalk-farm.jsonl"
OLD_MANIFEST = ".gridwalk-farm.json"       # what versions before the journal wrote: removed with the results
LOCK = ".gridwalk-farm.lock"               # held by the run writing the folder (its process id inside)


class StoreBusy(RuntimeError):
    """Another run holds the folder: two runs writing one output mixed their tiles."""


_HELD = {}    # folder (real path) -> [lock file descriptor, stores of this process holding it]


def write_atomically(path: Path, data) -> None:
    """Write `data` (bytes, or an array saved as .npy) to a temporary name,
    then rename: a reader (or a re-run after the process was killed) sees the
    old file or the whole new one, never a part."""
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        if isinstance(data, np.ndarray):
            np.lib.format.write_array(f, np.ascontiguousarray(data), allow_pickle=False)
        else:
            f.write(data)
    os.replace(tmp, path)


class ResultStore:
    """results = ResultStore(folder, digest); results.find("tile_0003") -> Path or None;
    results.put("tile_0003", ".npy", array_or_bytes)."""

    def __init__(self, folder, digest: str):
        """StoreBusy where another run (of any job) holds `folder`: each run locks it until
        close() or remove() (an exclusive flock, which a killed run's system releases)."""
        self.folder = Path(folder)
        self.digest = digest
        self.folder.mkdir(parents=True, exist_ok=True)
        self._lock = self._take_lock()
        self.records = {}
        try:
            data = (self.folder / JOURNAL).read_bytes()
        except OSError:
            data = b""
        if data and not data.endswith(b"\n"):   # a line cut short: the next one must start afresh
            self._append(b"\n")
        lines = data.split(b"\n")
        for line in lines:
            try:
                record = json.loads(line)
            except ValueError:          # empty, or cut short by a crash
                continue
            if isinstance(record, dict) and isinstance(record.get("stem"), str):
                self.records[record["stem"]] = record
        if len(lines) > 2 * len(self.records) + 64:
            # A frames folder keeps its journal from run to run (a line per frame
            # each time): written again with the current lines only.
            write_atomically(self.folder / JOURNAL, b"".join(self._line(r) for r in self.records.values()))

    def find(self, stem: str) -> Path | None:
        """The finished result `stem` of this job, or None."""
        record = self.records.get(stem)
        if not isinstance(record, dict) or record.get("digest") != self.digest:
            return None
        path = self.folder / str(record.get("file", ""))
        return path if path.is_file() else None

    def put(self, stem: str, suffix: str, data) -> Path:
        """Keep `data` (bytes, or an array saved as .npy) as the result `stem`."""
        path = self.folder / (stem + suffix)
        write_atomically(path, data)
        record = {"stem": stem, "file": path.name, "digest": self.digest}
        self._append(self._line(record))
        self.records[stem] = record
        return path

    @staticmethod
    def _line(record: dict) -> bytes:
        return json.dumps(record, separators=(",", ":")).encode() + b"\n"

    def _append(self, line: bytes) -> None:
        """Append `line` in one write (O_APPEND); OSError if the disk takes only part of it."""
        fd = os.open(self.folder / JOURNAL, os.O_WRONLY | os.O_APPEND | os.O_CREAT, 0o644)
        try:
            written = os.write(fd, line)
        finally:
            os.close(fd)
        if written != len(line):        # a full disk: the part written is a torn line, skipped when read
            raise OSError(f"{self.folder / JOURNAL}: only {written} of {len(line)} bytes written (disk full?)")

    def _take_lock(self):
        """The folder's key in _HELD, its lock taken (shared by the stores of this process: a
        process's own re-runs open the folder again), or None without fcntl."""
        if fcntl is None:
            return None
        key = os.path.realpath(self.folder)
        if key in _HELD:
            _HELD[key][1] += 1
            return key
        fd = os.open(self.folder / LOCK, os.O_RDWR | os.O_CREAT, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.read(fd, 32).decode(errors="replace").strip() or "?"
            os.close(fd)
            raise StoreBusy(f"{self.folder} is in use by another farm run (process {holder}) writing the same "
                            "output: wait for it to end, or give this run another output") from None
        os.ftruncate(fd, 0)
        os.write(fd, str(os.getpid()).encode())
        _HELD[key] = [fd, 1]
        return key

    def close(self) -> None:
        """Let other runs use the folder (its results stay)."""
        key, self._lock = getattr(self, "_lock", None), None
        if key is not None and key in _HELD:
            _HELD[key][1] -= 1
            if _HELD[key][1] == 0:
                os.close(_HELD.pop(key)[0])      # (closing the descriptor releases the flock)

    def __del__(self):
        self.close()

    def remove(self) -> None:
        """Delete the stored results of every job, and the folder if that empties it. The lock
        goes last, while still held (a run starting meanwhile is refused, not handed the
        results being deleted), and only by this process's last store holding it."""
        for record in self.records.values():
            if isinstance(record, dict) and record.get("file"):
                (self.folder / record["file"]).unlink(missing_ok=True)
        (self.folder / JOURNAL).unlink(missing_ok=True)
        (self.folder / OLD_MANIFEST).unlink(missing_ok=True)
        if self._lock is None or _HELD.get(self._lock, [None, 0])[1] == 1:
            (self.folder / LOCK).unlink(missing_ok=True)
        self.close()
        try:
            self.folder.rmdir()
        except OSError:
            pass
