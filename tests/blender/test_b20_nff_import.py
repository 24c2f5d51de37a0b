"""File > Import > NFF in real Blender (bpy 4.5 and 5.0).

The SPD scenes import with the expected objects; exporting them again gives
the arrays of gridwalk.io.load_nff (spheres, triangles and background exactly;
materials in every shading term but the Phong highlight; camera and lights
within float32 tolerance, lights with the documented falloff approximation);
and GRIDWALK's render of the import looks like the core's own render of the
file. PLY goes through Blender's own importer and exporter (test_b21)."""
import os

import numpy as np
import pytest

from gridwalk.io import load_nff
from nff_roundtrip import import_nff, imported_fixture
from runner import ALL_BLENDERS, ROOT, missing_reason

SPD = ROOT.parent / "shared" / "scenes" / "spd"
# scene: spheres, polygons, polygon corners, lights, and bounds on the render's
# mean absolute difference and its luminance correlation with the core's. The
# bounds are what the two documented approximations cost: Blender's light
# falloff (balls: lights 5-6 units away, ~0.05) and NFF's broad Phong highlight
# on the mirror balls (~0.05). mount's light is 170 units away: nearly exact.
SCENES = {"balls_s1": (10, 1, 4, 3, 1e-3, 0.999), "balls_s2": (91, 1, 4, 3, 1e-3, 0.999),
          "mount_s4": (4, 512, 1536, 1, 1e-3, 0.999)}
DOCS_IMAGE = ROOT / "docs" / "images" / "nff_import_balls.png"


imported = imported_fixture(SCENES, lambda name, out: SPD / f"{name}.nff")


def _shading(m):
    """What a material does to the image, but for the Phong highlight's shape:
    diffuse albedo, mirror, transmission (and its ior), roughness, has a highlight."""
    m = m if isinstance(m, dict) else m.__dict__
    return (*np.round(np.asarray(m["color"]) * m["kd"], 5), round(m["mirror"], 6),
            round(m["transmittance"], 6), round(m["ior"], 5) if m["transmittance"] > 0 else 1.0,
            m["roughness"], m["ks"] > 0)


def test_import_makes_the_expected_objects(imported):
    info = imported["info"]
    spheres, polygons, corners, lights, _, _ = SCENES[imported["name"]]
    assert info["result"] == ["FINISHED"] and info["warnings"] == []
    assert info["spheres"] == spheres and len(info["light_objects"]) == lights
    assert info["cameras"] == [info["scene_camera"]] and info["resolution"] == [512, 512]
    assert info["objects"] == spheres + 1 + lights + 1 and info["collections"] == [imported["name"]]
    (mesh,) = info["meshes"].values()                 # the polygons, kept as n-gons
    assert (mesh["polygons"], mesh["loops"]) == (polygons, corners)
    assert not mesh["smooth"] and not mesh["custom_normals"]   # no pp: flat, as in the core
    assert all(light["type"] == "POINT" and light["radius"] == 0 for light in info["light_objects"])


def test_spheres_round_trip_exactly_with_their_materials(imported):
    a, nff, mats = imported["arrays"], imported["nff"], imported["info"]["materials"]
    ours = [(*c, r, *_shading(mats[m])) for c, r, m in
            zip(a["sphere_centers"], a["sphere_radii"], a["sphere_materials"])]
    theirs = [(*c, r, *_shading(nff["materials"][m])) for c, r, m in
              zip(nff["sphere_centers"], nff["sphere_radii"], nff["sphere_materials"])]
    assert sorted(ours) == sorted(theirs)


def test_triangles_round_trip_as_sets_with_their_materials(imported):
    info, a, nff = imported["info"], imported["arrays"], imported["nff"]

    def triangles(vertices, tris, tri_mats, materials):
        return sorted((tuple(sorted(tuple(np.round(v, 5)) for v in vertices[t])), _shading(materials[m]))
                      for t, m in zip(tris, tri_mats))
    assert info["has_normals"] == (nff["normals"] is not None)
    assert (triangles(a["vertices"], a["triangles"], a["triangle_materials"], info["materials"])
            == triangles(nff["vertices"], nff["triangles"], nff["triangle_materials"], nff["materials"]))


