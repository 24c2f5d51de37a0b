"""Bad scenes give a clear message in Blender's report, never a crash."""
import json

import pytest

from runner import run_script


@pytest.mark.parametrize("scene, message", [
    ("empty", "Gridwalk: Nothing to render"),
    ("nan", "skipped as invalid: 'Cube'"),    # a NaN vertex: the object is skipped and named
    ("no_camera", "no camera"),      # Blender itself stops before the engine runs
])
def test_bad_scene_reports_a_clear_error(any_blender, tmp_path, scene, message):
    run_script(any_blender, "render_scene.py", scene, tmp_path, "GRIDWALK")
    info = json.loads((tmp_path / "gridwalk.json").read_text())
    assert message in info.get("error", ""), info
