"""Texture coordinates that depend on the view (Texture.coordinates "normal", "camera",
"window", "reflection": Blender's Texture Coordinate node's Normal, Camera, Window and
Reflection outputs; "geometry_normal", "true_normal", "incoming": its Geometry node's
Normal, True Normal and Incoming) are computed at each hit as Cycles computes them,
checked against numpy's evaluation of its rules: the image position of every pixel
centre under a perspective camera with lens shift and under an orthographic one, each
hit point in camera space, the view mirrored about a sphere's normal, the object-space
normal interpolated, normalised and turned over on a back face, the world's shading and
geometric normals turned over likewise, and the direction back along each ray. A bump map at Camera
coordinates bends the normal as the same map at Position coordinates does through the
camera's matrix; at Normal, Reflection or Window coordinates it bends nothing. What a
scene lacks for them is refused, naming the array. Blender's side: tests/blender/test_b47."""
import numpy as np
import pytest

import gridwalk as gw

W, H = 40, 30
VERTS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])


def _pick(axis, scale=1.0, offset=0.0):
    """A vector_transform whose x is `scale` times the coordinates' component `axis` plus
    `offset`: a linear Gradient then shows that value (kept within [0, 1] by the caller)."""
    m = [0.0] * 12
    m[axis], m[3] = scale, offset
    return tuple(m)


def _emitting(texture, verts=VERTS * 100, tris=TRIS, camera=None, **scene):
    """The linear Gradient `texture` as the emission of the triangles (or of what `scene` gives)."""
    s = gw.Scene(verts, tris, camera=camera, materials=[gw.Material(kd=0, emission=1.0, color_texture=0)],
                 textures=[texture], **scene)
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()


def _gradient(coordinates, transform):
    return gw.Texture(kind="gradient", coordinates=coordinates, vector_transform=transform)


def _camera_axes(eye, target, up):
    fwd = np.subtract(target, eye, dtype=float)
    fwd /= np.linalg.norm(fwd)
    right = np.cross(fwd, up)
    right /= np.linalg.norm(right)
    return fwd, right, np.cross(right, fwd)


PERSPECTIVE = dict(eye=(0.7, -3.0, 2.5), target=(0.2, 0.3, 0.0), up=(0, 0, 1), fov=50, width=W, height=H,
                   shift=(0.1, -0.05))
