"""World(inset=...) shows part of the environment in detail (a sky's sun, which the environment's
texels blur): rays that miss see the inset's texture within its square, u along the frame's x axis
and v along its y axis, and the environment everywhere else, the environment's strength scaling
both; lighting reads the environment alone; bad insets are refused with ValueError."""
import math

import numpy as np
import pytest

import gridwalk as gw

BLUE = (0.1, 0.2, 0.9)
# the square: 10 degrees either way about +X; x to the image's right (-Y, looking along +X with Z up), y up
FRAME = (0, -1, 0, 0, 0, 1, 1, 0, 0)
EXTENT = math.tan(math.radians(10))
QUADRANTS = np.array([[(1, 0, 0), (0, 1, 0)], [(1, 1, 1), (1, 1, 0)]], np.float32)   # red green / white yellow


def _scene(inset=1, width=64, fov=40.0, **world):
    sky = np.broadcast_to(np.array(BLUE, np.float32), (8, 16, 3))
    verts = np.array([[50, 50, 50], [51, 50, 50], [50, 51, 50]], np.float32)   # out of view
    cam = gw.Camera(eye=(0, 0, 0), target=(1, 0, 0), up=(0, 0, 1), fov=fov, width=width, height=width)
    textures = [gw.Texture(gw.Image(sky)), gw.Texture(gw.Image(QUADRANTS), interpolation="closest", extension="extend")]
    return gw.Scene(verts, [[0, 1, 2]], camera=cam, textures=textures,
                    world=gw.World(environment=0, environment_strength=2.0, inset=inset, inset_frame=FRAME,
                                   inset_extent=EXTENT, **world))


def test_rays_in_the_square_see_the_inset_and_the_others_the_environment():
    rgba = gw.render(_scene())[..., :3]
    c = 32                                            # the image's centre: the square's centre (+X)
    half = int(32 * EXTENT / math.tan(math.radians(20)))                 # the square's half-width, pixels
    assert 12 <= half <= 16
    assert np.allclose(rgba[c - 3, c - 3], 2 * QUADRANTS[0, 0])          # top left: red
    assert np.allclose(rgba[c - 3, c + 2], 2 * QUADRANTS[0, 1])          # top right: green
    assert np.allclose(rgba[c + 2, c - 3], 2 * QUADRANTS[1, 0])          # bottom left: white
    assert np.allclose(rgba[c + 2, c + 2], 2 * QUADRANTS[1, 1])          # bottom right: yellow
    for y, x in ((c, c + half + 2), (c, c - half - 3), (c - half - 3, c), (c + half + 2, c), (2, 2)):
        assert np.allclose(rgba[y, x], 2 * np.array(BLUE)), (y, x)
    plain = gw.render(_scene(inset=-1))[..., :3]
    assert np.allclose(plain, 2 * np.array(BLUE))


def test_the_inset_does_not_light_surfaces():
    def render(inset):
        verts = np.array([[2, -1, -1], [2, 1, -1], [2, 1, 1], [2, -1, 1]], np.float32)    # a wall facing -X
        cam = gw.Camera(eye=(0, 0, 0), target=(1, 0, 0), up=(0, 0, 1), fov=30.0, width=8, height=8)
        sky = np.broadcast_to(np.array(BLUE, np.float32), (8, 16, 3))
        textures = [gw.Texture(gw.Image(sky)), gw.Texture(gw.Image(QUADRANTS * 50))]
        scene = gw.Scene(verts, [[0, 1, 2], [0, 2, 3]], camera=cam, textures=textures,
                         materials=[gw.Material(color=(1, 1, 1), kd=1.0)],
                         world=gw.World(environment=0, environment_light=True, inset=inset,
                                        inset_frame=(0, 1, 0, 0, 0, 1, -1, 0, 0), inset_extent=1.0))
        return gw.render(scene, gw.RenderSettings(threads=1))
    lit = render(-1)
    assert lit[..., :3].min() > 0
    assert np.array_equal(render(1), lit)


@pytest.mark.parametrize("world, message", [
    (dict(inset=5), "World.inset = 5 is out of range"),
    (dict(inset=-2), "inset"),
    (dict(inset_extent=float("nan")), "inset_extent"),
    (dict(inset_extent=-1.0), "inset_extent"),
    (dict(inset_frame=(1, 0, 0, 1, 0, 0, 0, 0, 1)), "inset_frame"),
    (dict(inset_frame=(1, 0, 0, 0, float("inf"), 0, 0, 0, 1)), "inset_frame")])
def test_a_bad_inset_is_refused(world, message):
    with pytest.raises(ValueError, match=message):
        sky = np.zeros((4, 8, 3), np.float32)
        verts = np.array([[50, 50, 50], [51, 50, 50], [50, 51, 50]], np.float32)
        gw.Scene(verts, [[0, 1, 2]], textures=[gw.Texture(gw.Image(sky)), gw.Texture(gw.Image(sky))],
                 world=gw.World(**{**dict(environment=0, inset=1, inset_extent=0.1), **world}))


def test_a_procedural_inset_is_refused():
    sky = np.zeros((4, 8, 3), np.float32)
    verts = np.array([[50, 50, 50], [51, 50, 50], [50, 51, 50]], np.float32)
    with pytest.raises(ValueError, match="World.inset = 1 names a procedural texture"):
        gw.Scene(verts, [[0, 1, 2]], textures=[gw.Texture(gw.Image(sky)), gw.Texture(kind="checker")],
                 world=gw.World(environment=0, inset=1, inset_extent=0.1))
