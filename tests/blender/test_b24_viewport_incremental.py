"""The viewport's incremental updates (bpy 4.5 and 5.0, no GUI).

scripts/viewport_session.py drives a viewport session with real depsgraph
updates. Moving an object reads no mesh and transforms one instance, in the
core (Scene.moved); editing
a mesh shared by two objects reads it once; a modifier change reads that
object only; a material, light, world (a Sky Texture's too), object colour (read by Object Info) or render-setting change, or moving
an empty whose Object coordinates a texture reads, restarts
without touching geometry; a colour-management edit does not restart; a resize waits until it settles.
Instances of one mesh are transformed together, in chunks (blender_addon/export/assemble.py),
so deleting one of two linked duplicates transforms the other again (their chunk changed), and
nothing else (test28 checks that with hundreds of instances).
After every edit the incremental
arrays equal a fresh export's, and the image shown equals a render of the
fresh export (half the shared mesh's faces carry a Checker at Generated
coordinates: moved in the core, they keep their pattern). Stopping the
session leaves no thread running.
"""
import json

import pytest

from runner import BPY_VENVS, script_output

EDITS = {   # edit: (meshes read, instances transformed)
    "move_object": (0, 1),
    "rotate_linked_duplicate": (0, 1),
    "move_texture_empty": (0, 0),    # the empty whose Object coordinates Smooth's Checker reads
    "edit_shared_mesh": (1, 2),
    "change_modifier": (1, 1),
    "change_material": (0, 0),
    "change_object_colour": (0, 0),    # Twin's Viewport Display colour, which its Object Info reads
    "change_light": (0, 0),
    "change_world": (0, 0),
    "sky_world": (0, 0),         # a Sky Texture linked into the world (its image baked in the session)
    "change_sky": (0, 0),        # its sun raised: baked again, the image as a fresh export's
    "change_render_setting": (0, 0),
    "delete_object": (0, 1),     # Twin deleted: Plain, its chunk's other instance, is a chunk of its own
}


@pytest.fixture(scope="module", params=list(BPY_VENVS))
def session(request, tmp_path_factory):
    out = script_output(request.param, tmp_path_factory, "viewport_session.py", timeout=240)
    return json.loads((out / "viewport_session.json").read_text())


def test_linked_duplicates_share_one_exported_mesh(session):
    assert session["initial_reads"] == 2            # Plain and its Twin share a mesh; Smooth has its own


@pytest.mark.parametrize("edit", list(EDITS))
def test_an_edit_reexports_only_what_it_changed(session, edit):
    result = session[edit]
    assert result["restarted"]
    assert (result["reads"], result["transforms"]) == EDITS[edit]


@pytest.mark.parametrize("edit", list(EDITS))
def test_a_transform_edit_moves_the_instance_in_the_core(session, edit):
    """Only a transform edit takes the core's move (Scene.moved); every other edit exports again."""
    assert session[edit]["moved_in_core"] == (1 if edit in ("move_object", "rotate_linked_duplicate") else 0)


@pytest.mark.parametrize("edit", ["initial", *EDITS])
def test_incremental_scene_and_image_equal_a_fresh_export(session, edit):
    result = session[edit]
    assert result["arrays_equal_fresh_export"]
    assert result["image_equals_fresh_render"] and result["coverage"] > 0.1


def test_colour_management_edit_does_not_restart(session):
    assert session["colour_management"] == {"restarted": False, "reads": 0, "transforms": 0, "moved_in_core": 0}


def test_a_resize_is_debounced(session):
    assert session["resize_waits"]                          # nothing rendered in the first 0.15 s
    assert session["resize_rendered_after"] >= 0.3          # RESIZE_DEBOUNCE_SECONDS
    assert session["resized_shape"] == [60, 100, 4]


def test_stopping_leaves_no_thread(session):
    assert session["threads_before"] == 0 and session["threads_rendering_session"] == 1
    assert session["threads_after_stop"] == {"render": 0, "viewport": 0}
    assert session["redraws"] > 0


def test_first_pixels_after_an_edit_do_not_wait_for_the_full_structure(session):
    """A move in a scene of 250k triangles: the coarse pass traces the quick
    uniform grid, so its first pixels arrive before the render settings'
    structure (the adaptive grid) has been built for the full passes."""
    edit = session["large_edit"]
    assert edit["triangles"] > 240_000 and edit["moved_in_core"] == 1
    assert edit["edit_to_pixels"] < edit["edit_to_full_grid"], edit
    assert edit["grid"] < edit["full_grid"], edit
