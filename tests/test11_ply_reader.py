"""PLY reader: the three encodings, polygons, normals (and the smooth shading they give), colours, the default view and
one test per kind of malformed input (scanner layouts: test18)."""
import math

import numpy as np
import plyfile
import pytest

from gridwalk.io import SceneFileError, default_view, load_ply, load_ply_mesh, load_scene

VERTEX_DTYPE = [("x", "f4"), ("y", "f4"), ("z", "f4"), ("nx", "f4"), ("ny", "f4"), ("nz", "f4"),
                ("red", "u1"), ("green", "u1"), ("blue", "u1")]
# A unit square (quad) and a triangle above it.
VERTICES = [(0, 0, 0, 0, 0, 2, 255, 0, 0), (1, 0, 0, 0, 0, 1, 0, 255, 0),
            (1, 1, 0, 0, 0, 1, 0, 0, 255), (0, 1, 0, 0, 0, 1, 51, 102, 153),
            (0, 0, 1, 3, 0, 4, 0, 0, 0), (1, 0, 1, 0, 1, 0, 0, 0, 0), (0, 1, 1, 0, 0, 1, 0, 0, 0)]
FACES = [[0, 1, 2, 3], [4, 5, 6]]
ENCODINGS = {"ascii": (True, "="), "binary_little_endian": (False, "<"),
             "binary_big_endian": (False, ">")}
HEADER = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")
BODY = "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"


def write_ply(path, vertices=VERTICES, faces=FACES, dtype=VERTEX_DTYPE, encoding="ascii",
              index_name="vertex_indices"):
    text, byte_order = ENCODINGS[encoding]
    vertex = np.array([tuple(v) for v in vertices], dtype=dtype)
    face = np.empty(len(faces), dtype=[(index_name, "O")])
    face[index_name] = [np.array(f, dtype=np.int32) for f in faces]
    elements = [plyfile.PlyElement.describe(vertex, "vertex"),
                plyfile.PlyElement.describe(face, "face")]
    plyfile.PlyData(elements, text=text, byte_order=byte_order).write(str(path))
    return path


def write_text(tmp_path, text, name="mesh.ply"):
    path = tmp_path / name
    path.write_bytes(text.encode() if isinstance(text, str) else text)
    return path


@pytest.mark.parametrize("encoding", sorted(ENCODINGS))
def test_every_encoding_gives_the_same_triangulated_mesh(tmp_path, encoding):
    mesh = load_ply_mesh(write_ply(tmp_path / "mesh.ply", encoding=encoding))
    assert mesh.vertices.dtype == np.float32 and mesh.triangles.dtype == np.int32
    assert mesh.vertices.tolist() == [list(map(float, v[:3])) for v in VERTICES]
    assert mesh.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [4, 5, 6]]


def test_vertex_normals_are_read_and_normalised(tmp_path):
    mesh = load_ply_mesh(write_ply(tmp_path / "mesh.ply", encoding="binary_little_endian"))
    assert mesh.normals.dtype == np.float32
    np.testing.assert_allclose(mesh.normals[[0, 4, 5]], [[0, 0, 1], [0.6, 0, 0.8], [0, 1, 0]],
                               rtol=1e-6)


def test_byte_colours_are_scaled_to_unit_range(tmp_path):
    mesh = load_ply_mesh(write_ply(tmp_path / "mesh.ply"))
    np.testing.assert_allclose(mesh.colors[:4], [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.2, 0.4, 0.6]],
                               rtol=1e-6)


def test_float_colours_are_kept_and_missing_normals_and_colours_are_none(tmp_path):
    dtype = [("x", "f8"), ("y", "f8"), ("z", "f8"), ("red", "f4"), ("green", "f4"), ("blue", "f4")]
    vertices = [(0, 0, 0, 0.5, 0.25, 1), (1, 0, 0, 0, 0, 0), (0, 1, 0, 0, 0, 0)]
    mesh = load_ply_mesh(write_ply(tmp_path / "c.ply", vertices, [[0, 1, 2]], dtype))
    assert mesh.colors[0].tolist() == [0.5, 0.25, 1]
    mesh = load_ply_mesh(write_ply(tmp_path / "plain.ply", [v[:3] for v in vertices], [[0, 1, 2]],
                                   dtype[:3]))
    assert mesh.normals is None and mesh.colors is None


