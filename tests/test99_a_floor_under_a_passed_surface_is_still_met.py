"""A ray that passes a surface (hidden from its kind, or an alpha cut-out's
uncovered part) goes on from where it was: a surface lying in the plane of the
one passed is still met. A cube standing on a floor has its bottom face in the
floor's plane; moving the ray's origin just off the face moved it past the
floor too, and where the face was met before the floor (the cube's triangles
first, or a tie on t) the floor showed a hole: the world, or a transparent
film, along the footprint."""
import numpy as np
import pytest

import gridwalk as gw

N = 48
CUBE_CORNERS = np.array([[x, y, z] for z in (0, 1) for y in (-0.5, 0.5) for x in (-0.5, 0.5)], np.float32)
CUBE_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                       [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]], np.int32)
FLOOR = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
# a floor of many triangles too, so that its triangles' t along a ray differ from the cube's by
# rounding in every way (ties, a few ulps either side)
FLOOR_GRID = np.array([[x, y, 0] for y in np.linspace(-20, 20, 41) for x in np.linspace(-20, 20, 41)], np.float32)


def _grid_floor():
    quads = [(j * 41 + i, j * 41 + i + 1, (j + 1) * 41 + i + 1, (j + 1) * 41 + i) for j in range(40) for i in range(40)]
    return np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.int32)


def scene(cube=None, cube_first=True, grid_floor=False, copies=1):
    """A grey floor at z = 0 and (cube: Material fields, or None for none) `copies` red unit cubes
    standing on it, their triangles before the floor's or after; film transparent, one light."""
    floor_v, floor_t = (FLOOR_GRID, _grid_floor()) if grid_floor else (FLOOR, np.array([[0, 1, 2], [0, 2, 3]], np.int32))
    parts = [(floor_v, floor_t, 0)]
    offsets = [np.float32([1.3 * k - 1.3 * (copies - 1) / 2, 0.1 * k, 0]) for k in range(copies)]
    if cube is not None:
        parts += [(CUBE_CORNERS + offset, CUBE_FACES, 1) for offset in offsets]
    if cube_first:
        parts = parts[1:] + parts[:1]
    verts, tris, mats, ranges, base = [], [], [], [], 0
    for v, t, m in parts:
        if m == 1:
            ranges.append((sum(len(x) for x in tris), len(t)))
        verts.append(v)
        tris.append(t + base)
        mats += [m] * len(t)
        base += len(v)
    kw = {}
    if copies > 1:
        matrices = np.repeat(np.eye(4)[None], copies, axis=0)
        matrices[:, :3, 3] = np.array(offsets) - offsets[0]      # (each copy: the first, moved)
        kw = dict(instance_triangles=np.array(ranges, np.int64), instance_meshes=np.zeros(copies, np.int64),
                  instance_matrices=matrices)
    camera = gw.Camera(eye=(2, -4, 7), target=(0, 0, 0.3), up=(0, 0, 1), fov=35, width=N, height=N)
    return gw.Scene(vertices=np.concatenate(verts), triangles=np.concatenate(tris), triangle_materials=mats,
                    materials=[gw.Material(color=(0.6, 0.6, 0.6)), gw.Material(color=(0.9, 0.1, 0.1), **(cube or {}))],
                    camera=camera, lights=[gw.Light(position=(3, -2, 8), color=(1, 1, 1))],
                    world=gw.World(transparent=True), **kw)


def render(sc, **settings):
    job = gw.RenderJob(sc, gw.RenderSettings(**{"aa": "jittered", "aa_samples": 3, "threads": 2, **settings})).start()
    job.wait()
    return job.image


@pytest.mark.parametrize("cube_first", [True, False])
@pytest.mark.parametrize("grid_floor", [False, True])
def test_a_floor_under_a_cube_hidden_from_the_camera_and_shadows_renders_as_without_it(cube_first, grid_floor):
    alone = render(scene(None, grid_floor=grid_floor))
    hidden = render(scene(dict(visible_camera=False, visible_shadow=False), cube_first, grid_floor))
    assert np.all(alone[..., 3] == 1.0)                    # (the floor fills the view)
    assert np.all(hidden[..., 3] == 1.0), f"{int((hidden[..., 3] < 1).sum())} pixels see through the floor"
    np.testing.assert_allclose(hidden, alone, rtol=0, atol=1e-5)


