"""An object's Ray Visibility (Camera, Glossy, Transmission, Shadow off) renders
as in Cycles: a cube hidden from the camera keeps its shadow and its
reflection, a cube that casts no shadow is seen without one, and a sphere
hidden from glossy rays is seen but not in the mirror."""
import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, script_output


@pytest.fixture(scope="module", params=ALL_BLENDERS)
def renders(request, tmp_path_factory):
    out = script_output(request.param, tmp_path_factory, "ray_visibility.py")
    return {engine: exr.rgba(exr.read_exr(out / f"{engine}.exr"), "ViewLayer.Combined.")[..., :3]
            for engine in ("gridwalk", "cycles")}


def luminance(rgb):
    return rgb @ np.array([0.2126, 0.7152, 0.0722], np.float32)


def test_the_image_and_its_shadows_match_cycles(renders):
    ours, theirs = renders["gridwalk"], renders["cycles"]
    assert np.corrcoef(luminance(ours).ravel(), luminance(theirs).ravel())[0, 1] > 0.95
    # the shadows (and the black sky): the hidden cube's stays, the shadowless cube casts none
    dark = lambda rgb: luminance(rgb) < 0.4 * np.median(luminance(rgb)[60:])
    a, b = dark(ours), dark(theirs)
    assert (a & b).sum() / (a | b).sum() > 0.93


@pytest.mark.parametrize("engine", ["gridwalk", "cycles"])
def test_each_object_is_seen_only_by_the_rays_that_see_it(renders, engine):
    rgb = renders[engine]
    red = (rgb[..., 0] > 0.08) & (rgb[..., 0] > 3 * rgb[..., 1])
    strong_red = (rgb[..., 0] > 0.2) & (rgb[..., 0] > 4 * rgb[..., 1])
    blue = (rgb[..., 2] > 0.08) & (rgb[..., 2] > 3 * rgb[..., 0])
    # (128 x 80: the mirror fills rows up to 40 behind the objects; the hidden cube is on the left,
    # the sphere on the right)
    assert not strong_red[42:, :40].any(), "the cube hidden from the camera is not seen directly"
    assert red[:40, :40].sum() > 30, "but its reflection is"
    assert blue.sum() > 300, "the sphere hidden from glossy rays is seen directly"
    assert not blue[:32, 80:].any(), "but not in the mirror"
