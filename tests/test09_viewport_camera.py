"""The viewport's camera from a view and projection matrix
(blender_addon/export/viewport_camera.py; numpy only, no Blender): OpenGL
frustums built here from their planes give the rays the planes say; a
camera frame inside a region is found where it is; a panorama stretched over
the region keeps the frame's angles at the frame's edges."""
import dataclasses
import math

import numpy as np
import pytest

import gridwalk as gw
from blender_addon.export.viewport_camera import frame_in_region, stretch_panorama, view_camera


def frustum(left, right, bottom, top, near, far):
    return np.array([[2 * near / (right - left), 0, (right + left) / (right - left), 0],
                     [0, 2 * near / (top - bottom), (top + bottom) / (top - bottom), 0],
                     [0, 0, -(far + near) / (far - near), -2 * far * near / (far - near)],
                     [0, 0, -1, 0]])


def ortho(left, right, bottom, top, near, far):
    return np.array([[2 / (right - left), 0, 0, -(right + left) / (right - left)],
                     [0, 2 / (top - bottom), 0, -(top + bottom) / (top - bottom)],
                     [0, 0, -2 / (far - near), -(far + near) / (far - near)],
                     [0, 0, 0, 1]])


def look_from(eye):
    """World -> view for a view at `eye` looking along +y with +z up (view -z = world +y)."""
    to_world = np.eye(4)
    to_world[:3, 0], to_world[:3, 1], to_world[:3, 2] = (1, 0, 0), (0, 0, 1), (0, -1, 0)
    to_world[:3, 3] = eye
    return np.linalg.inv(to_world)


def test_perspective_view_gives_the_frustums_rays_and_clipping():
    # an off-centre frustum at near = 0.5: at distance 1 it spans x in [-0.6, 1.0], y in [-0.25, 0.45]
    p = frustum(-0.3, 0.5, -0.125, 0.225, 0.5, 40.0)
    cam = view_camera(look_from((1, -5, 2)), p, 160, 70)
    o, d, tmin, tmax = cam.rays([0, 160, 0], [0, 0, 70])         # top-left, top-right, bottom-left corners
    expected = [(-0.6, 1, 0.45), (1.0, 1, 0.45), (-0.6, 1, -0.25)]
    np.testing.assert_allclose(d, [np.array(e) / np.linalg.norm(e) for e in expected], atol=1e-5)
    np.testing.assert_allclose(o, np.tile([1, -5, 2], (3, 1)))
    np.testing.assert_allclose(tmin * d[:, 1], 0.5, rtol=1e-4)   # near and far: planes across the view axis
    np.testing.assert_allclose(tmax * d[:, 1], 40.0, rtol=1e-4)
    exact = view_camera(look_from((1, -5, 2)), p.astype(np.float32), 160, 70, clip=(0.5, 40.0))
    assert (exact.hither, exact.yon) == (0.5, 40.0)
    assert cam.origin_ahead == 0.0 and exact.origin_ahead == 0.0   # (the eye is the view point)


def test_orthographic_view_moves_the_eye_to_the_near_plane():
    p = ortho(-4, 4, -1, 2, -10, 10)               # Blender's ortho views put the near plane behind the eye
    cam = view_camera(look_from((0, 0, 0)), p, 80, 30)
    assert cam.projection == "orthographic"
    o, d, tmin, tmax = cam.rays([0, 80], [0, 30])
    np.testing.assert_allclose(d, [[0, 1, 0], [0, 1, 0]], atol=1e-7)
    np.testing.assert_allclose(o, [[-4, -10, 2], [4, -10, -1]], atol=1e-5)
    np.testing.assert_allclose(tmax, 20.0, rtol=1e-6)
    assert cam.pixel_aspect == pytest.approx(1.0)
    # Camera texture coordinates stay measured from the view point, as Cycles measures them
    ahead = np.asarray(cam.eye) + np.subtract(cam.target, cam.eye) * cam.origin_ahead
    np.testing.assert_allclose(ahead, [0, 0, 0], atol=1e-6)
    assert cam.origin_ahead == pytest.approx(10.0)


def test_non_square_pixels_follow_from_the_frustum():
    cam = view_camera(look_from((0, 0, 0)), frustum(-1, 1, -1, 1, 1, 10), 100, 50)    # square view, 2:1 image
    assert cam.pixel_aspect == pytest.approx(0.5)
    _, d, _, _ = cam.rays([100], [25])
    np.testing.assert_allclose(d[0], np.array([1, 1, 0]) / math.sqrt(2), atol=1e-6)


def test_camera_frame_is_found_in_the_region():
    camera_p = frustum(-0.4, 0.4, -0.3, 0.3, 1, 100)         # the camera's own projection
    region_p = frustum(-0.8, 0.8, -0.45, 0.45, 1, 100)        # the region sees twice as wide, 1.5 as high
    x0, y0, x1, y1 = frame_in_region(camera_p, region_p, 200, 90)
    assert (x0, x1) == pytest.approx((50, 150)) and (y0, y1) == pytest.approx((15, 75))
    x0, y0, x1, y1 = frame_in_region(ortho(-1, 1, -1, 1, 0, 9), ortho(-2, 2, -1, 3, 0, 9), 40, 40)
    assert (x0, x1) == pytest.approx((10, 30)) and (y0, y1) == pytest.approx((0, 20))


@pytest.mark.parametrize("projection", ["equirectangular", "fisheye_equisolid", "mirror_ball",
                                        "central_cylindrical"])
def test_panorama_stretched_over_the_region_keeps_the_frame_angles(projection):
    pano = gw.Camera(projection=projection, longitude=(-1.0, 2.0), latitude=(-0.5, 0.7), width=100,
                     height=50, shift=(0.05, -0.1), fisheye_lens=9.0, sensor=(30.0, 15.0),
                     cylinder_height=(-0.4, 0.9))
    frame = (50, 15, 150, 75)                                  # region pixels, from the bottom left
    fields = stretch_panorama(pano, frame, 200, 90)
    cam = gw.Camera(eye=(0, 0, 0), target=(0, 1, 0), width=200, height=90, **fields)
    ref = dataclasses.replace(pano, eye=(0, 0, 0), target=(0, 1, 0))
    # points of the frame (rows from the top: the region's 90 - 75 = 15 and 90 - 15 = 75)
    _, d_region, _, _ = cam.rays([50, 150, 50, 100, 80], [15, 15, 75, 45, 30])
    _, d_frame, _, _ = ref.rays([0, 100, 0, 50, 30], [0, 0, 50, 25, 12.5])
    np.testing.assert_allclose(d_region, d_frame, atol=1e-5)