"""Blender survives bad input with a clear message in the render report (issue 7).

One Blender session per Blender (bpy 4.5, bpy 5.0, Debian's 3.4 binary) renders
every case of scripts/bad_input.py: an empty scene, no camera (refused by
Blender; deleted mid-animation; the engine called directly), a camera with
zero scale or an empty panorama, a camera inside an object, a 1 x 1 image and
render borders, NaN / Inf transforms, meshes
without faces and with zero-area faces, and a scene too large for the memory
limit. The messages are read from what Blender printed for its reports.
"""
import json
import re

import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, script_output

COMBINED = "ViewLayer.Combined."


class Results:
    def __init__(self, out_dir):
        self.dir = out_dir
        self.info = json.loads((out_dir / "bad_input.json").read_text())

    def __getitem__(self, case):
        return self.info[case]

    def cases(self):
        return [name for name in self.info if name != "blender"]

    def error(self, case):
        """The first line of the RuntimeError text (Blender lists each ERROR report on a line)."""
        return (self.info[case]["error"] or "").strip().split("\n")[0]

    def warnings(self, case):
        return [line for line in self.info[case]["log"].splitlines() if line.startswith("Warning: Gridwalk: ")]

    def image(self, name):
        return exr.rgba(exr.read_exr(self.dir / f"{name}.exr"), COMBINED)


@pytest.fixture(scope="module", params=list(ALL_BLENDERS))
def results(request, tmp_path_factory):
    # exit code 0: the session survived every case
    return Results(script_output(request.param, tmp_path_factory, "bad_input.py", timeout=240))


def test_no_case_crashes_or_prints_a_traceback(results):
    assert len(results.cases()) == 31
    for case in results.cases():
        log = results[case]["log"]
        assert "Traceback" not in log and "Segmentation" not in log, (case, log[-2000:])
        error = results.error(case)
        assert not error or "Gridwalk: " in error or "no camera" in error, (case, error)


def test_lights_scaled_to_zero_give_no_light_and_are_named(results):
    # (Cycles renders such a scene as if the lights were not there)
    assert results.error("zero_scale_lights") == ""
    warnings = results.warnings("zero_scale_lights")
    for name in ("ZeroSun", "ZeroSpot", "ZeroArea"):
        assert (f"Warning: Gridwalk: Skipped light '{name}': its object is scaled to zero, so it points nowhere "
                "and gives no light") in warnings
    assert ("Warning: Gridwalk: Skipped light 'SizeZero': its size (times its object's scale) is zero, "
            "so it gives no light") in warnings
    np.testing.assert_array_equal(results.image("zero_scale_lights"), results.image("full_frame"))


def test_settings_the_core_does_not_model_are_named_in_warnings(results):
    assert results.error("ignored_settings") == ""
    warnings = "\n".join(results.warnings("ignored_settings"))
    for expected in (                     "Light 'Narrow': Spread 29 degrees is not supported",
                     "Light 'Negative': negative power (a light that darkens) is not supported",
                     "Light 'Stretched': a non-uniform scale does not stretch its cone",
                     "Motion blur is not supported: each object renders where it is at the current frame",
                     "Render passes not written (only Combined, Depth, Normal, Object and Material Index, the "
                     "denoising data and Cryptomatte are): Mist, Shader AOV 'mask', Light Group 'key_group'"):
        assert expected in warnings, expected
    assert "NoShadow" not in warnings          # Cast Shadow off is rendered (test05 checks the light)
    assert "Holdout" not in warnings and "Mask" not in warnings   # holdouts are rendered (test_b45)
    assert "CameraInvisible" not in warnings   # ray visibility is rendered (test_b46)
    assert "aperture" not in warnings          # six aperture blades are rendered (test_b12 compares the bokeh)
    if results["blender"][0] >= 4:             # (light linking came with 4.0)
        assert ("Light and shadow linking are not supported (every light reaches every object, every object "
                "casts shadows): 'Key'") in warnings


def test_an_empty_scene_renders_the_world_with_a_warning(results):
    # (an error before, which stopped animations and farms at such a frame; Cycles renders the world)
    assert results.error("empty") == ""
    assert ("Warning: Gridwalk: Nothing to render: the scene has no visible object with faces (check 'Disable "
            "in Renders' and excluded collections): the frame shows the world alone") in results.warnings("empty")
    image = results.image("empty")
    assert image.shape[0] > 0 and image[..., 3].max() == 0.0          # transparent film: the world's alpha 0


