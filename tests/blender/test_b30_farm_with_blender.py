"""The farm driving Debian's real `blender -b` (3.4.1) from a real Dask
LocalCluster with 2 worker processes, on a small animation (frames 1-3, frame
3 refused by Gridwalk's memory limit): frames equal single renders of the
plain headless command in every pass, a failing frame is named and the others
are kept, a re-run renders only what is missing, a frame split into border
tiles equals the whole frame, and a worker whose Blender lacks the add-on
fails loudly. Then the Flamenco job type: its commands, run as a Flamenco
worker runs them, render the same frames, and fail without the add-on."""
import json
import logging
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import psutil
import pytest
from distributed import LocalCluster

import exr
import gridwalk
from gridwalk import FarmError
from runner import BLENDER34_SITE, ROOT, _pythonpath, missing_reason, run, run_script
from test_b05_blender_cli import _in, user_env  # noqa: F401  (a fixture: Blender with the add-on enabled)

ADDON = ROOT / "blender_addon"
JOB_TYPE = ROOT / "core" / "python" / "gridwalk" / "renderfarm" / "flamenco_gridwalk.js"
FLAMENCO_HOST = ROOT / "tests" / "blender" / "flamenco_host.js"
REGISTER = "import blender_addon; blender_addon.register()"


@pytest.fixture(scope="module")
def animation(tmp_path_factory):
    """A folder with anim.blend and ref_0001.exr, ref_0002.exr rendered by the plain command."""
    reason = missing_reason("blender34")
    if reason:
        pytest.skip(reason)
    folder = tmp_path_factory.mktemp("farm_blend")
    run_script("blender34", "farm_scene.py", folder / "anim.blend", "failing_frame=3")
    env = _in(folder, dict(os.environ, PYTHONPATH=_pythonpath(BLENDER34_SITE)))
    run(["blender", "-b", "anim.blend", "--python-expr", REGISTER, "-E", "GRIDWALK", "-o", "//ref_####",
         "-s", "1", "-e", "2", "-a"], env, timeout=180, cwd=folder)
    return folder


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """A LocalCluster whose workers' Blender has no user preferences (no add-on enabled)."""
    prefs = tmp_path_factory.mktemp("no_user_prefs")
    env = {"BLENDER_USER_CONFIG": str(prefs / "config"), "BLENDER_USER_SCRIPTS": str(prefs / "scripts")}
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR, env=env) as cluster:
        yield cluster.scheduler_address


def farm(animation, scheduler, out, **options):
    return gridwalk.farm(animation / "anim.blend", out, scheduler=scheduler, addon=ADDON,
                         blender_pythonpath=str(BLENDER34_SITE), **options)


@pytest.fixture(scope="module")
def failed_run(animation, scheduler):
    """All frames of the .blend (its range, read by Blender on a worker): frame 3 fails."""
    out = animation / "frames"
    with pytest.raises(FarmError) as info:
        farm(animation, scheduler, out)
    return out, str(info.value)


def assert_same_exr(path, reference):
    got, want = exr.read_exr(path), exr.read_exr(reference)
    assert sorted(got) == sorted(want)
    for name in want:
        assert np.array_equal(got[name], want[name]), f"{path.name}: channel {name} differs"


def test_blend_frames_equal_single_renders_of_the_plain_command(failed_run, animation):
    out, _ = failed_run
    for frame in (1, 2):
        assert_same_exr(out / f"frame_{frame:04d}.exr", animation / f"ref_{frame:04d}.exr")
    first, second = (exr.read_exr(out / f"frame_{f:04d}.exr")["ViewLayer.Combined.R"] for f in (1, 2))
    assert not np.array_equal(first, second)                 # the monkey turns: frames differ


def test_a_failing_frame_is_named_and_the_other_frames_are_kept(failed_run):
    out, message = failed_run
    assert message.startswith("1 of 3 frames failed:\n  frame 3 failed on worker tcp://"), message
    assert "more than the limit of 1 MiB" in message                # Gridwalk's own reason
    assert f"2 finished frames are kept in {out}; run the same command again" in message
    assert sorted(p.name for p in out.glob("frame_*")) == ["frame_0001.exr", "frame_0002.exr"]


def test_a_rerun_renders_only_the_missing_frames(failed_run, animation, scheduler):
    out, _ = failed_run
    before = {p.name: p.stat().st_mtime_ns for p in out.glob("frame_*")}
    report = farm(animation, scheduler, out, frames="1-2")
    assert report.reused == [1, 2] and report.rendered == []
    with pytest.raises(FarmError, match=r"^1 of 1 frames failed:\n  frame 3 failed"):
        farm(animation, scheduler, out, frames="1-3")
    assert {p.name: p.stat().st_mtime_ns for p in out.glob("frame_*")} == before


