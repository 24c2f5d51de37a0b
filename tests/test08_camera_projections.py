"""Every camera projection and option, checked against analytic expectations
(no Blender): the core's own rays (Camera.rays) and renders of spheres whose
silhouettes are known in closed form.

Perspective, orthographic and equirectangular projections; lens shift; pixel
aspect; near and far clipping (hither, yon); mirroring; a camera 1e7 from the
origin; and the refusal of bad values, naming the field.
"""
import math

import numpy as np
import pytest

import gridwalk as gw

CENTER = dict(aa="center", threads=2)


def sphere_scene(camera, center=(0.0, 0.0, 0.0), radius=1.0):
    return gw.Scene(sphere_centers=[center], sphere_radii=[radius], sphere_materials=[0],
                    lights=[gw.Light(position=(0, -10, 10))], camera=camera)


def alpha(camera, **kw):
    job = gw.RenderJob(sphere_scene(camera, **kw), gw.RenderSettings(**CENTER)).start()
    return job.wait()[..., 3], job


def pixel_centres(w, h):
    gx, gy = np.meshgrid(np.arange(w) + 0.5, np.arange(h) + 0.5)
    return gx.reshape(-1), gy.reshape(-1)


def sphere_hit(o, d, center, radius):
    """Whether each ray (float64) meets the sphere at t > 0."""
    oc = o - np.asarray(center, np.float64)
    b = np.sum(oc * d, axis=1)
    c = np.sum(oc * oc, axis=1) - radius * radius
    disc = b * b - c
    return (disc >= 0) & (-b + np.sqrt(np.maximum(disc, 0)) > 0)


def test_perspective_ray_through_a_pixel_follows_the_pinhole_formula():
    cam = gw.Camera(eye=(0, -10, 0), target=(0, 0, 0), fov=60, width=40, height=20, shift=(0.1, -0.05))
    o, d, tmin, tmax = cam.rays([30.5], [4.5])
    half_h = math.tan(math.radians(30))
    x = (2 * 30.5 / 40 - 1) * half_h * 2 + 0.1 * 2 * half_h * 2     # shift in units of the larger side
    y = (1 - 2 * 4.5 / 20) * half_h - 0.05 * 2 * half_h * 2
    expected = np.array([x, 1.0, y]) / np.linalg.norm([x, 1.0, y])
    np.testing.assert_allclose(d[0], expected, atol=1e-6)
    np.testing.assert_array_equal(o[0], [0, -10, 0])
    assert tmin[0] == 0 and tmax[0] == np.inf


def test_orthographic_rays_are_parallel_and_spaced_by_the_view_height():
    cam = gw.Camera(projection="orthographic", ortho_height=4.0, eye=(1, -10, 2), target=(1, 0, 2),
                    width=8, height=4, shift=(0.25, 0.0))
    px, py = pixel_centres(8, 4)
    o, d, _, _ = cam.rays(px, py)
    np.testing.assert_allclose(d, np.tile([0, 1, 0], (len(d), 1)), atol=0)
    np.testing.assert_allclose(o[:, 1], -10)                     # all on the plane through the eye
    pixel = 4.0 / 4                                              # ortho_height / height
    np.testing.assert_allclose(np.diff(np.unique(o[:, 0])), pixel, rtol=1e-6)
    np.testing.assert_allclose(np.diff(np.unique(o[:, 2])), pixel, rtol=1e-6)
    # the view is 8 x 4 units, centred on the eye, moved by 0.25 of its larger side (8)
    assert o[:, 0].min() == pytest.approx(1 - 4 + 0.5 + 2.0) and o[:, 0].max() == pytest.approx(1 + 4 - 0.5 + 2.0)
    assert o[:, 2].min() == pytest.approx(2 - 2 + 0.5) and o[:, 2].max() == pytest.approx(2 + 2 - 0.5)


def test_orthographic_render_shows_a_sphere_at_its_true_size_at_any_distance():
    areas = []
    for distance in (5.0, 50.0):
        cam = gw.Camera(projection="orthographic", ortho_height=4.0, eye=(0, -distance, 0), width=64, height=64)
        a, _ = alpha(cam)
        areas.append(a)
    np.testing.assert_array_equal(areas[0], areas[1])            # parallel rays: no perspective shrink
    pixel_area = (4.0 / 64) ** 2
    assert areas[0].sum() * pixel_area == pytest.approx(math.pi, rel=0.02)


