"""Peak memory and time of the scene-file readers on junk and on real files.

    .venv/bin/python core/bench/bench_readers.py [--before /work/main/.venv/bin/python] [--big]

Each file is loaded (gridwalk.io.load_scene) in a fresh Python process, which
reports the growth of its resident memory's peak (VmHWM after resetting it
through /proc/self/clear_refs), the time, and the first 120 characters of the
error. Junk files are written to a temporary folder (zeros sparse, so they
take no disk) and deleted afterwards. --before runs the same files through
another Python (an older gridwalk) side by side; --big adds the 1 GB cases.
Prints a Markdown table (docs/robustness.md quotes it).
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import textwrap
from pathlib import Path

import numpy as np

from bench_common import SPD

MEASURE = textwrap.dedent("""
    import json, sys, time

    def kib(field):
        with open("/proc/self/status") as f:
            return next(int(line.split()[1]) for line in f if line.startswith(field))

    from gridwalk.io import load_scene
    import gridwalk                            # imports done: measure the reading only
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")
    before, t0 = kib("VmRSS"), time.perf_counter()
    try:
        load_scene(sys.argv[1])
        result = "read"
    except Exception as err:
        result = f"{type(err).__name__}: {str(err)[:4000]}"
    seconds = time.perf_counter() - t0
    print(json.dumps({"mb": (kib("VmHWM") - before) / 1024, "s": seconds, "result": result,
                      "length": len(result)}))
""")


def junk(folder: Path, big: bool) -> dict:
    """{label: path} of the junk files of issue 16 (and the real SPD file for scale)."""
    files = {}

    def sparse(name, head, size):
        path = folder / name
        with open(path, "wb") as f:
            f.write(head)
            f.truncate(size)
        return path
    files["100 MB of zero bytes (.nff)"] = sparse("zeros100.nff", b"", 100 << 20)
    if big:
        files["1 GB of zero bytes (.nff)"] = sparse("zeros1g.nff", b"", 1 << 30)
        files["1 GB comment line: '#' then zero bytes (.nff)"] = sparse("comment1g.nff", b"#", 1 << 30)
    view = b"v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\n"
    token = folder / "token.nff"
    token.write_bytes(view + b"s " + b"7" * (50 << 20))
    files["a 50 MB token after 's ' (.nff)"] = token
    files["mount_s8.nff (11 MB, 131,072 triangles)"] = SPD / "mount_s8.nff"
    files.update(plys(folder))
    return files


def plys(folder: Path) -> dict:
    """A 1M-vertex, 2M-triangle grid as binary and ASCII PLY."""
    import plyfile
    n = 1000
    y, x = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    vertex = np.empty(n * n, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    vertex["x"], vertex["y"], vertex["z"] = x.ravel(), y.ravel(), np.sin(x.ravel() * 0.01)
    v = np.arange(n * n).reshape(n, n)
    tris = np.concatenate([np.stack([v[:-1, :-1], v[1:, :-1], v[:-1, 1:]], -1).reshape(-1, 3),
                           np.stack([v[:-1, 1:], v[1:, :-1], v[1:, 1:]], -1).reshape(-1, 3)])
    face = np.empty(len(tris), dtype=[("vertex_indices", "i4", (3,))])
    face["vertex_indices"] = tris
    out = {}
    for text, label in ((False, "binary"), (True, "ASCII")):
        path = folder / f"grid_{label}.ply"
        plyfile.PlyData([plyfile.PlyElement.describe(vertex, "vertex"),
                         plyfile.PlyElement.describe(face, "face")], text=text).write(str(path))
        out[f"{label} PLY, 1 M vertices, 2 M triangles ({path.stat().st_size >> 20} MB)"] = path
    return out


def measure(python: str, path: Path) -> dict:
    proc = subprocess.run([python, "-c", MEASURE, str(path)], capture_output=True, text=True, timeout=1800)
    if proc.returncode != 0:
        tail = (proc.stderr or proc.stdout).strip().splitlines()[-1:] or ["?"]
        return {"mb": float("nan"), "s": float("nan"), "result": f"crashed: {tail[0][:200]}", "length": 0}
    return json.loads(proc.stdout.strip().splitlines()[-1])


def row(label, r):
    shown = r["result"].replace("|", "\\|").replace(str(Path(tempfile.gettempdir())), "/tmp")
    shown = shown if len(shown) <= 120 else shown[:117] + "..."
    return f"| {label} | {r['mb']:.0f} MB | {r['s']:.2f} s | {r['length']} | {shown} |"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--before", help="another Python whose gridwalk to measure side by side")
    parser.add_argument("--big", action="store_true", help="add the 1 GB junk files")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        files = junk(Path(tmp), args.big)
        for name, python in (("this checkout", sys.executable), ("before", args.before)):
            if not python:
                continue
            print(f"\n{name} ({python}):\n")
            print("| file | peak memory growth | time | message length | result |\n|---|---|---|---|---|")
            for label, path in files.items():
                print(row(label, measure(python, path)), flush=True)


if __name__ == "__main__":
    main()
