"""Scripts that end through blender_addon.scripting (the README's demo, the
benchmarks, these tests) and the farm's Blender tasks (in_blender.py) leave
with os._exit, which skips Blender's own removal of its session folder
(blender_XXXXXX in its temporary folder); gridwalk.renderfarm.blender_exit
removes it first. Before, every demo render and every farm task left one
behind (thousands in /tmp after a few test runs)."""
import json
import os

import pytest

from gridwalk.renderfarm.blender import BlenderSetup, run_blender
from runner import BLENDER34_SITE, ROOT, missing_reason, run, run_script


def test_the_session_temp_folder_is_removed_at_exit(any_blender, tmp_path):
    run_script(any_blender, "temp_folder.py", tmp_path)
    info = json.loads((tmp_path / "temp_folder.json").read_text())
    assert info["existed"] is True        # (with a file in it)
    assert os.path.basename(os.path.normpath(info["session"])).startswith("blender_")
    assert not os.path.exists(info["session"])


def test_a_farm_task_leaves_no_session_folder(tmp_path, monkeypatch):
    reason = missing_reason("blender34")
    if reason:
        pytest.skip(reason)
    run_script("blender34", "render_scene.py", "showcase", tmp_path, "GRIDWALK", "blend=true")
    base = tmp_path / "temp"
    base.mkdir()
    (tmp_path / "config").mkdir()
    monkeypatch.setenv("TMPDIR", str(base))                           # Blender's temporary folder ...
    monkeypatch.setenv("BLENDER_USER_CONFIG", str(tmp_path / "config"))   # ... where no preferences say otherwise
    # The control: Blender left by os._exit alone leaves its folder there.
    run(["blender", "-b", "-noaudio", "--python-expr", "import os; os._exit(0)"], dict(os.environ), timeout=120)
    left = list(base.glob("blender_*"))
    assert len(left) == 1, left
    left[0].rmdir()
    # A farm task (the probe of a .blend) through the farm's own runner.
    setup = BlenderSetup(addon=str(ROOT / "blender_addon"), pythonpath=str(BLENDER34_SITE))
    result, output = run_blender(setup, tmp_path / "scene.blend", {"action": "probe", "frame": None}, lambda: False)
    assert result["width"] > 0, output
    assert list(base.iterdir()) == []
