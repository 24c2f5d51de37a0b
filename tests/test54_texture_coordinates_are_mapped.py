"""Texture.uv_transform (Blender's Mapping node on the UV map): every lookup
of a surface texture reads the image at (a u + b v + c, d u + e v + f),
checked against test23's numpy lookup at the mapped coordinates; bad
transforms are refused with the field named."""
import math

import numpy as np
import pytest

import gridwalk as gw
from test23_textures_and_world import BYTES, N, _expected, _ortho, _pixel_uvs, _render_texture, _square, _srgb

# scale (2.3, 1.7), turned 30 degrees, moved by (0.35, -0.2): a map with every coefficient non-zero
C, S = math.cos(math.radians(30)), math.sin(math.radians(30))
MAP = (2.3 * C, -1.7 * S, 0.35, 2.3 * S, 1.7 * C, -0.2)


def _mapped(u, v, m):
    return m[0] * u + m[1] * v + m[2], m[3] * u + m[4] * v + m[5]


@pytest.mark.parametrize("interpolation", ["closest", "linear"])
@pytest.mark.parametrize("extension", ["repeat", "clip", "mirror"])
def test_a_colour_texture_is_read_at_the_mapped_coordinates(interpolation, extension):
    rgba, _ = _render_texture(gw.Image(BYTES), interpolation=interpolation, extension=extension, uv_transform=MAP)
    u, v = _mapped(*_pixel_uvs(0.0, 1.0), MAP)
    expected = _srgb(_expected(BYTES / 255.0, u, v, interpolation, extension))
    np.testing.assert_allclose(rgba[..., :3], expected, atol=2e-4)
    unmapped, _ = _render_texture(gw.Image(BYTES), interpolation=interpolation, extension=extension)
    assert np.abs(unmapped[..., :3] - expected).max() > 0.1      # the map changed what is seen


def test_a_map_without_a_linear_part_shows_one_texel_everywhere():
    # (a Mapping node whose own Vector is unlinked maps the constant 0 vector)
    point = (0.3, 0.7)
    rgba, _ = _render_texture(gw.Image(BYTES), interpolation="closest", uv_transform=(0, 0, *point[:1], 0, 0,
                                                                                        point[1]))
    texel = _srgb(BYTES[::-1][int(point[1] * BYTES.shape[0]), int(point[0] * BYTES.shape[1])] / 255.0)
    np.testing.assert_allclose(rgba[..., :3], np.broadcast_to(texel, (N, N, 3)), atol=1e-6)


def test_an_alpha_texture_is_read_at_its_mapped_coordinates():
    # an alpha checker scaled 2x: the holes repeat twice as often as the unmapped one's
    # (the image's bottom-left texel, row 1 of the array, is opaque)
    checker = (np.indices((2, 2)).sum(axis=0) % 2).astype(np.float32)
    alpha = gw.Image(np.dstack([checker] * 4))
    verts, tris, uvs = _square()

    def render(transform):
        scene = gw.Scene(verts, tris, uvs=uvs, camera=_ortho(), background=(0, 0, 1),
                         materials=[gw.Material(kd=0, emission=1.0, color=(1, 0, 0), alpha_texture=0)],
                         textures=[gw.Texture(alpha, interpolation="closest", use_alpha=True,
                                              uv_transform=transform)])
        return gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()
    plain, doubled = render((1, 0, 0, 0, 1, 0)), render((2, 0, 0, 0, 2, 0))
    u, v = _pixel_uvs(0.0, 1.0)
    for image, k in ((plain, 1), (doubled, 2)):
        red = (np.floor(u * 2 * k) + np.floor(v * 2 * k)) % 2 == 0
        np.testing.assert_allclose(image[..., 0], red.astype(float), atol=1e-6)
        np.testing.assert_allclose(image[..., 2], (~red).astype(float), atol=1e-6)


@pytest.mark.parametrize("bad, message", [((1, 0, float("nan"), 0, 1, 0), "uv_transform has a non-finite"),
                                          ((1, 0, 0, float("inf"), 1, 0), "uv_transform has a non-finite"),
                                          ((1, 0, 0, 1), "6 components")])
def test_a_bad_transform_is_refused_naming_the_field(bad, message):
    verts, tris, uvs = _square()
    with pytest.raises(ValueError, match=message):
        gw.Scene(verts, tris, uvs=uvs, materials=[gw.Material(color_texture=0)],
                 textures=[gw.Texture(gw.Image(BYTES), uv_transform=bad)])


def test_an_environment_refuses_a_uv_transform():
    verts, tris, _ = _square()
    with pytest.raises(ValueError, match="environment_rotation"):
        gw.Scene(verts, tris, world=gw.World(environment=0),
                 textures=[gw.Texture(gw.Image(BYTES), uv_transform=(2, 0, 0, 0, 1, 0))])
