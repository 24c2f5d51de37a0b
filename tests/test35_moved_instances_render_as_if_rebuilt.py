"""A viewport transform edit moves instances in the core (Scene.moved) instead of assembling the
scene's arrays again, and walks an older version's uniform grid with the rays mapped back
(MovedGrid, through gridwalk._core.follow_grid) instead of building one. The moved scene holds
the arrays that transforming the instances in numpy gives (as the Blender exporter does), the
followed grid finds brute force's hits over a chain of moves, both refuse what they cannot
serve, and the ProgressiveRenderer's image after a move is a fresh render's."""
import dataclasses

import numpy as np
import pytest

import gridwalk as gw
from gridwalk import _core
from meshes import uv_sphere

GRID = gw.RenderSettings(threads=1, accel="grid", grid_density=1.0)
BRUTE = gw.RenderSettings(accel="none")   # its answers do not depend on the thread count: every core
V, F = uv_sphere(24, 48, radius=1.0, center=np.zeros(3), seed=1)
V = V.astype(np.float32)
N = (V / np.linalg.norm(V, axis=1, keepdims=True)).astype(np.float32)


def matrix(seed: int, mirror: bool = False) -> np.ndarray:
    """A rotation, non-uniform scale (mirrored if asked) and translation, rows as in Blender."""
    rng = np.random.default_rng(seed)
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    m = np.eye(4)
    m[:3, :3] = q * rng.uniform(0.5, 2.0, 3) * (np.array([-1, 1, 1]) if mirror else 1)
    m[:3, 3] = rng.normal(0, 3, 3)
    return m


def world(m, kind):
    """One instance in world space, as the exporter makes it: (vertices, local triangles, normals)."""
    p = V.astype(np.float64) @ m[:3, :3].T + m[:3, 3]
    if kind == "flat":                                   # unshared corners with face normals
        corners = p[F.reshape(-1)].reshape(-1, 3, 3)
        n = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
        length = np.linalg.norm(n, axis=1, keepdims=True)   # (0 at the poles' degenerate triangles)
        np.divide(n, length, out=n, where=length > 0)
        return corners.reshape(-1, 3), np.arange(3 * len(F)).reshape(-1, 3), np.repeat(n, 3, axis=0)
    n = N.astype(np.float64) @ np.linalg.inv(m[:3, :3])
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    return p, F, n if kind == "smooth" else None


def assemble(mats, kinds):
    verts, tris, normals, offset = [], [], [], 0
    for m, kind in zip(mats, kinds):
        p, t, n = world(m, kind)
        verts.append(p.astype(np.float32))
        tris.append(t + offset)
        normals.append(n)
        offset += len(p)
    out = {"vertices": np.concatenate(verts), "triangles": np.concatenate(tris).astype(np.int32)}
    if any(n is not None for n in normals):
        out["normals"] = np.concatenate(normals).astype(np.float32)
    return out


def move(scene, mats, kinds, index, new, previous=True):
    """scene with instance `index` moved to matrix `new` (mats updated)."""
    starts = np.cumsum([0] + [3 * len(F) if k == "flat" else len(V) for k in kinds])
    kind = kinds[index]
    positions = V[F.reshape(-1)] if kind == "flat" else V
    m = gw.InstanceMove(int(starts[index]), index * len(F), len(F), positions, new,
                        normals=N if kind == "smooth" else None, flat=kind == "flat",
                        previous_matrix=mats[index] if previous else None)
    mats[index] = new
    return scene.moved([m])


def rays(n=20000, seed=5):
    rng = np.random.default_rng(seed)
    o = rng.normal(0, 7, (n, 3)).astype(np.float32)
    d = (rng.normal(0, 2, (n, 3)) - o).astype(np.float32)
    return o, d, np.zeros(n, np.float32), np.full(n, np.inf, np.float32)


def trace(accel, settings):
    t, prim, kind, *_ = _core.intersect(accel, *rays(), settings.to_core(), False)
    return t, prim


@pytest.mark.parametrize("kinds", [["smooth", "smooth", "flat"], ["plain", "plain"], ["flat", "smooth"]])
def test_a_moved_scene_holds_the_arrays_of_the_instances_transformed_in_numpy(kinds):
    mats = [matrix(i) for i in range(len(kinds))]
    scene = gw.Scene(**assemble(mats, kinds))
    for step, (index, mirror) in enumerate([(0, False), (len(kinds) - 1, True), (0, True), (1, False)]):
        scene = move(scene, mats, kinds, index, matrix(10 + step, mirror))
        got, want = scene.geometry(), assemble(mats, kinds)
        assert np.array_equal(got["triangles"], want["triangles"])
        np.testing.assert_array_max_ulp(got["vertices"], want["vertices"], maxulp=1)
        if "normals" in want:
            np.testing.assert_array_max_ulp(got["normals"], want["normals"], maxulp=2)
        else:
            assert got["normals"] is None
        lo, hi = scene.bounds
        assert np.allclose(lo, want["vertices"].min(0)) and np.allclose(hi, want["vertices"].max(0))


