"""An Image Texture's Projection renders as in Cycles, in bpy 4.5, bpy 5.0 and Debian's 3.4:
Box (three flat lookups blended by the object-space normal: a cube shaded smooth, so the
blend shows along its edges), Sphere and Tube, each at a cube's Generated coordinates
through a Mapping node. Before, each was read as Flat with a warning.
Scene: procedural_scenes.procedural_checker_scene (variant "image")."""
import numpy as np
import pytest

from runner import luminance_by_engine

ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
VARIANTS = {"box": {"variant": "image", "projection": "BOX", "blend": 0.3, "smooth": True},
            "box_sharp": {"variant": "image", "projection": "BOX"},
            "sphere": {"variant": "image", "projection": "SPHERE"},
            "tube": {"variant": "image", "projection": "TUBE"},
            "flat": {"variant": "image"}}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"projections_{module_blender}")
    return luminance_by_engine(module_blender, out, "procedural_checker", ENGINES, VARIANTS)


@pytest.mark.parametrize("name", ["box", "box_sharp", "sphere", "tube"])
def test_the_projected_image_lands_where_cycles_puts_it(renders, name):
    ours, cycles = renders[("GRIDWALK", name)], renders[("CYCLES", name)]
    assert cycles.std() > 0.05
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.98
    assert np.abs(ours - cycles).mean() < 0.02
    assert np.abs(ours - renders[("GRIDWALK", "flat")]).mean() > 0.02      # not the flat projection


@pytest.mark.parametrize("name", ["box", "sphere", "tube"])
def test_the_export_names_the_projection_without_a_warning(export, name):
    out = export("procedural_checker", **VARIANTS[name])
    (texture,) = out.textures
    assert texture["projection"] == name and texture["coordinates"] == "generated"
    assert not out.warnings, out.warnings
    assert ("object_normals" in out.arrays) == (name == "box")
    if name == "box":
        assert texture["projection_blend"] == pytest.approx(0.3)
