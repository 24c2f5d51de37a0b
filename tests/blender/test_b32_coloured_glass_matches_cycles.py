"""Coloured glass: a Glass BSDF's Color and a Principled BSDF's Base Color under Transmission tint
the light the glass lets through (and the Glass BSDF what it reflects), as in Cycles, in bpy 4.5,
bpy 5.0 and Debian's 3.4; the shadows they cast on a white floor are tinted too (Whitted's
transparent shadows; Cycles lights them through caustics, so only their hue is compared). Before,
both spheres rendered clear and grey, without a warning; then the Principled sphere of 4.0+ was
tinted by the colour at each crossing where Cycles tints by its square root (a review probe). Scene: material_scenes.coloured_glass_scene."""
import numpy as np
import pytest

from runner import rgb_by_engine


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"coloured_glass_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=64"}
    return rgb_by_engine(module_blender, out, "coloured_glass", engines)


def _sphere_centres(rgb):
    """The mean colour of a patch at the middle of each sphere (left, right)."""
    h, w = rgb.shape[:2]
    rows = slice(int(0.38 * h), int(0.5 * h))
    return [rgb[rows, int(c * w) - 3:int(c * w) + 3].reshape(-1, 3).mean(axis=0) for c in (0.33, 0.67)]


def test_the_spheres_show_the_world_tinted_by_their_colour(renders):
    for ours, cycles in zip(_sphere_centres(renders["GRIDWALK"]), _sphere_centres(renders["CYCLES"])):
        assert cycles[1] > 3 * cycles[0]                            # Cycles' glass is green
        assert ours[1] > 3 * ours[0] and ours[1] > 3 * ours[2]     # and ours
        # every channel within 10% (4.0+: within 1%): Blender 4.0+'s Principled tints each crossing by
        # the colour's square root, as Cycles does (it tinted twice by the colour, red and blue 0.1x)
        assert np.abs(ours / cycles - 1).max() < 0.1


def test_the_shadows_are_tinted_like_the_glass(renders):
    ours = renders["GRIDWALK"]
    floor = ours[int(0.75 * ours.shape[0]):]                        # the floor below the spheres
    dark = floor.sum(axis=2) < np.percentile(floor.sum(axis=2), 20)  # the shadowed part
    green_share = floor[dark][:, 1] / floor[dark].sum(axis=1)
    assert np.median(green_share) > 0.45                           # green, not grey (1/3)
