"""Renders of every feature stay bit-identical to renders stored before a
refactoring (tests/references/golden.npz). Each case exercises a different
part of the core: primitive kinds, light kinds, every anti-aliasing, shadow,
lens and glossy mode, refraction, smooth normals, the acceleration structures.

A change that is meant to alter images regenerates the references on purpose:
    GRIDWALK_REGEN=1 .venv/bin/python -m pytest tests/test07_images_stay_bit_identical.py
and says why in its commit message.
"""
import os
from pathlib import Path

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls, distant
from meshes import icosphere

REF = Path(__file__).parent / "references" / "golden.npz"
RES = 40


def balls_scene():
    kw = balls(1)
    kw["camera"].width = kw["camera"].height = RES
    kw["lights"] = [gw.Light(position=l.position, color=l.color, kind="sphere", radius=0.3) for l in kw["lights"]]
    kw["materials"][0].roughness = 0.2
    return gw.Scene(**kw)


def mesh_scene():
    """A smooth glass icosphere and a mirror cone on a floor, lit by a rect, a
    disk, a spot and a sun light."""
    V, F = icosphere(2, radius=0.8, center=(0, 0, 0.8))
    normals = (V - np.array([0, 0, 0.8], np.float32)) / 0.8
    floor_v = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], np.float32)
    verts = np.vstack([V, floor_v])
    tris = np.vstack([F, np.array([[0, 1, 2], [0, 2, 3]]) + len(V)])
    nrm = np.vstack([normals, np.tile([0, 0, 1], (4, 1))]).astype(np.float32)
    mats = [gw.Material(color=(0.9, 0.9, 1.0), kd=0.1, ks=0.5, shininess=60, transmittance=0.8, ior=1.5),
            gw.Material(color=(0.8, 0.7, 0.5), kd=0.7, mirror=0.2),
            gw.Material(color=(0.6, 0.8, 0.6), kd=0.5, mirror=0.4, roughness=0.3)]
    lights = [gw.Light(kind="rect", position=(0, -2, 3), size=(1.0, 0.5), direction=(0, 0.5, -1), color=(3, 3, 3)),
              gw.Light(kind="disk", position=(2, 1, 3), radius=0.4, direction=(-0.5, 0, -1), color=(2, 2, 2),
                       inverse_square=True),
              gw.Light(kind="spot", position=(-2, 0, 3), direction=(1, 0, -1.5), spot_size=0.8, color=(1, 1, 1)),
              gw.Light(kind="sun", direction=(0.3, 0.2, -1), angle=0.1, color=(0.3, 0.3, 0.3))]
    cam = gw.Camera(eye=(0.5, -5, 2.5), target=(0, 0, 0.6), fov=45, width=RES, height=RES, shift=(0.05, -0.02))
    return gw.Scene(vertices=verts, triangles=tris, normals=nrm,
                    triangle_materials=np.r_[np.zeros(len(F)), np.ones(2)].astype(np.int32),
                    cylinder_base=[[1.5, 0.5, 0]], cylinder_apex=[[1.5, 0.5, 1.2]], cylinder_base_radius=[0.4],
                    cylinder_apex_radius=[0.1], cylinder_materials=[2],
                    materials=mats, lights=lights, camera=cam, background=(0.1, 0.2, 0.3))