def test_equirectangular_directions_cover_the_longitude_and_latitude_ranges():
    cam = gw.Camera(projection="equirectangular", eye=(0, 0, 0), target=(0, 1, 0), width=8, height=4,
                    longitude=(-math.pi, math.pi), latitude=(-math.pi / 2, math.pi / 2))
    # image centre: the view axis; a quarter from the left: longitude -90 deg (left);
    # three quarters: +90 deg (right); the top edge: straight up
    _, d, _, _ = cam.rays([4, 2, 6, 4, 4], [2, 2, 2, 0, 4])
    np.testing.assert_allclose(d, [[0, 1, 0], [-1, 0, 0], [1, 0, 0], [0, 0, 1], [0, 0, -1]], atol=1e-6)


def test_equirectangular_render_matches_the_analytic_silhouette_and_radial_depth():
    lon, lat = (-1.0, 1.5), (-0.5, 0.7)
    cam = gw.Camera(projection="equirectangular", eye=(0, 0, 0), target=(0, 1, 0), width=96, height=48,
                    longitude=lon, latitude=lat)
    center, radius = (2.0, 4.0, 1.0), 1.5                          # to the right of and above the axis
    a, job = alpha(cam, center=center, radius=radius)
    px, py = pixel_centres(96, 48)
    lo = lon[0] + px / 96 * (lon[1] - lon[0])
    la = lat[1] - py / 48 * (lat[1] - lat[0])
    d = np.stack([np.cos(la) * np.sin(lo), np.cos(la) * np.cos(lo), np.sin(la)], axis=1)   # right, forward, up
    expected = sphere_hit(np.zeros_like(d), d, center, radius).reshape(48, 96)
    assert expected.sum() > 100
    assert np.mean((a > 0.5) != expected) < 0.002
    # the Depth pass of a panorama is the distance from the eye
    hit = expected & (a > 0.5)
    depth = job.depth[hit]
    dist_to_center = np.linalg.norm(center)
    assert np.all((depth >= dist_to_center - radius - 1e-3) & (depth <= dist_to_center + 1e-3))


def test_pixel_aspect_two_shows_twice_the_width_per_pixel():
    square = gw.Camera(fov=40, width=64, height=64)
    wide = gw.Camera(fov=40, width=32, height=64, pixel_aspect=2.0)
    a_square, _ = alpha(square, radius=2.5)
    a_wide, _ = alpha(wide, radius=2.5)
    # a wide pixel spans two square ones: its centre is their shared edge
    i = np.arange(32)
    _, d_wide, _, _ = wide.rays(i + 0.5, np.full(32, 10.5))
    _, d_square, _, _ = square.rays(2.0 * i + 1.0, np.full(32, 10.5))
    np.testing.assert_allclose(d_wide, d_square, atol=2e-7)
    assert a_wide.sum() * 2 == pytest.approx(a_square.sum(), rel=0.01)
    rows, cols = np.nonzero(a_wide > 0.5)
    assert (rows.max() - rows.min() + 1) == pytest.approx(2 * (cols.max() - cols.min() + 1), abs=3)   # tall in pixels


def test_far_clip_removes_what_lies_beyond_and_near_clip_what_lies_before():
    base = dict(eye=(0, -10, 0), fov=40, width=32, height=32)
    full, _ = alpha(gw.Camera(**base))
    assert full.sum() > 20
    assert alpha(gw.Camera(**base, yon=5.0))[0].sum() == 0          # the sphere is 9 to 11 away
    assert np.array_equal(alpha(gw.Camera(**base, yon=12.0))[0], full)
    assert alpha(gw.Camera(**base, hither=12.0))[0].sum() == 0
    ortho = dict(base, projection="orthographic", ortho_height=4.0)
    assert alpha(gw.Camera(**ortho, yon=8.0))[0].sum() == 0
    assert alpha(gw.Camera(**ortho, yon=9.5))[0].sum() > 20          # clipped sphere: its front cap shows
    _, _, _, tmax = gw.Camera(**base, yon=5.0).rays([0.5], [0.5])
    _, d, _, _ = gw.Camera(**base).rays([0.5], [0.5])
    assert tmax[0] == pytest.approx(5.0 / d[0, 1], rel=1e-6)       # a plane across the view axis


@pytest.mark.parametrize("projection", ["perspective", "orthographic", "equirectangular"])
def test_mirror_flips_the_image_left_to_right(projection):
    kw = dict(projection=projection, eye=(0, -6, 0), width=48, height=32, ortho_height=4.0,
              longitude=(-1.0, 1.0), latitude=(-0.6, 0.6))
    center = (1.2, 0.0, 0.4)                                       # off-centre to the right
    plain, _ = alpha(gw.Camera(**kw), center=center)
    mirrored, _ = alpha(gw.Camera(**kw, mirror=True), center=center)
    assert plain[:, 24:].sum() > 10 * plain[:, :24].sum()          # right half
    assert np.mean((mirrored > 0.5) != (plain[:, ::-1] > 0.5)) < 0.005


