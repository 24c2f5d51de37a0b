"""Values per object instance as Cycles gives them, in bpy 4.5, bpy 5.0 and Debian's 3.4: the
Object Info node's Random, Color, Alpha, Object Index and Location, and the Attribute node's Object and
Instancer types (custom properties of five kinds; an instancer's own; a Geometry Nodes instance
attribute), into an Emission colour. Layouts: twelve objects of one mesh (ASCII and UTF-8 names:
Random hashes a name), a collection shown by two instancing Empties, 64 Geometry Nodes copies of
one tile; also through a Color Ramp and a Math Divide. Before, the nodes were named in a warning
and every tile kept the Emission's own colour (the Attribute node read the mesh's attribute).
Scene: object_info_scenes.object_info_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
VARIANTS = {
    "random_objects": {"output": "Random"},
    "random_collection": {"output": "Random", "layout": "collection"},
    "random_copies": {"output": "Random", "layout": "copies"},
    "random_ramp": {"output": "Random", "ramp": True},
    "color_objects": {"output": "Color"},
    "alpha_collection": {"output": "Alpha", "layout": "collection"},
    "index_objects": {"output": "Object Index", "divide": 12.0},
    "index_collection": {"output": "Object Index", "divide": 6.0, "layout": "collection"},
    "color_copies": {"output": "Color", "layout": "copies"},
    "location_objects": {"output": "Location"},         # each tile's place, x 0.2 + 0.5, as its colour
    "location_copies": {"output": "Location", "layout": "copies"},
    # the Attribute node's Object and Instancer types (object_attributes.py)
    "object_attribute": {"attribute": "OBJECT", "output": "Color"},
    "object_attribute_fac_ramp": {"attribute": "OBJECT", "output": "Fac", "ramp": True},
    "instancer_attribute_collection": {"attribute": "INSTANCER", "output": "Color", "layout": "collection"},
    "instancer_attribute_copies": {"attribute": "INSTANCER", "output": "Color", "layout": "copies"},
}
BULK = ("instancer_attribute_copies",)     # Blender 4.3+ (evaluated_geometry) reads these


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"object_info_{module_blender}")
    return luminance_by_engine(module_blender, out, "object_info", ENGINES, VARIANTS)


def _away_from_edges(image):
    """Pixels whose 3 x 3 neighbourhood is one value (a tile's inside, or the background):
    there the two engines' pixel filters agree, and each tile's value is compared exactly."""
    h, w = image.shape
    padded = np.pad(image, 1, mode="edge")
    around = np.stack([padded[y:y + h, x:x + w] for y in range(3) for x in range(3)])
    return np.ptp(around, axis=0) < 0.005


@pytest.mark.parametrize("name", VARIANTS)
def test_each_instance_shows_its_value_as_in_cycles(renders, name, module_blender):
    if name in BULK and module_blender == "blender34":
        pytest.skip("Blender 3.4 has no evaluated_geometry: instance attributes are named in a warning instead")
    ours, cycles = renders[("GRIDWALK", name)], renders[("CYCLES", name)]
    assert cycles.std() > 0.05                                            # the tiles differ from the background
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.98
    inside = _away_from_edges(cycles) & (cycles > 0.01)
    assert inside.mean() > 0.1
    assert np.abs(ours - cycles)[inside].max() < 0.01


def test_random_copies_each_get_their_own_value_in_bulk(export):
    out = export("object_info", output="Random", layout="copies")
    assert not out.warnings, out.warnings
    if out.blender >= [4, 3, 0]:                   # (each copy's random_id read with it as it is listed)
        assert out.bulk_copies == 64
    colours = out.colors.reshape(-1, 2, 3, 3)      # (each copy: two triangles, three corners)
    assert np.all(colours == colours[:, :1, :1])   # one value over each copy
    assert len(np.unique(colours[:, 0, 0, 0])) == 64
    assert out.corner_arrays_read == {"uvs": False, "colors": True}


def test_a_colour_for_every_copy_keeps_the_bulk_path(export):
    out = export("object_info", output="Color", layout="copies")
    colours = out.colors.reshape(-1, 3)
    assert len(np.unique(colours, axis=0)) == 1
    if out.blender >= [4, 3, 0]:
        assert out.bulk_copies == 64


def test_unread_outputs_and_spheres_are_named(export):
    index = export("object_info", output="Material Index")
    assert any("Material Index output" in w for w in index.warnings), index.warnings
    assert "colors" not in index.arrays
    spheres = export("object_info", output="Random", sphere=True)
    assert any("Object Info or an Object or Instancer attribute are rendered as their meshes" in w and "'Élan'" in w
               for w in spheres.warnings), spheres.warnings
    assert not any("light nothing" in w for w in spheres.warnings), spheres.warnings   # (they are meshes)
    assert len(spheres.arrays["sphere_radii"]) == 0 and len(np.unique(spheres.colors[:, 0, 0])) == 12
    points = export("object_info", output="Random", points=True)
    assert len(points.arrays["sphere_radii"]) == 4
    assert any("not read on point clouds and hair" in w and "'Dots'" in w for w in points.warnings), \
        points.warnings


@pytest.mark.parametrize("copies", [8, 3])
def test_instance_attributes_come_with_the_copies_or_are_named(export, copies):
    # (9 copies: under the bulk path's 64, taken in bulk because a material reads instance attributes)
    out = export("object_info", output="Color", attribute="INSTANCER", layout="copies", copies=copies)
    if out.blender >= [4, 3, 0]:
        assert out.bulk_copies == copies ** 2 and not out.warnings, out.warnings
        assert len(np.unique(out.colors.reshape(-1, 3), axis=0)) == copies ** 2
    else:
        assert any("instance attributes were not read" in w and "'tint' of 'Carrier'" in w for w in out.warnings)


def test_object_attributes_read_custom_properties(export):
    out = export("object_info", output="Color", attribute="OBJECT")
    assert not out.warnings, out.warnings
    tiles = out.colors.reshape(12, 2, 3, 3)[:, 0, 0]          # (one value per tile; tile k has TINTS[(k + 1) % 5])
    assert np.all(tiles[0::5] == tiles[0::5, :1]) and len(np.unique(tiles[0::5, 0])) == 3   # numbers: grey
    assert np.all(tiles[1::5] == 1) and np.all(tiles[3::5] == 1)   # a whole number 1, a true boolean
    assert np.all(tiles[2::5] == 0)                                # no property: black
    assert len(np.unique(tiles[4::5], axis=0)) == 2 and np.all(np.ptp(tiles[4::5], axis=1) > 0)   # colours


def test_two_colour_sources_on_one_mesh_are_named(export):
    out = export("object_info", output="Random", second="attribute")
    assert any("read different corner colours" in w for w in out.warnings), out.warnings


def test_particle_instances_read_their_particle_settings_first(export):
    # (Cycles: an Instancer attribute of a particle instance is the particle settings' property
    # before the emitter's)
    out = export("object_info", output="Color", attribute="INSTANCER", layout="particles")
    colours = out.colors.reshape(-1, 3)
    red = np.all(np.isclose(colours, [0.9, 0.1, 0.1]), axis=1)
    assert red.sum() == 4 * 2 * 3                       # the four copies' corners (the source tile: its own)
    assert not np.any(np.all(np.isclose(colours, [0.1, 0.9, 0.1]), axis=1))     # not the emitter's
