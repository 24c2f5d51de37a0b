"""Tangent-space normal maps (Material.normal_texture, Blender's Normal Map
node): the normal pass and the diffuse shading of a square seen from above
follow the normal the map's colour encodes in the frame of the UV tangent,
the bitangent and the shading normal, computed here with numpy; mirrored UVs
mirror the tilt; Strength blends as Cycles' does; a flat map (0.5, 0.5, 1)
changes nothing."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk.validate import camera_rays

N = 8
SUN = np.array([0.6, 0.0, -0.8])   # travelling down and towards +x: lights normals tilted towards -x best


def _square(mirror_u=False, rotate=False):
    """[-1, 1]^2 at z = 0; u along +x (-x when mirror_u), v along +y; rotate: u along +y, v along -x."""
    verts = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    uv = {0: (0, 0), 1: (1, 0), 2: (1, 1), 3: (0, 1)}
    if mirror_u:
        uv = {k: (1 - u, v) for k, (u, v) in uv.items()}
    if rotate:
        uv = {k: (v, 1 - u) for k, (u, v) in uv.items()}   # x -> -v, y -> u
    uvs = np.array([[uv[i] for i in t] for t in tris], np.float32)
    return verts, tris, uvs


def _render(color, strength=1.0, mapped=True, **square):
    verts, tris, uvs = _square(**square)
    image = gw.Image(np.full((2, 2, 3), color, np.float32), "data")
    material = gw.Material(color=(1, 1, 1), kd=1.0, normal_texture=0 if mapped else -1, normal_strength=strength)
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=1.0,
                    width=N, height=N)
    scene = gw.Scene(verts, tris, uvs=uvs, camera=cam, materials=[material], textures=[gw.Texture(image)],
                     lights=[gw.Light(kind="sun", direction=tuple(SUN), color=(1, 1, 1))])
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start()
    rgba = job.wait()
    return rgba, job.normal


def bump_shadowing(smooth, mapped, to_light):
    """Chiang, Li & Burley 2019 (Cycles' bump shadowing): G1 with alpha^2 = tan^2(angle the map turned) / 8."""
    cos_i = float(smooth @ to_light)
    if cos_i <= 0:
        return 0.0
    cos_d = min(abs(float(smooth @ mapped)), 1.0)
    alpha2 = min(max(0.125 * (1 - cos_d ** 2) / cos_d ** 2, 0.0), 1.0)
    return 2 / (1 + np.sqrt(1 + alpha2 * (1 - cos_i ** 2) / cos_i ** 2))


def _unit(v):
    v = np.asarray(v, np.float64)
    return v / np.linalg.norm(v)


def _encode(n):
    return tuple(0.5 * np.asarray(n) + 0.5)


@pytest.mark.parametrize("tangent_space, frame", [
    ((0.5, 0.0, 0.866), dict()),                  # tilted along the tangent: u runs along +x
    ((0.0, 0.6, 0.8), dict()),                    # along the bitangent: v runs along +y
    ((-0.6, 0.0, 0.8), dict(mirror_u=True)),      # u runs along -x: the tilt mirrors
    ((0.6, 0.0, 0.8), dict(rotate=True)),         # u runs along +y
])
def test_normal_pass_and_shading_follow_the_map(tangent_space, frame):
    t = np.array(tangent_space)
    tangent = np.array([0.0, 1.0, 0.0]) if frame.get("rotate") else np.array([-1.0 if frame.get("mirror_u") else 1.0, 0, 0])
    bitangent = np.array([-1.0, 0.0, 0.0]) if frame.get("rotate") else np.array([0.0, 1.0, 0.0])
    expected = _unit(t[0] * tangent + t[1] * bitangent + t[2] * np.array([0, 0, 1.0]))
    rgba, normal = _render(_encode(t), **frame)
    flat, flat_normal = _render(_encode(t), mapped=False, **frame)
    np.testing.assert_allclose(normal.reshape(-1, 3), np.broadcast_to(expected, (N * N, 3)), atol=2e-6)
    np.testing.assert_allclose(flat_normal.reshape(-1, 3), np.broadcast_to([0, 0, 1.0], (N * N, 3)), atol=1e-7)
    # Diffuse under the sun: the pixel scales with max(0, n . -SUN), and the bumps' shadowing.
    ratio = rgba[..., 0] / flat[..., 0]
    up = np.array([0, 0, 1.0])
    want = max(float(expected @ -SUN), 0.0) / float(up @ -SUN) * bump_shadowing(up, expected, -SUN)
    np.testing.assert_allclose(ratio, want, rtol=1e-5)


def _kept_above(n, wo, ng=np.array([0, 0, 1.0])):
    """n, or where it mirrors wo into the surface, the normal between it and ng
    (found by bisection) whose mirror image of wo rises min(0.9 wo.ng, 0.01) above it."""
    h = min(0.9 * float(wo @ ng), 0.01)
    height = lambda m: float((2 * (m @ wo) * m - wo) @ ng)
    if height(n) >= h:
        return n
    lo, hi = 0.0, 1.0                     # the mix towards ng: 0 is n (too low), 1 is ng
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if height(_unit((1 - mid) * n + mid * ng)) >= h else (mid, hi)
    return _unit((1 - hi) * n + hi * ng)


def test_strength_blends_from_the_shading_normal_as_cycles_does():
    t = _unit((0.6, 0.0, 0.8))
    z = np.array([0, 0, 1.0])
    for strength in (0.0, 0.5, 2.0):      # (at 2 the normal leans 63 degrees: kept reflecting above, below)
        _, normal = _render(_encode(t), strength=strength)
        want = _kept_above(_unit(z + (t - z) * strength), z)
        np.testing.assert_allclose(normal[0, 0], want, atol=2e-6)


def test_a_flat_map_changes_nothing():
    rgba, normal = _render((0.5, 0.5, 1.0))
    flat, _ = _render((0.5, 0.5, 1.0), mapped=False)
    np.testing.assert_allclose(normal[..., 2], 1.0, atol=1e-6)
    np.testing.assert_allclose(rgba, flat, rtol=1e-6)


def test_bad_normal_settings_are_refused():
    verts, tris, uvs = _square()
    image = gw.Image(np.full((1, 1, 3), 0.5, np.float32), "data")
    with pytest.raises(ValueError, match="normal_strength"):
        gw.Scene(verts, tris, uvs=uvs, materials=[gw.Material(normal_texture=0, normal_strength=-1.0)],
                 textures=[gw.Texture(image)])
    with pytest.raises(ValueError, match="normal_texture"):
        gw.Scene(verts, tris, uvs=uvs, materials=[gw.Material(normal_texture=3)], textures=[gw.Texture(image)])


def test_tangents_are_averaged_at_shared_corners_and_interpolated():
    """Two triangles of a flat square whose UVs run along different directions
    (the second's u along (2, 1)): at the corners they share (same vertex, same
    UV) the tangent is the angle-weighted mean of the two, elsewhere its
    triangle's own, interpolated over each triangle as Cycles interpolates its
    tangents; so the normal pass has no step along the shared edge."""
    n = 16
    verts = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    uv = {0: (0, 0), 1: (1, 0), 2: (1, 1), 3: (0, 2)}
    uvs = np.array([[uv[i] for i in t] for t in tris], np.float32)
    mapped = _unit((0.5, 0.3, 0.8))
    image = gw.Image(np.full((1, 1, 3), _encode(mapped), np.float32), "data")
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=2.0,
                    width=n, height=n)
    scene = gw.Scene(verts, tris, normals=np.tile([0, 0, 1.0], (4, 1)).astype(np.float32), uvs=uvs, camera=cam,
                     materials=[gw.Material(normal_texture=0)], textures=[gw.Texture(image)])
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start()
    job.wait()
    got = job.normal.reshape(n, n, 3)
    along_a, along_b = np.array([1.0, 0, 0]), _unit((2.0, 1.0, 0))
    shared = _unit(along_a + along_b)                     # both corners' angles are 45 degrees
    corner_t = {0: [shared, along_a, shared], 1: [shared, shared, along_b]}
    c = (np.arange(n) + 0.5) / n * 2 - 1
    for row in range(n):
        for col in range(n):
            x, y = c[col], c[n - 1 - row]
            t = 0 if y < x else 1
            p = verts[tris[t], :2].astype(np.float64)
            b1, b2 = np.linalg.solve(np.column_stack([p[1] - p[0], p[2] - p[0]]), np.array([x, y]) - p[0])
            tangent = _unit((1 - b1 - b2) * corner_t[t][0] + b1 * corner_t[t][1] + b2 * corner_t[t][2])
            bitangent = np.cross([0, 0, 1.0], tangent)
            want = _unit(mapped[0] * tangent + mapped[1] * bitangent + mapped[2] * np.array([0, 0, 1.0]))
            np.testing.assert_allclose(got[row, col], want, atol=1e-5, err_msg=f"pixel {row}, {col}")


