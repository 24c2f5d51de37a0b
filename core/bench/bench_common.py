"""Shared pieces of the benchmarks (bench_all.py): sizes, timing, machine info,
markdown tables, plots and the Blender subprocess."""
from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import matplotlib
import numpy as np

import gridwalk as gw

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
SPD = ROOT.parent / "shared" / "scenes" / "spd"
BPY_PYTHON = ROOT / ".venv-bpy45" / "bin" / "python"
BENCH = Path(__file__).resolve().parent
IMAGES = "images/benchmarks"
NPROC = os.cpu_count() or 1


@dataclass
class Sizes:
    """Everything the full run and the --quick run do differently."""
    quick: bool
    res: int = 512                       # section 1 and 4 image size
    none_budget: float = 12.0            # seconds of single-core brute force per scene
    seed_scenes: tuple = ("balls_s4", "mount_s8", "suzanne", "distant")
    distant_dof: int = 32
    embree_scenes: tuple = ("scan_on_plane", "scans_on_floor", "balls_s4", "balls_s4_analytic", "mount_s6",
                            "mount_s8", "suzanne")
    embree_rays: int = 512 * 512
    sphere_subdiv: int = 2               # icosphere level: 2 -> 320 triangles a sphere
    cycles_scene: str = "balls_s3"
    cycles_size: tuple = (320, 240)
    cycles_spp: tuple = (1, 4, 9, 16, 36, 64)
    cycles_ref_spp: int = 100            # per half (a square: n x n); the reference is the mean of two halves
    havran_scenes: tuple = ("balls_s4", "mount_s6", "mount_s8")
    sweep: tuple = (0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0, 6.0, 8.0)
    soups: tuple = (1_000, 4_000, 16_000, 64_000, 256_000, 1_000_000, 2_000_000)
    suzanne_levels: tuple = (1, 2, 3, 4, 5)
    reps: int = 3
    capacity: float = float(NPROC)       # effective cores measured at the start (parallel_capacity)

    @classmethod
    def make(cls, quick: bool) -> "Sizes":
        if not quick:
            return cls(quick=False)
        return cls(quick=True, res=48, none_budget=0.3, seed_scenes=("balls_s2", "mount_s4", "suzanne", "distant"),
                   distant_dof=4, embree_scenes=("scan_on_plane", "balls_s2", "balls_s2_analytic", "mount_s4", "suzanne"), embree_rays=4096,
                   sphere_subdiv=1, cycles_scene="balls_s1", cycles_size=(40, 30), cycles_spp=(1, 4, 9),
                   cycles_ref_spp=16, havran_scenes=("balls_s2", "mount_s4"), sweep=(1.0, 2.0, 4.0),
                   soups=(1_000, 4_000, 16_000), suzanne_levels=(1, 2), reps=1)


@dataclass
class Section:
    """One section of docs/benchmarks.md: its markdown, headline lines and gaps."""
    title: str
    lines: list = field(default_factory=list)
    headline: list = field(default_factory=list)
    gaps: list = field(default_factory=list)
    seconds: float = 0.0


# -- timing ---------------------------------------------------------------------

def render_once(scene, settings):
    """Render with RenderJob: the grid is built when the job is constructed, before the clock.
    Returns (wall seconds, stats with 'cpu_seconds': the process's CPU time during the render)."""
    job = gw.RenderJob(scene, settings)
    t0, c0 = time.perf_counter(), time.process_time()
    job.start()
    job.wait()
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    stats = job.stats
    stats["cpu_seconds"] = cpu
    stats["image"] = job.image
    return wall, stats


def check_identical(what: str, images: dict, region=None) -> None:
    """Raise if the renders in `images` ({label: rgba}) are not bit-identical (over
    `region` = (x, y, w, h) of the first one where given): acceleration settings,
    mailboxes and thread counts must never change an image."""
    labels = list(images)
    crop = (lambda im: im) if region is None else \
        (lambda im: im[region[1]:region[1] + region[3], region[0]:region[0] + region[2]])
    ref = crop(images[labels[0]])
    for label in labels[1:]:
        other = crop(images[label])
        if not np.array_equal(ref, other):
            bad = int(np.sum(np.any(ref != other, axis=-1)))
            raise RuntimeError(f"{what}: '{label}' renders a different image from '{labels[0]}' "
                               f"({bad} pixels differ)")


def timed_render(scene, settings, reps):
    """(best render seconds, stats of that render); build time is in stats['grid']."""
    best, stats = float("inf"), None
    for i in range(reps):
        dt, st = render_once(scene, settings)
        if dt < best:
            best, stats = dt, st
        if dt >= 20.0 or (dt >= 3.0 and i >= 1):
            break
    return best, stats