def test_a_followed_grid_finds_what_brute_force_finds_over_a_chain_of_moves():
    kinds = ["smooth", "flat", "smooth"]
    mats = [matrix(i) for i in range(3)]
    scene = gw.Scene(**assemble(mats, kinds))
    grids = [_core.build_accel(scene._native, GRID.to_core(), None, 0.1)]
    for step in range(6):
        scene = move(scene, mats, kinds, step % 3, matrix(20 + step, mirror=step == 4))
        want_t, want_prim = trace(_core.build_accel(scene._native, BRUTE.to_core(), None, 0.0), BRUTE)
        for g in grids:
            followed = _core.follow_grid(g, scene._native)
            assert followed is not None and "instances moved since" in followed.grid["note"]
            t, prim = trace(followed, GRID)
            assert np.isfinite(want_t).sum() > 800
            assert np.array_equal(np.isfinite(t), np.isfinite(want_t)), f"step {step}"
            assert np.mean(prim != want_prim) < 1e-3, f"step {step}"   # (a ray grazing an edge may differ)
            same = prim == want_prim
            assert np.allclose(t[same], want_t[same], rtol=1e-4, atol=0)
            o, d, lo, hi = rays()
            hit, _ = _core.occluded(followed, o, d, lo, np.where(np.isfinite(want_t), want_t * 1.01, 100.0),
                                    GRID.to_core(), False)
            assert np.array_equal(hit.astype(bool), np.isfinite(want_t))
        if step == 2:   # a grid of this version: the rest of the chain may follow either
            grids.append(_core.build_accel(scene._native, GRID.to_core(), None, 0.1))


@pytest.mark.parametrize("scale", [1.0, 0.01])
def test_rays_leaving_a_moved_instance_do_not_hit_it_again(scale):
    # The grid's version has the sphere at x = 1000 (floats 6e-5 apart there, against offsets of
    # about 5e-7 near the origin); it was moved next to the origin, and scaled down. Rays leave its
    # (bumpy) surface outwards; the followed grid, testing the sphere where it was, must find what
    # brute force finds, not the surface the ray leaves.
    far, kinds = np.eye(4), ["smooth"]
    far[:3, 3] = [1000.0, 0.0, 0.0]
    mats = [far]
    root = gw.Scene(**assemble(mats, kinds))
    grid = _core.build_accel(root._native, GRID.to_core(), None, 0.1)
    near = matrix(80)
    near[:3, :3] *= scale
    scene = move(root, mats, kinds, 0, near)
    followed = _core.follow_grid(grid, scene._native)
    rng = np.random.default_rng(8)
    centre = near[:3, 3]
    o = (centre + rng.normal(0, 1, (20000, 3)) * 5 * scale).astype(np.float32)
    d = (centre - o + rng.normal(0, 0.3 * scale, o.shape)).astype(np.float32)
    hits = scene.intersect(o, d, settings=BRUTE)
    keep = np.isfinite(hits.t)
    assert keep.sum() > 5000
    p = o + np.where(keep, hits.t, 0)[:, None] * d
    outward = hits.normal * np.sign((hits.normal * (p - centre)).sum(1, keepdims=True))   # (the mesh's winding varies)
    w = rng.normal(size=o.shape)
    w = np.where((w * outward).sum(1, keepdims=True) < 0, -w, w).astype(np.float32)
    start = scene.spawn_origins(o, d, hits, w)[keep]
    n = int(keep.sum())
    args = (start, w[keep], np.zeros(n, np.float32), np.full(n, np.inf, np.float32))
    t_brute, *_ = _core.intersect(_core.build_accel(scene._native, BRUTE.to_core(), None, 0.0), *args,
                                  BRUTE.to_core(), True)
    t, *_ = _core.intersect(followed, *args, GRID.to_core(), True)
    extra = np.isfinite(t) & ~np.isfinite(t_brute)
    # Rays within about half a degree of the surface (cos < 0.01; their light is weighted by that
    # cosine) may still re-hit it; no other may. Before the mapped rays skipped the span their
    # rounding can account for, 7516 of these rays re-hit the sphere at scale 0.01.
    steep = np.abs((w[keep] * outward[keep]).sum(1)) > 0.01
    assert not (extra & steep).any(), f"{int((extra & steep).sum())} of {n} rays hit the surface they left"
    assert extra.mean() < 5e-3
    assert np.mean(np.isfinite(t) != np.isfinite(t_brute)) < 2e-3 and np.isfinite(t_brute).sum() > 500


