"""Coloured glass (Material.tints_refraction: Cycles' Principled transmission and Glass BSDF)
multiplies what it refracts by its colour at each surface, and the light of shadow rays through
it (tint_sqrt: by its square root, as Blender 4.0+'s Principled BSDF); tints_reflection tints its reflection too. NFF's transmission stays untinted. Checked on a
pane (two parallel faces, IOR 1.5) seen straight through, and on its shadow, against
(1 - F)^2 x colour^2 per channel with F = ((n - 1) / (n + 1))^2."""
import numpy as np
import pytest

import gridwalk as gw

TINT = (0.2, 0.6, 1.0)
F = ((1.5 - 1) / (1.5 + 1)) ** 2


def _pane(z0, z1, size=4.0):
    """A box of glass between heights z0 and z1 (its sides far outside the view)."""
    h = size / 2
    v = np.array([[x, y, z] for z in (z0, z1) for y in (-h, h) for x in (-h, h)], np.float32)
    f = np.array([[0, 2, 1], [1, 2, 3], [4, 5, 6], [5, 7, 6], [0, 1, 5], [0, 5, 4], [2, 6, 7], [2, 7, 3],
                  [0, 4, 6], [0, 6, 2], [1, 3, 7], [1, 7, 5]])
    return v, f


def _glass(tinted, reflection=False):
    return gw.Material(color=TINT, kd=0.0, ks=0.0, transmittance=1.0, ior=1.5, tints_refraction=tinted,
                       tints_reflection=reflection)


def _over_quad(v, f, glass, emitting_z):
    """The pane and a white emitting quad parallel to it at height emitting_z, facing it; a black
    background, an orthographic camera looking straight down from z = 5."""
    quad = np.array([[-50, -50, emitting_z], [50, -50, emitting_z], [50, 50, emitting_z], [-50, 50, emitting_z]],
                    np.float32)
    n = len(v)
    verts, tris = np.concatenate([v, quad]), np.concatenate([f, [[n, n + 1, n + 2], [n, n + 2, n + 3]]])
    light = gw.Material(color=(0, 0, 0), kd=0.0, emission_color=(1, 1, 1))
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=1.0,
                    width=8, height=8)
    scene = gw.Scene(verts, tris, triangle_materials=np.array([0] * len(f) + [1, 1]), materials=[glass, light],
                     camera=cam, background=(0, 0, 0))
    return gw.render(scene, gw.RenderSettings(threads=1))[..., :3].reshape(-1, 3).mean(axis=0)


def test_a_pane_seen_through_is_tinted_once_per_surface():
    """Over a white emitting floor: what passes both faces. (The light bouncing between the faces
    adds F^2 of it: within 0.5%.)"""
    v, f = _pane(-0.05, 0.05)
    np.testing.assert_allclose(_over_quad(v, f, _glass(False), -1.0), [(1 - F) ** 2] * 3, rtol=5e-3)
    np.testing.assert_allclose(_over_quad(v, f, _glass(True), -1.0), (1 - F) ** 2 * np.square(TINT), rtol=5e-3,
                               atol=1e-3)


def test_a_square_root_tint_tints_a_closed_pane_by_the_colour():
    """tint_sqrt (Blender 4.0+'s Principled BSDF, as Cycles tints its transmission): each face by
    the colour's square root, so the pane seen through, and its shadow, by the colour once."""
    v, f = _pane(-0.05, 0.05)
    glass = gw.Material(color=TINT, kd=0.0, ks=0.0, transmittance=1.0, ior=1.5, tints_refraction=True, tint_sqrt=True)
    np.testing.assert_allclose(_over_quad(v, f, glass, -1.0), (1 - F) ** 2 * np.array(TINT), rtol=5e-3, atol=1e-3)
    # a single face (the pane's upper face alone: a sheet): the colour's square root
    top = f[[2, 3]]
    np.testing.assert_allclose(_over_quad(v, top, glass, -1.0), (1 - F) * np.sqrt(TINT), rtol=5e-3, atol=1e-3)


def test_the_shadow_of_coloured_glass_is_tinted():
    v, f = _pane(0.95, 1.05, size=1.0)
    floor = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], np.float32)
    verts = np.concatenate([floor, v])
    tris = np.concatenate([[[0, 1, 2], [0, 2, 3]], f + 4])
    cam = gw.Camera(eye=(0, 0, 0.5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=0.2,
                    width=8, height=8)   # (the floor under the pane's middle, below the pane itself)
    lamp = gw.Light(kind="point", position=(0, 0, 3), color=(9, 9, 9), inverse_square=True)
    lit = {}
    for name, glass in (("clear", _glass(False)), ("tinted", _glass(True)), ("none", None)):
        mats = [gw.Material(color=(1, 1, 1), kd=1.0), glass or gw.Material(color=(1, 1, 1), kd=1.0, alpha=0.0)]
        ids = np.array([0, 0] + [1] * len(f))
        scene = gw.Scene(verts, tris, triangle_materials=ids, materials=mats, lights=[lamp], camera=cam)
        lit[name] = gw.render(scene, gw.RenderSettings(threads=1))[..., :3].reshape(-1, 3).mean(axis=0)
    np.testing.assert_allclose(lit["clear"] / lit["none"], [(1 - F) ** 2] * 3, rtol=1e-3)
    np.testing.assert_allclose(lit["tinted"] / lit["none"], (1 - F) ** 2 * np.square(TINT), rtol=1e-3)


def test_the_glass_bsdf_tints_its_reflection_too():
    """Under a white emitting ceiling (behind the camera) over a black background: what the pane
    reflects, F of it (and F (1 - F)^2 more from its lower face, tinted twice on the way)."""
    v, f = _pane(-0.05, 0.05)
    clear, tinted = _over_quad(v, f, _glass(True, False), 10.0), _over_quad(v, f, _glass(True, True), 10.0)
    back = F * (1 - F) ** 2 * np.square(TINT)                 # the lower face's reflection, through the pane
    np.testing.assert_allclose(clear, F + back, rtol=0.02)
    np.testing.assert_allclose(tinted, F * np.array(TINT) + back * np.array(TINT), rtol=0.02, atol=1e-3)
