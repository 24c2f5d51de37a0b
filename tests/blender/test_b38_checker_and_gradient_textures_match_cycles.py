"""Blender's Checker Texture renders as in Cycles, in bpy 4.5, bpy 5.0 and
Debian's 3.4: at the Generated coordinates it reads when nothing feeds its
Vector, through a Texture Coordinate node's Generated output and a Mapping
node, on a cube with a Subdivision modifier (Generated spans the cube before
it) and on one twisted by a Simple Deform modifier (Generated is taken before
it), with a Value node into its Scale and an RGB node into its Color1, at the UV map, at a scaled cube's Object coordinates, its Fac output,
into a lit Principled BSDF; and an Image Texture at Generated coordinates.
Before, a Checker was a warning and its input's default colour. Shapes
without Generated coordinates (a 'Render as sphere' object, hair) export
without an error, each with a warning.
Blender's Gradient Texture, each of its seven types at a plane's Object
coordinates through a Mapping node, renders as in Cycles too, and so does a
Color Ramp of three stops after it (Linear, Ease and Constant; with two stops
at one position; in B-Spline and HSV over stops a script left out of order,
which goes out as Cycles' own table).
Scenes: procedural_scenes.procedural_checker_scene, checker_on_shapes_scene,
procedural_gradient_scene."""
import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = ("plane", "cube", "subdivided", "uv", "fac", "image", "principled",   # procedural_scenes.CHECKER_VARIANTS
            "object", "twisted", "valued", "position", "other_object")
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
GRADIENTS = ("LINEAR", "QUADRATIC", "EASING", "DIAGONAL", "SPHERICAL", "QUADRATIC_SPHERE", "RADIAL")


def _both(module_blender, tmp_path_factory, scene, key, values):
    """{(engine, value): luminance} of `scene` with its option `key` set to each of `values`."""
    out = tmp_path_factory.mktemp(f"{scene}_{module_blender}")
    return luminance_by_engine(module_blender, out, scene, ENGINES, {v: {key: v} for v in values})


def _like_cycles(renders, key, spread, correlation, difference):
    """(ours, Cycles') images after checking that Cycles' shows a pattern (its spread) and ours
    correlates with it and differs from it by less than `difference` on average."""
    ours, cycles = renders[("GRIDWALK", key)], renders[("CYCLES", key)]
    assert cycles.std() > spread                                         # a pattern, not a flat colour
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > correlation
    assert np.abs(ours - cycles).mean() < difference
    return ours, cycles


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    return _both(module_blender, tmp_path_factory, "procedural_checker", "variant", VARIANTS)


@pytest.mark.parametrize("variant", VARIANTS)
def test_the_checker_lands_where_cycles_puts_it(renders, variant):
    _like_cycles(renders, variant, 0.1, 0.99, 0.015)


def test_the_pattern_is_not_the_default_colour(renders):
    # the plane at Generated coordinates and at the UV map: shifted by a quarter square, not alike
    plane, uv = renders[("GRIDWALK", "plane")], renders[("GRIDWALK", "uv")]
    assert np.abs(plane - uv).mean() > 0.05


def test_the_export_names_generated_coordinates_and_the_checker(export):
    out = export("procedural_checker", variant="cube")
    (texture,) = out.textures
    assert texture["kind"] == "checker" and texture["coordinates"] == "generated"
    assert texture["scale"] == pytest.approx(3.7)
    assert out.generated.shape == (len(out.triangles), 3, 3)
    # the cube's corners are the corners of its texture space
    assert out.generated.min() == pytest.approx(0.0, abs=1e-6) and out.generated.max() == pytest.approx(1.0, abs=1e-6)
    assert not out.warnings, out.warnings
    assert out.corner_point_arrays == 1                   # what the memory estimate counts before the export
    assert out.corner_arrays_read == {"uvs": False, "colors": False}


def test_object_coordinates_are_the_corners_in_object_space(export):
    out = export("procedural_checker", variant="object")
    (texture,) = out.textures
    assert texture["coordinates"] == "object"
    corners = out.object_coords.reshape(-1, 3)
    np.testing.assert_allclose(np.abs(corners), 1.5, atol=1e-6)      # cube_object of size 3, before its scale
    assert "generated" not in out.arrays
    assert out.corner_point_arrays == 2                   # (the estimate counts Generated too: a checker's default)


def test_the_memory_estimate_counts_the_uvs_a_checker_reads(export):
    out = export("procedural_checker", variant="uv")
    (texture,) = out.textures
    assert texture["coordinates"] == "uv" and out.uvs.shape == (len(out.triangles), 3, 2)
    assert out.corner_arrays_read == {"uvs": True, "colors": False}   # no image: counted by the nodes


def test_constant_nodes_into_the_checker_give_their_values(export):
    out = export("procedural_checker", variant="valued")
    (texture,) = out.textures
    assert texture["scale"] == pytest.approx(out.expected["value_scale"])
    np.testing.assert_allclose(texture["color1"], out.expected["rgb"][:3], rtol=1e-6)
    assert not out.warnings, out.warnings


def test_object_coordinates_of_another_object_are_the_world_point_in_its_space(export):
    out = export("procedural_checker", variant="other_object")
    (texture,) = out.textures
    assert texture["coordinates"] == "position" and not out.warnings, out.warnings
    assert "object_coords" not in out.arrays and "generated" not in out.arrays
    # the Mapping after the empty's inverse world matrix: a world point on the empty's
    # origin maps to the Mapping's Location
    m = np.asarray(texture["vector_transform"]).reshape(3, 4)
    np.testing.assert_allclose(m @ np.append(out.expected["empty_location"], 1.0), out.expected["mapping_location"],
                               atol=1e-5)


