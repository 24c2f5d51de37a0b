"""A Geometry Nodes carrier's copies are read from its instances component in bulk
(export/carrier_instances.py; Blender 4.3 and later) and export exactly as when each is
read from the depsgraph one by one: the same arrays (to float32 rounding), warnings and
lights, for carriers scattering a cube, an icosphere their node tree makes (a geometry
set, whose copies come through temporary objects that take turns), either of two cubes
per point, a cube while hidden from renders, a cube scaled 1e29 (copies beyond 1e30
skipped and named), and a cube beside the carrier's own mesh. A carrier whose copies do
not map one to one onto its points (a collection of two cubes on each) or are not meshes
(a light) is read one by one, and so is one whose copy checked against the depsgraph
differs from what the bulk read gives ("tampered": that copy's transform moved by a unit
in the bulk read). Debian's Blender 3.4, without the API, reads every copy one by one.
Scene: scatter_scenes.carrier_scene; script: scripts/carrier_bulk.py."""
import json

import pytest

from runner import script_output

VARIANTS = ("object", "primitive", "collection", "picked", "light", "hidden", "far", "mixed", "tampered")
IN_BULK = ("object", "primitive", "picked", "hidden", "far", "mixed")
COPIES = 2000          # carrier_scene's default count


@pytest.fixture(scope="module")
def compared(module_blender, tmp_path_factory):
    out = script_output(module_blender, tmp_path_factory, "carrier_bulk.py", *VARIANTS, timeout=300)
    return json.loads((out / "carrier_bulk.json").read_text())


@pytest.mark.parametrize("variant", VARIANTS)
def test_copies_read_in_bulk_export_as_when_read_one_by_one(compared, variant):
    result = compared[variant]
    assert result["single_copies"] == 0                   # (the second export read every copy one by one)
    assert result["differ"] == {}, result["differ"]
    bulk, single = result["warnings"]
    assert bulk == single
    assert result["lights"][0] == result["lights"][1]
    if variant == "far":
        assert any("lie beyond" in w for w in bulk), bulk
    if variant == "hidden":
        assert result["triangles"] == 24                  # the floor and the cube made after the carrier


@pytest.mark.parametrize("variant", VARIANTS)
def test_carriers_whose_copies_check_out_are_read_in_bulk(compared, variant):
    expected = COPIES if compared["bulk_api"] and variant in IN_BULK else 0
    assert compared[variant]["bulk_copies"] == expected