def test_a_grid_is_followed_only_from_an_ancestor_with_few_instances_moved_since():
    kinds = ["plain"] * 10
    mats = [matrix(i) for i in range(10)]
    root = gw.Scene(**assemble(mats, kinds))
    grid = _core.build_accel(root._native, GRID.to_core(), None, 0.0)
    assert _core.follow_grid(grid, root._native) is None                   # not moved: nothing to follow
    unrelated = gw.Scene(**assemble(mats, kinds))
    moved = move(unrelated, list(mats), kinds, 0, matrix(30))
    assert _core.follow_grid(grid, moved._native) is None                  # another scene's grid
    scene = root
    for i in range(8):                                                     # 8 instances: still followed
        scene = move(scene, mats, kinds, i, matrix(40 + i))
    assert _core.follow_grid(grid, scene._native) is not None
    scene = move(scene, mats, kinds, 8, matrix(50))                        # a 9th: the root is forgotten
    assert _core.follow_grid(grid, scene._native) is None
    blind = move(root, mats, kinds, 0, matrix(60), previous=False)        # where it was is unknown
    assert _core.follow_grid(grid, blind._native) is None
    root_mats = [matrix(i) for i in range(10)]
    lied = root.moved([gw.InstanceMove(0, 0, len(F), V, matrix(61), previous_matrix=matrix(62))])
    assert _core.follow_grid(grid, lied._native) is None                  # a previous matrix that is wrong
    told = root.moved([gw.InstanceMove(0, 0, len(F), V, matrix(61), previous_matrix=root_mats[0])])
    assert _core.follow_grid(grid, told._native) is not None
    want = world(matrix(60), "plain")[0].astype(np.float32)
    np.testing.assert_array_max_ulp(blind.geometry()["vertices"][:len(V)], want, maxulp=1)   # moved all the same


def test_moves_that_do_not_fit_the_scene_are_refused_naming_the_move():
    kinds = ["smooth", "smooth"]
    scene = gw.Scene(**assemble([matrix(0), matrix(1)], kinds))
    m = matrix(2)

    def refused(match, **kw):
        args = dict(vertex_start=0, triangle_start=0, triangle_count=len(F), positions=V, matrix=m, normals=N)
        args.update(kw)
        with pytest.raises(ValueError, match=match):
            scene.moved([gw.InstanceMove(**args)])

    refused("outside the instance's vertices", triangle_start=len(F))            # another instance's triangles
    refused("which a move moves", triangle_count=len(F) - 1)                    # its last triangle left behind
    refused("beyond the scene's", vertex_start=len(V) + 1)
    refused("normals must have the shape", normals=None)
    refused("non-finite", matrix=np.where(np.eye(4) > 0, np.nan, m))
    refused("not finite in world space|beyond", matrix=m * np.diag([1e36, 1e36, 1e36, 1]))
    refused(r"shape \(4, 4\)", matrix=np.eye(3))
    refused("not its own corner", flat=True, normals=None)
    with pytest.raises(ValueError, match="share vertices or triangles"):
        one = gw.InstanceMove(0, 0, len(F), V, m, normals=N)
        scene.moved([one, one])


def test_the_viewport_follows_its_grid_when_an_instance_moves_and_renders_what_a_fresh_render_does():

    from test26_moved_objects_update_the_grid import wait_finished
    kinds = ["smooth", "flat"]
    mats = [matrix(0), matrix(1)]
    first = gw.Scene(**assemble(mats, kinds), lights=[gw.Light(position=(0.0, 9.0, 9.0))],
                     camera=gw.Camera(eye=(0.0, 2.0, 14.0), target=(0.0, 0.0, 0.0), fov=50.0))
    cam = dataclasses.replace(first.camera, width=48, height=36)
    s = gw.RenderSettings(threads=2, accel="grid", aa="random", aa_samples=1, seed=3)
    r = gw.ProgressiveRenderer()
    try:
        scene = first
        for step, expect_followed in enumerate([False, True, True]):
            if step:
                scene = move(scene, mats, kinds, step - 1, matrix(70 + step))
            rid, _ = r.submit(scene, [(1, s, cam)], cam.width, cam.height)
            status = wait_finished(r, rid)
            assert status["error"] == "" and status["structure_updated"] == [expect_followed]
            _, img = r.image()
            fresh = gw.Scene(**assemble(mats, kinds), lights=first.lights, camera=first.camera)
            ref = gw.RenderJob(fresh, s.replace(accel="none"), camera=cam).start().wait()
            ref[..., 3] = 1
            differ = np.any(np.abs(img[::-1] - ref) > 1e-3, axis=2)
            assert differ.mean() < 0.01 and ref[..., :3].std() > 0.05
    finally:
        r.stop()


