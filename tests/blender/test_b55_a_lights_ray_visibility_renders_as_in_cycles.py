"""A light object's Ray Visibility renders as in Cycles, in bpy 4.5, bpy 5.0 and Debian's 3.4:
a softbox over a grey floor and a chrome ball, hidden from diffuse rays (the floor goes dark, the
ball still shows the softbox), from glossy rays (the floor stays lit, the ball shows no softbox),
or from neither. Before, the switches were ignored. Scene: light_scenes.chrome_ball_scene;
the core's side: test97."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = {"none": {}, "diffuse": {"hide": ["diffuse"]}, "glossy": {"hide": ["glossy"]}}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"visibility_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4, "shadow_samples": 4}', "CYCLES": "samples=64"}
    variants = {k: dict(v, resolution=[64, 48]) for k, v in VARIANTS.items()}
    return luminance_by_engine(module_blender, out, "chrome_ball", engines, variants)


def _blocks(image):
    return image.reshape(6, 8, 8, 8).mean(axis=(1, 3))


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_what_the_light_reaches_matches_cycles(renders, variant, module_blender):
    ours, cycles = renders[("GRIDWALK", variant)], renders[("CYCLES", variant)]
    # (Cycles 3.4 renders this scene 1.10-1.14x as bright as Gridwalk with every switch on as well:
    # a difference of that Blender's, not of the switches)
    assert abs(ours.mean() / cycles.mean() - 1) < (0.15 if module_blender == "blender34" else 0.08)
    assert np.abs(_blocks(ours) - _blocks(cycles)).max() < 0.05 * cycles.max() + 0.02


def test_the_switches_change_the_image_as_they_do_in_cycles(renders):
    for engine in ("GRIDWALK", "CYCLES"):
        lit, no_diffuse, no_glossy = (renders[(engine, v)] for v in ("none", "diffuse", "glossy"))
        assert no_diffuse.mean() < 0.5 * lit.mean()                  # the floor goes dark
        assert no_diffuse.max() > 0.5 * lit.max()                    # the ball still shows the softbox
        assert no_glossy.max() < 0.5 * lit.max()                     # the ball shows no softbox
        assert no_glossy[-12:].mean() > 0.8 * lit[-12:].mean()       # the floor (the lowest rows) stays lit