def test_camera_far_from_the_origin_keeps_its_direction():
    """1e7 from the origin, float32 spacing is 1: target = eye + direction in
    float32 would point the camera the wrong way. The basis is kept in double."""
    offset = np.array([1e7, 1e7, 0.0])
    direction = np.array([12.0, 15.0, 16.0]) / 25.0
    images = []
    for eye in (np.zeros(3), offset):
        center = tuple(eye + 25 * direction)                       # whole numbers: exact in float32
        cam = gw.Camera(eye=tuple(eye), target=tuple(eye + direction), fov=30, width=101, height=101)
        a, _ = alpha(cam, center=center, radius=2.0)
        rows, cols = np.nonzero(a > 0.5)
        assert abs(rows.mean() - 50) < 1.0 and abs(cols.mean() - 50) < 1.0
        images.append(a)
    assert np.mean((images[0] > 0.5) != (images[1] > 0.5)) < 0.01


@pytest.mark.parametrize("changes, message", [
    (dict(projection="fisheye"), "Camera.projection must be one of"),
    (dict(projection="fisheye_equisolid", fisheye_lens=0.0), "Camera.fisheye_lens must be > 0 mm"),
    (dict(projection="fisheye_equidistant", fisheye_fov=float("inf")), "Camera.fisheye_fov must be finite"),
    (dict(projection="fisheye_polynomial", polynomial=(0, 1, 0, float("nan"), 0)), "Camera.polynomial must be finite"),
    (dict(projection="fisheye_polynomial", sensor=(36, -1)), "Camera.sensor sizes must be > 0 mm"),
    (dict(projection="central_cylindrical", cylinder_height=(2, 2)), "Camera.cylinder_height must span a range"),
    (dict(projection="mirror_ball", window=(0, 1, 0.5, 0.5)), "Camera.window must span a range"),
    (dict(projection="central_cylindrical", longitude=(-3e38, 3e38)), "Camera.longitude spans more than float32"),
    (dict(projection="orthographic", ortho_height=0.0), "Camera.ortho_height must be > 0"),
    (dict(projection="orthographic", ortho_height=1e-3, eye=(1e7, 0, 0), target=(1e7, 1, 0)),
     "Camera.ortho_height .* too small for float32 ray origins"),
    (dict(projection="equirectangular", longitude=(1.0, 1.0)), "Camera.longitude must span a range"),
    (dict(projection="equirectangular", latitude=(0.0, float("nan"))), "Camera.latitude must be finite"),
    (dict(pixel_aspect=0.0), r"Camera.pixel_aspect must be in \[1e-4, 1e4\]"),
    (dict(hither=2.0, yon=1.0), r"Camera.yon must be greater than Camera.hither \(2\)"),
    (dict(yon=float("nan")), "Camera.yon must be greater"),
    (dict(eye=(1e39, 0, 0)), "Camera.eye lies beyond the float32 range"),
    (dict(eye=(1e7, 0, 0), target=(1e7 + 1e-20, 0, 0)), "Camera.target coincides with Camera.eye"),
])
def test_bad_camera_values_are_refused_naming_the_field(changes, message):
    with pytest.raises(ValueError, match=message):
        gw.Camera(**changes).validate()


def test_a_job_renders_another_view_of_the_scene_on_the_same_grid():
    """The viewport's path: one scene and grid, a RenderJob per view. The
    image equals the render of a scene built with that camera."""
    view = gw.Camera(projection="orthographic", ortho_height=3.0, eye=(2, -8, 1), target=(0, 0, 0),
                     width=40, height=30)
    scene = sphere_scene(gw.Camera(width=8, height=8))
    settings = gw.RenderSettings(aa="jittered", aa_samples=2, threads=2)
    job = gw.RenderJob(scene, settings, camera=view)
    assert job.accel is gw.RenderJob(scene, settings).accel              # built once, shared
    image = job.start().wait()
    assert image.shape == (30, 40, 4) and image[..., 3].sum() > 50
    np.testing.assert_array_equal(image, gw.render(sphere_scene(view), settings))
    with pytest.raises(ValueError, match="Camera.ortho_height must be > 0"):
        gw.RenderJob(scene, settings, camera=gw.Camera(projection="orthographic", ortho_height=0.0))