def test_an_animation_goes_on_past_a_frame_with_nothing_to_render(results):
    # It stopped at frame 2 with "Nothing to render", and frame 3 was never written
    # (blender -b -a exited 1). The frame shows the world, as in Cycles, with a warning.
    assert results.error("empty_frame") == ""
    assert ("Warning: Gridwalk: Nothing to render: the scene has no visible object with faces (check 'Disable "
            "in Renders' and excluded collections): the frame shows the world alone") in results.warnings("empty_frame")
    frames = [results.image(f"empty_frame_{k:04d}") for k in (1, 2, 3)]
    np.testing.assert_array_equal(frames[0], frames[2])
    assert frames[0][..., 3].max() == 1.0                        # the cube, in frames 1 and 3
    assert frames[1][..., 3].max() == 0.0 and frames[1][..., :3].max() == 0.0   # transparent film: nothing


def test_no_camera(results):
    assert "Cannot render, no camera" in results.error("no_camera")     # Blender refuses first
    # deleted at frame 2 of an animation: Blender calls the engine, which says why it stops
    assert "Gridwalk: The scene has no active camera" in results.error("camera_deleted")
    assert (results.dir / "camera_deleted_0001.exr").exists()          # frame 1 had its camera
    # the engine's render() called directly on a scene without a camera
    direct = results["direct_no_camera"]
    message = "Gridwalk: The scene has no active camera: add a camera and make it active"
    assert [kind for kind, _ in direct["reports"]] == ["ERROR"] and message in direct["reports"][0][1]
    assert len(direct["errors"]) == 1 and message in direct["errors"][0]
    # an Empty as the active camera: rendered from it with Cycles' default lens, as Cycles does
    assert results.error("not_a_camera") == "" and (results.dir / "not_a_camera.exr").exists()
    assert "Camera 'Camera' has a non-finite transform (NaN or Inf)" in results.error("nan_camera")


def test_camera_without_a_viewing_direction_or_with_an_empty_panorama(results):
    assert ("Gridwalk: Camera 'Camera' has a zero scale (1, 0, 1 along its X, Y, Z axes): it has no viewing "
            "direction. Give it a non-zero scale") in results.error("zero_scale_camera")
    assert ("Gridwalk: Camera 'Camera': the panorama's Min Latitude and its maximum are equal (0.3), so the "
            "image spans nothing: set a range") in results.error("empty_panorama")
    if tuple(results["blender"][:2]) >= (4, 5):     # (rendered as a perspective camera, silently)
        assert ("Gridwalk: Camera 'Camera': the Custom camera type is not supported; choose Perspective, "
                "Orthographic or Panoramic") in results.error("custom_camera")
    else:
        assert results.error("custom_camera") == ""


@pytest.mark.parametrize("case", ["camera_inside_cube", "camera_inside_sphere"])
def test_camera_inside_an_object_renders_its_inside_with_a_warning(results, case):
    assert results.error(case) == ""
    assert any("The camera is inside a closed object" in w for w in results.warnings(case))
    rgba = results.image(case)
    assert np.isfinite(rgba).all() and np.all(rgba[..., 3] == 1.0)     # every pixel sees the object
    assert not any("camera is inside" in w for w in results.warnings("full_frame"))


def test_one_pixel_image(results):
    assert results.error("tiny_1x1") == ""
    rgba = results.image("tiny_1x1")
    assert rgba.shape == (1, 1, 4) and rgba[0, 0, 3] == 1.0 and rgba[0, 0, :3].max() > 0


def _region(x0, x1, y0, y1, width=64, height=48):
    """Rows / columns of Blender's border (fractions from the bottom left) in a top-down image."""
    f = np.float32
    cols = slice(int(f(x0) * f(width)), int(f(x1) * f(width)))
    rows = slice(height - int(f(y1) * f(height)), height - int(f(y0) * f(height)))
    return rows, cols


def test_render_border_renders_exactly_the_border(results):
    full = results.image("full_frame")
    assert full[..., 3].mean() > 0.05
    for case, border in (("border", (0.25, 0.6, 0.1, 0.55)), ("border_1px", (0.5, 0.52, 0.5, 0.53))):
        assert results.error(case) == "", case
        rgba = results.image(case)
        inside = np.zeros(full.shape[:2], bool)
        inside[_region(*border)] = True
        assert rgba.shape == full.shape
        np.testing.assert_array_equal(rgba[inside], full[inside])      # pixels are pure functions
        assert np.all(rgba[~inside] == 0.0), case
    assert _region(0.5, 0.52, 0.5, 0.53) == (slice(23, 24), slice(32, 33))
    assert results.image("border_1px")[23, 32, 3] == 1.0
    crop = results.image("border_crop")                                  # "Crop to Render Region"
    np.testing.assert_array_equal(crop, full[_region(0.25, 0.6, 0.1, 0.55)])