def test_camera_background_and_lights_round_trip(imported):
    info, nff = imported["info"], imported["nff"]
    cam, ref = info["camera"], nff["camera"]
    np.testing.assert_allclose(cam["eye"], ref.eye, atol=1e-6)
    forward = np.subtract(ref.target, ref.eye) / np.linalg.norm(np.subtract(ref.target, ref.eye))
    np.testing.assert_allclose(np.subtract(cam["target"], cam["eye"]), forward, atol=1e-6)
    up = np.asarray(ref.up) - forward * np.dot(ref.up, forward)
    np.testing.assert_allclose(cam["up"], up / np.linalg.norm(up), atol=1e-6)
    assert abs(cam["fov"] - ref.fov) < 1e-4 and (cam["width"], cam["height"]) == (ref.width, ref.height)
    assert cam["hither"] == pytest.approx(ref.hither, rel=1e-6)
    np.testing.assert_allclose(info["background"], nff["background"], rtol=1e-6)
    for light, blender, theirs in zip(info["lights"], info["light_objects"], nff["lights"]):
        np.testing.assert_allclose(light["position"], theirs.position, atol=1e-6)
        # exported as NFF's light: the same intensity, no distance falloff
        assert light["kind"] == "point" and not light["inverse_square"]
        np.testing.assert_allclose(light["color"], theirs.color, rtol=1e-6)
        # Blender's own power (for Cycles and the viewport) gives the NFF
        # intensity at the reference distance, which lies within the scene
        d0 = blender["nff_reference_distance"]
        gap = np.linalg.norm(np.subtract(theirs.position, nff["sphere_centers"]), axis=1)
        assert gap.min() - nff["sphere_radii"].max() < d0 < gap.max() + 20.0


