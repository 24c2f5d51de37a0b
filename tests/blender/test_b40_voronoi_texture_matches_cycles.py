"""Blender's Voronoi Texture renders as in Cycles, in bpy 4.5, bpy 5.0 and Debian's 3.4: the node
as Blender adds it (3D F1, Euclidean, its Distance at Generated coordinates), its Color and
Position outputs, F2 with the Manhattan metric, Smooth F1, Minkowski with less randomness, 2D,
4D and 1D cells, its Position into a Color Ramp (a vector read as a number: the average of
its coordinates; through a colour Mix first, a colour: its luminance), and (Blender 4.0 and later) several octaves normalized; Blender 5.0 hashes the
cells anew (PCG), as the export tells the core. Its Distance to Edge (also over octaves, 4.0
and later) and N-Sphere Radius features. Before, a Voronoi Texture was a warning and its
input's default colour (and, until a later change, those two features were). Scene: voronoi_scenes.voronoi_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = ("distance", "color", "position", "f2", "smooth", "minkowski", "2d", "4d", "1d",  # VORONOI_VARIANTS
            "fractal", "position_ramp", "tinted_position_ramp", "edge", "edge_fractal", "radius")
OCTAVES = ("fractal", "edge_fractal")                                # Blender 4.0 and later
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"voronoi_{module_blender}")
    variants = [v for v in VARIANTS if v not in OCTAVES or module_blender != "blender34"]
    return luminance_by_engine(module_blender, out, "voronoi", ENGINES, {v: {"variant": v} for v in variants})


@pytest.mark.parametrize("variant", [v for v in VARIANTS if v != "1d"])
def test_the_cells_are_where_cycles_puts_them(renders, module_blender, variant):
    if ("GRIDWALK", variant) not in renders:
        pytest.skip(f"{module_blender} has no octaves for its Voronoi Texture (Blender 4.0 added them)")
    ours, cycles = (renders[(engine, variant)][4:-4, 4:-4] for engine in ("GRIDWALK", "CYCLES"))
    assert cycles.std() > 0.05                                        # cells, not a flat colour
    # (the cells' edges, where Color and F2 jump, are anti-aliased by different samples)
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.995
    assert np.abs(ours - cycles).mean() < 0.06 * cycles.std()
    assert abs(float(ours.mean() - cycles.mean())) < 0.01 * max(1.0, float(cycles.mean()))


def test_one_dimensional_cells_give_one_colour_as_in_cycles(renders):
    ours, cycles = (renders[(engine, "1d")][4:-4, 4:-4] for engine in ("GRIDWALK", "CYCLES"))
    assert ours.std() < 1e-3 and abs(float(ours.mean() - cycles.mean())) < 2e-3


def test_every_feature_is_read(export):
    for variant, feature, output in (("edge", "distance_to_edge", "distance"), ("radius", "n_sphere_radius", "radius")):
        out = export("voronoi", variant=variant)
        assert "error" not in out.info, out.info.get("error")
        assert not out.warnings, out.warnings
        (texture,) = out.textures
        assert (texture["kind"], texture["voronoi_feature"], texture["voronoi_output"]) == ("voronoi", feature, output)
