"""Run Python scripts inside Blender in a subprocess, with a timeout.

Three kinds of Blender: the `bpy` module from PyPI in its own virtualenv
(.venv-bpy45: Blender 4.5 LTS, .venv-bpy50: Blender 5.0), and Debian's
`blender` binary (3.4.1, system Python 3.11) whose packages (numpy, gridwalk)
live in .venv-blender34 and reach it through PYTHONPATH. Scripts end with
`sys.stdout.flush(); os._exit(code)` because bpy can hang at interpreter exit
after image I/O; the timeout catches any other hang.
"""
from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
SCRIPTS = Path(__file__).resolve().parent / "scripts"
BPY_VENVS = {"bpy45": ROOT / ".venv-bpy45", "bpy50": ROOT / ".venv-bpy50"}
BLENDER34_SITE = ROOT / ".venv-blender34" / "lib" / "python3.11" / "site-packages"
ALL_BLENDERS = (*BPY_VENVS, "blender34")


def _pythonpath(*extra) -> str:
    parts = [str(p) for p in extra] + [str(ROOT)]
    if os.environ.get("PYTHONPATH"):
        parts.append(os.environ["PYTHONPATH"])
    return os.pathsep.join(parts)


def missing_reason(kind: str) -> str | None:
    """Why `kind` cannot run here (None when it can)."""
    if kind in BPY_VENVS:
        python = BPY_VENVS[kind] / "bin" / "python"
        if not python.exists():
            return f"{python} is missing: run .ci/setup_blender.sh"
        return None
    if shutil.which("blender") is None:
        return "the `blender` binary is missing: run .ci/setup_blender.sh (apt-get install blender)"
    if not BLENDER34_SITE.exists():
        return f"{BLENDER34_SITE} is missing: run .ci/setup_blender.sh"
    return None


def command(kind: str, script: Path, args=(), blend: Path | None = None) -> tuple[list, dict]:
    """(argv, env) running `script` with `args` in Blender `kind`."""
    env = dict(os.environ)
    if kind in BPY_VENVS:
        argv = [str(BPY_VENVS[kind] / "bin" / "python"), str(script), *map(str, args)]
        env["PYTHONPATH"] = _pythonpath()
    else:
        argv = ["blender", "-b", "--factory-startup", "-noaudio"]
        argv += [str(blend)] if blend else []
        argv += ["--python", str(script), "--", *map(str, args)]
        env["PYTHONPATH"] = _pythonpath(BLENDER34_SITE)
    return argv, env


def run_script(kind: str, name: str, *args, timeout: float = 180, blend=None, cwd=None):
    """Run tests/blender/scripts/<name> in Blender `kind`; fail with its output on error."""
    argv, env = command(kind, SCRIPTS / name, args, blend)
    return run(argv, env, timeout, cwd)


def render_batch(kind: str, jobs: list, timeout_per_job: float = 30) -> list:
    """Runs scripts/render_scene.py once in Blender `kind` for every job (a list
    of its argument lists: scene, folder, engine, options), each from a new
    empty file, and returns each job's share of the standard output. One
    Blender for many renders: its start-up (1-3 s) is most of a small render's time.
    (A hang fails after 60 s + timeout_per_job per job: the tests' renders take 0.1-3 s.)"""
    if not jobs:
        return []
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump([[str(a) for a in job] for job in jobs], f)
    try:
        proc = run_script(kind, "render_scene.py", "--batch", f.name,
                          timeout=60 + timeout_per_job * len(jobs))
    finally:
        os.unlink(f.name)
    parts = re.split(r"^@@render_scene job \d+\n", proc.stdout, flags=re.M)
    assert len(parts) == len(jobs) + 1, f"{len(parts) - 1} job markers for {len(jobs)} jobs:\n{proc.stdout[-3000:]}"
    return parts[1:]


def rendered_luminance(kind: str, folder: Path, scene: str, engine: str, *options):
    """Luminance of scripts/render_scene.py's render of `scene` with `engine` into a new `folder`
    (the film opaque; options as render_scene.py takes them, 'key=json')."""
    import exr
    folder.mkdir()
    run_script(kind, "render_scene.py", scene, folder, engine, "transparent=false", *options)
    return exr.luminance(exr.rgba(exr.read_exr(folder / f"{engine.lower()}.exr"), "ViewLayer.Combined."))


