"""Debian's real `blender` binary (3.4.1): the add-on installed in a user scripts
folder and enabled in saved preferences, then the plain headless command
`blender -b scene.blend -E GRIDWALK -o //out_ -f 1` (which never enters the
viewport's code), and Ctrl-C during a render."""
import os
import signal
import subprocess
import time

import numpy as np
import pytest

import exr
from runner import BLENDER34_SITE, ROOT, _pythonpath, missing_reason, run, run_script


@pytest.fixture(scope="module")
def user_env(tmp_path_factory):
    """Environment of a Blender user who installed and enabled the add-on."""
    reason = missing_reason("blender34")
    if reason:
        pytest.skip(reason)
    home = tmp_path_factory.mktemp("blender_user")
    (home / "scripts" / "addons").mkdir(parents=True)
    (home / "config").mkdir()
    os.symlink(ROOT / "blender_addon", home / "scripts" / "addons" / "gridwalk_blender")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(home / "scripts"),
               BLENDER_USER_CONFIG=str(home / "config"), PYTHONPATH=_pythonpath(BLENDER34_SITE))
    enable = ("import bpy; bpy.ops.preferences.addon_enable(module='gridwalk_blender'); "
              "bpy.ops.wm.save_userpref()")
    run(["blender", "-b", "--python-expr", enable], env, timeout=120)
    assert (home / "config" / "userpref.blend").exists()
    return env


def _in(directory, env):
    """Blender resolves relative paths against $PWD, not the process cwd."""
    return dict(env, PWD=str(directory))


def _blend(tmp_path, *options):
    run_script("blender34", "render_scene.py", "showcase", tmp_path, "GRIDWALK", "blend=true", *options)
    return tmp_path / "scene.blend"


VIEWPORT_CHECK = ("import sys; print('viewport modules:', sorted(m for m in sys.modules "
                  "if m.startswith('gridwalk_blender.viewport')))")


def test_headless_command_line_render_writes_the_image(user_env, tmp_path):
    _blend(tmp_path, "transparent=false", 'settings={"aa": "JITTERED", "aa_samples": 2}')
    proc = run(["blender", "-b", "scene.blend", "-E", "GRIDWALK", "-o", "//out_", "-f", "1",
                "--python-expr", VIEWPORT_CHECK], _in(tmp_path, user_env), timeout=180, cwd=tmp_path)
    assert "Gridwalk: finished" in proc.stdout
    assert "viewport modules: []" in proc.stdout      # the viewport's code (and its gpu import) never ran
    rgba = exr.rgba(exr.read_exr(tmp_path / "out_0001.exr"), "ViewLayer.Combined.")
    assert rgba.shape == (72, 96, 4)
    assert np.all(rgba[..., 3] == 1.0)                 # film not transparent: opaque
    lum = rgba[..., :3].mean(axis=-1)
    assert lum.std() > 0.05 and np.isfinite(lum).all()


def test_blenders_thread_limit_is_the_renders(user_env, tmp_path):
    # `blender -t 1` rendered on every core: Gridwalk's Threads (0, all) did not read Blender's count
    _blend(tmp_path, 'settings={"aa": "JITTERED", "aa_samples": 2}')
    for limit, said in (("1", "on 1 thread,"), ("2", "on 2 threads,")):
        proc = run(["blender", "-b", "scene.blend", "-E", "GRIDWALK", "-t", limit, "-o", "//out_", "-f", "1"],
                   _in(tmp_path, user_env), timeout=180, cwd=tmp_path)
        finished = [line for line in proc.stdout.splitlines() if line.startswith("Gridwalk: finished")]
        assert len(finished) == 1 and said in finished[0], proc.stdout[-2000:]


def test_ctrl_c_cancels_the_render_promptly(user_env, tmp_path):
    _blend(tmp_path, 'scene={"resolution": [1920, 1080]}',
           'settings={"aa": "JITTERED", "aa_samples": 8, "threads": 2}')
    proc = subprocess.Popen(["blender", "-b", "scene.blend", "-E", "GRIDWALK", "-o", "//big_", "-f", "1"],
                            env=_in(tmp_path, user_env), cwd=tmp_path, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, bufsize=1)
    try:
        lines = []
        for line in proc.stdout:
            lines.append(line)
            if "| Tiles " in line and not line.split("| Tiles ")[1].startswith("0/"):
                break
        t_sent = time.monotonic()
        proc.send_signal(signal.SIGINT)
        for line in proc.stdout:
            lines.append(line)
            if "Gridwalk: cancelled" in line:
                break
        reaction = time.monotonic() - t_sent
        proc.wait(timeout=30)
    finally:
        if proc.poll() is None:
            proc.kill()
    text = "".join(lines)
    assert "Gridwalk: cancelled" in text, text[-2000:]
    join_ms = float(text.split("stopped all workers in ")[1].split(" ms")[0])
    assert join_ms < 100.0
    assert reaction < 1.0, f"cancel took {reaction:.3f} s after Ctrl-C"