def test_float_colours_outside_the_unit_range_render_clipped_not_refused(tmp_path):
    # A negative colour is refused by the core (negative light): the reader clips to [0, 1]
    dtype = [("x", "f4"), ("y", "f4"), ("z", "f4"), ("red", "f4"), ("green", "f4"), ("blue", "f4")]
    vertices = [(0, 0, 0, -0.5, 2.0, 0.5), (1, 0, 0, -0.5, 2.0, 0.5), (0, 1, 0, -0.5, 2.0, 0.5)]
    scene = load_ply(write_ply(tmp_path / "c.ply", vertices, [[0, 1, 2]], dtype))
    colour = scene["materials"][int(scene["triangle_materials"][0])].color
    assert colour[0] == 0.0 and colour[1] == pytest.approx(1.0) and 0.0 < colour[2] < 1.0


def test_vertex_index_property_name_variant_is_accepted(tmp_path):
    mesh = load_ply_mesh(write_ply(tmp_path / "mesh.ply", index_name="vertex_index"))
    assert len(mesh.triangles) == 3


def test_load_ply_gives_scene_keywords_with_one_grey_material(tmp_path):
    plain = VERTEX_DTYPE[:6]
    scene = load_scene(write_ply(tmp_path / "MESH.PLY", [v[:6] for v in VERTICES], dtype=plain))
    assert scene["triangles"].tolist() == [[0, 1, 2], [0, 2, 3], [4, 5, 6]]
    assert scene["triangle_materials"].dtype == np.int32 and not scene["triangle_materials"].any()
    assert scene["sphere_radii"].shape == (0,) and scene["cylinder_base"].shape == (0, 3)
    assert scene["normals"].shape == (7, 3)
    (material,) = scene["materials"]
    assert (material.kd, material.ks, material.shininess) == (0.8, 0.2, 40.0)
    assert "colors" not in scene and "vertex_colors" not in scene
    assert len(scene["lights"]) == 2


def test_default_view_sees_every_vertex_within_its_field_of_view():
    rng = np.random.default_rng(1)
    vertices = rng.normal(size=(500, 3)) * (5, 1, 0.2) + (100, -40, 7)
    camera, lights = default_view(vertices)
    assert (camera.fov, camera.width, camera.height) == (40.0, 512, 512)
    eye, target = np.array(camera.eye), np.array(camera.target)
    np.testing.assert_allclose(target, (vertices.min(0) + vertices.max(0)) / 2)
    axis = (target - eye) / np.linalg.norm(target - eye)
    to_vertex = vertices - eye
    cos_angle = to_vertex @ axis / np.linalg.norm(to_vertex, axis=1)
    assert np.degrees(np.arccos(cos_angle)).max() < camera.fov / 2
    assert eye[2] > target[2]                           # looking down at the mesh
    assert lights[0].color == (0.8, 0.8, 0.8) and lights[0].kind == "point"
    assert np.linalg.norm(np.array(lights[0].position) - eye) < np.linalg.norm(target - eye)


def test_default_view_of_a_single_point_is_still_a_valid_camera():
    camera, _ = default_view(np.ones((3, 3)))
    camera.validate()                                     # raises if eye == target


def test_huge_declared_count_is_rejected_from_the_header(tmp_path):
    path = write_text(tmp_path, HEADER.replace("vertex 3", "vertex 4000000000") + BODY)
    with pytest.raises(SceneFileError, match="element 'vertex' declares 4000000000 records; the core "
                                             "indexes at most 2.31 - 1 vertices"):
        load_ply(path)
    path = write_text(tmp_path, HEADER.replace("vertex 3", "vertex 400000000") + BODY)
    with pytest.raises(SceneFileError, match="400000000 vertex, 1 face records, at least 2400000002 bytes, "
                                             "but only 26 bytes follow"):
        load_ply(path)


def test_truncated_binary_body_is_rejected(tmp_path):
    path = write_ply(tmp_path / "mesh.ply", encoding="binary_big_endian")
    path.write_bytes(path.read_bytes()[:-5])
    with pytest.raises(SceneFileError, match=str(path)):
        load_ply(path)


def test_declared_face_count_larger_than_ascii_body_is_rejected(tmp_path):
    path = write_text(tmp_path, HEADER.replace("face 1", "face 3") + BODY + "3 0 1 2\n")
    with pytest.raises(SceneFileError, match=r"element 'face' record 2 \(line 15\): the file ends here, but "
                                             r"the header declares 3 records \(truncated file\?\)"):
        load_ply(path)