def test_a_frame_split_into_border_tiles_equals_the_whole_frame(animation, scheduler, tmp_path):
    out = tmp_path / "tiled.exr"
    report = farm(animation, scheduler, out, frames="2", tiles=2)
    assert sorted(report.rendered) == [0, 1]
    whole = exr.rgba(exr.read_exr(animation / "ref_0002.exr"), "ViewLayer.Combined.")
    assert np.array_equal(exr.rgba(exr.read_exr(out)), whole)


def test_a_worker_without_the_addon_fails_loudly_instead_of_using_another_engine(animation, scheduler, tmp_path):
    with pytest.raises(FarmError) as info:
        gridwalk.farm(animation / "anim.blend", tmp_path / "frames", frames="1", scheduler=scheduler,
                      blender_pythonpath=str(BLENDER34_SITE))
    assert "frame 1 failed on worker" in str(info.value)
    assert "the GRIDWALK render engine is not registered in Blender 3.4.1 on this worker" in str(info.value)
    assert not list((tmp_path / "frames").glob("frame_*"))


def blender_processes() -> list:
    """Blender processes started below this test process (by the cluster's workers)."""
    return [p for p in psutil.Process().children(recursive=True) if p.name() == "blender"]


def test_ctrl_c_stops_blender_on_every_worker(animation, scheduler, tmp_path):
    argv = [sys.executable, "-m", "gridwalk", "farm", animation / "anim.blend", "-o", tmp_path / "frames",
            "--frames", "1-2", "--scheduler", scheduler, "--addon", ADDON, "--blender-pythonpath", BLENDER34_SITE]
    proc = subprocess.Popen([str(a) for a in argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 60
        while not blender_processes() and time.monotonic() < deadline and proc.poll() is None:
            time.sleep(0.05)
        assert blender_processes(), "no worker started Blender"
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and "gridwalk: cancelled" in err, err
    assert blender_processes() == []
    assert not list((tmp_path / "frames").glob("frame_*"))


def flamenco_tasks(settings: dict) -> dict:
    if shutil.which("node") is None:
        message = "node is missing: run .ci/setup_blender.sh (apt-get install nodejs)"
        if os.environ.get("CI"):             # .ci/setup installs it: in CI a missing node is a failure
            pytest.fail(message)
        pytest.skip(message)
    proc = subprocess.run(["node", str(FLAMENCO_HOST), str(JOB_TYPE), json.dumps(settings)],
                          capture_output=True, text=True, timeout=30)
    assert proc.returncode == 0, proc.stderr
    return json.loads(proc.stdout)


def flamenco_argv(command: dict) -> list:
    """{exe} {exeArgs} {argsBefore} {blendfile} {args}, as a Flamenco worker runs
    blender-render, with {blender} = blender and {blenderArgs} = its default -b -y."""
    p = command["parameters"]
    assert command["name"] == "blender-render" and (p["exe"], p["exeArgs"]) == ("{blender}", "{blenderArgs}")
    return ["blender", "-b", "-y", *p["argsBefore"], p["blendfile"], *p["args"]]


def test_flamenco_job_type_renders_gridwalk_frames_and_fails_without_the_addon(animation, user_env, tmp_path):
    compiled = flamenco_tasks({"frames": "1-2", "chunk_size": 2, "blendfile": str(animation / "anim.blend"),
                               "render_output_path": str(tmp_path / "flamenco_")})
    assert compiled["label"] == "Gridwalk Render"
    assert [t["name"] for t in compiled["tasks"]] == ["gridwalk-render-1-2"]
    argv = flamenco_argv(compiled["tasks"][0]["commands"][0])
    proc = run(argv, user_env, timeout=180)                   # a worker with the add-on installed and enabled
    assert "Saved:" in proc.stdout
    for frame in (1, 2):
        assert_same_exr(tmp_path / f"flamenco_{frame:06d}.exr", animation / f"ref_{frame:04d}.exr")

    bare = {**user_env, "BLENDER_USER_CONFIG": str(tmp_path / "none"), "BLENDER_USER_SCRIPTS": str(tmp_path / "none")}
    proc = subprocess.run(argv, env=bare, capture_output=True, text=True, timeout=180)
    assert proc.returncode == 1
    assert "GRIDWALK-FLAMENCO-ERROR the GRIDWALK render engine is not registered in Blender 3.4.1" in proc.stdout
    failing = flamenco_tasks({"frames": "3", "chunk_size": 1, "blendfile": str(animation / "anim.blend"),
                              "render_output_path": str(tmp_path / "flamenco_")})
    proc = subprocess.run(flamenco_argv(failing["tasks"][0]["commands"][0]), env=user_env, capture_output=True,
                          text=True, timeout=180)
    assert proc.returncode == 1 and "GRIDWALK-FLAMENCO-ERROR frame 3: " in proc.stdout
