"""While Blender's process-wide flag refuses Python's writes to ID data (a
render of a Python engine on a job thread can leave it so for a whole GUI
session: docs/blender.md), plain writes and every bpy.ops call fail, and a
window-manager property's update callback still writes and calls operators.
The GUI tests' scripts depend on it (scripts/write_permission.py), and
docs/blender.md gives it to users as the way out; checked in each Blender."""
import json

from runner import run_script


def test_writes_go_through_a_window_manager_property_update(any_blender, tmp_path):
    run_script(any_blender, "write_refused.py", tmp_path)
    info = json.loads((tmp_path / "write_refused.json").read_text())
    assert info["refused_outside"] is False
    # what a stuck flag does to a script
    assert info["refused_in_poll"] is True
    assert "Writing to ID classes in this context is not allowed" in info["plain_write"]
    assert "modify blend data in this state" in info["plain_operator"]   # (5.0: "cannot", before: "can't")
    # the way out: the write and the operator call inside the update both happen
    assert info["in_update"] == "done"
    assert info["operator_ran"] == 1
    assert info["color_after_update"] == [0.5, 0.25, 0.125]
    # the flag is as it was after the update, and an error inside it reaches the caller
    assert info["refused_after_update"] is True
    assert info["error_raised"] is True
