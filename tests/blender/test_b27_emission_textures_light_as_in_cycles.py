"""A Principled BSDF whose Emission Color is an image (a screen, a sign: what
glTF models' emissive maps become) shows the image times its Emission
Strength and lights the scene with it, as Cycles does, in bpy 4.5, bpy 5.0
and Debian's 3.4. Before, the input took its default value, with a warning:
a white or black panel. Scene: texture_scenes.emission_map_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine


@pytest.fixture(scope="module")
def panel(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"emission_map_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=64"}
    renders = luminance_by_engine(module_blender, out, "emission_map", engines, {"panel": {}})
    return renders[("GRIDWALK", "panel")], renders[("CYCLES", "panel")]


def test_the_panel_shows_the_image_times_the_strength(panel):
    ours, cycles = panel
    shown = cycles > 0.5
    assert 0.1 < shown.mean() < 0.4
    rows, cols = np.where(shown.any(axis=1))[0], np.where(shown.any(axis=0))[0]
    box = (slice(rows.min() + 1, rows.max()), slice(cols.min() + 1, cols.max()))
    assert cycles[box].std() > 0.1                                  # the image's colours
    assert np.corrcoef(ours[box].reshape(-1), cycles[box].reshape(-1))[0, 1] > 0.99
    assert abs(ours[shown].mean() / cycles[shown].mean() - 1) < 0.03


def test_the_panel_lights_the_floor_as_in_cycles(panel):
    ours, cycles = panel
    below = np.where((cycles > 0.5).any(axis=1))[0].max() + 3      # the floor rows under the panel
    assert cycles[below:].mean() > 0.02
    assert abs(ours[below:].mean() / cycles[below:].mean() - 1) < 0.08
