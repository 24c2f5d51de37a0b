"""Material.emission_texture (Principled's Emission Color fed by an image):
the camera sees the texture's colour times emission_color, and an emitter
with emits_light lights the scene with it, as the same emitter with that
colour as a constant does. Checked against numpy and against the constant
emitter; an index out of range is refused."""
import numpy as np
import pytest

import gridwalk as gw
from test23_textures_and_world import BYTES, _expected, _ortho, _pixel_uvs, _square, _srgb

STRENGTH = (2.0, 1.5, 0.5)


def test_the_camera_sees_the_texture_times_the_strength():
    verts, tris, uvs = _square()
    scene = gw.Scene(verts, tris, uvs=uvs, camera=_ortho(),
                     materials=[gw.Material(kd=0, emission_color=STRENGTH, emission_texture=0)],
                     textures=[gw.Texture(gw.Image(BYTES), interpolation="closest")])
    rgba = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()
    u, v = _pixel_uvs(0.0, 1.0)
    expected = _srgb(_expected(BYTES / 255.0, u, v, "closest", "repeat")) * STRENGTH
    np.testing.assert_allclose(rgba[..., :3], expected, rtol=1e-5, atol=1e-6)


def _lit_floor(textured: bool):
    """A grey floor lit only by an emissive square above it, facing down (one colour c over it)."""
    c = np.array([0.6, 0.3, 0.9], np.float32)
    floor = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], np.float32)
    lamp = np.array([[-0.5, -0.5, 1], [-0.5, 0.5, 1], [0.5, 0.5, 1], [0.5, -0.5, 1]], np.float32)
    verts = np.vstack([floor, lamp])
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    uvs = np.zeros((4, 3, 2), np.float32)
    emitter = (gw.Material(kd=0, emission_color=STRENGTH, emission_texture=0, emits_light=True) if textured
               else gw.Material(kd=0, emission_color=tuple(c * STRENGTH), emits_light=True))
    image = gw.Image(np.broadcast_to(c, (2, 2, 3)).astype(np.float32))
    camera = gw.Camera(eye=(0, -6, 5), target=(0, 0, 0), up=(0, 0, 1), fov=50, width=32, height=24)
    scene = gw.Scene(verts, tris, uvs=uvs, camera=camera, triangle_materials=[0, 0, 1, 1],
                     materials=[gw.Material(color=(0.8, 0.8, 0.8), kd=1.0), emitter],
                     textures=[gw.Texture(image)] if textured else [])
    return gw.RenderJob(scene, gw.RenderSettings(threads=1, aa="jittered", aa_samples=2)).start().wait()


def test_a_textured_emitter_lights_the_scene_as_its_colour_does():
    textured, constant = _lit_floor(True), _lit_floor(False)
    assert constant[..., :3].mean() > 0.005                    # the floor is lit
    np.testing.assert_allclose(textured[..., :3], constant[..., :3], rtol=1e-4, atol=1e-6)


@pytest.mark.parametrize("index, message", [(1, "emission_texture = 1 is out of range"),
                                            (-2, "emission_texture must be a texture index or -1")])
def test_an_emission_texture_out_of_range_is_refused(index, message):
    verts, tris, uvs = _square()
    with pytest.raises(ValueError, match=message):
        gw.Scene(verts, tris, uvs=uvs, materials=[gw.Material(emission_texture=index)],
                 textures=[gw.Texture(gw.Image(BYTES))])
