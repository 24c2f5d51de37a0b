"""PLY as scanners and tools write it: triangle strips, every index and coordinate
type in every encoding, concave faces, vertex colours, faces and strips together,
non-ASCII header comments, coordinates the core cannot hold, and files larger
than what the reader may hold (checked from the header, read in bounded memory)."""
import math
import subprocess
import sys
import textwrap

import numpy as np
import plyfile
import pytest

import gridwalk as gw
from gridwalk import memory
from gridwalk.io import SceneFileError, load_ply, load_ply_mesh
from gridwalk.io.ply import MAX_COLOURS
from gridwalk.io.triangulate import ear_clip, polygons

ENCODINGS = {"ascii": (True, "="), "binary_little_endian": (False, "<"), "binary_big_endian": (False, ">")}


def grid(rows=6, cols=8):
    """A bumpy (rows+1) x (cols+1) height field: positions and the two triangles
    of each quad in row order, (v00, v10, v01) and (v01, v10, v11)."""
    y, x = np.meshgrid(np.arange(rows + 1), np.arange(cols + 1), indexing="ij")
    z = 0.3 * np.sin(x * 0.9) * np.cos(y * 0.7)
    points = np.stack([x, y, z], axis=-1).reshape(-1, 3).astype(np.float32)
    v = np.arange((rows + 1) * (cols + 1)).reshape(rows + 1, cols + 1)
    tris = []
    for r in range(rows):
        for c in range(cols):
            tris += [(v[r, c], v[r + 1, c], v[r, c + 1]), (v[r, c + 1], v[r + 1, c], v[r + 1, c + 1])]
    return points, np.array(tris), v


def grid_strips(v):
    """The grid's rows as strips: rows 0-2 stitched into one record by repeated
    vertices, rows 3-4 in one record with -1 between them, row 5 alone."""
    rows = [np.stack([v[r], v[r + 1]], axis=1).reshape(-1) for r in range(len(v) - 1)]
    stitched = np.concatenate([rows[0], [rows[0][-1], rows[1][0]], rows[1], [rows[1][-1], rows[2][0]], rows[2]])
    return [stitched, np.concatenate([rows[3], [-1], rows[4]]), rows[5]]


def write_ply(path, points, faces=None, strips=None, encoding="binary_little_endian", index="i4",
              count="u1", coord="f4", extra=None):
    text, order = ENCODINGS[encoding]
    vertex = np.empty(len(points), dtype=[(c, coord) for c in "xyz"] + [(n, t) for n, t, _ in extra or []])
    for k, c in enumerate("xyz"):
        vertex[c] = points[:, k]
    for name, _, values in extra or []:
        vertex[name] = values
    elements = [plyfile.PlyElement.describe(vertex, "vertex")]
    for name, lists in (("face", faces), ("tristrips", strips)):
        if lists is not None:
            data = np.empty(len(lists), dtype=[("vertex_indices", "O")])
            data["vertex_indices"] = [np.asarray(f).astype(index) for f in lists]
            elements.append(plyfile.PlyElement.describe(data, name, val_types={"vertex_indices": index},
                                                        len_types={"vertex_indices": count}))
    plyfile.PlyData(elements, text=text, byte_order=order).write(str(path))
    return path


def render(kwargs, size=48):
    import dataclasses
    kwargs = dict(kwargs, camera=dataclasses.replace(kwargs["camera"], width=size, height=size))
    return gw.render(gw.Scene(**kwargs), gw.RenderSettings(threads=1, aa_samples=1))


@pytest.mark.parametrize("encoding", sorted(ENCODINGS))
def test_strips_written_by_plyfile_render_exactly_like_the_same_mesh_written_as_faces(tmp_path, encoding):
    points, triangles, v = grid()
    strips = write_ply(tmp_path / "strips.ply", points, strips=grid_strips(v), encoding=encoding,
                       count="i4")
    faces = write_ply(tmp_path / "faces.ply", points, faces=triangles, encoding=encoding)
    from_strips, from_faces = load_ply(strips), load_ply(faces)
    # the restarts, the alternating winding and the dropped stitches give the faces, in order
    assert from_strips["triangles"].tolist() == triangles.tolist()
    image = render(from_strips)
    assert image[..., 3].mean() > 0.1
    assert np.array_equal(image, render(from_faces))


