"""Rough metals: Principled BSDF spheres of Metallic 1 and Roughness 0.2-0.8 (glossy_scenes.
rough_metal_scene) as bright as Cycles' under a sun and in a grey world, in bpy 4.5, bpy 5.0
(Multiscatter GGX, their default) and Debian's 3.4 (GGX). Gridwalk's glossy lobe is GGX
(core/src/microfacet.h); its normalised Blinn-Phong lobe before gave 0.70x / 0.80x / 1.18x / 1.94x
Cycles' brightness under the sun at Roughness 0.2 / 0.3 / 0.5 / 0.8."""
import numpy as np
import pytest

from runner import GLOSSY_ENGINES, combined_rgb_by_variant, row_sphere_means

ROUGHNESS = (0.2, 0.35, 0.5, 0.8)        # glossy_scenes.ROUGH_METALS, left to right


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    """{(lit, engine): linear RGB} for both lightings and engines, in one Blender."""
    out = tmp_path_factory.mktemp(f"rough_metal_{module_blender}")
    return combined_rgb_by_variant(module_blender, out, "rough_metal", "lit", ("sun", "world"), GLOSSY_ENGINES)


def sphere_means(rgb):
    return row_sphere_means(rgb, len(ROUGHNESS))


@pytest.mark.parametrize("lit, tolerance", [("sun", 0.1), ("world", 0.06)])
def test_each_sphere_is_as_bright_as_in_cycles(renders, lit, tolerance):
    ours, cycles = sphere_means(renders[lit, "GRIDWALK"]), sphere_means(renders[lit, "CYCLES"])
    assert (cycles > 1e-3).all()
    ratio = ours.sum(axis=1) / cycles.sum(axis=1)
    assert np.abs(ratio - 1).max() < tolerance, dict(zip(ROUGHNESS, ratio.round(3)))
    # the metal's colour: red over blue as in Cycles (Schlick's Fresnel rising from the base colour)
    hue_ours, hue_cycles = ours[:, 0] / ours[:, 2], cycles[:, 0] / cycles[:, 2]
    assert np.abs(hue_ours / hue_cycles - 1).max() < 0.1, (hue_ours.round(2), hue_cycles.round(2))
