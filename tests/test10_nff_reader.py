"""NFF reader: the SPD scenes, the entity mapping, and one test per kind of malformed input."""
import math
from pathlib import Path

import numpy as np
import pytest

from gridwalk.io import SceneFileError, load_nff, load_scene
from gridwalk.model import Material

SPD_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "scenes" / "spd"
needs_spd = pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")

# file: (spheres, triangles, lights), from the SPD README table (each polygon a triangle
# in mount, the single square floor of balls split in two).
SPD_COUNTS = {
    "balls_s1.nff": (10, 2, 3), "balls_s2.nff": (91, 2, 3), "balls_s3.nff": (820, 2, 3),
    "balls_s4.nff": (7381, 2, 3), "mount_s4.nff": (4, 512, 1), "mount_s6.nff": (4, 8192, 1),
    "mount_s8.nff": (4, 131072, 1),
}
VIEW = "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 64 48\n"
VIEW_LINES = VIEW.count("\n")
TRIANGLE = "p 3\n0 0 0\n1 0 0\n0 1 0\n"


def write(tmp_path, text, name="scene.nff"):
    path = tmp_path / name
    path.write_text(text)
    return path


def check_arrays(scene):
    assert scene["vertices"].dtype == np.float32 and scene["vertices"].shape[1:] == (3,)
    assert scene["triangles"].dtype == np.int32 and scene["triangles"].shape[1:] == (3,)
    assert scene["sphere_centers"].dtype == np.float32 and scene["sphere_radii"].dtype == np.float32
    for key in ("triangle_materials", "sphere_materials", "cylinder_materials"):
        assert scene[key].dtype == np.int32
        ids = scene[key]
        assert ids.size == 0 or 0 <= ids.min() <= ids.max() < len(scene["materials"])
    assert len(scene["triangle_materials"]) == len(scene["triangles"])
    assert len(scene["sphere_materials"]) == len(scene["sphere_radii"])
    if len(scene["triangles"]):
        assert 0 <= scene["triangles"].min() and scene["triangles"].max() < len(scene["vertices"])


@needs_spd
@pytest.mark.parametrize("name", sorted(SPD_COUNTS))
def test_every_spd_file_loads_with_its_published_counts(name):
    scene = load_scene(SPD_DIR / name)
    check_arrays(scene)
    spheres, triangles, lights = SPD_COUNTS[name]
    assert len(scene["sphere_radii"]) == spheres
    assert len(scene["triangles"]) == triangles
    assert len(scene["lights"]) == lights
    assert scene["normals"] is None                    # SPD writes p, never pp
    assert scene["background"] == pytest.approx((0.078, 0.361, 0.753))


@needs_spd
def test_every_spd_file_in_shared_is_covered():
    assert sorted(p.name for p in SPD_DIR.glob("*.nff")) == sorted(SPD_COUNTS)


@needs_spd
def test_balls_s4_square_floor_becomes_two_triangles_under_7381_balls():
    scene = load_nff(SPD_DIR / "balls_s4.nff")
    assert len(scene["sphere_radii"]) == 7381
    assert scene["triangles"].tolist() == [[0, 1, 2], [0, 2, 3]]
    assert scene["vertices"].tolist() == [[12, 12, -0.5], [-12, 12, -0.5], [-12, -12, -0.5],
                                          [12, -12, -0.5]]
    assert scene["triangle_materials"].tolist() == [0, 0]
    assert set(scene["sphere_materials"].tolist()) == {1}
    floor, ball = scene["materials"]
    assert ball == Material(color=(1, 0.9, 0.7), kd=0.5, ks=0.5, shininess=3.0827,
                            transmittance=0, ior=1, mirror=0.5)
    assert floor.kd == 0.8 and floor.mirror == 0


@needs_spd
def test_mount_s8_has_131072_triangles_and_4_glass_spheres():
    scene = load_nff(SPD_DIR / "mount_s8.nff")
    assert len(scene["triangles"]) == 131072 and len(scene["sphere_radii"]) == 4
    glass, ground = scene["materials"]
    assert (glass.transmittance, glass.ior) == (0.9, 1.5)
    assert ground.ior == 1.0                           # SPD writes ior 0 for this opaque surface
    assert set(scene["sphere_materials"].tolist()) == {0}
    assert set(scene["triangle_materials"].tolist()) == {1}