@pytest.mark.parametrize("lean", [-30.0, 20.0, 60.0, 85.0])   # (-30: towards the camera)
def test_a_normal_turned_from_the_viewer_is_kept_reflecting_above_the_surface(lean):
    """Seen at a grazing angle, a map leaning away from the camera would mirror
    the view into the surface; as in Cycles, the normal is turned back towards
    the geometric one, in their plane, just far enough that the view's
    reflection rises min(0.9 wo.ng, 0.01) above the surface (and is left alone
    where it already does)."""
    verts, tris, uvs = _square()
    a = np.radians(lean)
    mapped = np.array([-np.sin(a), 0.0, np.cos(a)])            # leaning along -x (u runs along +x)
    image = gw.Image(np.full((2, 2, 3), _encode(mapped), np.float32), "data")
    eye = np.array([3.0, 0.0, 0.4])                              # low over the square, from +x
    cam = gw.Camera(eye=tuple(eye), target=(0, 0, 0), up=(0, 0, 1), fov=2.0, width=4, height=4)
    scene = gw.Scene(verts, tris, uvs=uvs, camera=cam, materials=[gw.Material(normal_texture=0)],
                     textures=[gw.Texture(image)])
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start()
    job.wait()
    depth = job.depth.reshape(-1)
    rays = camera_rays(cam, 16)[1]
    normals = job.normal.reshape(-1, 3)
    assert np.isfinite(depth).all() and (np.linalg.norm(normals, axis=1) > 0.5).all()   # every pixel sees the square
    corrected = 0
    for got, d in zip(normals, rays):
        wo = -_unit(d)
        want = _kept_above(mapped, wo)
        corrected += not np.allclose(want, mapped)
        np.testing.assert_allclose(got, want, atol=3e-5)
    assert corrected == (0 if lean < 0 else 16)


