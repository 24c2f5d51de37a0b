"""A Bump node whose Height an image gives (the usual way to add relief from
a height map) shades a diffuse plane as Cycles does, in bpy 4.5, bpy 5.0 and
Debian's 3.4: sine stripes of height lit from the side, also inverted at
Strength 0.6, on an object scaled 4 times (the gradient is taken along the
surface in the world, as Cycles takes it) and over a normal map leaning 30
degrees (the gradient's part along the bent normal is removed along the
geometric one, as Cycles removes it). Before, the Normal input was
warned about and the plane rendered flat. Scene: texture_scenes.bump_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = {"stripes": {}, "inverted": {"invert": True, "strength": 0.6}, "scaled": {"scale": 4.0},
            "tilted": {"tilt": 30.0}}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"bump_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=32"}
    return luminance_by_engine(module_blender, out, "bump", engines, VARIANTS)


@pytest.mark.parametrize("variant", VARIANTS)
def test_the_bumps_shade_as_in_cycles(renders, variant, module_blender):
    if variant == "tilted" and module_blender == "blender34":
        # (Cycles 3.4 also turns the bumped normal back from mirroring the view into the surface,
        # as 4.0 and later do only for the Normal Map's: it flattens the most tilted slopes)
        pytest.skip("Cycles 3.4 corrects bumped normals as 4.0+ does not; Gridwalk follows 4.0+")
    ours, cycles = renders[("GRIDWALK", variant)][:, 4:-4], renders[("CYCLES", variant)][:, 4:-4]
    columns_ours, columns_cycles = ours.mean(axis=0), cycles.mean(axis=0)
    assert columns_cycles.std() > 0.05 * columns_cycles.mean()                 # the stripes show
    assert np.corrcoef(columns_ours, columns_cycles)[0, 1] > 0.99
    # as deep: within 0.3% of Cycles 4.5 and 5.0; Cycles 3.4 bumps about 9% less
    depth = columns_ours.std() / columns_cycles.std()
    assert abs(depth - 1) < (0.13 if module_blender == "blender34" else 0.03), depth
    assert abs(ours.mean() / cycles.mean() - 1) < 0.04


def test_invert_turns_the_stripes_over(renders):
    plain = renders[("GRIDWALK", "stripes")][:, 4:-4].mean(axis=0)
    inverted = renders[("GRIDWALK", "inverted")][:, 4:-4].mean(axis=0)
    assert np.corrcoef(plain, inverted)[0, 1] < -0.9


def test_the_bump_settings_are_exported(export):
    out = export("bump", invert=True, strength=0.6, tilt=0.0)
    (material,) = [m for m in out.materials if m["bump_texture"] >= 0]
    assert material["bump_distance"] == pytest.approx(-0.3) and material["bump_strength"] == pytest.approx(0.6)
    assert material["normal_texture"] >= 0                     # the Normal Map under the Bump
    assert not out.warnings, out.warnings