@pytest.mark.parametrize("index", [3, -1])
def test_out_of_range_and_negative_indices_are_rejected(tmp_path, index):
    path = write_text(tmp_path, HEADER + BODY.replace("3 0 1 2", f"3 0 {index} 2"))
    with pytest.raises(SceneFileError, match=rf"element 'face' record 0 \(line 13\): uses vertex index {index}, "
                                             r"but there are 3 vertices \(0 to 2\)"):
        load_ply(path)


COLOURED = HEADER.replace("property float z\n", "property float z\nproperty uchar red\n")


@pytest.mark.parametrize("body, where, what", [
    ("0 0 0 255\n1 0 0 300\n0 1 0 0\n3 0 1 2\n", "vertex' record 1 \\(line 12\\)", "red = 300 does not fit its type uchar"),
    ("0 0 0 255\n1 0 0 -1\n0 1 0 0\n3 0 1 2\n", "vertex' record 1 \\(line 12\\)", "red = -1 does not fit its type uchar"),
    ("0 0 0 255\n1 0 0 2.5\n0 1 0 0\n3 0 1 2\n", "vertex' record 1 \\(line 12\\)", "red = 2.5 does not fit its type uchar"),
    ("0 0 0 1\n1 0 0 1\n0 1 0 1\n3 0 1 1.5\n", "face' record 0 \\(line 14\\)",
     "vertex_indices = 1.5 does not fit its type int \\(integers -2147483648 to 2147483647\\)"),
    ("0 0 0 1\n1 0 0 1\n0 1 0 1\n4 0 1 2 1.5\n", "face' record 0 \\(line 14\\)",
     "vertex_indices = 1.5 does not fit its type int"),      # (a quad line: the per-line path)
])
def test_ascii_values_outside_their_declared_type_are_refused(tmp_path, body, where, what):
    """A binary file cannot hold a 'uchar' of 300; in text it is a broken writer's, and was read as a colour
    above 1 (or, for an index, as an index a binary file could not hold)."""
    path = write_text(tmp_path, COLOURED + body)
    with pytest.raises(SceneFileError, match=f"element '{where}: {what}"):
        load_ply(path)


def test_non_numeric_token_is_rejected(tmp_path):
    path = write_text(tmp_path, HEADER + BODY.replace("1 0 0", "1 zero 0"))
    with pytest.raises(SceneFileError, match=r"element 'vertex' record 1 \(line 11\): bad number 'zero'"):
        load_ply(path)


def test_float_list_count_type_is_rejected_with_its_header_line(tmp_path):
    path = write_text(tmp_path, HEADER.replace("list uchar int", "list float int") + BODY)
    with pytest.raises(SceneFileError, match=r"mesh\.ply:8: bad list property 'property list float int "
                                             r"vertex_indices': the count type must be an integer"):
        load_ply(path)


def test_float_vertex_indices_are_rejected(tmp_path):
    path = write_text(tmp_path, HEADER.replace("list uchar int", "list uchar float") + BODY)
    with pytest.raises(SceneFileError, match=r"mesh\.ply:7: element 'face' has no 'vertex_indices' \(or "
                                             r"'vertex_index'\) list of integers"):
        load_ply(path)


@pytest.mark.parametrize("encoding", sorted(ENCODINGS))
def test_a_list_property_in_the_vertex_element_is_refused_not_misread(tmp_path, encoding):
    # Read as fixed-size records, a binary file's vertices came out as values
    # near 1e-40 (no error), or the next element was called truncated.
    vertex = np.empty(3, dtype=[("x", "f4"), ("y", "f4"), ("z", "f4"), ("ids", "O")])
    vertex["x"], vertex["y"], vertex["z"] = [0, 1, 0], [0, 0, 1], 0
    vertex["ids"] = [np.array([1, 2], np.int32)] * 3
    face = np.empty(1, dtype=[("vertex_indices", "O")])
    face["vertex_indices"] = [np.array([0, 1, 2], np.int32)]
    text, byte_order = ENCODINGS[encoding]
    path = tmp_path / "mesh.ply"
    plyfile.PlyData([plyfile.PlyElement.describe(vertex, "vertex"), plyfile.PlyElement.describe(face, "face")],
                    text=text, byte_order=byte_order).write(str(path))
    with pytest.raises(SceneFileError, match=r"mesh\.ply:3: element 'vertex' has list properties \('ids'\)"):
        load_ply(path)


def test_missing_vertex_element_is_rejected(tmp_path):
    header = HEADER.replace("element vertex 3", "element point 3")
    with pytest.raises(SceneFileError, match="no 'vertex' element"):
        load_ply(write_text(tmp_path, header + BODY))