def test_a_mesh_reads_the_same_with_every_index_type_coordinate_type_and_encoding(tmp_path):
    points, triangles, v = grid(4, 5)                       # 30 vertices: fits int8 indices
    quads = [[v[r, c], v[r + 1, c], v[r + 1, c + 1], v[r, c + 1]] for r in range(4) for c in range(5)]
    reference = None
    for encoding in ENCODINGS:
        for index in ("i1", "u1", "i2", "u2", "i4", "u4"):
            for count, coord in (("u1", "f4"), ("i4", "f8"), ("u2", "f8"), ("i1", "f4")):
                path = write_ply(tmp_path / f"{encoding}{index}{count}{coord}.ply", points, faces=quads,
                                 encoding=encoding, index=index, count=count, coord=coord)
                mesh = load_ply_mesh(path)
                if reference is None:
                    reference = mesh
                assert np.array_equal(mesh.vertices, reference.vertices), path.name
                assert np.array_equal(mesh.triangles, reference.triangles), path.name
    assert len(reference.triangles) == 40 and np.array_equal(reference.vertices, points)


@pytest.mark.parametrize("index", ["u1", "u2", "u4"])
def test_an_unsigned_restart_index_ends_a_strip(tmp_path, index):
    points = np.array([(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (2, 0, 0), (2, 1, 0)], np.float32)
    restart = np.iinfo(index).max
    path = write_ply(tmp_path / "s.ply", points, strips=[[0, 1, 2, 3, restart, 1, 4, 3, 5]], index=index)
    assert load_ply_mesh(path).triangles.tolist() == [[0, 1, 2], [2, 1, 3], [1, 4, 3], [3, 4, 5]]


def test_faces_and_strips_in_one_file_are_both_read(tmp_path):
    points, triangles, v = grid()
    path = write_ply(tmp_path / "both.ply", points, faces=triangles[:10], strips=grid_strips(v)[1:])
    mesh = load_ply_mesh(path)
    strip_triangles = 2 * 8 * 3                              # rows 3, 4 and 5
    assert len(mesh.triangles) == 10 + strip_triangles
    assert mesh.triangles[:10].tolist() == triangles[:10].tolist()
    assert mesh.triangles[10:].tolist() == triangles[-strip_triangles:].tolist()


# -- concave faces -----------------------------------------------------------------------
def shoelace(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def inside(points, xy):
    """Even-odd rule, for each of points (m, 2) against the polygon xy (n, 2); in blocks of
    points, each against every edge at once."""
    x1, y1 = xy[:, 0], xy[:, 1]
    x2, y2 = np.roll(x1, -1), np.roll(y1, -1)
    out = []
    for block in np.array_split(points, max(1, len(points) // 256)):
        x, y = block[:, :1], block[:, 1:]
        crosses = (y1 > y) != (y2 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            at = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
        out.append(np.count_nonzero(crosses & (x < at), axis=1) % 2 == 1)
    return np.concatenate(out)


def check_covers(xy, tris):
    """The triangles cover the polygon exactly once: their areas (all the
    polygon's winding) sum to its area and each one's centroid is inside it."""
    area = shoelace(xy)
    signed = [shoelace(xy[t]) for t in tris]
    assert len(tris) == len(xy) - 2
    assert all(s * area >= -1e-12 for s in signed), "a triangle winds the other way (a fold)"
    assert sum(signed) == pytest.approx(area, rel=1e-9)
    kept = [t for t in tris if abs(shoelace(xy[t])) > 1e-12]
    assert np.all(inside(np.array([xy[t].mean(axis=0) for t in kept]).reshape(-1, 2), xy))


CONCAVE = {
    "dart": [(0, 0), (2, 1), (0, 2), (0.5, 1)],
    "L": [(2, 1), (1, 1), (1, 2), (0, 2), (0, 0), (2, 0)],
    "star": [(math.cos(k * math.pi / 5) * (1 if k % 2 == 0 else 0.4),
              math.sin(k * math.pi / 5) * (1 if k % 2 == 0 else 0.4)) for k in range(10)],
    "comb": [(0, 0), (7, 0), (7, 3)] + [p for k in range(3, 0, -1) for p in ((2 * k, 3), (2 * k, 1),
                                                                             (2 * k - 1, 1), (2 * k - 1, 3))]
            + [(0, 3)],
    "spiral": [(math.cos(t) * t, math.sin(t) * t) for t in np.linspace(1, 12, 40)]
              + [(math.cos(t) * (t + 1.5), math.sin(t) * (t + 1.5)) for t in np.linspace(12, 1, 40)],
}


@pytest.mark.parametrize("name", sorted(CONCAVE))
def test_concave_faces_are_ear_clipped_not_fanned(tmp_path, name):
    xy = np.array(CONCAVE[name], dtype=np.float64)
    # tilted out of every axis plane, and written clockwise too
    tilt = np.linalg.qr(np.random.default_rng(len(xy)).normal(size=(3, 3)))[0]
    for outline in (xy, xy[::-1]):
        points = (np.column_stack([outline, np.zeros(len(outline))]) @ tilt.T).astype(np.float32)
        mesh = load_ply_mesh(write_ply(tmp_path / "c.ply", points, faces=[np.arange(len(points))]))
        check_covers(outline, mesh.triangles)
    fan = np.stack([np.zeros(len(xy) - 2, int), np.arange(1, len(xy) - 1), np.arange(2, len(xy))], 1)
    with pytest.raises(AssertionError):
        check_covers(xy, fan)                                 # a fan from corner 0 would fold


def test_random_simple_polygons_are_covered_exactly_once():
    rng = np.random.default_rng(7)
    for _ in range(200):
        n = int(rng.integers(4, 40))
        angles = np.sort(rng.uniform(0, 2 * np.pi, n))
        while np.diff(np.append(angles, angles[0] + 2 * np.pi)).max() >= np.pi:    # star-shaped: simple
            angles = np.sort(rng.uniform(0, 2 * np.pi, n))
        xy = np.column_stack([np.cos(angles), np.sin(angles)]) * rng.uniform(0.2, 1.0, (n, 1))
        tris, _ = polygons(np.column_stack([xy, np.zeros(n)]), [n])
        check_covers(xy, tris)


def test_ear_clipping_of_a_self_intersecting_outline_still_gives_n_minus_2_triangles():
    bow = np.array([(0, 0), (2, 2), (2, 0), (0, 2), (1, 3), (-1, 1)], float)
    assert len(ear_clip(bow)) == len(bow) - 2


# -- colours -------------------------------------------------------------------------
def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def test_vertex_colours_become_the_diffuse_colour_of_each_triangle(tmp_path):
    points, triangles, v = grid(2, 2)
    rgb = np.zeros((len(points), 3), np.uint8)
    rgb[v[:, :2].reshape(-1)] = (255, 128, 0)                 # columns 0-1 orange, column 2 blue
    rgb[v[:, 2]] = (0, 64, 255)
    extra = [(c, "u1", rgb[:, k]) for k, c in enumerate(("red", "green", "blue"))]
    kwargs = load_ply(write_ply(tmp_path / "c.ply", points, faces=triangles, extra=extra))
    colours = {tuple(np.round(m.color, 6)) for m in kwargs["materials"]}
    orange = tuple(np.round(srgb_to_linear(np.array([255, 128, 0]) / 255), 6))
    assert orange in colours and len(colours) == 3               # orange, blue, and the mixed column
    left = [k for k, t in enumerate(triangles) if np.all(np.isin(t, v[:, :2]))]
    assert {tuple(np.round(kwargs["materials"][m].color, 6)) for m in kwargs["triangle_materials"][left]} \
        == {orange}
    assert all(m.kd == 0.8 and m.ks == 0.2 for m in kwargs["materials"])
    image = render(kwargs)
    lit = image[..., 3] > 0.99
    assert (image[lit, 0] > 2 * image[lit, 2]).any() and (image[lit, 2] > 2 * image[lit, 0]).any()


def test_a_scan_of_300k_distinct_colours_stays_a_bounded_material_table(tmp_path):
    rng = np.random.default_rng(3)
    n = 300_000
    points = rng.random((n, 3)).astype(np.float32)
    rgb = rng.integers(0, 256, (n, 3)).astype(np.uint8)
    extra = [(c, "u1", rgb[:, k]) for k, c in enumerate(("red", "green", "blue"))]
    faces = np.arange(n - n % 3).reshape(-1, 3)
    kwargs = load_ply(write_ply(tmp_path / "scan.ply", points, faces=faces, extra=extra))
    assert 1000 < len(kwargs["materials"]) <= MAX_COLOURS
    # each triangle's colour is its mean colour, quantised to 4 bits in sRGB at the coarsest
    linear = srgb_to_linear(rgb / 255.0)
    mean = linear[faces].mean(axis=1)
    got = np.array([m.color for m in kwargs["materials"]])[kwargs["triangle_materials"]]
    to_srgb = np.where(mean <= 0.0031308, mean * 12.92, 1.055 * mean ** (1 / 2.4) - 0.055)
    got_srgb = np.where(got <= 0.0031308, got * 12.92, 1.055 * got ** (1 / 2.4) - 0.055)
    assert np.abs(got_srgb - to_srgb).max() <= 0.5 / 15 + 1e-6


# -- findings of issue 16 ------------------------------------------------------------------
HEADER = ("ply\nformat ascii 1.0\n{comment}element vertex 3\nproperty float x\nproperty float y\n"
          "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n")


def test_a_non_ascii_header_comment_is_accepted_and_a_non_ascii_keyword_named(tmp_path):
    path = tmp_path / "m.ply"
    path.write_bytes(HEADER.format(comment="comment scanné à Zürich \xff\n").encode("utf-8")
                     + b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    assert load_ply_mesh(path).triangles.tolist() == [[0, 1, 2]]
    path.write_bytes(HEADER.format(comment="").replace("property float z", "property float zé").encode()
                     + b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
    with pytest.raises(SceneFileError, match=r"m\.ply:6: header line 'property float z\\xc3\\xa9' is not ASCII"):
        load_ply(path)


def test_coordinates_beyond_the_cores_range_name_the_file_vertex_and_face(tmp_path):
    path = tmp_path / "far.ply"
    path.write_text(HEADER.format(comment="") + "0 0 0\n1e35 0 0\n0 1 0\n3 0 1 2\n")
    with pytest.raises(SceneFileError) as err:
        load_ply(path)
    assert str(err.value) == (f"{path}: element 'vertex' record 1 (line 11): the coordinate (1e+35, 0, 0) "
                              "lies beyond +-1e30, the core's limit (used by element 'face' record 0 (line 13))")


def test_an_unused_far_vertex_is_harmless_and_not_framed(tmp_path):
    path = tmp_path / "m.ply"
    path.write_text(HEADER.format(comment="").replace("vertex 3", "vertex 4") + "0 0 0\n1 0 0\n0 1 0\n"
                    "1e35 0 0\n3 0 1 2\n")
    kwargs = load_ply(path)
    assert np.abs(kwargs["camera"].eye).max() < 10


# -- size and memory -------------------------------------------------------------------------
def test_a_mesh_too_large_for_memory_is_refused_from_its_header(tmp_path):
    vertices, faces = 2_000_000_000, 1_000_000_000
    need = memory.estimate(faces, vertices, width=512, height=512, normals=False).total
    limit = memory.default_limit()
    if limit is None or need <= limit:
        pytest.skip(f"this machine's limit ({limit}) holds the {need}-byte estimate")
    path = tmp_path / "huge.ply"
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\n"
              "property float y\nproperty float z\nelement face 1000000000\n"
              "property list uchar int vertex_indices\nend_header\n").encode()
    with open(path, "wb") as f:
        f.write(header)
        f.truncate(len(header) + vertices * 12 + faces * 13)     # sparse: no disk used
    with pytest.raises(SceneFileError) as err:
        load_ply(path)
    assert "2,000,000,000 vertices and 1,000,000,000 faces: reading and rendering them needs an " \
           "estimated" in str(err.value)
    assert "more than the limit of" in str(err.value) and "of physical memory" in str(err.value)


PEAK = """
import sys
from gridwalk.io import load_ply_mesh

def kib(field):
    with open("/proc/self/status") as f:
        return next(int(line.split()[1]) for line in f if line.startswith(field))

with open("/proc/self/clear_refs", "w") as f:       # the peak (VmHWM) restarts from the current size
    f.write("5")
before = kib("VmRSS")
mesh = load_ply_mesh(sys.argv[1])
print(len(mesh.triangles), (kib("VmHWM") - before) // 1024)
"""


@pytest.mark.parametrize("encoding", ["ascii", "binary_little_endian"])
def test_a_large_file_is_read_in_bounded_memory(tmp_path, encoding):
    """60 MB of records the mesh does not use (an element of 2.5 M lines or
    records) pass through a reader that holds one chunk at a time."""
    rows = 2_500_000
    path = tmp_path / "big.ply"
    header = (f"ply\nformat {encoding} 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
              f"element scan_points {rows}\nproperty float a\nproperty float b\nproperty float c\n"
              "property list uchar float d\nend_header\n")
    with open(path, "wb") as f:
        f.write(header.encode())
        if encoding == "ascii":
            f.write(b"0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n")
            f.write(b"0.125 0.25 0.375 2 1 2\n" * rows)
        else:
            f.write(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], "<f4").tobytes())
            f.write(b"\x03" + np.array([0, 1, 2], "<i4").tobytes())
            record = np.array([0.125, 0.25, 0.375], "<f4").tobytes() + b"\x02" + np.array([1, 2], "<f4").tobytes()
            f.write(record * rows)
    size_mb = path.stat().st_size / 2 ** 20
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(PEAK), str(path)], capture_output=True,
                         text=True, timeout=120, check=True).stdout.split()
    triangles, grown_mb = int(out[0]), int(out[1])
    print(f"{encoding}: {size_mb:.0f} MB file, peak memory grew {grown_mb} MB")
    assert triangles == 1 and size_mb > 50
    assert grown_mb < 32


STRIP_LIMIT = """
import sys
from gridwalk import memory
from gridwalk.io import SceneFileError, load_ply_mesh

memory.default_limit = lambda fraction=0.5: 300 << 20     # as on a machine with 600 MiB
with open("/proc/self/clear_refs", "w") as f:
    f.write("5")
before = int(next(l for l in open("/proc/self/status") if l.startswith("VmRSS")).split()[1])
try:
    load_ply_mesh(sys.argv[1])
    print("loaded", 0)
except SceneFileError as err:
    grown = int(next(l for l in open("/proc/self/status") if l.startswith("VmHWM")).split()[1]) - before
    print(str(err).replace(" ", "_"), grown // 1024)
"""


def test_a_strip_too_large_for_memory_is_refused_before_it_becomes_triangles(tmp_path):
    """A strip's triangles are not in the header: one record of 2.5 M indices
    (10 MB) makes 2.5 M triangles, about 0.7 GB to read and render. Under a
    limit of 300 MiB it is refused after its indices are read, before the
    triangles are built (building them peaked at about 340 MB)."""
    n = 2_500_000
    path = tmp_path / "strip.ply"
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 1000\nproperty float x\n"
              "property float y\nproperty float z\nelement tristrips 1\n"
              "property list int int vertex_indices\nend_header\n")
    rng = np.random.default_rng(5)
    with open(path, "wb") as f:
        f.write(header.encode() + rng.random((1000, 3)).astype("<f4").tobytes())
        f.write(np.array([n], "<i4").tobytes() + rng.integers(0, 1000, n).astype("<i4").tobytes())
    out = subprocess.run([sys.executable, "-c", textwrap.dedent(STRIP_LIMIT), str(path)],
                         capture_output=True, text=True, timeout=120, check=True).stdout.split()
    message, grown_mb = out[0].replace("_", " "), int(out[1])
    assert "1,000 vertices and 2,500,000 faces and strip triangles (up to the record read)" in message
    assert "more than the limit of 300 MiB" in message
    assert grown_mb < 100


@pytest.mark.parametrize("corners, fmt", [(10_000, "%g"), (200_000, "%g"), (200_000, "%.9g")])
def test_a_regular_polygon_written_with_rounded_coordinates_is_convex(corners, fmt):
    # Six significant digits put more noise in a 10,000-gon's corners than its
    # turns: it was judged concave and ear-clipped (11 s), and a 200,000-gon
    # was refused as a non-convex polygon of too many corners. From about
    # 50,000 corners the fan check failed too, on thin triangles beside
    # corner 0, until its tolerance grew with the spoke's length.
    a = np.linspace(0.0, 2.0 * np.pi, corners, endpoint=False)
    text = "\n".join(f"{fmt} {fmt} 0" % (x, y) for x, y in zip(np.cos(a), np.sin(a)))
    points = np.loadtxt(text.splitlines())
    tri, poly = polygons(points, [corners])
    assert len(tri) == corners - 2 and np.all(poly == 0)
    # convex, so clipped in rounds (triangulate.FAN_CORNERS), not ear-clipped or refused; no corner
    # crowded as a fan's first one is (in all n - 2 triangles)
    assert np.bincount(tri.ravel()).max() <= 2 * np.log2(corners) + 2
    assert np.all(np.diff(tri, axis=1) > 0)                                    # corners in order: the winding
    p = points[tri]
    area = 0.5 * np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2].sum()
    assert area == pytest.approx(np.pi, rel=1e-6)