ORTHOGRAPHIC = dict(eye=(0.5, -1.0, 5.0), target=(0.3, -0.6, 0.0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=3.0, width=W, height=H, shift=(-0.1, 0.2))


def _pixel_centres():
    """(x, y) of every pixel centre in the image: 0 at its left / bottom edge, 1 at its right / top."""
    x = (np.arange(W) + 0.5) / W
    y = 1.0 - (np.arange(H) + 0.5) / H
    return np.meshgrid(x, y)


@pytest.mark.parametrize("camera", [PERSPECTIVE, ORTHOGRAPHIC], ids=["perspective", "orthographic"])
def test_window_coordinates_are_each_pixels_place_in_the_image(camera):
    # a plane at an angle to the view: the perspective division shows if it is skipped or wrong
    cam = gw.Camera(**camera)
    x, y = _pixel_centres()
    for axis, expected in ((0, x), (1, y)):
        image = _emitting(_gradient("window", _pick(axis)), camera=cam)[..., 0]
        np.testing.assert_allclose(image, expected, atol=2e-5)
    assert _emitting(_gradient("window", _pick(2, offset=0.5)), camera=cam)[..., 0] == pytest.approx(0.5)


PANORAMAS = [dict(projection="equirectangular"),
             dict(projection="equirectangular", longitude=(-1.0, 2.0), latitude=(-0.5, 1.2)),
             dict(projection="fisheye_equidistant", fisheye_fov=3.0),
             dict(projection="fisheye_equisolid", fisheye_lens=8.0, fisheye_fov=3.4, sensor=(30.0, 20.0)),
             dict(projection="fisheye_polynomial", fisheye_fov=3.0, sensor=(36.0, 24.0)),
             dict(projection="mirror_ball"), dict(projection="cubemap_face"),
             dict(projection="central_cylindrical", longitude=(-2.0, 2.0), cylinder_height=(-1.5, 1.0))]


@pytest.mark.parametrize("projection", PANORAMAS, ids=lambda p: "-".join(str(v) for v in p.values())[:40])
def test_window_coordinates_of_a_panorama_are_where_its_direction_lies_in_the_image(projection):
    # the camera inside a sphere: each pixel centre's ray meets it, and its point's direction
    # from the eye maps back to the pixel (Cycles' direction_to_panorama; a final render's image
    # spans the projection's unit square)
    cam = gw.Camera(eye=(0.2, -0.1, 0.3), target=(1.2, 0.4, 0.5), up=(0, 0, 1), width=W, height=H, **projection)
    x, y = _pixel_centres()
    for axis, expected in ((0, x), (1, y)):
        texture = _gradient("window", _pick(axis, 0.5, 0.25))          # (0.25 + u / 2: never clamped)
        s = gw.Scene(sphere_centers=[(0.0, 0.0, 0.0)], sphere_radii=[50.0], sphere_materials=[0], camera=cam,
                     materials=[gw.Material(kd=0, emission=1.0, color_texture=0)], textures=[texture])
        image = gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()
        seen = image[..., 0] > 0                   # (a fisheye's corners get no ray: black, and opaque as in Cycles)
        assert seen.sum() > W * H // 3
        np.testing.assert_allclose(image[..., 0][seen], 0.25 + 0.5 * expected[seen], atol=3e-4)


def _hits_on_the_plane_z0(camera):
    """World points where each pixel centre's ray meets the plane z = 0 (a pinhole camera)."""
    eye = np.asarray(camera["eye"], float)
    fwd, right, up = _camera_axes(camera["eye"], camera["target"], camera["up"])
    half_h = np.tan(np.radians(camera["fov"]) / 2)
    half_w = half_h * W / H
    big = 2 * max(half_w, half_h)
    x, y = _pixel_centres()
    sx = (2 * x - 1) * half_w + camera["shift"][0] * big
    sy = (2 * y - 1) * half_h + camera["shift"][1] * big
    d = fwd + right * sx[..., None] + up * sy[..., None]
    t = -eye[2] / d[..., 2]
    return eye + d * t[..., None], (eye, fwd, right, up)


def test_camera_coordinates_are_the_hit_point_in_camera_space():
    points, (eye, fwd, right, up) = _hits_on_the_plane_z0(PERSPECTIVE)
    cam = gw.Camera(**PERSPECTIVE)
    rel = points - eye
    # x right and y up of the view, z its depth along the view axis (Cycles' camera space),
    # each scaled into [0.05, 0.95] (never clamped by the gradient)
    for axis, frame_axis in ((0, right), (1, up), (2, fwd)):
        value = rel @ frame_axis
        scale = 0.9 / (value.max() - value.min())
        offset = 0.05 - value.min() * scale
        image = _emitting(_gradient("camera", _pick(axis, scale, offset)), camera=cam)[..., 0]
        np.testing.assert_allclose(image, value * scale + offset, atol=2e-4)


def test_camera_coordinates_are_measured_from_origin_ahead_along_the_view_axis():
    # the orthographic viewport moves its eye back to its near plane and measures Camera
    # coordinates from the view point: depth less origin_ahead, x and y unchanged
    scale, offset = 0.1, 0.2
    images = {ahead: _emitting(_gradient("camera", _pick(axis, scale, offset)),
                               camera=gw.Camera(**ORTHOGRAPHIC, origin_ahead=ahead))[..., 0]
              for axis in (2,) for ahead in (0.0, 2.5, -1.0)}
    assert 0.05 < images[0.0].min() and images[0.0].max() < 0.95         # the plane's depths, not clamped
    np.testing.assert_allclose(images[2.5], images[0.0] - 2.5 * scale, atol=2e-5)
    np.testing.assert_allclose(images[-1.0], images[0.0] + 1.0 * scale, atol=2e-5)
    across = [_emitting(_gradient("camera", _pick(0, scale, 0.5)), camera=gw.Camera(**ORTHOGRAPHIC, origin_ahead=a))
              for a in (0.0, 2.5)]
    np.testing.assert_array_equal(across[0], across[1])
    # Window coordinates are projected from the eye whatever origin_ahead says (a perspective
    # camera divides by the depth from the eye)
    for axis in (0, 1):
        window = [_emitting(_gradient("window", _pick(axis, 0.9, 0.05)), camera=gw.Camera(**PERSPECTIVE, origin_ahead=a))
                  for a in (0.0, 1.5)]
        np.testing.assert_array_equal(window[0], window[1])


def test_reflection_coordinates_mirror_the_view_about_a_spheres_normal():
    n = 48
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=2.2,
                    width=n, height=n)
    c = (np.arange(n) + 0.5) / n * 2.2 - 1.1
    x, y = np.meshgrid(c, c[::-1])
    inside = x ** 2 + y ** 2 < 0.9
    z = np.sqrt(np.clip(1 - x ** 2 - y ** 2, 0, None))
    normal = np.stack([x, y, z], axis=-1)
    wi = np.array([0.0, 0.0, 1.0])                                      # back along the camera's rays
    mirrored = 2 * (normal @ wi)[..., None] * normal - wi
    for axis in range(3):
        s = gw.Scene(sphere_centers=[(0, 0, 0)], sphere_radii=[1.0], sphere_materials=[0], camera=cam,
                     materials=[gw.Material(kd=0, emission=1.0, color_texture=0)],
                     textures=[_gradient("reflection", _pick(axis, 0.5, 0.5))])
        image = gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., 0]
        np.testing.assert_allclose(image[inside], 0.5 * mirrored[inside][:, axis] + 0.5, atol=1e-4)