def _srgb(x):
    x = np.clip(x[..., :3], 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def test_render_looks_like_the_cores_render_of_the_file(imported):
    core, ours = imported["core"], imported["rgba"]
    assert ours.shape == core.shape == (512, 512, 4)
    # coverage: the same pixels (but for a few float32 edge pixels) are covered
    assert np.mean(np.abs(core[..., 3] - ours[..., 3]) > 1e-3) < 1e-4
    a, b = np.clip(core[..., :3], 0, 1), np.clip(ours[..., :3], 0, 1)
    mad = float(np.abs(a - b).mean())
    correlation = np.corrcoef(a.mean(axis=-1).ravel(), b.mean(axis=-1).ravel())[0, 1]
    print(f"{imported['kind']} {imported['name']}: mean absolute difference {mad:.4f}, "
          f"luminance correlation {correlation:.3f}")
    assert mad < SCENES[imported["name"]][4] and correlation > SCENES[imported["name"]][5]
    if imported["name"] == "balls_s2" and imported["kind"] == "bpy45":
        from PIL import Image
        diff = np.abs(_srgb(core) - _srgb(ours)).mean(axis=-1, keepdims=True).repeat(3, axis=-1)
        strip = np.concatenate([_srgb(core), _srgb(ours), np.clip(diff * 4, 0, 1)], axis=1)
        image = Image.fromarray((strip * 255 + 0.5).astype(np.uint8))
        image.save(imported["out"] / "comparison.png")
        if os.environ.get("GRIDWALK_DOCS_IMAGES"):           # regenerate the docs image
            image.save(DOCS_IMAGE)


NFF_EXTRAS = """# cone, cylinder, n-gon, patch with vertex normals, primitives before any f
v
from 0 -9 3
at 0 0 0.6
up 0 0 1
angle 35
resolution 64 48
b 0.1 0.2 0.3
l 3 -4 6 0.9 0.8 0.7
s 2.2 0 0.5 0.5
f 0.9 0.3 0.2 0.7 0.2 20 0 1
c
-2 0 0 0.5
-2 0 1.5 -0.5
c
0 0 0 0.7
0 0 1.6 0
p 5
-1 -1 -0.01
1 -1 -0.01
1.5 1 -0.01
0 2 -0.01
-1.5 1 -0.01
f 0.2 0.5 0.9 0.6 0.1 10 0.5 1.3
pp 4
1 -2 0 0 -1 0.2
2 -2 0 0.3 -1 0.2
2 -2 1 0.3 -1 0
1 -2 1 0 -1 0
"""


@pytest.fixture(params=ALL_BLENDERS)          # Debian's 3.4 too: its socket names and mesh API
def extras(request, tmp_path):
    if missing_reason(request.param):
        pytest.skip(missing_reason(request.param))
    path = tmp_path / "extras.nff"
    path.write_text(NFF_EXTRAS)
    info, arrays = import_nff(request.param, path, tmp_path)
    return info, arrays, load_nff(path)


def test_cones_and_cylinders_become_tessellated_meshes_on_the_analytic_surface(extras):
    info, a, nff = extras
    assert info["meshes"]["extras cones"]["polygons"] == 2 * 32
    on_any = np.zeros(len(a["vertices"]), bool)
    for base, apex, rb, ra in zip(nff["cylinder_base"], nff["cylinder_apex"],
                                  nff["cylinder_base_radius"], nff["cylinder_apex_radius"]):
        length = np.linalg.norm(apex - base)
        axis = (apex - base) / length
        s = (a["vertices"] - base) @ axis / length
        radial = a["vertices"] - base - np.outer(s * length, axis)
        r = np.linalg.norm(radial, axis=1)
        on = (np.abs(r - (rb + (ra - rb) * s)) < 1e-5) & (s > -1e-6) & (s < 1 + 1e-6)
        on_any |= on
        # custom normals = the analytic ones, perpendicular to the slant (tips excepted)
        side = on & (r > 1e-4)
        slant = radial[side] / r[side, None] * (ra - rb) + axis * length
        slant /= np.linalg.norm(slant, axis=1, keepdims=True)
        assert np.abs(np.sum(a["normals"][side] * slant, axis=1)).max() < 2e-3
        assert np.all(np.sum(a["normals"][side] * radial[side], axis=1) > 0)     # outward
    assert on_any.sum() == 32 * 4 + 32 * 3                  # every cone corner is on a cone


def test_ngons_stay_ngons_and_patch_normals_round_trip(extras):
    info, a, nff = extras
    polygons = info["meshes"]["extras polygons"]
    assert (polygons["polygons"], polygons["loops"]) == (2, 9)
    assert polygons["custom_normals"] and polygons["smooth"]
    assert info["spheres"] == 1 and len(info["light_objects"]) == 1
    for p, n in zip(nff["vertices"], nff["normals"]):       # pp normals and p's face normals
        k = np.flatnonzero(np.linalg.norm(a["vertices"] - p, axis=1) < 1e-6)
        assert len(k) and np.abs(a["normals"][k] - n).max() < 2e-3
    assert len(a["triangles"]) == 3 + 2 + 2 * 32 + 32       # 5-gon, quad, cylinder, cone


def test_malformed_nff_is_an_error_report_and_adds_nothing(tmp_path):
    if missing_reason("bpy45"):
        pytest.skip(missing_reason("bpy45"))
    path = tmp_path / "bad.nff"
    path.write_text(NFF_EXTRAS.replace("p 5\n-1 -1 -0.01\n", "p 5\n-1 nan -0.01\n"))
    info, _ = import_nff("bpy45", path, tmp_path)
    assert f"{path}:" in info["error"] and "NaN" in info["error"] and "Traceback" not in info["error"]
    assert info["objects"] == 0 and info["collections"] == []