def test_a_large_convex_face_among_many_small_ones_does_not_crowd_the_grid(tmp_path):
    # A cylinder's cap written as one 8,192-corner face over 20,000 small triangles. Fanned from
    # corner 0, every triangle of the cap met the cells around that corner, and rays down onto
    # the cap tested 255 triangles each; clipped in rounds, about 5.
    rng = np.random.default_rng(0)
    n, m = 8192, 20_000
    a = 2 * np.pi * np.arange(n) / n
    cap = np.column_stack([0.5 * np.cos(a), 0.5 * np.sin(a), np.full(n, 1.2)])
    specks = (rng.uniform(-1, 1, (m, 1, 3)) + rng.normal(0, 0.02, (m, 3, 3))).reshape(-1, 3)
    faces = [list(range(3 * m, 3 * m + n))] + [[3 * k, 3 * k + 1, 3 * k + 2] for k in range(m)]
    mesh = load_ply_mesh(write_ply(tmp_path / "cap.ply", np.vstack([specks, cap]), faces, count="u2"))
    sc = gw.Scene(vertices=mesh.vertices, triangles=mesh.triangles)
    xy = rng.uniform(-0.35, 0.35, (4000, 2))
    o = np.column_stack([xy, np.full(4000, 3.0)]).astype(np.float32)
    d = np.tile(np.float32([0, 0, -1]), (4000, 1))
    hits = sc.intersect(o, d, settings=gw.RenderSettings(threads=1))
    brute = sc.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert np.array_equal(hits.prim, brute.prim) and np.array_equal(hits.t, brute.t)
    assert np.all(hits.prim < n - 2)                       # (the cap comes first: every ray meets it)
    assert hits.stats["prim_tests"] / len(o) < 20, hits.stats