def test_view_maps_to_camera_with_angle_between_outer_pixel_centres(tmp_path):
    scene = load_nff(write(tmp_path, VIEW + TRIANGLE))
    cam = scene["camera"]
    assert (cam.eye, cam.target, cam.up) == ((0, -5, 0), (0, 0, 0), (0, 0, 1))
    assert (cam.width, cam.height, cam.hither) == (64, 48, 0.01)
    # The centre of the top pixel row sits (H-1)/H of the half-height above the axis.
    top_row = math.degrees(math.atan(math.tan(math.radians(cam.fov / 2)) * 47 / 48))
    assert top_row == pytest.approx(20.0)


def test_a_new_image_size_keeps_the_angle_between_its_outer_pixel_centres(tmp_path):
    # --width / --height kept the file's field of view: rendered at 512, a 'resolution 64'
    # file framed differently from the same file at 'resolution 512'
    resized = load_scene(write(tmp_path, VIEW + TRIANGLE), width=200, height=150)["camera"]
    native = load_nff(write(tmp_path, VIEW.replace("resolution 64 48", "resolution 200 150") + TRIANGLE))["camera"]
    assert "resolution 64 48" in VIEW and (resized.width, resized.height) == (200, 150)
    assert resized.fov == pytest.approx(native.fov, rel=1e-6) and resized.fov != load_nff(
        write(tmp_path, VIEW + TRIANGLE))["camera"].fov
    top_row = math.degrees(math.atan(math.tan(math.radians(resized.fov / 2)) * 149 / 150))
    assert top_row == pytest.approx(20.0)


def test_view_without_hither_and_resolution_uses_spd_defaults(tmp_path):
    text = "v\nfrom 0 -5 0\nat 0 0 0\nup 0 0 1\nangle 40\n" + TRIANGLE
    cam = load_nff(write(tmp_path, text))["camera"]
    assert (cam.width, cam.height, cam.hither) == (512, 512, 0.0)


def test_lights_without_colour_get_spd_intensity_and_coloured_lights_keep_theirs(tmp_path):
    text = VIEW + "l 1 2 3\nl 4 5 6 0.5 0.25 1\nl 7 8 9\n" + TRIANGLE
    lights = load_nff(write(tmp_path, text))["lights"]
    assert [light.position for light in lights] == [(1, 2, 3), (4, 5, 6), (7, 8, 9)]
    assert lights[0].color == lights[2].color == pytest.approx((1 / math.sqrt(3),) * 3)
    assert lights[1].color == (0.5, 0.25, 1)
    assert {light.kind for light in lights} == {"point"}


def test_fill_line_maps_to_material_with_mirror_equal_to_ks(tmp_path):
    text = VIEW + "f 0.1 0.2 0.3 0.6 0.4 25 0.3 1.33\n" + TRIANGLE
    (mat,) = load_nff(write(tmp_path, text))["materials"]
    assert mat == Material(color=(0.1, 0.2, 0.3), kd=0.6, ks=0.4, shininess=25,
                           transmittance=0.3, ior=1.33, mirror=0.4)


def test_each_primitive_takes_the_latest_material_and_early_ones_a_default(tmp_path):
    text = (VIEW + "s 0 0 0 1\nf 1 0 0 1 0 1 0 1\ns 1 0 0 1\n" + TRIANGLE
            + "f 0 1 0 1 0 1 0 1\ns 2 0 0 1\n")
    scene = load_nff(write(tmp_path, text))
    assert scene["materials"][0] == Material()
    assert scene["sphere_materials"].tolist() == [0, 1, 2]
    assert scene["triangle_materials"].tolist() == [1]


