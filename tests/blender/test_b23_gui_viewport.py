"""Rendered viewport shading in Blender's GUI (Debian's blender 3.4 under Xvfb).

One GUI session (scripts/gui_viewport.py) screenshots the 3D view: through the
camera, after moving an object from a script, in the orthographic front
view; then, while rendering, it switches the engine, switches to Solid
shading, toggles a quad view on and off, closes the view (its area becomes an
Image Editor), loads a new file and quits, counting threads after each event.
"""
import json
import shutil

import numpy as np
import pytest
from PIL import Image

from gui import run_gui
from runner import missing_reason


class Session:
    def __init__(self, out, proc):
        self.out, self.proc = out, proc
        self.info = json.loads((out / "gui_viewport.json").read_text())

    def shot(self, name):
        return np.asarray(Image.open(self.out / name).convert("RGB"), dtype=np.float32)

    def region(self, name):
        """The 3D view's region of screenshot `name`, rows from the top."""
        x, y, w, h = self.info[name]["region"]
        top = self.info[name]["window_height"] - (y + h)
        return self.shot(name)[top:top + h, x:x + w]


@pytest.fixture(scope="module")
def gui(tmp_path_factory):
    reason = missing_reason("blender34") or (None if shutil.which("Xvfb") else "Xvfb is missing")
    if reason:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp("gui_viewport")
    proc = run_gui("gui_viewport.py", {"OUT": str(out)}, timeout=300)
    return Session(out, proc)


def rows_top_down(box, height):
    """(row0, row1, col0, col1) of a region box (x0, y0, x1, y1, origin bottom left)."""
    x0, y0, x1, y1 = box
    return int(height - y1), int(np.ceil(height - y0)), int(x0), int(np.ceil(x1))


@pytest.mark.parametrize("shot, final, frame", [("shot_camera.png", "final.png", "frame"),
                                                ("shot_panorama.png", "final_panorama.png", "frame_panorama"),
                                                ("shot_fisheye.png", "final_fisheye.png", "frame_fisheye"),
                                                ("shot_far.png", "final_far.png", "frame_far")])
def test_camera_view_matches_a_final_render_of_the_same_camera(gui, shot, final, frame):
    """At zoom 1:1 the camera's frame is the render's size; the frame's part of
    the screenshot must be the final render (both colour managed by Blender).
    A panoramic camera (equirectangular, and a fisheye with black corners) is
    stretched from its frame over the region;
    a camera 1e7 from the origin keeps its place and direction."""
    final = gui.shot(final)
    view = gui.region(shot)
    x0, y0, x1, y1 = gui.info[frame]
    assert (round(x1 - x0), round(y1 - y0)) == (final.shape[1], final.shape[0])
    r0, _, c0, _ = rows_top_down(gui.info[frame], view.shape[0])
    crop = view[r0:r0 + final.shape[0], c0:c0 + final.shape[1]]
    assert crop.std() > 20                                  # the objects are there
    diff = np.abs(crop - final).max(axis=2)
    # the same image up to sampling noise at edges (and the frame's half-pixel offset)
    assert np.abs(crop - final).mean() < 3.0
    assert (diff > 30).mean() < 0.02


def test_moving_an_object_changes_the_image_only_where_it_moved(gui):
    before, after = gui.region("shot_camera.png"), gui.region("shot_moved.png")
    changed = np.abs(after - before).max(axis=2) > 8
    height = before.shape[0]
    where = np.zeros_like(changed)
    for key in ("sphere_before", "sphere_after"):
        r0, r1, c0, c1 = rows_top_down(gui.info[key], height)
        where[max(r0 - 3, 0):r1 + 3, max(c0 - 3, 0):c1 + 3] = True
    assert changed[where].sum() > 1000, "the sphere's old and new places must change"
    assert changed[~where].sum() <= 0.001 * (~where).sum(), "nothing else may change"


def test_a_zero_scale_camera_seen_through_is_named_with_its_cause(gui):
    camera = gui.info["camera_name"]
    messages = gui.info["zero_scale_camera_messages"]
    assert messages and all(m.startswith(f"Gridwalk: Camera {camera!r} has a zero scale (1, 0, 1 along its X, Y, Z "
                                         "axes): it has no viewing direction") for m in messages), messages


def test_orthographic_front_view_keeps_equal_cubes_equal(gui):
    """Numpad 1 is orthographic: two equal cubes 6 units apart in depth have the
    same width, as Blender projects them; through the perspective camera, not."""
    assert gui.info["shot_front.png"]["perspective"] is False
    view = gui.region("shot_front.png")
    red = (view[..., 0] - view[..., 2]) > 40             # "Near"
    blue = (view[..., 2] - view[..., 0]) > 40            # "Far"
    widths = []
    for mask, name in ((red, "Near"), (blue, "Far")):
        cols = np.nonzero(mask.sum(axis=0) > 10)[0]
        widths.append(cols.max() - cols.min() + 1)
        x0, _, x1, _ = gui.info["front_boxes"][name]
        assert abs(widths[-1] - (x1 - x0)) <= 3, (name, widths[-1], x1 - x0)
    assert abs(widths[0] - widths[1]) <= 2
    near, far = (gui.info["camera_boxes"][n] for n in ("Near", "Far"))
    assert (near[2] - near[0]) > 1.3 * (far[2] - far[0])


