"""An Attribute node (Geometry type) into a colour reads the mesh's attribute of that name as
Cycles reads it, in bpy 4.5, bpy 5.0 and Debian's 3.4: a number on faces (all three channels),
a whole number on faces, a vector on points (interpolated across each face), a byte colour on
corners, an 8-bit whole number on faces (4.5 and 5.0), and the Fac of a number and of a colour
(its mean) through a Color Ramp; a name the mesh lacks reads black, with a warning, and so does
a 2D whole number, as in Cycles. Before, the node was named in a warning and the input kept its
own colour. Scene: attribute_scenes.attribute_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
NAMES = ("face_value", "face_int", "point_vector", "corner_colour", "missing")
NEWER = ("face_int8", "point_int2")      # attribute types Blender 4.0 added
VARIANTS = {**{n: {"attribute": n} for n in NAMES + NEWER},
            # a number's Fac and a colour's Fac (its mean) through a Color Ramp
            "value_ramp": {"attribute": "face_value", "output": "Fac", "ramp": True},
            "colour_ramp": {"attribute": "corner_colour", "output": "Fac", "ramp": True}}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"attributes_{module_blender}")
    variants = {k: v for k, v in VARIANTS.items() if module_blender != "blender34" or k not in NEWER}
    return luminance_by_engine(module_blender, out, "attribute", ENGINES, variants)


@pytest.mark.parametrize("name", NAMES[:4] + ("value_ramp", "colour_ramp", "face_int8"))
def test_the_attribute_shows_as_in_cycles(renders, name, module_blender):
    if name in NEWER and module_blender == "blender34":
        pytest.skip("Blender 3.4 has no 8-bit integer attributes")
    ours, cycles = renders[("GRIDWALK", name)], renders[("CYCLES", name)]
    assert cycles.std() > 0.05                                           # the values vary over the grid
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.98
    assert np.abs(ours - cycles).mean() < 0.02


@pytest.mark.parametrize("name", ["missing", "point_int2"])
def test_a_missing_attribute_reads_black_as_in_cycles(renders, name, module_blender):
    # (Cycles reads a 2D whole number as nothing: black too)
    if name in NEWER and module_blender == "blender34":
        pytest.skip("Blender 3.4 has no 2D integer attributes")
    ours, cycles = renders[("GRIDWALK", name)], renders[("CYCLES", name)]
    assert cycles.max() < 0.01 and ours.max() < 0.01


def test_the_export_reads_the_attribute_by_name(export):
    out = export("attribute", attribute="face_value")
    (texture,) = out.textures
    assert texture["kind"] == "attribute" and not out.warnings, out.warnings
    colours = out.colors.reshape(-1, 3, 3)
    np.testing.assert_array_equal(colours[..., 0], colours[..., 1])      # a number: grey
    # a face's value at all its corners: the grid's triangles take its quads' values, each twice
    assert np.all(colours[:, 0, 0] == colours[:, 1, 0]) and np.all(colours[:, 0, 0] == colours[:, 2, 0])
    values, counts = np.unique(colours[:, 0, 0], return_counts=True)
    assert len(values) == len(colours) // 2 and np.all(counts == 2)
    # what the memory estimate counts before the export: the corner colours, and no UVs
    assert out.corner_arrays_read == {"uvs": False, "colors": True}
    missing = export("attribute", attribute="missing")
    assert any("missing" in w for w in missing.warnings), missing.warnings