def textured_scene():
    """A floor with an 8-bit sRGB checker (closest, repeat), a cut-out pane
    (alpha from a texture's alpha channel, bilinear, clip) and an emissive
    sphere in an HDR environment with ambient light."""
    checker = ((np.indices((8, 8)).sum(axis=0) % 2) * 200 + 40).astype(np.uint8)
    floor_img = gw.Image(np.dstack([checker, checker // 2, 255 - checker]), name="checker")
    alpha = np.zeros((4, 4, 4), np.float32)
    alpha[..., :3], alpha[1:3, 1:3, 3] = 0.7, 1.0
    sky = np.dstack([*np.meshgrid(np.linspace(0, 2, 16), np.linspace(1, 0, 8)), np.full((8, 16), 0.5)])
    textures = [gw.Texture(floor_img, interpolation="closest"),
                gw.Texture(gw.Image(alpha, name="cutout"), extension="clip", use_alpha=True),
                gw.Texture(gw.Image(sky.astype(np.float32), name="sky"))]
    verts = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0],
                      [-1, 0, 0.2], [1, 0, 0.2], [1, 0, 2.2], [-1, 0, 2.2]], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    uvs = np.array([[[0, 0], [4, 0], [4, 4]], [[0, 0], [4, 4], [0, 4]],
                    [[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]], np.float32)
    mats = [gw.Material(color_texture=0, kd=0.9), gw.Material(alpha_texture=1, color=(0.2, 0.6, 0.9)),
            gw.Material(kd=0, emission_color=(2.0, 1.5, 0.5))]
    cam = gw.Camera(eye=(0.5, -6, 3), target=(0, 0, 0.8), fov=50, width=RES, height=RES)
    return gw.Scene(vertices=verts, triangles=tris, triangle_materials=[0, 0, 1, 1], uvs=uvs,
                    sphere_centers=[[1.5, 1.5, 0.6]], sphere_radii=[0.5], sphere_materials=[2],
                    materials=mats, textures=textures, camera=cam,
                    lights=[gw.Light(position=(-2, -3, 4), color=(12, 12, 12), inverse_square=True)],
                    world=gw.World(ambient=(0.1, 0.1, 0.15), environment=2, environment_strength=1.5))


def distant_scene():
    kw = distant()
    kw["camera"].width = kw["camera"].height = RES
    return gw.Scene(**kw)


CASES = {
    "balls-center": (balls_scene, dict()),
    "balls-jittered-area": (balls_scene, dict(aa="jittered", aa_samples=2, shadow="area", shadow_samples=2,
                                              glossy_samples=2)),
    "balls-random-gauss": (balls_scene, dict(aa="random", aa_samples=2, filter="gaussian", shadow="random",
                                             shadow_samples=2)),
    "balls-sobol": (balls_scene, dict(aa="sobol", aa_samples=2, glossy_samples=3)),
    "balls-adaptive": (balls_scene, dict(aa="adaptive", adaptive_depth=2, adaptive_threshold=0.02)),
    "balls-brute-force": (balls_scene, dict(accel="none", aa="jittered", aa_samples=2)),
    "mesh-center": (mesh_scene, dict()),
    "mesh-jittered-area": (mesh_scene, dict(aa="jittered", aa_samples=2, shadow="area", shadow_samples=2,
                                            glossy_samples=2, max_depth=6)),
    "mesh-uniform-m1": (mesh_scene, dict(accel="grid", grid_density=1.0, skip_empty=False, mailboxes=False)),
    "distant-dof": (distant_scene, dict(dof_samples=4, aa="jittered", aa_samples=2)),
    "textured-jittered": (textured_scene, dict(aa="jittered", aa_samples=2)),
}


def render_case(name):
    make, settings = CASES[name]
    job = gw.RenderJob(make(), gw.RenderSettings(threads=2, **settings)).start()
    rgba = job.wait()
    return {f"{name}/rgba": rgba, f"{name}/depth": job.depth, f"{name}/normal": job.normal}


@pytest.fixture(scope="module")
def references():
    if os.environ.get("GRIDWALK_REGEN"):
        arrays = {}
        for name in CASES:
            arrays.update(render_case(name))
        np.savez_compressed(REF, **arrays)
    return dict(np.load(REF))


@pytest.mark.parametrize("name", list(CASES))
def test_render_is_bit_identical_to_the_stored_reference(name, references):
    for key, value in render_case(name).items():
        ref = references[key]
        assert value.shape == ref.shape, key
        differ = ~((value == ref) | (np.isnan(value) & np.isnan(ref)))
        assert not differ.any(), f"{key}: {int(differ.sum())} values differ, max |diff| " \
                                 f"{np.nanmax(np.abs(np.where(differ, value - ref, 0))):.3g}"


# Cases that differ only in the acceleration structure: the same image.
ACCEL_TWINS = {"mesh-uniform-m1": "mesh-center"}


def test_acceleration_settings_do_not_change_the_image(references):
    for name, twin in ACCEL_TWINS.items():
        assert np.array_equal(references[f"{name}/rgba"], references[f"{twin}/rgba"]), (name, twin)


def test_the_cases_are_different_images(references):
    """Guards the reference set itself: every case renders something, and no two
    cases are the same image (each sampling setting really changed the render)."""
    images = {name: references[f"{name}/rgba"] for name in CASES if name not in ACCEL_TWINS}
    for name, img in images.items():
        assert img[..., 3].mean() > 0.2, name
        assert img[..., :3].std() > 0.01, name
    names = list(images)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            assert not np.array_equal(images[a], images[b]), (a, b)