def test_missing_face_element_is_rejected(tmp_path):
    header = HEADER.split("element face")[0] + "end_header\n"
    with pytest.raises(SceneFileError, match="no 'face' or 'tristrips' element: the file holds points only"):
        load_ply(write_text(tmp_path, header + "0 0 0\n1 0 0\n0 1 0\n"))


def test_face_with_two_corners_is_rejected(tmp_path):
    path = write_text(tmp_path, HEADER + BODY.replace("3 0 1 2", "2 0 1"))
    with pytest.raises(SceneFileError, match=r"element 'face' record 0 \(line 13\): a face of 2 corners; "
                                             "a face needs at least 3"):
        load_ply(path)


def test_nan_coordinate_is_rejected(tmp_path):
    path = write_text(tmp_path, HEADER + BODY.replace("1 0 0", "1 nan 0"))
    with pytest.raises(SceneFileError, match=r"element 'vertex' record 1 \(line 11\): the coordinate "
                                             r"\(1, nan, 0\) is NaN, infinite or beyond the float32 range"):
        load_ply(path)


@pytest.mark.parametrize("data", [b"", b"solid ascii stl\n",
                                  HEADER.split("end_header")[0].encode()])
def test_non_ply_or_truncated_header_is_rejected(tmp_path, data):
    with pytest.raises(SceneFileError, match="not a PLY file"):
        load_ply(write_text(tmp_path, data))


@pytest.mark.parametrize("variant", ["crlf", "cr", "byte order mark", "blanks after ply", "cr, binary"])
def test_header_variants_from_other_editors_are_read(tmp_path, variant):
    """Windows (CRLF), classic Mac OS (CR alone) line ends, a UTF-8 byte order
    mark and blanks after 'ply' (all read as "not a PLY file" before); line
    numbers in messages count the same lines."""
    text = (HEADER + BODY).replace("element vertex 3", "element vertex 4").replace("0 1 0\n", "0 1 0\n1 1 0\n")
    data = {"crlf": text.replace("\n", "\r\n").encode(), "cr": text.replace("\n", "\r").encode(),
            "byte order mark": b"\xef\xbb\xbf" + text.encode(),
            "blanks after ply": text.replace("ply\n", "ply \t\n", 1).encode()}.get(variant)
    if variant == "cr, binary":
        head = HEADER.replace("ascii", "binary_little_endian").replace("element vertex 3", "element vertex 4")
        data = (head.replace("\n", "\r").encode() + np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]], "<f4").tobytes()
                + b"\x03" + np.array([0, 1, 2], "<i4").tobytes())
    mesh = load_ply_mesh(write_text(tmp_path, data))
    assert mesh.vertices.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]
    assert mesh.triangles.tolist() == [[0, 1, 2]]
    if variant != "cr, binary":
        bad = data.replace(b"3 0 1 2", b"3 0 7 2")
        with pytest.raises(SceneFileError, match=r"element 'face' record 0 \(line 14\): uses vertex index 7"):
            load_ply_mesh(write_text(tmp_path, bad))


def test_unknown_format_is_rejected(tmp_path):
    path = write_text(tmp_path, HEADER.replace("ascii 1.0", "binary_middle_endian 1.0") + BODY)
    with pytest.raises(SceneFileError, match=r"mesh\.ply:2: unsupported format"):
        load_ply(path)


def test_convex_hexagon_is_a_fan_covering_its_area(tmp_path):
    angles = np.arange(6) * math.pi / 3
    vertices = [(math.cos(a), math.sin(a), 0.0) for a in angles]
    mesh = load_ply_mesh(write_ply(tmp_path / "hex.ply", vertices, [list(range(6))],
                                   VERTEX_DTYPE[:3]))
    v = mesh.vertices.astype(np.float64)[mesh.triangles]
    area = np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]), axis=1).sum() / 2
    assert mesh.triangles.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]]
    assert area == pytest.approx(3 * math.sqrt(3) / 2, rel=1e-6)

