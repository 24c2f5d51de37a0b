"""The camera's aperture shape (no Blender): the core's lens points (the ray
origins Camera.rays gives for lens samples over [0, 1)^2) fill a disc, or the
regular polygon of `blades` corners on the aperture's radius, turned by
blade_rotation (an edge faces the image's right at 0, as in Cycles' polygon
sampler), and aperture_ratio narrows it across; a render of a point-like light
far out of focus shows that shape; bad values are refused naming the field.
"""
import math

import numpy as np
import pytest

import gridwalk as gw

RADIUS = 0.5


def lens_points(**kw):
    """(x, y) of the lens points in the camera's right / up axes (the camera looks along +y, up +z)."""
    cam = gw.Camera(eye=(0, 0, 0), target=(0, 1, 0), width=16, height=16, aperture=RADIUS, focus_distance=4.0, **kw)
    n = 64
    lu, lv = np.meshgrid(np.linspace(0, 1 - 1e-6, n), np.linspace(0, 1 - 1e-6, n))   # (the edges included)
    points = [cam.rays([8.0], [8.0], lens=(u, v))[0][0] for u, v in zip(lu.ravel(), lv.ravel())]
    return np.array(points)[:, [0, 2]].astype(np.float64)


def inside_polygon(xy, blades, rotation, ratio=1.0, radius=RADIUS):
    """Whether each point lies in the polygon (corners at `radius`, at rotation +- pi / blades, ...)."""
    x, y = xy[:, 0] * ratio, xy[:, 1]
    apothem = radius * math.cos(math.pi / blades)
    ok = np.ones(len(xy), bool)
    for k in range(blades):
        a = rotation + 2 * math.pi * k / blades           # the middle of edge k
        ok &= x * math.cos(a) + y * math.sin(a) <= apothem * (1 + 1e-5)
    return ok


def polygon_area(blades):
    return 0.5 * blades * RADIUS ** 2 * math.sin(2 * math.pi / blades)


def hull_area(xy):
    """The area of the points' convex hull (Andrew's monotone chain)."""
    pts = sorted(set(map(tuple, np.round(xy, 9))))
    cross = lambda o, a, b: (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    def chain(points):
        out = []
        for p in points:
            while len(out) >= 2 and cross(out[-2], out[-1], p) <= 0:
                out.pop()
            out.append(p)
        return out[:-1]
    hull = np.array(chain(pts) + chain(pts[::-1]))
    x, y = hull[:, 0], hull[:, 1]
    return 0.5 * abs(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def test_a_round_aperture_fills_the_disc():
    xy = lens_points()
    r = np.hypot(xy[:, 0], xy[:, 1])
    assert r.max() <= RADIUS * (1 + 1e-5) and r.max() > 0.97 * RADIUS
    assert hull_area(xy) == pytest.approx(math.pi * RADIUS ** 2, rel=0.03)


@pytest.mark.parametrize("blades, rotation, ratio", [(6, 0.0, 1.0), (5, 0.3, 1.0), (3, -1.1, 1.0), (6, 0.3, 1.5),
                                                     (8, 2.0, 0.5)])
def test_blades_turn_and_ratio_shape_the_lens_as_cycles_polygon(blades, rotation, ratio):
    xy = lens_points(blades=blades, blade_rotation=rotation, aperture_ratio=ratio)
    assert inside_polygon(xy, blades, rotation, ratio).all()
    # ... and fill it (its hull's area is the polygon's, narrowed by the ratio)
    assert hull_area(xy) == pytest.approx(polygon_area(blades) / ratio, rel=0.03)
    # the corners lie on the radius, half a sector either side of each edge's middle
    corner = rotation + math.pi / blades
    reach = (xy[:, 0] * ratio) * math.cos(corner) + xy[:, 1] * math.sin(corner)
    assert reach.max() == pytest.approx(RADIUS, rel=0.03)


def test_fewer_than_three_blades_is_round():
    np.testing.assert_array_equal(lens_points(blades=2), lens_points(blades=0))


def test_a_far_point_light_out_of_focus_images_as_the_aperture():
    """A small glowing sphere far behind the focus plane: its image is the aperture, upright (a
    pentagon, which a half turn would not map onto itself), turned 0.3 radians, narrowed across by 1.5."""
    blades, rotation, ratio = 5, 0.3, 1.5
    w = 96
    cam = gw.Camera(eye=(0, 0, 0), target=(0, 1, 0), fov=40, width=w, height=w, aperture=0.2, focus_distance=1.0,
                    blades=blades, blade_rotation=rotation, aperture_ratio=ratio)
    glow = gw.Material(color=(0, 0, 0), kd=0, ks=0, emission_color=(1, 1, 1))
    scene = gw.Scene(sphere_centers=[(0, 20, 0)], sphere_radii=[0.3], sphere_materials=[0], materials=[glow],
                     camera=cam)
    image = gw.render(scene, gw.RenderSettings(aa="jittered", aa_samples=4, dof_samples=64, threads=2))[..., 0]
    lit = image > 0.25 * np.percentile(image, 95)
    # a ray from lens point L through the focus plane (y = 1) at F reaches y = 20 at 20 F - 19 L:
    # it meets the sphere's centre where F = (19 / 20) L, the aperture scaled, upright
    half = math.tan(math.radians(20))
    px = ((np.arange(w) + 0.5) / w * 2 - 1) * half                   # x on the focus plane
    X, Z = np.meshgrid(px, -px)                                     # (rows from the top)
    scale = 19.0 / 20.0
    expected = inside_polygon(np.stack([X.ravel(), Z.ravel()], 1) / scale, blades, rotation, ratio,
                              radius=0.2).reshape(w, w)
    assert 0.1 < expected.mean() < 0.6
    overlap = (lit & expected).sum() / (lit | expected).sum()
    assert overlap > 0.85, overlap
