"""An alpha cut-off as Blender's glTF importer builds it (Alpha Mode Mask: the image's Alpha through
a Math node's Less Than of the cutoff, then 1 - that, into the Principled BSDF's Alpha; or a
Greater Than) cuts where Cycles cuts, in bpy 4.5, bpy 5.0 and Debian's 3.4: the comparison is
read as the Constant Color Ramp it equals (value_nodes.StepRamp). Before, the Alpha took its
default value (opaque), with a warning. Scene: material_scenes.alpha_mask_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = {"less_than": {"operation": "LESS_THAN", "cutoff": 0.5},
            "greater_than": {"operation": "GREATER_THAN", "cutoff": 0.3}}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"alpha_mask_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 2}', "CYCLES": "samples=8"}
    return luminance_by_engine(module_blender, out, "alpha_mask", engines, VARIANTS)


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_the_cut_lies_where_cycles_puts_it(renders, variant):
    # (each column one texel of the alpha ramp; the plane's own edge columns left out)
    ours, cycles = (renders[(engine, variant)][4:-4, 2:-2].mean(axis=0) for engine in ("GRIDWALK", "CYCLES"))
    centre = np.arange(2, 62) + 0.5
    cutoff = VARIANTS[variant]["cutoff"]
    shown = centre > 64 * cutoff                      # (both keep the texels past the cutoff)
    clear_of_it = np.abs(centre - 64 * cutoff) > 1.5
    assert np.all(cycles[shown & clear_of_it] > 0.9) and np.all(cycles[~shown & clear_of_it] < 0.05)
    np.testing.assert_allclose(ours[clear_of_it], cycles[clear_of_it], atol=0.05)
    assert np.abs(ours - cycles).mean() < 0.02