def test_vertex_normals_shade_a_coarse_sphere_like_a_fine_one(tmp_path):
    # A 6 x 12 UV sphere read with its vertex normals is shaded smoothly: away from the
    # silhouette, it is far closer to a 96 x 192 sphere (flat shading, as good as smooth at that
    # size) than the same coarse sphere read without normals, whose facets show.
    import dataclasses

    import gridwalk as gw
    from meshes import uv_sphere

    def sphere_ply(name, rings, with_normals):
        v, f = uv_sphere(rings, 2 * rings, jitter=0.0)
        dtype = VERTEX_DTYPE[:6] if with_normals else VERTEX_DTYPE[:3]
        rows = np.hstack([v, v / np.linalg.norm(v, axis=1, keepdims=True)]) if with_normals else v
        return load_ply(write_ply(tmp_path / name, rows.tolist(), f.tolist(), dtype, "binary_little_endian"))

    fine = sphere_ply("fine.ply", 96, False)
    camera = dataclasses.replace(fine["camera"], width=64, height=64)
    images = {}
    for name, scene in (("fine", fine), ("smooth", sphere_ply("smooth.ply", 6, True)),
                        ("flat", sphere_ply("flat.ply", 6, False))):
        scene = dict(scene, camera=camera, lights=fine["lights"])
        images[name] = gw.render(gw.Scene(**scene), gw.RenderSettings(threads=1, aa_samples=1))
    inside = np.all([image[..., 3] == 1 for image in images.values()], axis=0)
    for _ in range(2):   # away from the silhouettes, which differ (the coarse one is a polygon)
        inside[1:-1, 1:-1] &= inside[:-2, 1:-1] & inside[2:, 1:-1] & inside[1:-1, :-2] & inside[1:-1, 2:]
    assert inside.mean() > 0.1

    def error(name):
        return float(np.abs(images[name][inside, :3] - images["fine"][inside, :3]).mean())
    # (0.011 against 0.041: the rest is the coarse sphere's shadow terminator and highlight)
    assert error("smooth") < 0.5 * error("flat"), (error("smooth"), error("flat"))


NORMAL_DTYPE = [("x", "f4"), ("y", "f4"), ("z", "f4"), ("nx", "f8"), ("ny", "f8"), ("nz", "f8")]


def test_zero_and_tiny_normals_of_used_vertices_are_read(tmp_path):
    # MeshLab writes 0 0 0 for a degenerate face's vertices; a whole file was refused for one.
    # A tiny double normal (1e-300) is a direction too: it vanished in float32 before normalising.
    vertices = [(0, 0, 0, 0, 0, 0), (1, 0, 0, 0, 0, 1e-300), (0, 1, 0, 0, 0, 1),
                (0, 0, 1, 0, 0, 0), (1, 0, 1, 0, 0, 0), (0, 1, 1, 0, 0, 0)]
    mesh = load_ply_mesh(write_ply(tmp_path / "zero.ply", vertices, [[0, 1, 2], [3, 4, 5]], NORMAL_DTYPE))
    np.testing.assert_array_equal(mesh.normals, [[0, 0, 0], [0, 0, 1], [0, 0, 1], [0, 0, 0], [0, 0, 0], [0, 0, 0]])
    import gridwalk as gw
    scene = gw.Scene(vertices=mesh.vertices, triangles=mesh.triangles, normals=mesh.normals)
    # Rays straight down onto each triangle: the first is shaded by its two unit normals,
    # the second (all three 0) by its geometric normal, (0, 0, -1) or (0, 0, 1) by winding.
    o = np.array([[0.2, 0.2, 5.0], [0.2, 0.2, 0.5]], np.float32)
    hits = scene.intersect(o, np.tile(np.float32([0, 0, -1]), (2, 1)))
    assert hits.kind.tolist() == [1, 1]
    np.testing.assert_allclose(np.abs(hits.normal), [[0, 0, 1], [0, 0, 1]], atol=1e-6)


def test_invalid_vertices_no_face_uses_are_accepted_and_used_ones_refused(tmp_path):
    # A scanner's organised grid marks missing points with NaN; only the faces' vertices matter.
    text = HEADER.replace("element vertex 3", "element vertex 5") + "0 0 0\n1 0 0\n0 1 0\nnan nan nan\n1e39 0 0\n3 0 1 2\n"
    mesh = load_ply_mesh(write_text(tmp_path, text))
    assert np.isfinite(mesh.vertices).all() and mesh.triangles.tolist() == [[0, 1, 2]]
    with pytest.raises(SceneFileError, match=r"element 'vertex' record 3 \(line 13\): the coordinate \(nan, nan, nan\) "
                                             r"is NaN, infinite or beyond the float32 range \(used by element 'face' "
                                             r"record 0"):
        load_ply_mesh(write_text(tmp_path, text.replace("3 0 1 2", "3 0 1 3")))