@pytest.mark.parametrize("accel", ["grid", "none"])
def test_the_uniform_grid_and_brute_force_leave_the_floor_whole_too(accel):
    alone = render(scene(None, grid_floor=True), accel=accel, aa="center")
    hidden = render(scene(dict(visible_camera=False, visible_shadow=False), True, grid_floor=True), accel=accel,
                    aa="center")
    assert np.all(hidden[..., 3] == 1.0), f"{int((hidden[..., 3] < 1).sum())} pixels see through the floor"
    np.testing.assert_allclose(hidden, alone, rtol=0, atol=1e-5)


@pytest.mark.parametrize("cube_first", [True, False])
def test_a_floor_under_a_half_covering_cube_covers_every_pixel(cube_first):
    half = render(scene(dict(alpha=0.5, visible_shadow=False), cube_first, grid_floor=True))
    assert np.all(half[..., 3] == 1.0), f"{int((half[..., 3] < 1).sum())} pixels see through the floor"
    red = (half[..., 0] - half[..., 1]) > 0.1
    assert red.sum() > 50                                  # the cube is there, half covering


def test_copies_of_a_hidden_cube_through_the_instanced_grid_leave_the_floor_whole():
    sc = scene(dict(visible_camera=False, visible_shadow=False), True, grid_floor=True, copies=3)
    assert sc.grid_info(gw.RenderSettings(instancing="on"))["kind"] == "instanced adaptive grid"
    alone = render(scene(None, grid_floor=True))
    for instancing in ("on", "off"):
        hidden = render(sc, instancing=instancing)
        assert np.all(hidden[..., 3] == 1.0), (instancing, int((hidden[..., 3] < 1).sum()))
        np.testing.assert_allclose(hidden, alone, rtol=0, atol=1e-5)


def test_a_half_covering_square_of_two_triangles_is_crossed_once_along_its_diagonal():
    # camera rays through the shared edge meet both triangles, a t a few ulps apart: the
    # surface is passed once (alpha 0.25 everywhere), not twice (0.4375)
    v = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), fov=20, width=N, height=N)
    sc = gw.Scene(vertices=v, triangles=np.array([[0, 1, 2], [0, 2, 3]], np.int32), camera=cam,
                  materials=[gw.Material(kd=0, emission_color=(1, 0, 0), alpha=0.25)], world=gw.World(transparent=True))
    image = render(sc, aa="center")
    assert set(np.unique(image[..., 3]).tolist()) == {0.25}


@pytest.mark.parametrize("accel", ["adaptive", "grid", "none"])
def test_a_half_covering_analytic_sphere_is_crossed_twice_as_a_mesh_one_is(accel):
    # (a sphere's test gives the root nearest tmin: a ray resumed past its front met the front
    # again, which it then rejected, and never the back; a sphere passed moves the origin on)
    from gridwalk.scenes import icosphere
    mat = [gw.Material(kd=0, emission_color=(1, 0, 0), alpha=0.5)]
    cam = gw.Camera(eye=(0.01, 0.013, 5), target=(0.01, 0.013, 0), up=(0, 1, 0), fov=10, width=16, height=16)
    ball = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], materials=mat, camera=cam,
                    world=gw.World(transparent=True))
    v, t = icosphere(4)
    mesh = gw.Scene(vertices=np.asarray(v, np.float32), triangles=np.asarray(t, np.int32), materials=mat,
                    camera=cam, world=gw.World(transparent=True))
    a, b = render(ball, aa="center", accel=accel), render(mesh, aa="center", accel=accel)
    assert a[8, 8, 3] == pytest.approx(0.75) and b[8, 8, 3] == pytest.approx(0.75)   # 1 - 0.5 x 0.5
    np.testing.assert_allclose(a[8, 8], b[8, 8], rtol=1e-5)
