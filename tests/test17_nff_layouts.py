"""NFF as the SPD tools write and read it: every entity and every SPD-like scene
of the generated corpus (tests/nff_corpus.py) reads the same in every layout
(libpr2's one-line cones, the NFF text's three-line cones, one entity a line,
one line for the whole file, random line breaks / tabs / CRLF / comments),
errors keep the line of the bad token in every layout, and concave polygons
(gears) are covered exactly once."""
from pathlib import Path

import numpy as np
import pytest

import gridwalk as gw
import nff_corpus as corpus
from gridwalk.io import SceneFileError, load_nff, read_nff
from gridwalk.io.nff import spd_light_intensity
from gridwalk.model import Light, Material

SPD_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "scenes" / "spd"
SCENES = {**corpus.GENERATORS, "every_entity": corpus.every_entity}


def write(path: Path, text: str) -> Path:
    path.write_bytes(text.encode("utf-8"))
    return path


def assert_same_scene(a: dict, b: dict, what: str):
    assert a.keys() == b.keys()
    for key in a:
        if isinstance(a[key], np.ndarray) or a[key] is None:
            assert (a[key] is None) == (b[key] is None), (what, key)
            assert a[key] is None or np.array_equal(a[key], b[key]), (what, key)
        else:
            assert a[key] == b[key], (what, key)


@pytest.mark.parametrize("name", sorted(SCENES))
def test_every_layout_of_a_generated_scene_reads_the_same(tmp_path, name):
    scene = SCENES[name]()
    reference = load_nff(write(tmp_path / "spd.nff", corpus.write(scene, "spd")))
    for layout in corpus.LAYOUTS[1:]:
        got = load_nff(write(tmp_path / f"{layout}.nff", corpus.write(scene, layout, seed=len(name))))
        assert_same_scene(reference, got, layout)
    n = corpus.counts(scene)
    assert (len(reference["sphere_radii"]), len(reference["cylinder_base"]), len(reference["triangles"]),
            len(reference["lights"])) == (n["spheres"], n["cones"], n["triangles"], n["lights"])


@pytest.mark.parametrize("name", sorted(corpus.GENERATORS))
def test_every_generated_scene_renders(tmp_path, name):
    import dataclasses
    kwargs = load_nff(write(tmp_path / "s.nff", corpus.write(SCENES[name](), "spd")))
    kwargs["camera"] = dataclasses.replace(kwargs["camera"], width=40, height=40)
    image = gw.render(gw.Scene(**kwargs), gw.RenderSettings(threads=1, aa_samples=1))
    assert image[..., 3].mean() > 0.05 and len(np.unique(image[..., :3].reshape(-1, 3), axis=0)) > 20


def test_every_entity_maps_to_the_scene(tmp_path):
    kwargs = load_nff(write(tmp_path / "e.nff", corpus.write(corpus.every_entity(), "spd")))
    cam = kwargs["camera"]
    assert (cam.eye, cam.target, cam.up, cam.width, cam.height, cam.hither) == \
        ((0, -9, 3), (0, 0, 0.6), (0, 0, 1), 64, 48, 0.01)
    assert kwargs["background"] == (0.1, 0.2, 0.3)
    gain = spd_light_intensity(2)
    assert kwargs["lights"] == [Light(position=(3, -4, 6), color=(gain, gain, gain)),
                                Light(position=(-3, -4, 5), color=(0.9, 0.8, 0.7))]
    default, red, glass = kwargs["materials"]
    assert default == Material()
    assert red == Material(color=(0.9, 0.3, 0.2), kd=0.7, ks=0.2, shininess=20, mirror=0.2)
    assert (glass.transmittance, glass.ior) == (0.5, 1.3)
    f32 = np.float32
    assert kwargs["sphere_radii"].tolist() == [0.5, f32(0.3)]                # |-0.3|: inside visible
    assert kwargs["sphere_materials"].tolist() == [0, 2]
    assert kwargs["cylinder_base_radius"].tolist() == [0.5, f32(0.7)]
    assert kwargs["cylinder_apex_radius"].tolist() == [0.5, 0.0]             # |-0.5|
    assert kwargs["cylinder_apex"].tolist() == [[-2, 0, 1.5], [0, 0, f32(1.6)]]
    assert kwargs["triangle_materials"].tolist() == [1, 1, 1, 2, 2]         # the 5-gon, the patch
    normals = kwargs["normals"]
    np.testing.assert_allclose(normals[:5], [[0, 0, 1]] * 5, atol=1e-7)   # the p's plane
    np.testing.assert_allclose(np.linalg.norm(normals, axis=1), 1, rtol=1e-6)