def _square_view(from_front=True, n=24):
    eye = (0, 0, 5) if from_front else (0, 0, -5)
    return gw.Camera(eye=eye, target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=2.0,
                     width=n, height=n)


def test_normal_coordinates_are_the_object_space_normal_turned_over_on_a_back_face():
    # every corner's normal (0.6, 0, 0.8) in its object's space, whatever the world's
    normals = np.tile([0.6, 0.0, 0.8], (2, 3, 1)).astype(np.float32)
    texture = _gradient("normal", _pick(0, 0.5, 0.5))
    front = _emitting(texture, verts=VERTS, camera=_square_view(True), object_normals=normals)[..., 0]
    back = _emitting(texture, verts=VERTS, camera=_square_view(False), object_normals=normals)[..., 0]
    np.testing.assert_allclose(front, 0.8, atol=1e-6)
    np.testing.assert_allclose(back, 0.2, atol=1e-6)


def test_normal_coordinates_interpolate_the_corners_normals_and_normalise_them():
    n = 24
    corners = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1]], np.float32)
    normals = np.stack([corners, corners[[0, 2, 1]]])                   # triangle 2: corners 0, 2, 3
    c = (np.arange(n) + 0.5) / n * 2 - 1
    x, y = np.meshgrid(c, c[::-1])
    # barycentrics of each pixel centre in its triangle ((0, 1, 2) below the diagonal, (0, 2, 3) above)
    lower = x > y
    b_lower = np.stack([(1 - x) / 2, (x - y) / 2, (y + 1) / 2], axis=-1)
    b_upper = np.stack([(1 - y) / 2, (x + 1) / 2, (y - x) / 2], axis=-1)
    weights = np.where(lower[..., None], b_lower, b_upper)
    keep = np.abs(x - y) > 0.1                                           # pixels off the diagonal
    for axis in range(3):
        image = _emitting(_gradient("normal", _pick(axis)), verts=VERTS, camera=_square_view(True, n),
                          object_normals=normals)[..., 0]
        blend = np.where(lower[..., None], weights @ corners, weights @ corners[[0, 2, 1]])
        expected = blend[..., axis] / np.linalg.norm(blend, axis=-1)
        np.testing.assert_allclose(image[keep], expected[keep], atol=2e-5)


