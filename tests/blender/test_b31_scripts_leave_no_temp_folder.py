"""Scripts that end through blender_addon.scripting (the README's demo, the
benchmarks, these tests) leave with os._exit, which skips Blender's own
removal of its session folder /tmp/blender_XXXXXX; scripting.leave removes it
first. Before, every demo render left one behind (thousands after a few test
runs). Checked in each Blender, with a file left in the folder."""
import json
import os

from runner import run_script


def test_the_session_temp_folder_is_removed_at_exit(any_blender, tmp_path):
    run_script(any_blender, "temp_folder.py", tmp_path)
    info = json.loads((tmp_path / "temp_folder.json").read_text())
    assert info["existed"] is True
    assert os.path.basename(os.path.normpath(info["session"])).startswith("blender_")
    assert not os.path.exists(info["session"])