def test_convex_polygon_is_fan_triangulated_with_its_own_vertices(tmp_path):
    pentagon = "p 5\n0 0 0\n2 0 0\n3 1 0\n1 2 0\n-1 1 0\n"
    scene = load_nff(write(tmp_path, VIEW + TRIANGLE + pentagon))
    assert len(scene["vertices"]) == 8
    assert scene["triangles"].tolist() == [[0, 1, 2], [3, 4, 5], [3, 5, 6], [3, 6, 7]]
    assert scene["vertices"][3:].tolist() == [[0, 0, 0], [2, 0, 0], [3, 1, 0], [1, 2, 0],
                                              [-1, 1, 0]]


def test_polygon_patch_normals_are_per_vertex_and_plain_polygons_get_their_plane_normal(tmp_path):
    patch = "pp 3\n0 0 1 0 0 2\n1 0 1 1 0 1\n0 1 1 0 3 4\n"
    clockwise = "p 3\n0 0 0\n0 1 0\n1 0 0\n"
    scene = load_nff(write(tmp_path, VIEW + TRIANGLE + clockwise + patch))
    normals = scene["normals"]
    assert normals.dtype == np.float32 and normals.shape == (9, 3)
    assert normals[:3].tolist() == [[0, 0, 1]] * 3                 # counter-clockwise p
    assert normals[3:6].tolist() == [[0, 0, -1]] * 3               # clockwise p
    np.testing.assert_allclose(normals[6:], [[0, 0, 1], [0.70710677, 0, 0.70710677], [0, 0.6, 0.8]],
                               rtol=1e-6)
    assert scene["triangles"].tolist() == [[0, 1, 2], [3, 4, 5], [6, 7, 8]]


def test_cone_lines_give_base_and_apex_with_absolute_radii(tmp_path):
    cone = "c\n0 0 0 1.5\n0 0 2 0.5\nc\n1 1 1 -1\n1 1 3 -1\n"
    scene = load_nff(write(tmp_path, VIEW + cone))
    assert scene["cylinder_base"].tolist() == [[0, 0, 0], [1, 1, 1]]
    assert scene["cylinder_apex"].tolist() == [[0, 0, 2], [1, 1, 3]]
    assert scene["cylinder_base_radius"].tolist() == [1.5, 1.0]
    assert scene["cylinder_apex_radius"].tolist() == [0.5, 1.0]
    assert scene["cylinder_materials"].tolist() == [0, 0]


def test_sphere_with_negative_radius_keeps_its_absolute_radius(tmp_path):
    scene = load_nff(write(tmp_path, VIEW + "s 1 2 3 -0.25\n"))
    assert scene["sphere_centers"].tolist() == [[1, 2, 3]]
    assert scene["sphere_radii"].tolist() == [0.25]


def test_comments_blank_lines_and_tabs_are_skipped_even_inside_a_polygon(tmp_path):
    text = "# header\n\n" + VIEW + "p\t3\n0 0 0\n# a comment\n\n 1 0 0 \n0\t1\t0\n"
    scene = load_nff(write(tmp_path, text))
    assert scene["vertices"].tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0]]