def test_a_face_convex_only_as_seen_from_its_first_corner_keeps_its_fan():
    # Corner 0 and a fine arc bulging towards it: every corner passes the convexity tolerance and
    # the fan from corner 0 covers the face exactly, but clipped in rounds, later rounds' chords
    # of the concave arc would cover ground outside it (1,892 triangles turned the wrong way).
    phi = np.linspace(0, np.pi / 2, 5000)
    r = 1 - 0.5 * np.sin(2 * phi)
    points = np.vstack([[0.0, 0.0, 0.0], np.column_stack([r * np.cos(phi), r * np.sin(phi), np.zeros(5000)])])
    tri, _ = polygons(points, [len(points)])
    p = points[tri]
    area = 0.5 * np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])[:, 2]
    assert len(tri) == len(points) - 2 and np.all(area >= -1e-12)
    outline = 0.5 * np.sum(points[:, 0] * np.roll(points[:, 1], -1) - np.roll(points[:, 0], -1) * points[:, 1])
    assert area.sum() == pytest.approx(outline, rel=1e-9)


def test_a_concave_arc_of_many_fine_corners_is_not_fanned():
    # Each corner of a quarter annulus' inner arc turns the wrong way by less
    # than the convexity tolerance; a fan from corner 0 would reach into the
    # hole (1.6% of the square covered wrongly, 3.2% twice).
    a = np.linspace(0.0, np.pi / 2, 2000)
    outer = np.column_stack([np.cos(a), np.sin(a)])
    inner = 0.5 * outer[::-1]
    xy = np.concatenate([outer, inner])
    tris, _ = polygons(np.column_stack([xy, np.zeros(len(xy))]), [len(xy)])
    assert not np.all(tris[:, 0] == 0)
    check_covers(xy, tris)
