"""Bad scenes give a clear message in Blender's report, never a crash."""
import json

import pytest

from runner import run_script


@pytest.mark.parametrize("scene, message", [
    ("no_camera", "no camera"),      # Blender itself stops before the engine runs
])
def test_bad_scene_reports_a_clear_error(any_blender, tmp_path, scene, message):
    run_script(any_blender, "render_scene.py", scene, tmp_path, "GRIDWALK")
    info = json.loads((tmp_path / "gridwalk.json").read_text())
    assert message in info.get("error", ""), info


@pytest.mark.parametrize("scene, message", [
    ("empty", "Gridwalk: Nothing to render: the scene has no visible object with faces"),
    ("nan", "skipped as invalid: 'Cube'"),    # a NaN vertex: the object is skipped and named
])
def test_a_scene_with_nothing_to_render_shows_the_world_and_says_why(any_blender, tmp_path, scene, message):
    # (these were errors, which stopped an animation or a farm at such a frame; Cycles renders the world)
    proc = run_script(any_blender, "render_scene.py", scene, tmp_path, "GRIDWALK")
    info = json.loads((tmp_path / "gridwalk.json").read_text())
    assert not info.get("error"), info
    warned = [line for line in proc.stdout.splitlines() if message in line]
    assert warned and warned[0].endswith("the frame shows the world alone"), proc.stdout[-3000:]
