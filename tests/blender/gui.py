"""Blender's GUI with GRIDWALK, under Xvfb (Debian's blender 3.4): screenshots.

    python tests/blender/gui.py docs/images/blender_gridwalk.png   # a finished render
    python tests/blender/gui.py viewport docs/images                # the Rendered viewport

Starts Xvfb on a free display, a user profile with the add-on installed and the
splash screen off, runs scripts/gui_screenshot.py in the GUI and waits for it.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from runner import BLENDER34_SITE, ROOT, SCRIPTS, _pythonpath, run  # noqa: E402

SIZE = (1600, 900)


def start_xvfb():
    """(process, display) of a new Xvfb on a free display number."""
    read, write = os.pipe()
    proc = subprocess.Popen(["Xvfb", "-displayfd", str(write), "-screen", "0", f"{SIZE[0]}x{SIZE[1]}x24",
                             "-nolisten", "tcp"], pass_fds=(write,), stderr=subprocess.DEVNULL)
    os.close(write)
    with os.fdopen(read) as f:
        display = f.readline().strip()
    return proc, f":{display}"


def user_profile(home: Path) -> dict:
    (home / "scripts" / "addons").mkdir(parents=True)
    (home / "config").mkdir()
    os.symlink(ROOT / "blender_addon", home / "scripts" / "addons" / "gridwalk_blender")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(home / "scripts"), BLENDER_USER_CONFIG=str(home / "config"),
               PYTHONPATH=_pythonpath(BLENDER34_SITE))
    prefs = ("import bpy; bpy.ops.preferences.addon_enable(module='gridwalk_blender'); "
             "bpy.context.preferences.view.show_splash = False; bpy.ops.wm.save_userpref()")
    run(["blender", "-b", "--python-expr", prefs], env, timeout=120)
    return env


def run_gui(script: str, env: dict, timeout: float = 300):
    """Run scripts/<script> in Blender's GUI under a new Xvfb; `env` adds
    variables. Returns the finished process (fails on a non-zero exit)."""
    xvfb, display = start_xvfb()
    try:
        with tempfile.TemporaryDirectory() as home:
            full_env = dict(user_profile(Path(home)), DISPLAY=display, **env)
            return run(["blender", "--window-geometry", "0", "0", str(SIZE[0]), str(SIZE[1]), "-noaudio",
                        "--python", str(SCRIPTS / script)], full_env, timeout=timeout)
    finally:
        xvfb.terminate()
        xvfb.wait(timeout=10)


def screenshot(out: Path, timeout: float = 300) -> Path:
    out = Path(out).resolve()
    run_gui("gui_screenshot.py", {"SHOT": str(out)}, timeout)
    return out


def viewport_images(folder: Path):
    """docs/images/viewport_*.png: the Rendered viewport through the camera (the
    whole window) and in the orthographic front view (the 3D view), from the
    GUI test's session (scripts/gui_viewport.py)."""
    import json

    from PIL import Image
    folder = Path(folder).resolve()
    with tempfile.TemporaryDirectory() as out:
        run_gui("gui_viewport.py", {"OUT": out})
        info = json.loads((Path(out) / "gui_viewport.json").read_text())
        x, y, w, h = info["shot_front.png"]["region"]
        top = info["shot_front.png"]["window_height"] - (y + h)
        for name, image in (("viewport_camera.png", Image.open(Path(out) / "shot_camera.png")),
                            ("viewport_front.png", Image.open(Path(out) / "shot_front.png").crop(
                                (x, top, x + w, top + h)))):
            image.convert("RGB").quantize(256).save(folder / name, optimize=True)     # 256 colours: smaller
    return folder


if __name__ == "__main__":
    if sys.argv[1:2] == ["viewport"]:
        print(viewport_images(Path(sys.argv[2] if len(sys.argv) > 2 else ".")))
    else:
        print(screenshot(Path(sys.argv[1] if len(sys.argv) > 1 else "blender_gridwalk.png")))