def parallel_capacity(seconds: float = 0.3, threads: int = NPROC) -> float:
    """Cores this process can get right now: `threads` threads each hash the same data (hashlib
    releases the GIL); effective cores = threads * (time for one thread) / (time for all of them).
    Median of 3. Other work on the machine, or cores that slow down when their neighbours are busy,
    show up as fewer than `threads`."""
    import hashlib
    import threading
    data = os.urandom(1 << 24)
    t0 = time.perf_counter()
    hashlib.sha256(data).digest()
    rounds = max(1, int(seconds / max(time.perf_counter() - t0, 1e-4)))

    def work():
        for _ in range(rounds):
            hashlib.sha256(data).digest()

    def timed(n):
        threads = [threading.Thread(target=work) for _ in range(n)]
        t = time.perf_counter()
        for th in threads:
            th.start()
        for th in threads:
            th.join()
        return time.perf_counter() - t
    timed(1)   # warm-up: a core waking from idle runs the first round slower (1 thread read 1.28x)
    return float(np.median([threads * timed(1) / timed(threads) for _ in range(3)]))


def interleaved(scene, columns, reps):
    """{label: (best seconds, stats)} rendering the columns in turn, `reps` rounds (so that a change in
    the machine's load hits every column alike); a column whose render takes 20 s or more runs once."""
    best = {}
    for r in range(reps):
        for label, settings in columns:
            if r and best[label][0] >= 20.0:
                continue
            dt, st = render_once(scene, settings)
            if label not in best or dt < best[label][0]:
                best[label] = (dt, st)
    return best


def alternate(fa, fb, reps, clock=time.process_time, budget=None):
    """Time fa() and fb() in turn, `reps` rounds (no new round once `budget` seconds of wall time have
    gone, where one is given): (best a seconds, a's result, best b seconds, b's result). By default the
    time is the process's CPU time, not wall time: both calls run on the calling thread alone, and on
    a machine shared with other work CPU time is what the call costs, where wall time would also count
    the time other processes held the core."""
    best = [float("inf"), None, float("inf"), None]
    start = time.perf_counter()
    for k in range(reps):
        if k and budget is not None and time.perf_counter() - start > budget:
            break
        for i, fn in ((0, fa), (2, fb)):
            t0 = clock()
            out = fn()
            dt = clock() - t0
            if dt < best[i]:
                best[i], best[i + 1] = dt, out
    return tuple(best)


def alternate_builds(fa, fb):
    """alternate() for two builds: wall time (both build on all cores), best of up to 3 rounds, no new
    round after 2 s. A build of a few milliseconds moves by 30% and more from one call to the next
    (thread start-up, page faults); the best of a few is what the build costs."""
    return alternate(fa, fb, 3, clock=time.perf_counter, budget=2.0)


# -- machine ----------------------------------------------------------------------

def cpu_model() -> str:
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine_info() -> dict:
    import importlib.metadata as md

    def version(name):
        try:
            return md.version(name)
        except md.PackageNotFoundError:
            return "not installed"
    return {"nproc": NPROC, "cpu": cpu_model(), "load": os.getloadavg(), "capacity": parallel_capacity(),
            "python": platform.python_version(),
            "gridwalk": gw.__version__, "embreex": version("embreex"), "numpy": np.__version__,
            "os": platform.platform()}


# -- markdown and plots -------------------------------------------------------------

def table(headers, rows) -> list:
    out = ["| " + " | ".join(headers) + " |", "|" + "---|" * len(headers)]
    out += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return out + [""]


def hms(seconds: float) -> str:
    """The seed's style: 12m14s, 2h21m3s, 1.5s, 0.052s."""
    if seconds >= 3600:
        h, rest = divmod(round(seconds), 3600)
        return f"{h}h{rest // 60}m{rest % 60}s"
    if seconds >= 60:
        m, s = divmod(round(seconds), 60)
        return f"{m}m{s}s"
    return f"{seconds:.2f}s" if seconds >= 0.1 else f"{seconds:.3f}s"


def figure(ncols=1, width=5.0, height=3.6):
    fig, axes = plt.subplots(1, ncols, figsize=(width * ncols, height), squeeze=False)
    return fig, axes[0]


def save(fig, out: Path, name: str) -> str:
    """Save under OUT/images/benchmarks/NAME.png; returns the markdown image line."""
    path = out / IMAGES / f"{name}.png"
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return f"![{name}]({IMAGES}/{name}.png)"


# -- Blender ------------------------------------------------------------------------

def bpy_missing() -> str | None:
    return None if BPY_PYTHON.exists() else f"{BPY_PYTHON} is missing (run .ci/setup_blender.sh)"


def run_bpy(*args, timeout: float = 600) -> str:
    """Run bench_bpy.py with `args` in the bpy 4.5 virtualenv; returns its stdout."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run([str(BPY_PYTHON), str(BENCH / "bench_bpy.py"), *map(str, args)], env=env,
                          capture_output=True, text=True, timeout=timeout)
    if proc.returncode != 0:
        raise RuntimeError(f"bench_bpy.py {' '.join(map(str, args))} failed:\n{proc.stdout[-3000:]}\n"
                           f"{proc.stderr[-3000:]}")
    return proc.stdout


def blender_version(stdout: str) -> str:
    for line in stdout.splitlines():
        if line.startswith("{"):
            return json.loads(line).get("blender", "?")
    return "?"


def log(*args):
    print(*args, file=sys.stderr, flush=True)
