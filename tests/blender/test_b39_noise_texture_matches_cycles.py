"""Blender's Noise Texture renders as in Cycles, in bpy 4.5, bpy 5.0 and Debian's 3.4: the node
as Blender adds it (3D fBM at Generated coordinates, its Color output), its Fac output with a
fraction of an octave, roughness and distortion, 2D, 4D and 1D noise, its Fac through a Color
Ramp, and (Blender 4.1 and later) the multifractal, ridged, hybrid and hetero-terrain types;
a point over a million out (wrapped by 4.0 and later, not by 3.4); and a Bump node fed by a
Noise or a Gradient Texture (a procedural height).
Before, a Noise Texture was a warning and its input's default colour.
Scenes: noise_scenes.procedural_noise_scene, noise_bump_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = ("color", "fac", "2d", "4d", "1d", "ramp",                # noise_scenes.NOISE_VARIANTS
            "multifractal", "ridged", "hybrid", "hetero", "far")
TYPED = ("multifractal", "ridged", "hybrid", "hetero")              # noise types: Blender 4.1 and later
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"noise_{module_blender}")
    variants = [v for v in VARIANTS if v not in TYPED or module_blender != "blender34"]
    return luminance_by_engine(module_blender, out, "procedural_noise", ENGINES, {v: {"variant": v} for v in variants})


@pytest.mark.parametrize("variant", [v for v in VARIANTS if v != "1d"])
def test_the_noise_is_where_cycles_puts_it(renders, module_blender, variant):
    if ("GRIDWALK", variant) not in renders:
        pytest.skip(f"{module_blender} has no noise types (Blender 4.1 added them)")
    ours, cycles = renders[("GRIDWALK", variant)], renders[("CYCLES", variant)]
    inner = (slice(4, -4), slice(4, -4))                             # (the plane's edges meet the black world)
    assert cycles[inner].std() > 0.03                                 # a pattern, not a flat colour
    # (what differs is the pixel filter's share of the finest octaves: Cycles' 1.5-pixel
    # Blackman-Harris blurs them a little more than our 4 jittered samples)
    assert np.corrcoef(ours[inner].reshape(-1), cycles[inner].reshape(-1))[0, 1] > 0.995
    assert np.abs(ours - cycles)[inner].mean() < 0.08 * cycles[inner].std()


def test_one_dimensional_noise_is_one_colour_as_in_cycles(renders):
    ours, cycles = renders[("GRIDWALK", "1d")], renders[("CYCLES", "1d")]
    inner = (slice(4, -4), slice(4, -4))
    assert ours[inner].std() < 1e-3 and abs(float(ours[inner].mean() - cycles[inner].mean())) < 2e-3


def test_each_setting_changes_the_pattern(renders):
    base = renders[("GRIDWALK", "color")]
    for variant in ("fac", "2d", "4d", "ramp"):
        assert np.abs(renders[("GRIDWALK", variant)] - base).mean() > 0.02, variant


@pytest.fixture(scope="module")
def bumps(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"noise_bump_{module_blender}")
    return luminance_by_engine(module_blender, out, "noise_bump", ENGINES, {h: {"height": h} for h in ("NOISE", "GRADIENT")})


@pytest.mark.parametrize("height", ["NOISE", "GRADIENT"])
def test_a_bump_node_fed_by_a_procedural_texture_shades_as_in_cycles(bumps, module_blender, height):
    ours, cycles = (bumps[(engine, height)][4:-4, 4:-4] for engine in ("GRIDWALK", "CYCLES"))
    assert cycles.std() > 0.01                                        # the bumps show
    # Cycles 3.4 takes the height's slope over a whole pixel's footprint (a forward difference:
    # smoother, half a pixel off) and bumps about 9% less (test_b28); 4.0 and later over a tenth.
    old = module_blender == "blender34"
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > (0.95 if old else 0.997)
    assert np.abs(ours - cycles).mean() < (0.03 if old else 0.005)
    assert abs(float(ours.mean() - cycles.mean())) < (0.01 if old else 0.002)


def test_a_brick_bump_is_named_for_its_steps(export):
    # (the mortar's edges are steps: central differences show them as speckle where Cycles' bump
    # shows lines, 8% brighter, found by a review probe; Noise, Voronoi and Wave bumps match)
    out = export("noise_bump", height="BRICK")
    assert any("a Brick Texture: its mortar's edges are steps" in w for w in out.warnings), out.warnings
    assert not any("steps" in w for w in export("noise_bump", height="NOISE").warnings)