# One case per kind of malformed input: (file text, line named in the error, phrase in it).
MALFORMED = {
    "unknown_entity": (VIEW + "q 1 2 3\n", VIEW_LINES + 1, "unknown entity 'q'"),
    "missing_numbers_at_the_end": (VIEW + "s 0 0 0\n", VIEW_LINES + 1,
                                   "'s' needs 4 numbers (x y z radius), but the file ends after 3"),
    "missing_numbers_before_an_entity": (VIEW + "s 0 0 0\n" + TRIANGLE, VIEW_LINES + 1,
                                         "'s' needs 4 numbers (x y z radius), but only 3 follow before "
                                         f"the entity 'p' on line {VIEW_LINES + 2}"),
    "missing_view_numbers": ("v\nfrom 0 -5\n" + TRIANGLE, 2,
                             "'from' needs 3 numbers (x y z), but only 2 follow before the entity 'p'"),
    "nan": (VIEW + "s 0 nan 0 1\n", VIEW_LINES + 1, "'s': 'nan' is NaN or infinite"),
    "inf_in_vertex": (VIEW + "p 3\n0 0 0\n1 inf 0\n0 1 0\n", VIEW_LINES + 3, "'inf' is NaN or infinite"),
    "float32_overflow": (VIEW + "l 1e39 0 0\n" + TRIANGLE, VIEW_LINES + 1,
                         "'l': '1e39' is beyond the float32 range"),
    "bad_number": (VIEW + "p 3\n0 0 0\n1 1.2.3 0\n0 1 0\n", VIEW_LINES + 3, "bad number '1.2.3'"),
    "bad_word_in_entity": (VIEW + "b 0 x 0\n" + TRIANGLE, VIEW_LINES + 1, "'b': bad number 'x'"),
    "underscore_in_number": (VIEW + "s 0 0 0 1_0\n", VIEW_LINES + 1, "'s': bad number '1_0'"),
    "fewer_vertices_than_declared": (VIEW + "p 4\n0 0 0\n1 0 0\n0 1 0\n" + "s 0 0 0 1\n",
                                     VIEW_LINES + 1, "'p' needs 12 numbers (x y z per vertex), but only 9 "
                                                     f"follow before the entity 's' on line {VIEW_LINES + 5}"),
    "truncated_polygon": (VIEW + "p 3\n0 0 0\n1 0 0\n", VIEW_LINES + 1,
                          "'p' needs 9 numbers (x y z per vertex), but the file ends after 6: truncated?"),
    "truncated_line": (VIEW + "p 3\n0 0 0\n1 0 0\n0 1", VIEW_LINES + 1, "the file ends after 8"),
    "extra_number": (VIEW + "s 0 0 0 1\n1 2 3\n", VIEW_LINES + 2,
                     f"unexpected number '1': the 's' on line {VIEW_LINES + 1} has all its numbers"),
    "bad_vertex_count": (VIEW + "p 2\n0 0 0\n1 0 0\n", VIEW_LINES + 1,
                         "'p' expects a vertex count (an integer from 3 to 1000000), got '2'"),
    "bad_angle": (VIEW.replace("angle 40", "angle 180") + TRIANGLE, 5, "between 0 and 180"),
    "bad_resolution": (VIEW.replace("64 48", "64.5 48") + TRIANGLE, 7, "positive integers"),
    "zero_patch_normal": (VIEW + "pp 3\n0 0 0 0 0 1\n1 0 0 0 0 0\n0 1 0 0 0 1\n",
                          VIEW_LINES + 1, "'pp' has a vertex normal of zero length"),
    "starts_with_numbers": ("1 2 3\n" + VIEW + TRIANGLE, 1, "a number, '1', before any entity; expected an entity"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_malformed_nff_names_file_line_and_expectation(tmp_path, case):
    text, line, phrase = MALFORMED[case]
    path = write(tmp_path, text)
    with pytest.raises(SceneFileError) as err:
        load_nff(path)
    message = str(err.value)
    assert message.startswith(f"{path}:{line}: "), message
    assert phrase in message, message


@pytest.mark.parametrize("text, phrase", [
    ("", "no geometry"),
    (VIEW + "l 1 1 1\nf 1 1 1 1 0 1 0 1\n", "no geometry"),
    ("s 0 0 0 1\n", "the view lacks from, at, up, angle"),
])
def test_file_without_geometry_or_view_is_rejected(tmp_path, text, phrase):
    with pytest.raises(SceneFileError, match=phrase):
        load_nff(write(tmp_path, text))


def test_binary_file_is_rejected_as_not_text(tmp_path):
    path = tmp_path / "scene.nff"
    path.write_bytes(b"v\n\xff\xfe\x00garbage")
    with pytest.raises(SceneFileError, match=r"scene\.nff:2: binary or non-ASCII data, '\\xff\\xfe\\x00garbage': "
                                             "not an NFF text file"):
        load_nff(path)


def test_scene_file_error_is_a_value_error():
    assert issubclass(SceneFileError, ValueError)


def test_load_scene_rejects_unknown_extensions(tmp_path):
    with pytest.raises(SceneFileError, match="unknown scene file type '.obj'"):
        load_scene(write(tmp_path, TRIANGLE, name="mesh.obj"))