def luminance_by_engine(kind: str, out: Path, scene: str, engines: dict, variants: dict) -> dict:
    """{(engine, variant): rendered_luminance} of `scene` with each engine's option string
    (engines: {engine: option}) and each variant's scene options (variants: {variant: dict}),
    all rendered in one Blender (render_batch)."""
    import exr
    keys = [(engine, key) for engine in engines for key in variants]
    for engine, key in keys:
        (out / f"{engine}_{key}").mkdir()
    render_batch(kind, [[scene, out / f"{engine}_{key}", engine, "transparent=false",
                         f"scene={json.dumps(variants[key])}", engines[engine]] for engine, key in keys])
    return {(engine, key): exr.luminance(exr.rgba(exr.read_exr(out / f"{engine}_{key}" / f"{engine.lower()}.exr"),
                                                  "ViewLayer.Combined."))
            for engine, key in keys}


def rgb_by_engine(kind: str, out: Path, scene: str, engines: dict) -> dict:
    """{engine: linear RGB (h, w, 3)} of `scene` rendered opaque with each engine's option
    string (engines: {engine: option}), all in one Blender (render_batch)."""
    import exr
    for engine in engines:
        (out / engine).mkdir()
    render_batch(kind, [[scene, out / engine, engine, "transparent=false", engines[engine]] for engine in engines])
    return {engine: exr.rgba(exr.read_exr(out / engine / f"{engine.lower()}.exr"), "ViewLayer.Combined.")[..., :3]
            for engine in engines}


def script_output(kind: str, tmp_path_factory, script: str, *args, timeout: float = 180) -> Path:
    """For module fixtures: skip when Blender `kind` is missing, else run
    scripts/<script> OUT_DIR *args in it and return OUT_DIR (a new folder)."""
    import pytest
    reason = missing_reason(kind)
    if reason:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp(f"{Path(script).stem}_{kind}")
    run_script(kind, script, out, *args, timeout=timeout)
    return out


def run(argv, env=None, timeout: float = 180, cwd=None) -> subprocess.CompletedProcess:
    try:
        proc = subprocess.run(argv, env=env, cwd=cwd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired as exc:
        raise AssertionError(f"timed out after {timeout} s: {' '.join(argv)}\n"
                             f"{(exc.stdout or '')[-3000:]}\n{(exc.stderr or '')[-3000:]}") from None
    if proc.returncode != 0:
        raise AssertionError(f"exit code {proc.returncode}: {' '.join(argv)}\n"
                             f"--- stdout\n{proc.stdout[-4000:]}\n--- stderr\n{proc.stderr[-4000:]}")
    return proc




# Gridwalk at 6 x 6 jittered samples and 4 glossy rays against Cycles at 128 samples: the
# comparisons of glossy surfaces (test_b34, test_b35).
GLOSSY_ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 6, "glossy_samples": 4}',
                  "CYCLES": "samples=128"}


def combined_rgb_by_variant(kind: str, out: Path, scene: str, key: str, values, engines: dict) -> dict:
    """{(value, engine): linear RGB} of scripts/render_scene.py's `scene` with scene option
    `key` set to each of `values`, rendered by each engine (option strings as render_scene.py
    takes them), all in one Blender `kind` (render_batch), the film opaque."""
    import exr
    jobs, folders = [], {}
    for value in values:
        for engine, option in engines.items():
            folders[value, engine] = out / f"{value}_{engine}"
            folders[value, engine].mkdir()
            jobs.append([scene, folders[value, engine], engine, "transparent=false", option,
                         f'scene={{"{key}": "{value}"}}'])
    render_batch(kind, jobs)
    return {k: exr.rgba(exr.read_exr(folder / f"{k[1].lower()}.exr"), "ViewLayer.Combined.")[..., :3]
            for k, folder in folders.items()}


def row_sphere_means(rgb, count: int):
    """(count, 3) mean colours of glossy_scenes' row of spheres (radius 0.8 at x = -3, -1, 1, ...,
    seen by an orthographic camera 8 units wide), each over the square inside its outline."""
    import numpy as np
    h, w = rgb.shape[:2]
    half = int(0.8 / 8.0 * w * 0.7)                 # 0.7 of the radius, in pixels
    out = []
    for i in range(count):
        x = int(round((0.5 + (-3.0 + 2.0 * i) / 8.0) * w))
        out.append(rgb[h // 2 - half:h // 2 + half, x - half:x + half].reshape(-1, 3).mean(axis=0))
    return np.array(out)