@pytest.mark.parametrize("layout", corpus.LAYOUTS)
def test_a_bad_number_is_reported_at_its_own_line_in_every_layout(tmp_path, layout):
    scene = corpus.rings(1)
    k = next(i for i, (w, _) in enumerate(scene) if w == "c")
    scene[k + 20] = ("c", [7.125, 0, 0, 0.5, 1, 1, 1, 0.5])
    text = corpus.write(scene, layout, seed=5).replace("7.125", "7.1x25")
    path = write(tmp_path / "bad.nff", text)
    line = text[:text.index("7.1x25")].count("\n") + 1
    with pytest.raises(SceneFileError) as err:
        load_nff(path)
    assert str(err.value).startswith(f"{path}:{line}: 'c': bad number '7.1x25'"), str(err.value)


def token_lines(text: str):
    """(token, line) of each token outside comments; lines end at LF (CRLF included)."""
    return [(t, n) for n, line in enumerate(text.split("\n"), 1)
            for t in line.split("#")[0].replace("\x0b", " ").replace("\x0c", " ").split()]


@pytest.mark.parametrize("layout", corpus.LAYOUTS)
def test_a_missing_number_is_reported_at_the_entity_and_names_the_next_one(tmp_path, layout):
    scene = corpus.tree(1)
    k = next(i for i, (w, _) in enumerate(scene) if w == "c")
    scene[k] = ("c", [0, 0, 0, 0.15, 0, 0, 1])                   # 7 of the 8 numbers
    text = corpus.write(scene, layout, seed=2)
    tokens = token_lines(text)
    c = next(i for i, (t, _) in enumerate(tokens) if t == "c")
    assert tokens[c + 8][0] == "s"
    path = write(tmp_path / "bad.nff", text)
    with pytest.raises(SceneFileError) as err:
        load_nff(path)
    assert str(err.value) == (f"{path}:{tokens[c][1]}: 'c' needs 8 numbers (base x y z radius, apex x y z "
                              f"radius), but only 7 follow before the entity 's' on line {tokens[c + 8][1]}")


@pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")
@pytest.mark.parametrize("name", ["balls_s2.nff", "mount_s4.nff"])
def test_real_spd_files_read_the_same_as_one_stream_or_scrambled(tmp_path, name):
    text = (SPD_DIR / name).read_text()
    reference = load_nff(SPD_DIR / name)
    for layout in ("stream", "scrambled"):
        got = load_nff(write(tmp_path / f"{layout}.nff", corpus.relayout(text.split(), layout, seed=9)))
        assert_same_scene(reference, got, layout)


def test_gear_faces_are_concave_and_covered_exactly_once(tmp_path):
    nff = read_nff(write(tmp_path / "gears.nff", corpus.write(corpus.gears(1), "spd")))
    kw, polys = nff.kwargs, nff.polygons
    faces = np.flatnonzero(polys.counts == 48)
    assert len(faces) == 2
    triangles = kw["triangles"]
    owner = np.repeat(np.arange(len(polys.counts)), polys.counts - 2)
    for k in faces:
        xy = kw["vertices"][polys.starts[k]:polys.starts[k] + 48, :2].astype(np.float64)
        tris = triangles[owner == k] - polys.starts[k]
        fan_area = sum(abs(_area(xy[[0, j, j + 1]])) for j in range(1, 47))
        assert fan_area > abs(_area(xy)) * 1.01                    # a fan would overlap itself
        signed = [_area(xy[t]) for t in tris]
        assert all(s * _area(xy) > 0 for s in signed)
        assert sum(signed) == pytest.approx(_area(xy), rel=1e-6)


def _area(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