def test_geometry_normals_are_the_shading_and_the_geometric_normal_turned_to_the_ray():
    # vertex normals leaning along x: the shading normal (0.6, 0, 0.8), the geometric one (0, 0, 1)
    normals = np.tile([0.6, 0.0, 0.8], (4, 1)).astype(np.float32)
    for kind, front_x in (("geometry_normal", 0.6), ("true_normal", 0.0)):
        for axis, front in ((0, front_x), (2, 0.8 if kind == "geometry_normal" else 1.0)):
            texture = _gradient(kind, _pick(axis, 0.5, 0.5))
            seen = [_emitting(texture, verts=VERTS, normals=normals, camera=_square_view(side))[..., 0]
                    for side in (True, False)]
            np.testing.assert_allclose(seen[0], 0.5 + 0.5 * front, atol=1e-6)
            np.testing.assert_allclose(seen[1], 0.5 - 0.5 * front, atol=1e-6)     # the back: turned over


def test_the_back_of_a_face_is_told_by_its_winding_not_its_vertex_normals():
    # vertex normals (0, 0, -1) against the winding's (0, 0, 1), seen from +z: the front of the face
    # (Cycles: N is the vertex normal as it is, Ng the winding's; neither turned over)
    normals = np.tile([0.0, 0.0, -1.0], (4, 1)).astype(np.float32)
    for kind, z in (("geometry_normal", -1.0), ("true_normal", 1.0)):
        image = _emitting(_gradient(kind, _pick(2, 0.5, 0.5)), verts=VERTS, normals=normals,
                          camera=_square_view(True))[..., 0]
        np.testing.assert_allclose(image, 0.5 + 0.5 * z, atol=1e-6)


def test_incoming_is_the_unit_direction_back_along_the_ray():
    points, (eye, *_) = _hits_on_the_plane_z0(PERSPECTIVE)
    back = eye - points
    back /= np.linalg.norm(back, axis=-1, keepdims=True)
    for axis in range(3):
        image = _emitting(_gradient("incoming", _pick(axis, 0.5, 0.5)), camera=gw.Camera(**PERSPECTIVE))[..., 0]
        np.testing.assert_allclose(image, 0.5 + 0.5 * back[..., axis], atol=2e-5)


def _bumped(coordinates, transform, **scene):
    light = gw.Light(kind="sun", direction=(-0.4, -0.2, -1.0), color=(0.8, 0.8, 0.8))
    s = gw.Scene(VERTS, TRIS, lights=[light], camera=gw.Camera(**{**PERSPECTIVE, "target": (0, 0, 0)}),
                 textures=[gw.Texture(kind="noise", coordinates=coordinates, vector_transform=transform, scale=3.0)],
                 materials=[gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0, bump_texture=0, bump_distance=0.3)],
                 **scene)
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., 0]


def test_a_bump_map_at_camera_coordinates_bends_as_at_the_points_in_camera_space():
    eye = np.asarray(PERSPECTIVE["eye"], float)
    fwd, right, up = _camera_axes(PERSPECTIVE["eye"], (0, 0, 0), PERSPECTIVE["up"])
    rows = np.stack([right, up, fwd])
    to_camera = np.hstack([rows, -(rows @ eye)[:, None]]).reshape(-1)
    identity = (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0)
    at_camera = _bumped("camera", identity)
    at_position = _bumped("position", tuple(to_camera))
    flat = _bumped("position", (0,) * 12)
    assert np.abs(at_position - flat).max() > 0.05                     # the noise bends the normal
    # (the same up to rounding: the central differences of the noise amplify it here and there)
    difference = np.abs(at_camera - at_position)
    assert difference.max() < 0.01 and difference.mean() < 5e-4


@pytest.mark.parametrize("coordinates", ["normal", "reflection", "window", "geometry_normal", "true_normal",
                                         "incoming"])
