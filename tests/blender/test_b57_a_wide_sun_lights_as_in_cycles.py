"""A sun of any Angle lights a floor as Cycles lights it, in bpy 4.5, bpy 5.0 and Debian's 3.4: from
4.0 on, Cycles keeps the Strength as the irradiance on a surface facing the sun at any angle (the
core's rule, test96); Blender 3.4's Cycles spread it over a disc of radius tan(half the angle) at
unit distance, so a facing floor gets 2 cos h / (1 + cos h) of it (none at 180 degrees), which the
export follows there (lights._sun_units). Before, a 180-degree sun lit the floor with half its
Strength in 4.5 and 5.0 (a review probe: 0.433 against Cycles' 0.553 in display values).
Scene: light_scenes.wide_sun_scene."""
import pytest

from runner import luminance_by_engine

ANGLES = (0.5, 60.0, 120.0, 180.0)


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"wide_sun_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 2, "shadow_samples": 16}', "CYCLES": "samples=64"}
    return luminance_by_engine(module_blender, out, "wide_sun", engines,
                               {f"{a:g}": {"angle_degrees": a} for a in ANGLES})


@pytest.mark.parametrize("angle", ANGLES)
def test_the_floor_gets_what_cycles_gives_it(renders, angle, module_blender):
    ours, cycles = (float(renders[(engine, f"{angle:g}")].mean()) for engine in ("GRIDWALK", "CYCLES"))
    assert ours == pytest.approx(cycles, rel=0.01, abs=1e-4)
    if module_blender != "blender34":
        assert cycles == pytest.approx(float(renders[("CYCLES", "0.5")].mean()), rel=0.01)   # (the same at any angle)