def test_object_coordinates_of_an_object_scaled_to_zero_are_named_in_a_warning(export):
    # (its transform has no inverse: the export used to stop with "Singular matrix")
    out = export("procedural_checker", variant="other_object", flat_empty=True)
    (texture,) = out.textures
    assert "error" not in out.info and texture["coordinates"] == "generated"     # the Checker's own default
    assert any("'Empty', whose transform cannot be inverted" in w for w in out.warnings), out.warnings


def test_a_coordinate_source_not_read_is_named_in_a_warning(export):
    # (the Texture Coordinate node's outputs are all read: test_b47)
    out = export("procedural_checker", variant="cube", coordinates="Geometry:Parametric")
    (texture,) = out.textures
    assert texture["coordinates"] == "generated"                      # the Checker's own default
    assert any("ShaderNodeNewGeometry Parametric" in w for w in out.warnings), out.warnings


def test_shapes_without_generated_coordinates_are_exported_with_a_warning(export):
    out = export("checker_on_shapes")
    assert "error" not in out.info, out.info.get("error")
    assert len(out.sphere_radii) == 0                     # Ball and Bumpy (its bump's checker) went out as their
    assert len(out.generated) == len(out.triangles) > 0   # meshes, with Generated coordinates
    warnings = " ".join(out.warnings)
    assert "rendered as their meshes: 'Ball', 'Bumpy'" in warnings
    if out.expected["hair"]:
        textures = [out.materials[i]["color_texture"] for i in np.unique(out.cylinder_materials)]
        assert textures == [-1]                           # the strands' copy of the material has no checker
        assert "not read on point clouds and hair" in warnings


RAMPS = ("LINEAR", "EASE", "CONSTANT", "SHARED", "ODD", "AFTER", "TINTED")    # procedural_gradient_scene's ramps
RAMP_COLORS = ((0.9, 0.2, 0.1), (0.1, 0.8, 0.2))           # its first two stops (procedural_scenes.RAMP)


@pytest.fixture(scope="module")
def gradients(module_blender, tmp_path_factory):
    """Each gradient type, and the linear one through each kind of ramp ("ramp LINEAR" ...)."""
    out = tmp_path_factory.mktemp(f"gradient_{module_blender}")
    variants = {**{g: {"gradient": g} for g in GRADIENTS}, **{f"ramp {r}": {"ramp": r} for r in RAMPS}}
    return luminance_by_engine(module_blender, out, "procedural_gradient", ENGINES, variants)


@pytest.mark.parametrize("gradient", GRADIENTS)
def test_the_gradient_ramps_as_in_cycles(gradients, gradient):
    ours, cycles = _like_cycles(gradients, gradient, 0.15, 0.998, 0.005)
    # (the plane's edges meet the black world; the radial ramp's seam, where it jumps from 1 to 0, is
    # anti-aliased by different samples in each engine: two rows of pixels there differ by a sample's share)
    inner = np.abs(ours - cycles)[3:-3, 3:-3]
    assert np.percentile(inner, 98) < 0.005


@pytest.mark.parametrize("ramp", RAMPS)
def test_a_color_ramp_colours_the_gradient_as_in_cycles(gradients, ramp):
    ours, cycles = _like_cycles(gradients, f"ramp {ramp}", 0.03, 0.995, 0.003)   # (SHARED: a hard edge)
    # (Constant's steps are anti-aliased by different samples in each engine)
    assert np.percentile(np.abs(ours - cycles)[3:-3, 3:-3], 90) < 0.002
    other = gradients[("GRIDWALK", "ramp " + ("EASE" if ramp == "LINEAR" else "LINEAR"))]
    assert np.abs(ours - other).max() > 0.02                     # each interpolation shows


def test_nodes_before_and_after_a_color_ramp_are_exported_around_it(export):
    # (before, the nodes after a ramp left the input at its default value, with a warning)
    out = export("procedural_gradient", ramp="AFTER")
    texture = out.textures[out.materials[int(out.triangle_materials[0])]["color_texture"]]
    assert not out.warnings, out.warnings
    assert len(texture["ramp"]) == 3                                   # (three stops)
    assert texture["gain"] == pytest.approx((0.8,) * 3) and texture["bias"] == pytest.approx((0.1,) * 3)
    assert texture["ramp_channel"] == 1 and texture["ramp_clamp"]
    assert texture["ramp_gain"] == pytest.approx((2.0,) * 3) and texture["ramp_bias"] == pytest.approx((-0.3,) * 3)


def test_a_color_ramp_of_a_constant_fac_gives_its_colour_there(export, any_blender, tmp_path_factory):
    # (before, the input's own value, with a warning: Cycles shows the ramp's colour)
    out = export("procedural_gradient", ramp="FIXED")
    assert "error" not in out.info and not any("Color Ramp" in w or "ValToRGB" in w for w in out.warnings), out.warnings
    assert out.textures == [] and all(m["color_texture"] == -1 for m in out.materials)
    # Linear between (0.15, red) and (0.5, green) at 0.3: 3/7 of the way
    want = np.array(RAMP_COLORS[0]) + (np.array(RAMP_COLORS[1]) - np.array(RAMP_COLORS[0])) * (0.15 / 0.35)
    np.testing.assert_allclose(out.materials[int(out.triangle_materials[0])]["color"], want[:3], atol=1e-5)
    renders = luminance_by_engine(any_blender, tmp_path_factory.mktemp("fixed"), "procedural_gradient", ENGINES,
                                  {"fixed": {"ramp": "FIXED"}})
    ours, cycles = renders[("GRIDWALK", "fixed")][4:-4, 4:-4], renders[("CYCLES", "fixed")][4:-4, 4:-4]
    assert cycles.mean() > 0.1 and abs(float(ours.mean() - cycles.mean())) < 0.01 * float(cycles.mean())
