"""Texture.projection (Blender's Image Texture Projection): an image at 3D coordinates is
looked up where Cycles' rules put it, checked against numpy's evaluation of them pixel by
pixel. A float image whose red is its u and green its v (bilinear, extended) shows the
looked-up coordinates themselves: Sphere and Tube take the angles of 2 (p - 0.5) (Cycles'
map_to_sphere and map_to_tube); Box looks up three flat projections along the object's axes
and blends them by the object-space normal (Scene(object_normals=...)) within
projection_blend, each face turned as Cycles turns it. A box projection without the
normals is refused. Blender's side: tests/blender/test_b50."""
import math

import numpy as np
import pytest

import gridwalk as gw

N, R = 48, 256
# a plane through the unit box, tilted: every pixel's point differs in all three coordinates
A, B, C = 0.35, -0.25, 0.55
HALF = 0.7


def _ramp_image():
    """(R, R, 3) float: red the texel column's u, green its row's v (row 0 at the top)."""
    c = (np.arange(R) + 0.5) / R
    u, v = np.meshgrid(c, c[::-1])
    return gw.Image(np.dstack([u, v, np.zeros_like(u)]).astype(np.float32))


def _points():
    """World (and object) points at the pixel centres: the plane z = A x + B y + C seen from above."""
    c = 0.5 + ((np.arange(N) + 0.5) / N * 2 - 1) * HALF
    x, y = np.meshgrid(c, c[::-1])
    return np.stack([x, y, A * x + B * y + C], axis=-1)


def _render(projection, blend=0.0, normal=(0.0, 0.0, 1.0)):
    corners = np.array([[0.5 - 2, 0.5 - 2], [0.5 + 2, 0.5 - 2], [0.5 + 2, 0.5 + 2], [0.5 - 2, 0.5 + 2]])
    verts = np.array([[x, y, A * x + B * y + C] for x, y in corners], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    normals = np.tile(np.asarray(normal, np.float32), (2, 3, 1))
    cam = gw.Camera(eye=(0.5, 0.5, 5), target=(0.5, 0.5, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=2 * HALF, width=N, height=N)
    s = gw.Scene(verts, tris, object_coords=verts[tris], object_normals=normals, camera=cam, images=[_ramp_image()],
                 textures=[gw.Texture(image=0, coordinates="object", extension="extend", projection=projection,
                                      projection_blend=blend)],
                 materials=[gw.Material(kd=0, emission=1.0, color_texture=0)])
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., :2]


def _interior(uv):
    return np.all((uv > 2.0 / R) & (uv < 1 - 2.0 / R), axis=-1)


def test_a_sphere_projection_takes_the_points_longitude_and_latitude():
    q = (_points() - 0.5) * 2
    u = 0.5 - np.arctan2(q[..., 0], q[..., 1]) / (2 * math.pi)
    v = 1 - np.arccos(np.clip(q[..., 2] / np.linalg.norm(q, axis=-1), -1, 1)) / math.pi
    expected = np.stack([u, v], axis=-1)
    inside = _interior(expected)
    assert inside.sum() > N * N // 2
    np.testing.assert_allclose(_render("sphere")[inside], expected[inside], atol=2e-4)


def test_a_tube_projection_takes_the_angle_about_z_and_the_height():
    q = (_points() - 0.5) * 2
    r = np.hypot(q[..., 0], q[..., 1])
    u = (1 - np.arctan2(q[..., 0] / r, q[..., 1] / r) / math.pi) * 0.5
    v = (q[..., 2] + 1) * 0.5
    expected = np.stack([u, v], axis=-1)
    inside = _interior(expected)
    assert inside.sum() > N * N // 2
    np.testing.assert_allclose(_render("tube")[inside], expected[inside], atol=2e-4)


def _box_weights(n, blend):
    """Cycles' svm_node_tex_image_box weights, transcribed."""
    n = np.abs(np.asarray(n, float))
    n = n / n.sum()
    limit = 0.5 * (1 + blend)
    x, y, z = n
    if x > limit * (x + y) and x > limit * (x + z):
        return np.array([1.0, 0, 0])
    if y > limit * (x + y) and y > limit * (y + z):
        return np.array([0, 1.0, 0])
    if z > limit * (x + z) and z > limit * (y + z):
        return np.array([0, 0, 1.0])
    sat = lambda w: min(max(w, 0.0), 1.0)
    if z < (1 - limit) * (y + x):
        wx = sat((x / (x + y) - 0.5 * (1 - blend)) / blend)
        return np.array([wx, 1 - wx, 0])
    if x < (1 - limit) * (y + z):
        wy = sat((y / (y + z) - 0.5 * (1 - blend)) / blend)
        return np.array([0, wy, 1 - wy])
    if y < (1 - limit) * (x + z):
        wx = sat((x / (x + z) - 0.5 * (1 - blend)) / blend)
        return np.array([wx, 0, 1 - wx])
    return ((2 - limit) * n + (limit - 1)) / (2 * limit - 1)


@pytest.mark.parametrize("normal, blend", [((0.2, -0.3, 0.93), 0.0), ((-0.9, 0.2, 0.3), 0.0), ((0.3, 0.95, -0.1), 0.0),
                                           ((0.6, -0.55, 0.58), 0.4), ((0.7, 0.2, -0.68), 0.5), ((0.62, 0.6, 0.5), 0.9)])
def test_a_box_projection_blends_three_flat_lookups_by_the_object_normal(normal, blend):
    n = np.asarray(normal) / np.linalg.norm(normal)
    p = _points()
    w = _box_weights(n, blend)
    faces = [np.stack([1 - p[..., 1] if n[0] < 0 else p[..., 1], p[..., 2]], axis=-1),
             np.stack([1 - p[..., 0] if n[1] > 0 else p[..., 0], p[..., 2]], axis=-1),
             np.stack([1 - p[..., 1] if n[2] > 0 else p[..., 1], p[..., 0]], axis=-1)]
    expected = sum(wk * f for wk, f in zip(w, faces))
    inside = np.all([_interior(f) for f, wk in zip(faces, w) if wk > 0], axis=0)
    assert inside.sum() > N * N // 4
    np.testing.assert_allclose(_render("box", blend, n)[inside], expected[inside], atol=2e-4)


def test_a_box_projection_without_object_normals_is_refused():
    verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32)
    with pytest.raises(ValueError, match=r"object_normals"):
        gw.Scene(verts, np.array([[0, 1, 2]]), object_coords=verts[None], images=[_ramp_image()],
                 textures=[gw.Texture(image=0, coordinates="object", projection="box")],
                 materials=[gw.Material(color_texture=0)])
