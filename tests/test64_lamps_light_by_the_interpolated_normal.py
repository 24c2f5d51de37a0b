"""A lamp lights a smooth surface by its interpolated normal even where that normal turns away from the viewer,
as Cycles' diffuse does. The renderer used to fall back to the geometric normal there, which lit points whose
interpolated normal faces away from the light as well: a Weighted Normal modifier's rim showed lit slivers
where Cycles is black."""
import numpy as np
import pytest

import gridwalk as gw


def floor_pixel(normal):
    """The centre pixel of a white matte floor (winding normal +z) seen from above at 45 degrees, its three
    vertex normals all `normal`, under a sun 37 degrees off the zenith on the camera's side."""
    cam = gw.Camera(eye=(0, -3, 3), target=(0, 0, 0), up=(0, 0, 1), fov=20, width=8, height=8)
    sun = gw.Light(kind="sun", direction=(0, 0.6, -0.8), color=(1, 1, 1))
    scene = gw.Scene(vertices=[[-5, -5, 0], [5, -5, 0], [0, 5, 0]], triangles=[[0, 1, 2]],
                     normals=np.tile(np.asarray(normal, float) / np.linalg.norm(normal), (3, 1)), camera=cam,
                     lights=[sun], materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)])
    return gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()[4, 4]


def test_a_normal_turned_away_from_viewer_and_light_leaves_the_point_unlit():
    # (0, 1, 0.3): away from the viewer (0, -0.71, 0.71) and from the sun (0, -0.6, 0.8)
    assert list(floor_pixel((0, 1, 0.3))[:3]) == [0.0, 0.0, 0.0]


@pytest.mark.parametrize("normal, lit", [((0, 0, 1), 0.8), ((0, -0.6, 0.8), 1.0)])
def test_normals_facing_the_viewer_are_lit_by_lamberts_law(normal, lit):
    np.testing.assert_allclose(floor_pixel(normal)[:3], [lit] * 3, rtol=1e-5)
