"""Materials made of node groups render as in Cycles, in bpy 4.5, bpy 5.0 and Debian's 3.4: a
group holding the shader (its Color from a Checker and a Color Ramp outside, its Strength from
the group node's own value), a group holding the texture (its Scale from the group's input), a
group nested in a group (times the outer group's Gain), one group in two materials at two
Scales, and a group passing its unlinked input through. Before, a group node was named in a
warning and its input kept its own value (a grouped shader: the viewport colour).
Scene: group_scenes.node_group_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
VARIANTS = {v: {"variant": v} for v in ("shader", "texture", "nested", "twice", "constant")}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"node_groups_{module_blender}")
    return luminance_by_engine(module_blender, out, "node_group", ENGINES, VARIANTS)


@pytest.mark.parametrize("name", VARIANTS)
def test_a_grouped_material_renders_as_in_cycles(renders, name):
    ours, cycles = renders[("GRIDWALK", name)], renders[("CYCLES", name)]
    if name == "constant":
        assert np.abs(cycles - cycles.mean()).max() < 0.01 and abs(ours.mean() - cycles.mean()) < 0.01
        assert cycles.mean() > 0.3       # (the group node's orange, not the group's grey default)
        return
    assert cycles.std() > 0.05                                       # the checker shows
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.97
    assert np.abs(ours - cycles).mean() < 0.03


def test_the_export_reads_through_groups_without_warnings(export):
    for variant in VARIANTS:
        out = export("node_group", variant=variant)
        assert not out.warnings, (variant, out.warnings)
        if variant != "constant":
            assert any(t["kind"] == "checker" for t in out.textures), (variant, out.textures)
    twice = export("node_group", variant="twice")
    checkers = [t for t in twice.textures if t["kind"] == "checker"]
    assert {t["scale"] for t in checkers} == {3.0, 9.0}         # one group, its two Scales


def test_a_group_used_twice_in_one_chain_passes_the_value_through_both(export):
    out = export("group_edge", variant="twice_through")
    assert not out.warnings, out.warnings
    assert out.materials[1]["emission_color"] == pytest.approx([0.9, 0.5, 0.1], abs=1e-6)


def test_a_colour_through_a_number_socket_is_named_not_read_as_the_colour(export):
    # (Cycles makes the colour a number at the group's socket: the grey of its luminance)
    out = export("group_edge", variant="narrowed")
    assert any("ShaderNodeGroup" in w for w in out.warnings), out.warnings
    assert out.materials[1]["emission_color"] != pytest.approx([0.9, 0.5, 0.1], abs=1e-6)


def test_a_world_reads_its_background_through_a_group(export):
    out = export("group_edge", variant="world")
    assert not out.warnings, out.warnings
    assert out.background == pytest.approx([0.9, 0.5, 0.1], abs=1e-6)     # (Strength 1)