def _two_squares(unshared=False, shift=0.0, turn=0.0):
    """The distorted-UV square of the test above (vertex normals +z), and a second plain one at x + 3,
    that one moved by `shift` along y and turned by `turn` radians about z. unshared: every corner its own vertex."""
    verts = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    uv = {0: (0, 0), 1: (1, 0), 2: (1, 1), 3: (0, 2)}
    uvs = np.array([[uv[i] for i in t] for t in tris], np.float32)
    if unshared:
        verts, tris = verts[tris.reshape(-1)], np.arange(6).reshape(2, 3)
    c, s = np.cos(turn), np.sin(turn)
    second = verts @ np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]], np.float32) + np.array([3, shift, 0], np.float32)
    all_verts = np.concatenate([verts, second]).astype(np.float32)
    all_tris = np.concatenate([tris, tris + len(verts)])
    normals = np.tile([0, 0, 1.0], (len(all_verts), 1)).astype(np.float32)
    return all_verts, all_tris, normals, np.concatenate([uvs, uvs])


def _normal_pass(verts, tris, normals, uvs, scene=None):
    image = gw.Image(np.full((1, 1, 3), _encode(_unit((0.5, 0.3, 0.8))), np.float32), "data")
    cam = gw.Camera(eye=(1.5, 0, 8), target=(1.5, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=3.0,
                    width=32, height=16)
    scene = scene or gw.Scene(verts, tris, normals=normals, uvs=uvs, camera=cam,
                              materials=[gw.Material(normal_texture=0)], textures=[gw.Texture(image)])
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start()
    job.wait()
    return job.normal.copy(), scene


def test_corners_are_grouped_by_position_normal_and_uv_not_by_vertex_index():
    """Exporters give every corner its own vertex where normals are per corner (custom normals, sharp
    edges): the tangents are those of shared vertices (a 16.9 degree step along the diagonal otherwise)."""
    shared, _ = _normal_pass(*_two_squares())
    unshared, _ = _normal_pass(*_two_squares(unshared=True))
    assert np.abs(shared).sum() > 0
    np.testing.assert_allclose(unshared, shared, atol=1e-6)


def test_a_moved_instance_gets_the_tangents_of_a_scene_built_where_it_went():
    """Scene.moved recomputes the moved instance's tangents (only its own: instances share no vertex)."""
    verts, tris, normals, uvs = _two_squares()
    _, scene = _normal_pass(verts, tris, normals, uvs)
    turn = np.radians(90)
    c, s = np.cos(turn), np.sin(turn)
    matrix = np.array([[c, -s, 0, 3], [s, c, 0, 0.5], [0, 0, 1, 0], [0, 0, 0, 1]])
    move = gw.InstanceMove(4, 2, 2, verts[:4].copy(), matrix, normals=normals[:4].copy())
    moved, _ = _normal_pass(None, None, None, None, scene=scene.moved([move]))
    fresh, _ = _normal_pass(*_two_squares(shift=0.5, turn=turn))
    assert np.abs(fresh).sum() > 0
    np.testing.assert_allclose(moved, fresh, atol=1e-5)
