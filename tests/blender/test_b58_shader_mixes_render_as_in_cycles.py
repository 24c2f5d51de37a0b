"""Mix and Add Shaders one Whitted material holds (blender_addon/export/shader_mix.py): spheres
of a Diffuse and a Glossy BSDF mixed by a constant Fac, by a Fresnel node and by a Layer Weight's
Fresnel, and of a Diffuse BSDF plus an Emission (glossy_scenes.shader_mix_scene) are as bright
and of the hue of Cycles' under a sun and in a grey world, in bpy 4.5, bpy 5.0 and Debian's 3.4.
They rendered in their viewport colour before (grey 0.8), with a warning."""
import numpy as np
import pytest

from runner import GLOSSY_ENGINES, combined_rgb_by_variant, row_sphere_means

MIXES = ("constant", "fresnel", "layer_weight", "emission")      # glossy_scenes.SHADER_MIXES


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"shader_mix_{module_blender}")
    return combined_rgb_by_variant(module_blender, out, "shader_mix", "lit", ("sun", "world"), GLOSSY_ENGINES)


def sphere_means(rgb):
    return row_sphere_means(rgb, len(MIXES))


@pytest.mark.parametrize("lit", ["sun", "world"])
def test_each_mix_is_as_bright_and_of_the_hue_of_cycles(renders, lit):
    ours, cycles = sphere_means(renders[lit, "GRIDWALK"]), sphere_means(renders[lit, "CYCLES"])
    assert (cycles > 1e-3).all()
    ratio = ours / cycles
    assert np.abs(ratio - 1).max() < 0.1, {m: r.round(3).tolist() for m, r in zip(MIXES, ratio)}