def test_a_bump_map_at_the_normals_reflection_incoming_or_window_bends_nothing(coordinates):
    normals = np.tile([0.0, 0.0, 1.0], (2, 3, 1)).astype(np.float32)
    identity = (1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0)
    np.testing.assert_array_equal(_bumped(coordinates, identity, object_normals=normals),
                                  _bumped("position", (0,) * 12, object_normals=normals))


def _one_texture_scene(coordinates, **scene):
    return gw.Scene(materials=[gw.Material(color_texture=0)], textures=[_gradient(coordinates, _pick(0))], **scene)


def test_normal_coordinates_without_object_normals_are_refused_naming_the_array():
    with pytest.raises(ValueError, match=r"normal coordinates.*Scene\(object_normals=\.\.\.\)"):
        _one_texture_scene("normal", vertices=VERTS, triangles=TRIS)


@pytest.mark.parametrize("bad, message", [(np.zeros((2, 3, 2), np.float32), "object_normals must have shape"),
                                          (np.full((2, 3, 3), np.nan, np.float32),
                                           r"object_normals\[0\] has a non-finite value")])
def test_bad_object_normals_are_refused(bad, message):
    with pytest.raises(ValueError, match=message):
        _one_texture_scene("normal", vertices=VERTS, triangles=TRIS, object_normals=bad)


def test_normal_coordinates_are_refused_on_a_sphere_but_the_others_are_not():
    sphere = dict(sphere_centers=[(0, 0, 0)], sphere_radii=[1.0], sphere_materials=[0])
    with pytest.raises(ValueError, match="normal coordinates, which spheres do not have"):
        _one_texture_scene("normal", **sphere)
    for coordinates in ("camera", "window", "reflection", "geometry_normal", "true_normal", "incoming"):
        _one_texture_scene(coordinates, **sphere)


VIEW_COORDINATES = ("normal", "camera", "window", "reflection", "geometry_normal", "true_normal", "incoming")


@pytest.mark.parametrize("projection", ["perspective", "orthographic", "equirectangular", "fisheye_polynomial"])
def test_every_texture_at_every_view_coordinate_renders_finite_pixels(projection):
    # a mirror floor through the eye's height sends rays to a wall behind the camera: points on
    # the eye's plane (Window divides by 0 there) and behind it, seen by reflection rays
    from gridwalk.model import TEXTURE_KINDS
    floor = np.array([[-9, -9, 0], [9, -9, 0], [9, 9, 0], [-9, 9, 0]], np.float32)
    wall = np.array([[-9, -3, -9], [9, -3, -9], [9, -3, 9], [-9, -3, 9]], np.float32)
    verts = np.concatenate([floor, wall])
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    normals = np.tile([0.0, 0.0, 1.0], (4, 3, 1)).astype(np.float32)
    image = gw.Image(np.random.default_rng(1).random((4, 4, 3)).astype(np.float32))
    cam = gw.Camera(eye=(0, 0, 0), target=(0, 1, -0.4), up=(0, 0, 1), width=6, height=6, projection=projection)
    for kind in TEXTURE_KINDS:
        for coordinates in VIEW_COORDINATES:
            texture = gw.Texture(kind=kind, coordinates=coordinates, image=image if kind == "image" else None)
            # (a sphere too, but not at Normal coordinates: spheres have no object-space normals)
            ball = {} if coordinates == "normal" else dict(sphere_centers=[(0, 4, 0)], sphere_radii=[1.0],
                                                              sphere_materials=[0])
            s = gw.Scene(verts, tris, object_normals=normals, colors=normals * 0.5 + 0.5, camera=cam, textures=[texture],
                         materials=[gw.Material(kd=0.3, mirror=0.5, emission=1.0, color_texture=0, bump_texture=0)],
                         **ball)
            out = gw.RenderJob(s, gw.RenderSettings(threads=1, max_depth=3)).start().wait()
            assert np.isfinite(out).all() and out.min() >= 0, (kind, coordinates)