@pytest.mark.parametrize("mirror", [False, True])
def test_an_instance_scaled_to_zero_along_an_axis_gets_its_flattened_surface_normals(mirror):
    # A smooth sphere scaled to zero along its (rotated) local z is a disc. Its normals map by
    # the cofactors of the singular matrix, as its edges' cross products do: along the disc's
    # normal, on the side of the sphere each came from, or, mirrored, the other side (with its
    # triangles' winding). Scene.moved and the exporter agree; both once mapped them by the
    # matrix itself, which turned them edge-on, across the disc.
    from blender_addon.export._matrix import transform_normals
    q, _ = np.linalg.qr(np.random.default_rng(3).normal(size=(3, 3)))
    q[:, 0] *= np.sign(np.linalg.det(q))                 # a rotation
    flat = np.eye(4)
    flat[:3, :3] = q @ np.diag([-2.0 if mirror else 2.0, 0.5, 0.0])
    flat[:3, 3] = (1, -2, 3)
    mats, kinds = [matrix(0)], ["smooth"]
    moved = move(gw.Scene(**assemble(mats, kinds)), mats, kinds, 0, flat)
    got = moved.geometry()["normals"]
    np.testing.assert_allclose(got, transform_normals(flat, N.astype(np.float64)), atol=1e-6)
    side = N[:, 2] * (-1 if mirror else 1)
    along = got @ q[:, 2]
    assert np.allclose(along[side > 1e-3], 1, atol=1e-6) and np.allclose(along[side < -1e-3], -1, atol=1e-6)
    # The same map takes each triangle's object-space normal (its edges' cross product) to its
    # flattened triangle's, winding included (mirrored or not).
    p = moved.geometry()["vertices"].astype(np.float64)[F]
    world = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    big = np.linalg.norm(world, axis=1) > 1e-3 * np.linalg.norm(world, axis=1).max()
    world = world[big] / np.linalg.norm(world[big], axis=1, keepdims=True)
    v = V.astype(np.float64)[F[big]]
    mapped = transform_normals(flat, np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0]))
    assert np.all(np.einsum("ij,ij->i", mapped, world) > 0.999)


@pytest.mark.parametrize("kinds", [["smooth", "flat"], ["plain", "plain"]])
def test_a_moved_scene_renders_what_a_scene_built_from_its_arrays_renders_to_the_bit(kinds):
    # Whatever the core derives from the triangles follows a move: the bounds, the tangents and
    # the weights by which emissive triangles are picked as lights (their areas). Here the
    # emissive instance moves; with the weights copied from before the move the image came out up
    # to 2e-8 off the scene built from the moved arrays.
    mats = [matrix(0), matrix(1)]
    materials = [gw.Material(color=(0.8, 0.8, 0.8)),
                 gw.Material(color=(1.0, 0.6, 0.3), emission=3.0, emits_light=True)]
    tri_mats = np.repeat(np.arange(2, dtype=np.int32), len(F))
    shared = dict(triangle_materials=tri_mats, lights=[gw.Light(position=(0.0, 9.0, 9.0))],
                  camera=gw.Camera(eye=(0.0, 2.0, 14.0), target=(0.0, 0.0, 0.0), fov=50.0, width=40, height=30))
    scene = gw.Scene(**assemble(mats, kinds), materials=materials, **shared)
    s = gw.RenderSettings(threads=2, aa="random", aa_samples=2, shadow="random", shadow_samples=4, seed=3)
    for step in range(2):
        scene = move(scene, mats, kinds, 1, matrix(90 + step))
        g = scene.geometry()
        arrays = {k: g[k] for k in ("vertices", "triangles", "normals") if g[k] is not None}
        built = gw.Scene(**arrays, materials=materials, **shared)
        moved_image = gw.RenderJob(scene, s).start().wait()
        built_image = gw.RenderJob(built, s).start().wait()
        assert np.array_equal(moved_image, built_image), f"step {step}: {np.abs(moved_image - built_image).max()}"
        # (the emitter lights the other instance: without it, as a plain emissive surface, the image differs)
        unlit = gw.Scene(**arrays, materials=[materials[0], dataclasses.replace(materials[1], emits_light=False)],
                         **shared)
        assert np.abs(gw.RenderJob(unlit, s).start().wait() - built_image).max() > 0.01
