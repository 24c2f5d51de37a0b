"""A scene scaled by any power of ten within the core's range renders the same
image: hits, normals, light directions and shadows are scale-free.

In float, a triangle's normal (the squared length of its edges' cross product)
overflowed for edges from about 4e9 and underflowed below about 1e-10, and a
light's squared distance overflowed from about 1.8e19 and underflowed below
about 1e-19: such scenes rendered with normals of 0 or no light at all."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import icosphere

FLOOR_V = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float64)
FLOOR_F = np.array([[0, 1, 2], [0, 2, 3]], np.int32)


def render(scale: float, accel: str) -> np.ndarray:
    """A floor, an analytic sphere and a tessellated one, a point light and a
    rectangular area light (neither falls off with distance), all times `scale`."""
    ball_v, ball_f = icosphere(2, radius=1.0, center=(-2.5, 1.0, 1.0), dtype=np.float64)
    vertices = (np.concatenate([FLOOR_V, ball_v]) * scale).astype(np.float32)
    triangles = np.concatenate([FLOOR_F, ball_f + len(FLOOR_V)]).astype(np.int32)
    floor = gw.Material(color=(1.0, 0.5, 0.25), kd=0.5, ks=0.3, shininess=20.0, mirror=0.25)
    ball = gw.Material(color=(0.3, 0.6, 0.9), kd=0.8, ks=0.2, shininess=40.0)
    materials = np.zeros(len(triangles), np.int32)
    materials[len(FLOOR_F):] = 1
    camera = gw.Camera(eye=(0, -6 * scale, 8 * scale), target=(0, 0, 0), up=(0, 0, 1), fov=50,
                       width=40, height=30)
    lights = [gw.Light(position=(3 * scale, 0, 5 * scale), color=(1.5, 1.5, 1.5)),
              gw.Light(kind="rect", position=(-2 * scale, -2 * scale, 6 * scale), size=(2 * scale, 2 * scale),
                       direction=(0, 0, -1), color=(1.0, 0.9, 0.8))]
    scene = gw.Scene(vertices=vertices, triangles=triangles, triangle_materials=materials,
                     sphere_centers=[[1.5 * scale, 0.5 * scale, 1.2 * scale]], sphere_radii=[1.2 * scale],
                     sphere_materials=[1], materials=[floor, ball], lights=lights, camera=camera,
                     background=(0.2, 0.3, 0.4))
    return gw.render(scene, gw.RenderSettings(threads=2, accel=accel, shadow_samples=4))


@pytest.fixture(scope="module")
def unit_images():
    return {accel: render(1.0, accel) for accel in ("adaptive", "grid")}


@pytest.mark.parametrize("scale", [1e-33, 1e-20, 1e-12, 1e10, 1e20, 1e25])
@pytest.mark.parametrize("accel", ["adaptive", "grid"])
def test_a_scaled_scene_renders_the_same_image(unit_images, scale, accel):
    reference = unit_images[accel]
    lit = reference[..., :3].max(axis=-1) > 0.5           # the lights reach most of the floor and both balls
    assert lit.mean() > 0.5
    image = render(scale, accel)
    assert np.isfinite(image).all()
    np.testing.assert_allclose(image, reference, atol=2e-3)


def falloff_image(scale: float) -> np.ndarray:
    """A floor lit by one inverse-square point light of intensity 30 * scale^2
    (Blender's lights fall off so): the same image at every scale."""
    vertices = (FLOOR_V * scale).astype(np.float32)
    camera = gw.Camera(eye=(0, -6 * scale, 8 * scale), target=(0, 0, 0), up=(0, 0, 1), fov=50,
                       width=24, height=18)
    power = np.float32(30.0 * scale * scale)
    light = gw.Light(position=(1 * scale, 0, 4 * scale), color=(power,) * 3, inverse_square=True)
    scene = gw.Scene(vertices=vertices, triangles=FLOOR_F, triangle_materials=np.zeros(2, np.int32),
                     materials=[gw.Material(color=(0.8, 0.8, 0.8), kd=1.0, ks=0.0)], lights=[light],
                     camera=camera, background=(0.0, 0.0, 0.0))
    return gw.render(scene, gw.RenderSettings(threads=2))


@pytest.mark.parametrize("scale", [1e-21, 1e-12, 1e15])
def test_inverse_square_falloff_is_scale_free_below_the_floats_square(scale):
    """At 1e-21 the light's squared distance (about 2e-41) is below float's
    smallest normal and its inverse beyond float's range: it is divided in
    double. (The intensity, 3e-41, is a subnormal float good to about 1e-4.)"""
    reference = falloff_image(1.0)
    assert reference[..., 0].max() > 0.5 and (reference[..., 0] > 0.05).mean() > 0.5
    np.testing.assert_allclose(falloff_image(scale), reference, rtol=2e-3, atol=1e-4)
