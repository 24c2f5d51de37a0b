"""Blender's Wave, Magic, White Noise and Brick Textures render as in Cycles, in bpy 4.5, bpy 5.0
and Debian's 3.4: each node as Blender adds it; Wave rings with distortion and Wave diagonal
bands; Magic far out (Cycles takes its point modulo 2 pi); a White Noise's hashed colour and 4D
value at one point, at the zero vector that Cycles makes of a Mapping of Scale 0 (its Location
left out) and of an unlinked Vector, and at the Location of a Mapping of constants; bricks with every setting moved,
and their mortar (Fac); Blender 3.4's Musgrave Texture of each type (as a Noise Texture, as
Blender 4.1 converts it), a Detail below 1 too. Before, each was a warning and its input's
default colour.
Scene: pattern_scenes.pattern_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = ("wave", "wave_rings", "wave_diagonal", "magic", "magic_far", "brick", "brick_custom",  # PATTERN_VARIANTS
            "brick_fac")
POINTS = ("white_noise", "white_noise_4d", "white_noise_zero", "white_noise_unlinked", "white_noise_constant",
          "brick_zero")
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}


MUSGRAVE = ("musgrave_fbm", "musgrave_fbm_low", "musgrave_multifractal", "musgrave_ridged", "musgrave_hybrid",
            "musgrave_hetero")                                       # MUSGRAVE_VARIANTS: Blender 3.4 only here


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"patterns_{module_blender}")
    variants = VARIANTS + POINTS + (MUSGRAVE + ("musgrave_hybrid_negative",) if module_blender == "blender34" else ())
    return luminance_by_engine(module_blender, out, "pattern", ENGINES, {v: {"variant": v} for v in variants})


def blurred(image):
    """A 3 x 3 box average: the bricks' and rings' sharp edges are anti-aliased by different
    samples and pixel filters (Cycles' 1.5-pixel Blackman-Harris blurs them a little more
    than our 4 jittered samples in a box), a difference within a pixel that this takes out."""
    p = np.pad(image, 1, mode="edge")
    return sum(p[i:i + image.shape[0], j:j + image.shape[1]] for i in range(3) for j in range(3)) / 9


@pytest.mark.parametrize("variant", VARIANTS + MUSGRAVE)
def test_the_pattern_is_where_cycles_puts_it(renders, module_blender, variant):
    if ("CYCLES", variant) not in renders:
        pytest.skip(f"{module_blender} has no Musgrave Texture (Blender 4.1 made it part of the Noise Texture)")
    ours, cycles = (renders[(engine, variant)][4:-4, 4:-4] for engine in ("GRIDWALK", "CYCLES"))
    assert cycles.std() > 0.03                                       # a pattern, not a flat colour
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.97
    assert np.corrcoef(blurred(ours).reshape(-1), blurred(cycles).reshape(-1))[0, 1] > 0.99
    assert abs(float(ours.mean() - cycles.mean())) < 0.01 * max(1.0, float(cycles.mean()))


@pytest.mark.parametrize("variant", POINTS)
def test_one_colour_settings_give_cycles_colour(renders, variant):
    """A White Noise at one point (its hash), and bricks of negative width (all mortar)."""
    ours, cycles = (renders[(engine, variant)][4:-4, 4:-4] for engine in ("GRIDWALK", "CYCLES"))
    assert ours.std() < 1e-4 and cycles.std() < 1e-4
    assert abs(float(ours.mean() - cycles.mean())) < 1e-3


def test_a_negative_musgrave_detail_is_clamped_to_0_as_in_cycles(renders, module_blender):
    """(Blender 3.4's socket takes -0.5 from a script: Cycles clamps it to 0, and Hybrid's one
    octave times 0 is 0, flat; taken as it came, it was a pattern)"""
    if ("CYCLES", "musgrave_hybrid_negative") not in renders:
        pytest.skip(f"{module_blender} has no Musgrave Texture (Blender 4.1 made it part of the Noise Texture)")
    ours, cycles = (renders[(engine, "musgrave_hybrid_negative")][4:-4, 4:-4] for engine in ("GRIDWALK", "CYCLES"))
    assert cycles.std() < 1e-4 and ours.std() < 1e-4 and abs(float(ours.mean() - cycles.mean())) < 1e-3
