"""Texture(kind="attribute") (Blender's Attribute node): the triangles' corner colours
(Scene(colors=...)) interpolated at the hit, as a texture: its colour is what a material with
vertex_color shows, its Fac (use_alpha) their mean, through the same channel, ramp and bump
machinery as any texture. A scene whose triangles read one without corner colours is refused,
naming the array. Blender's side: tests/blender/test_b51."""
import numpy as np
import pytest

import gridwalk as gw

N = 32
VERTS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
COLORS = np.array([[0.9, 0.1, 0.3], [0.2, 0.7, 0.4], [0.5, 0.5, 1.0], [0.0, 0.3, 0.8]], np.float32)[TRIS]
CAMERA = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=2.0,
                   width=N, height=N)


def _emitting(material, textures=None, colors=COLORS, **scene):
    s = gw.Scene(VERTS, TRIS, colors=colors, camera=CAMERA, textures=textures, materials=[material], **scene)
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., :3]


def test_an_attribute_texture_shows_the_corner_colours():
    by_texture = _emitting(gw.Material(kd=0, emission=1.0, color_texture=0), [gw.Texture(kind="attribute")])
    by_material = _emitting(gw.Material(kd=0, emission=1.0, vertex_color=True))
    np.testing.assert_allclose(by_texture, by_material, atol=1e-6)
    assert by_texture.std() > 0.1


def test_its_fac_is_the_colours_mean():
    grey = _emitting(gw.Material(kd=0, emission=1.0, color_texture=0), [gw.Texture(kind="attribute", use_alpha=True)])
    colour = _emitting(gw.Material(kd=0, emission=1.0, vertex_color=True))
    np.testing.assert_allclose(grey, np.repeat(colour.mean(axis=-1, keepdims=True), 3, axis=-1), atol=1e-6)


def test_a_ramp_colours_its_fac():
    # a ramp from black at 0 to white at 1: the grey of the mean, again
    ramp = (0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0)
    ramped = _emitting(gw.Material(kd=0, emission=1.0, color_texture=0),
                       [gw.Texture(kind="attribute", use_alpha=True, ramp=ramp)])
    colour = _emitting(gw.Material(kd=0, emission=1.0, vertex_color=True))
    np.testing.assert_allclose(ramped[..., 0], colour.mean(axis=-1), atol=1e-5)


def test_an_attribute_bump_bends_the_normal_by_its_slope():
    light = gw.Light(kind="sun", direction=(-0.3, -0.2, -1.0), color=(1, 1, 1))

    def lit(bump):
        extra = dict(bump_texture=0, bump_distance=2.0) if bump else {}
        return _emitting(gw.Material(color=(1, 1, 1), kd=1.0, **extra), [gw.Texture(kind="attribute", use_alpha=True)],
                         lights=[light])
    flat, bumped = lit(False), lit(True)
    assert flat.std() < 1e-5 and np.abs(bumped - flat).max() > 0.02


def test_an_attribute_texture_without_corner_colours_is_refused():
    with pytest.raises(ValueError, match=r"attribute texture.*Scene\(colors=\.\.\.\)"):
        _emitting(gw.Material(color_texture=0), [gw.Texture(kind="attribute")], colors=None)