def test_material_and_world_previews_render_with_gridwalk(gui):
    """Thumbnails (bl_use_preview): the material's shows the green sphere, the
    world's its (constant) background colour; GRIDWALK says it rendered them."""
    output = gui.proc.stdout
    assert "Gridwalk: finished preview;" in output and "Gridwalk: preview of the background" in output
    material, world = gui.info["previews"]["material"], gui.info["previews"]["world"]
    r, g, b = material["mean"]
    assert g > r + 0.03 and g > b + 0.03 and max(material["std"]) > 0.05     # a lit green sphere
    r, g, b = world["mean"]
    assert b > g > r and max(world["std"]) < 1e-3                            # the blue world, uniform
    seconds = [float(line.split("total ")[1].split(" s")[0]) for line in output.splitlines()
               if line.startswith("Gridwalk: finished preview;")]
    seconds += [float(line.split(" in ")[1].split(" s")[0]) for line in output.splitlines()
                if line.startswith("Gridwalk: preview of the background")]
    # the goal is 1 s per thumbnail (docs/blender.md gives the times measured); 2 s leaves room
    # for a busy machine
    assert seconds and max(seconds) < 2.0, seconds


def test_ui_stays_responsive_while_rendering(gui):
    """While the viewport renders, Blender's main thread only draws: every call
    into the engine there (view_update, view_draw: upload and draw the image)
    returns quickly, and the view keeps redrawing as the image refines."""
    assert gui.info["rendering"]["render"] >= 1
    calls = [seconds for session in gui.info["main_thread"] for _, seconds in session]
    draws = [seconds for session in gui.info["main_thread"] for kind, seconds in session if kind == "view_draw"]
    assert len(draws) >= 3, gui.info["main_thread"]
    assert max(calls) < 0.25, sorted(calls)[-5:]


def test_a_quad_view_renders_in_four_sessions_and_stops_three_when_it_ends(gui):
    """Engine state lives per instance: each of the four views has its own
    engine, session and worker; leaving the quad view stops three of them."""
    info = gui.info
    assert info["quad_view_regions"] == 4
    assert info["quad_view"]["viewport"] == 4 and info["quad_view"]["render"] >= 1, info["quad_view"]
    assert info["after_quad_view"]["viewport"] == 1, info["after_quad_view"]


def test_operators_called_from_python_while_four_views_render_do_not_crash(gui):
    """Blender 3.4-5.0 read a temp_override's dict without the GIL whenever
    another Python thread held it, and crashed (the viewport once rendered from
    Python threads; docs/blender.md). 400 operator calls, each while four views
    re-render after one of 40 moves: Blender lives on and the views keep restarting."""
    storm = gui.info["operator_storm"]
    assert storm["calls"] == 400 and storm["sessions"] == 4, storm
    assert storm["requests_after"] - storm["requests_before"] >= 4 * 20, storm     # the views restarted
    assert gui.info["after_quad_view"]["viewport"] == 1


def test_threads_stop_on_engine_switch_shading_switch_closing_the_view_file_load_and_quit(gui):
    info = gui.info
    assert info["before"] == {"render": 0, "viewport": 0}
    for rendering in ("rendering", "rendering_again", "rendering_before_quad_view", "rendering_before_new_file",
                      "rendering_before_quit"):
        assert info[rendering]["render"] >= 1 and info[rendering]["viewport"] == 1, (rendering, info[rendering])
    for event in ("after_engine_switch", "after_solid_shading", "after_closing_the_view", "after_new_file"):
        assert info[event] == {"render": 0, "viewport": 0}, (event, info[event])
    assert info["completed"]
    output = gui.proc.stdout + gui.proc.stderr
    before_quit, _, at_quit = output.partition("quitting while rendering")
    assert "Gridwalk: viewport render stopped" in at_quit
    assert "Traceback" not in before_quit and "Segmentation" not in output and "Gridwalk viewport:" not in output
    quit_while_refused = any(entry[0] == "quit_blender" for entry in gui.info.get("write_refused", []))
    assert_quit_is_clean(at_quit, quit_while_refused)


READONLY_UNREGISTER = "can't run in readonly state"


def tracebacks(text):
    """Each traceback in text: its lines up to and including the exception's line."""
    blocks, current = [], None
    for line in text.splitlines():
        if line.startswith("Traceback (most recent call last):"):
            current = [line]
            blocks.append(current)
        elif current is not None:
            current.append(line)
            if line and not line.startswith(" "):     # the exception line ends the block
                current = None
    return blocks


def assert_quit_is_clean(at_quit, quit_while_refused):
    """No traceback at quit, except Blender's own write-flag race (docs/blender.md):
    when Blender already refused the script's writes as it quit, its exit
    disables every add-on with the flag read-only, and each unregister_class
    fails, Blender's bundled add-ons (Cycles) as well as ours."""
    blocks = tracebacks(at_quit)
    if not blocks:
        return
    assert quit_while_refused, ("tracebacks at quit while writes were allowed", blocks)
    for block in blocks:
        assert READONLY_UNREGISTER in block[-1] and any("addon_utils.py" in line for line in block), block
    assert any("cycles" in line for block in blocks for line in block), ("only some add-ons failed", blocks)
