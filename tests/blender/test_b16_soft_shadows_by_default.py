"""A Blender light with a size casts a soft shadow with GRIDWALK's default
settings, as it does in Cycles and EEVEE (Blender's defaults: shadow "area",
2 x 2, one quarter of the light per pixel sample), while Hard gives an edge.
Scene: pane_shadow_scene with a 3 x 3 area light 5 units above a pane 2 units
above the floor: the penumbra spreads 2 units (16 pixels) around the shadow."""
import json

import numpy as np
import pytest

import exr
from runner import run_script


def _render(kind, folder, *options):
    folder.mkdir()
    run_script(kind, "render_scene.py", "pane_shadow", folder, "GRIDWALK",
               'scene={"pane": "opaque", "light": "area"}', "transparent=false", *options)
    info = json.loads((folder / "gridwalk.json").read_text())
    assert "error" not in info, info
    rgba = exr.rgba(exr.read_exr(folder / "gridwalk.exr"), "ViewLayer.Combined.")
    return exr.luminance(rgba)


@pytest.fixture(scope="module")
def shadows(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"soft_{module_blender}")
    return {"default": _render(module_blender, out / "default"),
            "hard": _render(module_blender, out / "hard", 'settings={"shadow": "HARD"}')}


def _band(lum, lo, hi):
    """Mean over the pixels whose Chebyshev distance from the centre, in scene
    units (64 pixels span 8 units), lies in (lo, hi): square bands around the
    pane (half-width 0.5) and its hard shadow (half-width 5/3 x 0.5 = 0.83)."""
    c = (np.arange(64) + 0.5) / 8 - 4
    d = np.maximum(np.abs(c)[:, None], np.abs(c)[None, :])
    return float(lum[(d > lo) & (d < hi)].mean())


def test_the_default_shadow_of_an_area_light_has_a_penumbra(shadows):
    soft, hard = shadows["default"], shadows["hard"]
    lit = _band(hard, 0.9, 1.6)          # just outside the hard shadow: fully lit
    # Under the pane's rim the hard shadow is black; the default one lets in
    # part of the light (the penumbra, about 2 units wide, has no umbra here).
    assert _band(hard, 0.55, 0.78) < 0.05 * lit
    assert _band(soft, 0.55, 0.78) > 0.3 * lit
    # Just outside, the soft shadow darkens floor that the hard one leaves lit.
    assert _band(soft, 0.9, 1.6) < 0.9 * lit
    # Far from the pane both see the whole light: the same brightness on average.
    assert _band(soft, 3.0, 4.0) == pytest.approx(_band(hard, 3.0, 4.0), rel=0.05)