def test_nan_transforms_are_skipped_with_a_warning_naming_each_object(results):
    assert results.error("nan_transforms") == ""
    warnings = results.warnings("nan_transforms")
    for name in ("NaNLocation", "NaNRotation", "NaNSphere"):
        assert f"Warning: Gridwalk: Skipped object '{name}': its transform is not finite (NaN or Inf)" in warnings
    assert ("Warning: Gridwalk: Skipped object 'InfScale': its vertices lie beyond +-1e+30 in world space"
            in warnings)
    assert ("Warning: Gridwalk: Skipped object 'NaNVertex': its mesh has non-finite vertex coordinates "
            "(NaN or Inf)" in warnings)
    assert "Warning: Gridwalk: Skipped light 'NaNLight': its transform is not finite (NaN or Inf)" in warnings
    # what is left is exactly the valid scene: no silently wrong pixel
    np.testing.assert_array_equal(results.image("nan_transforms"), results.image("full_frame"))
    assert results.error("nan_only") == "" and (
        "Warning: Gridwalk: Nothing to render: the scene has no visible object with faces (skipped as invalid: "
        "'NaNCube'): the frame shows the world alone") in results.warnings("nan_only")
    assert not any("SkippedTranslucent" in w for w in results.warnings("nan_only"))   # its material unread


def test_a_copy_with_a_nan_transform_is_skipped_and_the_other_copies_render(results):
    skipped = "Warning: Gridwalk: Skipped object 'NaNInstanced': its transform is not finite (NaN or Inf)"
    assert results.error("nan_instance") == "" and skipped in results.warnings("nan_instance")
    assert not any("NaNInstanced" in w for w in results.warnings("nan_instance_removed"))
    image = results.image("nan_instance")
    np.testing.assert_array_equal(image, results.image("nan_instance_removed"))
    assert (image[..., 3] > 0).sum() > (results.image("full_frame")[..., 3] > 0).sum() + 20   # the copies show


def test_meshes_without_faces_and_with_zero_area_faces(results):
    faceless = ("Warning: Gridwalk: Objects without faces (only vertices or edges) are not rendered: "
                "'Edges', 'Points'")
    assert results.error("no_faces") == "" and faceless in results.warnings("no_faces")
    np.testing.assert_array_equal(results.image("no_faces"), results.image("full_frame"))
    assert results.error("no_faces_only") == "" and any(
        w.endswith("(without faces: 'Edges', 'Points'): the frame shows the world alone")
        for w in results.warnings("no_faces_only"))
    assert results.error("degenerate") == ""
    assert ("Warning: Gridwalk: Object 'ZeroArea': 3 of 3 triangles have zero area and are invisible"
            in results.warnings("degenerate"))
    rgba = results.image("degenerate")
    assert np.isfinite(rgba).all()
    grown = (rgba[..., 3] > 0) & (results.image("full_frame")[..., 3] == 0)
    assert grown.any()      # the cube squashed flat by a zero scale still shows its front


ESTIMATE = re.compile(r"needs an estimated ([\d.]+) MiB of memory \(scene arrays .*grid .*images .*\), "
                      r"more than the limit of ([\d.]+) MiB \((.*)\)")


def test_a_border_render_is_estimated_for_its_region_not_the_frame(results):
    # (1% of a 16000 x 16000 frame was refused for the frame's memory, which it never allocates)
    refused = results.error("large_frame")
    assert refused.startswith("Error: Gridwalk: This scene (12 triangles, 0 spheres, 3000 x 3000 pixels)"), refused
    assert results.error("large_frame_border") == ""
    assert "Gridwalk: memory estimate" in results["large_frame_border"]["log"]
    rgba = results.image("large_frame_border")
    assert rgba.shape[:2] == (150, 150) and rgba[..., 3].mean() > 0.1


@pytest.mark.parametrize("case, limit, source", [
    ("too_large_property", 4.0, "Render Properties > Performance > Memory Limit"),
    ("too_large_env", 2.5, "set by GRIDWALK_MEMORY_LIMIT_MB"),
])
def test_scene_too_large_is_refused_with_the_estimate_and_the_limit(results, case, limit, source):
    error = results.error(case)
    assert error.startswith("Error: Gridwalk: This scene (62,988 triangles, 0 spheres, 64 x 48 pixels)"), error
    match = ESTIMATE.search(error)
    assert match, error
    estimate = float(match.group(1))
    assert float(match.group(2)) == limit and match.group(3) == source
    assert 8.0 < estimate < 40.0 and estimate > limit   # (16 MiB of it the crowded roots' allowance)
    assert "Gridwalk: finished" not in results[case]["log"]             # refused before the export
    # the same scene under the default limit (a fraction of physical memory) renders
    assert results.error("fits_default_limit") == ""
    assert re.search(r"limit [\d.]+ [KMGT]iB \(75% of physical memory\)", results["fits_default_limit"]["log"])
    assert results.image("fits_default_limit")[..., 3].mean() > 0.1
