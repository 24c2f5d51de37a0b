"""PLY through Blender's own importer and exporter (bpy 4.5 and 5.0).

A PLY written with plyfile imports with bpy.ops.wm.ply_import and renders with
GRIDWALK, covering exactly the pixels the core's render of the same file (same
camera) covers; a PLY that Blender writes (bpy.ops.wm.ply_export of a
subdivided Suzanne) reads back with gridwalk.io.load_ply as the mesh the
add-on's exporter sends to the core."""
import dataclasses
import json

import numpy as np
import plyfile
import pytest

import exr
import gridwalk
from gridwalk.io import load_ply
from runner import missing_reason, run_script

SETTINGS = {"aa": "JITTERED", "aa_samples": 2}


def write_torus_ply(path, n=48, m=24, big=1.0, small=0.35):
    """A torus of n x m quads (binary little endian), tilted off the axes."""
    u, v = np.meshgrid(2 * np.pi * np.arange(n) / n, 2 * np.pi * np.arange(m) / m, indexing="ij")
    ring = big + small * np.cos(v)
    xyz = np.stack([ring * np.cos(u), ring * np.sin(u), small * np.sin(v)], axis=-1).reshape(-1, 3)
    c, s = np.cos(-0.6), np.sin(-0.6)      # tilted towards the default camera
    xyz = xyz @ np.array([[1, 0, 0], [0, c, -s], [0, s, c]]).T + (0.3, -0.2, 0.5)
    i, j = np.meshgrid(np.arange(n), np.arange(m), indexing="ij")
    quads = np.stack([i * m + j, ((i + 1) % n) * m + j, ((i + 1) % n) * m + (j + 1) % m,
                      i * m + (j + 1) % m], axis=-1).reshape(-1, 4)
    vertex = np.array([tuple(p) for p in xyz], dtype=[("x", "f4"), ("y", "f4"), ("z", "f4")])
    face = np.array([(q,) for q in quads], dtype=[("vertex_indices", "i4", (4,))])
    plyfile.PlyData([plyfile.PlyElement.describe(vertex, "vertex"),
                     plyfile.PlyElement.describe(face, "face")]).write(str(path))


def _kind(request):
    if missing_reason(request.param):
        pytest.skip(missing_reason(request.param))
    return request.param


def _rows(a):
    return np.unique(np.asarray(a, np.float32).reshape(-1, 3), axis=0)


@pytest.fixture(scope="module", params=["bpy45", "bpy50"])
def torus(request, tmp_path_factory):
    kind = _kind(request)
    out = tmp_path_factory.mktemp(f"ply_{kind}")
    write_torus_ply(out / "torus.ply")
    kw = load_ply(out / "torus.ply")
    kw["camera"] = dataclasses.replace(kw["camera"], width=256, height=192)
    view = {"camera": dataclasses.asdict(kw["camera"]), "settings": SETTINGS,
            "lights": [dataclasses.asdict(light) for light in kw["lights"]]}
    (out / "view.json").write_text(json.dumps(view))
    run_script(kind, "ply_blender.py", "import", out / "torus.ply", out, out / "view.json", timeout=300)
    settings = gridwalk.RenderSettings(**json.loads((out / "render_settings.json").read_text()))
    return {"kw": kw, "core": gridwalk.render(gridwalk.Scene(**kw), settings),
            "rgba": exr.rgba(exr.read_exr(out / "gridwalk.exr"), "ViewLayer.Combined."),
            "arrays": dict(np.load(out / "arrays.npz"))}


def test_imported_ply_renders_with_gridwalk(torus):
    rgba = torus["rgba"]
    assert rgba.shape == (192, 256, 4) and np.all(np.isfinite(rgba))
    covered = rgba[..., 3] > 0.99
    assert 0.1 < covered.mean() < 0.9
    lum = rgba[..., :3].mean(axis=-1)[covered]
    assert lum.max() > 0.2 and lum.std() > 0.03            # shaded, not flat


def test_imported_ply_is_the_same_mesh_and_covers_the_same_pixels_as_the_core(torus):
    kw, arrays = torus["kw"], torus["arrays"]
    assert len(arrays["triangles"]) == len(kw["triangles"]) == 2 * 48 * 24
    assert np.array_equal(_rows(arrays["vertices"]), _rows(kw["vertices"]))
    ours, core = torus["rgba"][..., 3], torus["core"][..., 3]
    assert np.mean(np.abs(ours - core) > 1e-3) < 1e-3
    assert abs(ours.mean() - core.mean()) < 1e-3


@pytest.fixture(params=["bpy45", "bpy50"])
def suzanne(request, tmp_path):
    run_script(_kind(request), "ply_blender.py", "export", tmp_path, timeout=300)
    return load_ply(tmp_path / "suzanne.ply"), dict(np.load(tmp_path / "arrays.npz"))


def test_ply_written_by_blender_reads_back_as_the_exported_mesh(suzanne):
    kw, arrays = suzanne
    assert len(kw["triangles"]) == len(arrays["triangles"]) > 5000
    # the same positions (Blender splits vertices at UV seams; sets ignore that)
    assert np.array_equal(_rows(kw["vertices"]), _rows(arrays["vertices"]))
    # and the same triangles: both split quads along their 0-2 diagonal
    def triangles(v, t):
        return np.unique(np.sort(v[t].view([("", "f4")] * 3).reshape(len(t), 3), axis=1), axis=0)
    assert np.array_equal(triangles(kw["vertices"], kw["triangles"]),
                          triangles(arrays["vertices"], arrays["triangles"]))
