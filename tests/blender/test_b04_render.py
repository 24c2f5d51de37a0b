"""Rendering through Blender: GRIDWALK's image equals the core's render of the
exported arrays, its coverage equals Cycles' alpha, and the passes are written."""
import numpy as np
import pytest

import exr
from runner import missing_reason, run_script

AA = {"aa": "JITTERED", "aa_samples": 3}


@pytest.fixture(scope="module", params=["bpy45", "bpy50"])
def renders(request, tmp_path_factory):
    reason = missing_reason(request.param)
    if reason:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp(request.param)
    run_script(request.param, "render_scene.py", "showcase", out, "GRIDWALK",
               f'settings={{"aa": "JITTERED", "aa_samples": 3}}', "core=true")
    run_script(request.param, "render_scene.py", "showcase", out, "CYCLES", "samples=16")
    gw, cy = exr.read_exr(out / "gridwalk.exr"), exr.read_exr(out / "cycles.exr")
    return {"gridwalk": gw, "cycles": cy, "core": dict(np.load(out / "core.npz")),
            "rgba": exr.rgba(gw, "ViewLayer.Combined."), "cycles_rgba": exr.rgba(cy, "ViewLayer.Combined.")}


def test_image_is_not_trivial(renders):
    rgba = renders["rgba"]
    assert rgba.shape == (72, 96, 4)
    covered = rgba[..., 3] > 0.99
    assert 0.05 < covered.mean() < 0.5
    lum = rgba[..., :3].mean(axis=-1)
    assert lum[covered].std() > 0.05          # shading varies over the objects
    assert lum[covered].max() > 0.2 and np.all(np.isfinite(rgba))
    red = rgba[covered][:, 0] > 2 * rgba[covered][:, 2] + 0.02
    assert red.any(), "the red monkey is missing"


def test_image_equals_the_core_render_of_the_exported_arrays(renders):
    np.testing.assert_array_equal(renders["rgba"], renders["core"]["rgba"])


def test_object_coverage_matches_cycles_alpha(renders):
    ours, theirs = renders["rgba"][..., 3], renders["cycles_rgba"][..., 3]
    assert abs(ours.mean() - theirs.mean()) < 0.01
    assert np.abs(ours - theirs).mean() < 0.02
    assert np.mean((ours > 0.5) != (theirs > 0.5)) < 0.01


def test_depth_and_normal_passes_are_written(renders):
    gw, core = renders["gridwalk"], renders["core"]
    depth = gw["ViewLayer.Depth.Z"]
    expected = np.nan_to_num(core["depth"], posinf=1e10)
    np.testing.assert_array_equal(depth, expected)
    hit = np.isfinite(core["depth"])
    assert hit.mean() > 0.05 and np.all((depth[hit] > 5) & (depth[hit] < 15))
    normal = np.stack([gw[f"ViewLayer.Normal.{c}"] for c in "XYZ"], axis=-1)
    np.testing.assert_array_equal(normal, core["normal"])
    np.testing.assert_allclose(np.linalg.norm(normal[hit], axis=-1), 1.0, atol=1e-3)


def test_depth_agrees_with_cycles(renders):
    ours, theirs = renders["gridwalk"]["ViewLayer.Depth.Z"], renders["cycles"]["ViewLayer.Depth.Z"]
    both = (ours < 1e9) & (theirs < 1e9) & (renders["rgba"][..., 3] > 0.99)
    assert both.mean() > 0.05
    # the analytic sphere vs Cycles' tessellated one: allow a small relative error
    assert np.median(np.abs(ours[both] - theirs[both]) / theirs[both]) < 0.01
