"""Texture.channel, gain, bias and clamp (Blender's Separate Color, Math, Mix
and Invert nodes between an image and a shader input): a colour input sees
the picked channel (or luminance) as grey, times gain plus bias channel by
channel, clamped where asked; a scalar input (alpha) sees that grey value
itself. Checked against numpy on an emissive square; bad values are refused."""
import numpy as np
import pytest

import gridwalk as gw
from test23_textures_and_world import BYTES, N, _expected, _ortho, _pixel_uvs, _render_texture, _square, _srgb

LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def _linear_texels():
    u, v = _pixel_uvs(0.0, 1.0)
    return _srgb(_expected(BYTES / 255.0, u, v, "closest", "repeat"))


@pytest.mark.parametrize("channel", [0, 1, 2, 3])
def test_a_colour_input_sees_one_channel_as_grey(channel):
    rgba, _ = _render_texture(gw.Image(BYTES), interpolation="closest", channel=channel)
    texels = _linear_texels()
    grey = texels @ LUMINANCE if channel == 3 else texels[..., channel]
    np.testing.assert_allclose(rgba[..., :3], np.repeat(grey[..., None], 3, axis=-1), atol=1e-5)


@pytest.mark.parametrize("clamp", [False, True])
def test_gain_and_bias_apply_channel_by_channel_then_the_clamp(clamp):
    gain, bias = (2.5, -1.0, 0.5), (-0.3, 1.2, 0.1)
    rgba, _ = _render_texture(gw.Image(BYTES), interpolation="closest", gain=gain, bias=bias, clamp=clamp)
    expected = _linear_texels() * gain + bias
    if clamp:
        expected = np.clip(expected, 0, 1)
    else:
        assert expected.max() > 1.5 and expected.min() < -0.2             # the clamp would matter
        expected = np.maximum(expected, 0)                                   # (the film keeps no negative light)
    np.testing.assert_allclose(rgba[..., :3], expected, atol=2e-5)


def _alpha_from(texture):
    """A red emitter over a blue background, its alpha from `texture`: (red, blue) seen."""
    verts, tris, uvs = _square()
    scene = gw.Scene(verts, tris, uvs=uvs, camera=_ortho(), background=(0, 0, 1),
                     materials=[gw.Material(kd=0, emission=1.0, color=(1, 0, 0), alpha_texture=0)],
                     textures=[texture])
    rgba = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()
    return rgba[..., 0], rgba[..., 2]


def test_a_scalar_input_takes_the_adjusted_grey_value():
    # alpha from the green channel x 0.5 + 0.25
    red, blue = _alpha_from(gw.Texture(gw.Image(BYTES), interpolation="closest", channel=1,
                                       gain=(0.5, 0.5, 0.5), bias=(0.25, 0.25, 0.25)))
    alpha = _linear_texels()[..., 1] * 0.5 + 0.25
    np.testing.assert_allclose(red, alpha, atol=1e-5)
    np.testing.assert_allclose(blue, 1 - alpha, atol=1e-5)


def test_a_scalar_input_takes_the_luminance_of_a_tinted_colour():
    # (a Mix tinting the colour before a float input: Blender converts the result by its luminance)
    gain, bias = np.array([0.9, 0.3, 0.6]), np.array([0.05, 0.0, 0.1])
    red, _ = _alpha_from(gw.Texture(gw.Image(BYTES), interpolation="closest", gain=tuple(gain), bias=tuple(bias)))
    alpha = (_linear_texels() * gain + bias) @ LUMINANCE
    np.testing.assert_allclose(red, alpha, atol=1e-5)
    assert np.abs(alpha - _linear_texels()[..., 0] * gain[0] - bias[0]).max() > 0.05    # not the red channel


@pytest.mark.parametrize("field, value, message", [("channel", 5, "channel = 5"), ("channel", -2, "channel = -2"),
                                                   ("gain", (1, float("nan"), 1), "gain has a non-finite"),
                                                   ("bias", (0, 0, float("inf")), "bias has a non-finite")])
def test_bad_values_are_refused_naming_the_field(field, value, message):
    verts, tris, uvs = _square()
    with pytest.raises(ValueError, match=message):
        gw.Scene(verts, tris, uvs=uvs, materials=[gw.Material(color_texture=0)],
                 textures=[gw.Texture(gw.Image(BYTES), **{field: value})])


def test_an_environment_refuses_an_adjusted_texture():
    verts, tris, _ = _square()
    with pytest.raises(ValueError, match="environment_strength"):
        gw.Scene(verts, tris, world=gw.World(environment=0),
                 textures=[gw.Texture(gw.Image(BYTES), gain=(2, 2, 2))])


def test_a_colour_texture_and_a_colour_attribute_multiply():
    # (a Mix multiplying the image by the colour attribute: the glTF importer's textured vertex colours)
    verts, tris, uvs = _square()
    tint = np.array([0.5, 1.0, 0.25], np.float32)
    colors = np.broadcast_to(tint, (2, 3, 3)).copy()

    def render(vertex_color, texture):
        material = gw.Material(kd=0, emission=1.0, color_texture=0 if texture else -1, vertex_color=vertex_color)
        scene = gw.Scene(verts, tris, uvs=uvs, colors=colors, camera=_ortho(), materials=[material],
                         textures=[gw.Texture(gw.Image(BYTES), interpolation="closest")])
        return gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()[..., :3]
    np.testing.assert_allclose(render(True, True), _linear_texels() * tint, rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(render(False, True), _linear_texels(), rtol=1e-5, atol=1e-6)
    np.testing.assert_allclose(render(True, False), np.broadcast_to(tint, (N, N, 3)), rtol=1e-6)
