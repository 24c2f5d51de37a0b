"""Holdouts (an object's Visibility > Holdout, a collection set to Holdout in
the view layer, a Holdout shader) clear the film where the camera sees them,
black and transparent, with the film opaque or transparent, where Cycles does;
a mirror still shows the object set to Holdout (Cycles holds objects out from
camera rays only)."""
import json

import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, script_output


@pytest.fixture(scope="module", params=ALL_BLENDERS)
def renders(request, tmp_path_factory):
    out = script_output(request.param, tmp_path_factory, "holdout.py")
    images = {(engine, film): exr.rgba(exr.read_exr(out / f"{engine}_{film}.exr"), "ViewLayer.Combined.")
              for engine in ("gridwalk", "cycles") for film in ("opaque", "transparent")}
    return images | {"blender": json.loads((out / "info.json").read_text())}


@pytest.mark.parametrize("film", ["opaque", "transparent"])
def test_the_film_is_clear_where_cycles_clears_it(renders, film):
    ours, theirs = renders["gridwalk", film], renders["cycles", film]
    clear_ours, clear_theirs = ours[..., 3] < 0.5, theirs[..., 3] < 0.5
    iou = (clear_ours & clear_theirs).sum() / (clear_ours | clear_theirs).sum()
    assert iou > 0.97, iou
    assert abs(ours[..., 3].mean() - theirs[..., 3].mean()) < 0.01
    # black where clear, in both
    assert ours[..., :3][ours[..., 3] < 0.02].max() < 0.02
    assert theirs[..., :3][theirs[..., 3] < 0.02].max() < 0.02


def test_each_kind_of_holdout_clears_its_object(renders):
    clear = renders["gridwalk", "opaque"][..., 3] < 0.5
    assert 0.1 < clear.mean() < 0.5
    # the object, the collection and the shader holdout: left, middle and right thirds of the frame
    thirds = np.array_split(clear, 3, axis=1)
    assert all(part.sum() > 100 for part in thirds), [int(part.sum()) for part in thirds]
    # an opaque film stays opaque elsewhere: the background and the floor
    assert (renders["gridwalk", "opaque"][..., 3] > 0.999).mean() > 0.5


@pytest.mark.parametrize("engine", ["gridwalk", "cycles"])
def test_a_mirror_shows_the_held_out_object_as_it_is(renders, engine):
    rgb = renders[engine, "opaque"][..., :3]
    red = (rgb[..., 0] > 0.03) & (rgb[..., 0] > 3 * rgb[..., 1])     # (its side the sun lights, dim)
    assert red.sum() > 30, "the red sphere set to Holdout, in the mirror"
