"""The instanced grid (core/src/instanced_grid.h): copies of a mesh declared
with Scene(instance_triangles=, instance_meshes=, instance_matrices=) are
traced through one grid of the mesh, placed by a grid over the copies, and
find the hits the flat grid finds over every copy's triangles."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk import memory
from meshes import icosphere, random_rays, scattered_copies as scattered

INSTANCED, FLAT = gw.RenderSettings(threads=2, instancing="on"), gw.RenderSettings(threads=2, instancing="off")


def rays(n=60000, seed=2, extent=20.0):
    o, d = random_rays(n, (-extent, -extent, 0.0), (extent, extent, 3.0), seed=seed)
    return o, d


def test_copies_find_the_hits_of_the_flat_grid_and_of_brute_force():
    scene = gw.Scene(**scattered())
    info = scene.grid_info(INSTANCED)
    assert info["kind"] == "instanced adaptive grid"
    assert info["note"].startswith("398 copies of 2 meshes")          # each mesh's first copy stays in the rest
    assert "did not match" not in info["note"]
    assert scene.grid_info(FLAT)["kind"] == "adaptive grid"
    o, d = rays()
    a, b = scene.intersect(o, d, settings=INSTANCED), scene.intersect(o, d, settings=FLAT)
    brute = scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert np.array_equal(b.prim, brute.prim) and np.array_equal(b.kind, brute.kind)
    hits = a.kind > 0
    assert 0.3 < hits.mean() < 0.99
    same = (a.prim == b.prim) & (a.kind == b.kind)
    # Copies are met as their mesh's first copy moved into their place: the same
    # triangle, except where float rounding decides between two (an edge, two
    # copies touching), and the hit point to within 1e-5 of the scene's size (20;
    # unit directions): a few float spacings there, more along grazing rays.
    assert same.mean() > 0.9995, f"{(~same).sum()} rays hit another primitive"
    both = same & hits
    np.testing.assert_allclose(a.t[both], b.t[both], rtol=0, atol=2e-4)
    assert np.median(np.abs(a.t[both] - b.t[both])) < 2e-6
    assert np.percentile(np.abs(a.u[both] - b.u[both]) + np.abs(a.v[both] - b.v[both]), 99.9) < 1e-3
    on_copies = both & (a.kind == 1) & (a.prim >= 80) & (a.prim < 400 * 80)
    assert on_copies.sum() > 1000                 # (the copies are really hit)
    far = np.full(len(o), 1.5, np.float32)
    occ_a = scene.occluded(o, d, tmax=far, settings=INSTANCED)
    occ_b = scene.occluded(o, d, tmax=far, settings=FLAT)
    assert 0.05 < occ_b.mean() < 0.95
    assert (occ_a != occ_b).sum() <= 3


def test_the_instanced_grid_is_much_smaller_and_faster_to_build():
    scene = gw.Scene(**scattered(n=3000))
    inst, flat = scene.grid_info(INSTANCED), scene.grid_info(FLAT)
    assert inst["kind"] == "instanced adaptive grid"
    assert inst["bytes"] < flat["bytes"] / 4, (inst["bytes"], flat["bytes"])


def test_copies_that_coincide_give_the_hit_to_the_lower_index_as_the_flat_grid_does():
    # Two copies of one mesh in the same place, neither its first: both are walked with
    # the same mapped ray, so every hit comes at the same t from both, and goes to the
    # lower index (Scene::intersect_with's rule), as in the flat grid and brute force.
    # (Against the mesh's first copy, traced in the rest, a coinciding copy's t is
    # computed in another frame: equal only to within rounding, architecture.md.)
    kw = scattered(n=4, mirrored_every=0)
    v, t = kw["vertices"], kw["triangles"]
    mine = t[80:160]                                   # instance 1's triangles
    used = np.unique(mine)
    k = len(v)
    kw["vertices"] = np.concatenate([v, v[used]])
    kw["triangles"] = np.concatenate([t, np.searchsorted(used, mine).astype(np.int32) + k])
    kw["instance_triangles"] = np.concatenate([kw["instance_triangles"], [[len(t), 80]]])
    kw["instance_meshes"] = np.append(kw["instance_meshes"], 0)
    kw["instance_matrices"] = np.concatenate([kw["instance_matrices"], kw["instance_matrices"][1:2]])
    scene = gw.Scene(**kw)
    assert scene.grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
    target = v[used].mean(axis=0)
    rng = np.random.default_rng(5)
    o = (target + rng.normal(0, 1, (2000, 3)) * 3 + [0, 0, 3]).astype(np.float32)
    d = (target - o + rng.normal(0, 0.2, (2000, 3))).astype(np.float32)
    for settings in (INSTANCED, FLAT, gw.RenderSettings(accel="none")):
        h = scene.intersect(o, d, settings=settings)
        on_it = (h.kind == 1) & (h.prim >= 80) & (h.prim < 160)
        assert on_it.mean() > 0.5
        assert not np.any((h.kind == 1) & (h.prim >= len(t)))     # never the later, coinciding copy


def test_a_declared_copy_that_does_not_match_its_mesh_is_traced_as_its_own_triangles():
    kw = scattered(n=200)
    bent = 5                                           # instance 5: one corner moved by 0.05
    first = kw["triangles"][bent * 80, 0]
    kw["vertices"] = kw["vertices"].copy()
    kw["vertices"][first] += np.float32(0.05)
    scene = gw.Scene(**kw)
    info = scene.grid_info(INSTANCED)
    assert info["kind"] == "instanced adaptive grid"
    assert "1 declared instances did not match" in info["note"]
    # Rays at the moved corner find what brute force finds there, to the bit.
    corner = kw["vertices"][first]
    rng = np.random.default_rng(3)
    o = (corner + rng.normal(0, 0.3, (3000, 3)) + [0, 0, 2]).astype(np.float32)
    d = (corner + rng.normal(0, 0.05, (3000, 3)) - o).astype(np.float32)
    a = scene.intersect(o, d, settings=INSTANCED)
    brute = scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    own = (brute.kind == 1) & (brute.prim >= bent * 80) & (brute.prim < (bent + 1) * 80)
    assert own.sum() > 300
    assert np.array_equal(a.prim[own], brute.prim[own]) and np.array_equal(a.t[own], brute.t[own])


def _permute_copy(kw, i, rng):
    """Copy i's vertices listed in another order (its triangles renumbered to match): the same
    corners, but not its mesh's first copy's vertex ids plus one offset."""
    tris = kw["triangles"][i * 80:(i + 1) * 80]
    lo = tris.min()
    n = tris.max() + 1 - lo
    order = rng.permutation(n)
    block = kw["vertices"][lo:lo + n].copy()
    kw["vertices"][lo + order] = block
    kw["triangles"][i * 80:(i + 1) * 80] = lo + order[tris - lo]


def test_copies_listing_their_vertices_in_another_order_are_checked_corner_by_corner():
    # The build checks a copy at one corner per vertex where its vertex ids are its first
    # copy's shifted (how exporters lay copies out), else at every corner: both find the
    # same copies, and a moved corner is refused either way.
    kw = scattered(n=200)
    kw["vertices"], kw["triangles"] = kw["vertices"].copy(), kw["triangles"].copy()
    rng = np.random.default_rng(5)
    before = gw.Scene(**kw).intersect(*rays(8000), settings=INSTANCED)
    for i in (4, 8, 13, 21):
        _permute_copy(kw, i, rng)
    scene = gw.Scene(**kw)
    info = scene.grid_info(INSTANCED)
    assert info["note"].startswith("198 copies of 2 meshes") and "did not match" not in info["note"]
    after = scene.intersect(*rays(8000), settings=INSTANCED)
    assert np.array_equal(before.prim, after.prim) and np.array_equal(before.t, after.t)
    # a corner moved in a renumbered copy, and one in a copy laid out as its first copy
    for i in (8, 30):
        kw["vertices"][kw["triangles"][i * 80 + 17, 2]] += np.float32(0.05)
    assert "2 declared instances did not match" in gw.Scene(**kw).grid_info(INSTANCED)["note"]


def test_a_copy_with_one_corner_split_off_to_a_vertex_of_its_own_is_refused():
    # One corner of copy 40 that shared a vertex with earlier corners now has a vertex of its
    # own, moved: its corners no longer share vertices as its first copy's do, so every
    # corner is checked (one corner per vertex would only see the earlier ones).
    kw = scattered(n=200)
    corners = kw["triangles"][40 * 80:41 * 80].reshape(-1)
    v = corners[0]
    later = np.flatnonzero(corners == v)[-1]
    assert later > 0
    kw["vertices"] = np.concatenate([kw["vertices"], kw["vertices"][v:v + 1] + np.float32(0.05)])
    kw["triangles"] = kw["triangles"].copy()
    kw["triangles"][40 * 80 + later // 3, later % 3] = len(kw["vertices"]) - 1
    assert "1 declared instances did not match" in gw.Scene(**kw).grid_info(INSTANCED)["note"]


def test_copies_whose_vertex_ids_are_spread_out_are_checked_at_every_corner():
    # Every copy's 42 vertices lie 1,000 ids apart (unused vertices between them): the
    # one-corner-per-vertex table would span 41,001 ids for 240 corners, so every corner
    # is checked, and a moved corner is still refused.
    kw = scattered(n=60, mirrored_every=0)
    gap = 1000
    tris = kw["triangles"].copy()
    copies = tris[:60 * 80]
    spread = np.zeros((len(kw["vertices"]) - 4 + 60 * 42 * (gap - 1) + 4, 3), np.float32)
    new_id = np.arange(60 * 42) * gap                   # vertex j of the copies -> id j * gap
    spread[new_id] = kw["vertices"][:60 * 42]
    spread[-4:] = kw["vertices"][-4:]                   # the floor's corners, last
    tris[:60 * 80] = new_id[copies]
    tris[60 * 80:] += len(spread) - len(kw["vertices"])
    kw["vertices"], kw["triangles"] = spread, tris
    info = gw.Scene(**kw).grid_info(INSTANCED)
    assert info["note"].startswith("59 copies of 1 meshes") and "did not match" not in info["note"]
    spread[tris[33 * 80 + 5, 1]] += np.float32(0.05)
    assert "1 declared instances did not match" in gw.Scene(**kw).grid_info(INSTANCED)["note"]


def test_a_wrong_matrix_is_refused_not_trusted():
    kw = scattered(n=200)
    kw["instance_matrices"] = kw["instance_matrices"].copy()
    kw["instance_matrices"][7, 0, 3] += 0.5            # declared half a unit away from where it is
    scene = gw.Scene(**kw)
    assert "1 declared instances did not match" in scene.grid_info(INSTANCED)["note"]


def test_auto_instancing_builds_the_instanced_grid_only_where_it_pays():
    # "auto" (the default): copies must make at least half of the primitives and over
    # 2^20 triangles; below, the flat grid builds fast and traces faster. "on": wherever
    # a copy checks out.
    auto = gw.RenderSettings(threads=2)
    assert auto.instancing == "auto"
    few = scattered(n=400)                                   # 31,840 copied triangles
    assert gw.Scene(**few).grid_info(auto)["kind"] == "adaptive grid"
    kw = scattered(n=4, mirrored_every=0)                    # copies beside a bigger mesh
    big_v, big_t = icosphere(4, radius=3.0, center=(0, 0, 10))
    kw["triangles"] = np.concatenate([kw["triangles"], big_t + len(kw["vertices"])])
    kw["vertices"] = np.concatenate([kw["vertices"], big_v])
    assert gw.Scene(**kw).grid_info(auto)["kind"] == "adaptive grid"
    assert gw.Scene(**kw).grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
    many = scattered(n=13200, extent=60.0)                   # 1,055,840 copied triangles
    assert (13200 - 2) * 80 > memory.INSTANCING_AUTO_TRIANGLES
    assert gw.Scene(**many).grid_info(auto)["kind"] == "instanced adaptive grid"


def test_spawned_rays_leave_a_copy_without_meeting_it_again():
    scene = gw.Scene(**scattered())
    o, d = rays(seed=7)
    h = scene.intersect(o, d, settings=INSTANCED)
    on_copies = (h.kind == 1) & (h.prim >= 80) & (h.prim < 400 * 80)
    o, d, h_prim = o[on_copies], d[on_copies], h.prim[on_copies]
    hits = scene.intersect(o, d, settings=INSTANCED)
    assert np.array_equal(hits.prim, h_prim)
    # leave each hit by the mirror direction, from the renderer's offset origin
    n = hits.normal
    r = d - 2 * np.sum(d * n, axis=1, keepdims=True) * n
    start = scene.spawn_origins(o, d, hits, r.astype(np.float32))
    again = scene.intersect(start, r.astype(np.float32), settings=INSTANCED, spawned=True)
    back = (again.kind == 1) & (again.prim == h_prim) & (again.t < 1e-3)
    assert back.sum() == 0
    assert not scene.occluded(start, r.astype(np.float32), tmax=1e-3, settings=INSTANCED, spawned=True).any()


def test_a_render_of_copies_matches_the_flat_grids_render():
    kw = scattered(n=300, extent=6.0)
    camera = gw.Camera(eye=(0, -14, 9), target=(0, 0, 0.3), up=(0, 0, 1), fov=45, width=96, height=72)
    scene = gw.Scene(**kw, camera=camera, materials=[gw.Material(color=(0.7, 0.6, 0.5), mirror=0.3)],
                     lights=[gw.Light(position=(4, -6, 12), color=(1, 1, 1))])

    def render(settings):
        job = gw.RenderJob(scene, settings.replace(aa="jittered", aa_samples=2)).start()
        job.wait()
        return job.image
    a, b = render(INSTANCED), render(FLAT)
    assert scene.grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
    assert np.array_equal(a, render(INSTANCED.replace(threads=1, tile_size=7)))   # any threads and tiles
    assert a.std() > 0.05                              # a real picture (copies, floor, shadows)
    differ = np.abs(a - b).max(axis=2) > 2 / 255
    assert differ.mean() < 0.002, f"{differ.sum()} pixels differ"


def test_a_copy_moved_in_the_viewport_stays_a_copy_where_it_now_is():
    # Scene.moved (a transform edit) gives a moved instance its new matrix: the next
    # structure is instanced again, and finds the copy in its new place.
    kw = scattered(n=200, mirrored_every=0)
    scene = gw.Scene(**kw)
    assert scene.grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
    m = kw["instance_matrices"][3]
    start, count = (int(x) for x in kw["instance_triangles"][3])
    first_vertex = int(kw["triangles"][start].min())
    positions = icosphere(1, dtype=np.float64)[0]
    moved_m = m.copy()
    moved_m[:3, 3] += [3.0, 0.0, 0.0]
    moved = scene.moved([gw.InstanceMove(first_vertex, start, count, positions, moved_m, previous_matrix=m)])
    info = moved.grid_info(INSTANCED)
    # (with its old matrix kept, the moved copy would no longer match its mesh: the note would count it)
    assert info["kind"] == "instanced adaptive grid" and "did not match" not in info["note"], info["note"]
    centre = moved_m[:3, 3].astype(np.float32)
    rng = np.random.default_rng(4)
    o = (centre + rng.normal(0, 1, (2000, 3)) + [0, 0, 4]).astype(np.float32)
    d = (centre + rng.normal(0, 0.1, (2000, 3)) - o).astype(np.float32)
    a = moved.intersect(o, d, settings=INSTANCED)
    brute = moved.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    on_it = (brute.kind == 1) & (brute.prim >= start) & (brute.prim < start + count)
    assert on_it.sum() > 500
    assert (a.prim[on_it] == brute.prim[on_it]).mean() > 0.995
    np.testing.assert_allclose(a.t[on_it], brute.t[on_it], rtol=0, atol=1e-4)


@pytest.mark.parametrize("change, message", [
    (dict(instance_meshes=None), "all three or none"),
    (dict(instance_triangles=np.array([[0, 80], [40, 80]]), instance_meshes=np.array([0, 0]),
          instance_matrices=np.stack([np.eye(4)] * 2)), "overlap"),
    (dict(instance_triangles=np.array([[0, 10 ** 9]]), instance_meshes=np.array([0]),
          instance_matrices=np.eye(4)[None]), "lie beyond"),
    (dict(instance_triangles=np.array([[0, 80]]), instance_meshes=np.array([0]),
          instance_matrices=np.full((1, 4, 4), np.nan)), "non-finite"),
    (dict(instance_triangles=np.array([[-1, 80]]), instance_meshes=np.array([0]),
          instance_matrices=np.eye(4)[None]), ">= 0"),
    (dict(instance_meshes=np.array([-1] * 400)), "instance_meshes"),
    (dict(instance_matrices=np.zeros((400, 3, 4))), "instance_matrices must have shape"),
    (dict(instance_matrices=np.zeros((400, 4, 4), complex)), "of real numbers"),   # (the API fuzzer's find)
    (dict(instance_triangles=np.zeros((400, 3), np.int64)), "instance_triangles must be"),
])
def test_bad_instances_are_refused_with_a_clear_error(change, message):
    kw = scattered()
    kw.update(change)
    with pytest.raises(ValueError, match=message):
        gw.Scene(**kw)


def leaves(places, mesh=((-1, -1, 0), (1, -1, 0), (0, 1, 0))):
    """One triangle copied to `places` (translations), each declared a copy: the kwargs."""
    base = np.asarray(mesh, np.float64)
    verts, mats = [], []
    for place in places:
        m = np.eye(4)
        m[:3, 3] = place
        verts.append((base + m[:3, 3]).astype(np.float32))
        mats.append(m)
    v = np.concatenate(verts)
    return dict(vertices=v, triangles=np.arange(len(v), dtype=np.int32).reshape(-1, 3),
                instance_triangles=np.array([(i, 1) for i in range(len(places))]),
                instance_meshes=np.zeros(len(places), np.int32), instance_matrices=np.array(mats))


def test_a_copy_far_from_its_first_casts_contact_shadows():
    # Copies 141 units from the origin, their mesh's first copy at it: a shadow ray
    # leaving a surface 0.1 mm below a copy is blocked, as in the flat grid (the skip
    # along spawned rays was 64 float spacings and lost it below about 1 mm).
    scene = gw.Scene(**leaves([(0, 0, 0)] + [(100.0 + 3 * i, 100.0, 1.0) for i in range(1, 4)]))
    assert scene.grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
    for gap in (1e-2, 5e-4, 1e-4):
        o = np.array([[103.0, 100.0, 1.0 - gap]], np.float32)
        up = np.array([[0, 0, 1]], np.float32)
        for settings in (INSTANCED, FLAT):
            assert scene.occluded(o, up, settings=settings, spawned=True)[0], (gap, settings.instancing)
            assert scene.intersect(o, up, settings=settings, spawned=True).prim[0] == 1


def test_a_small_copy_of_another_shape_far_from_the_origin_is_refused():
    # 1 mm triangles at 100: one copy's corner moved by 0.7 mm is not a copy (the
    # tolerance is a few float spacings of the coordinates, not 2^-18 of them).
    kw = leaves([(100.0, 100.0, 100.0 + i) for i in range(3)], mesh=((0, 0, 0), (1e-3, 0, 0), (0, 1e-3, 0)))
    kw["vertices"][7] = (np.array([100.0005, 100.0007, 102.0]) ).astype(np.float32)
    scene = gw.Scene(**kw)
    info = scene.grid_info(INSTANCED)
    assert info["kind"] == "adaptive grid" or "did not match" in info["note"]
    o, d = np.array([[100.0009, 100.00005, 105]], np.float32), np.array([[0, 0, -1]], np.float32)
    brute = scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert brute.prim[0] == 1                       # outside the changed copy, through the next one
    assert scene.intersect(o, d, settings=INSTANCED).prim[0] == 1


def test_mesh_ids_may_be_any_non_negative_int32():
    # (ids were indices into tables sized by the largest: 2^31 - 1 asked for 24 GiB)
    kw = scattered(n=50)
    kw["instance_meshes"] = np.where(kw["instance_meshes"] == 0, 2 ** 31 - 1, 7 * 10 ** 8).astype(np.int64)
    scene = gw.Scene(**kw)
    assert scene.grid_info(INSTANCED)["note"].startswith("48 copies of 2 meshes")


def test_a_ray_from_far_away_with_a_tiny_sideways_step_starts_in_the_right_cell():
    # 50 thin copies 0.02 apart along x beside a triangle 1e6 across; a ray from
    # y = 1e12 whose x component (5e-13 of its y) the DDA's direction drops still moves
    # it by 0.5 along x before it reaches them: the walk must start where it really is.
    kw = leaves([(0.02 * i, 0, 0) for i in range(50)], mesh=((-0.003, 0, 0), (0.003, 0, 0), (0, 0, 1)))
    big = np.array([[-5e5, -5e5, -5e5], [5e5, -5e5, -5e5], [0, -5e5, 5e5]], np.float32)
    kw["triangles"] = np.concatenate([kw["triangles"], [[150, 151, 152]]]).astype(np.int32)
    kw["vertices"] = np.concatenate([kw["vertices"], big])
    scene = gw.Scene(**kw)
    assert scene.grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
    o = np.array([[0, 1e12, 0.3]], np.float32)
    d = np.array([[0.5 / 1e12, -1.0, 0.0]], np.float32)
    brute = scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert brute.kind[0] == 1 and brute.prim[0] == 25
    assert scene.intersect(o, d, settings=INSTANCED).prim[0] == 25


def test_copies_crowding_into_a_few_cells_get_the_flat_grid():
    # 2,000 copies within 20 units and one 1e5 away: the grid over the copies, sized by
    # their whole box, would list the cluster in one cell, which every ray into it would
    # clip copy by copy (37x the flat grid's time); the flat adaptive grid refines there.
    kw = scattered(n=2000, extent=10.0, mirrored_every=0)
    start, count = kw["instance_triangles"][-1]
    far = np.unique(kw["triangles"][start:start + count])
    kw["vertices"] = kw["vertices"].copy()
    kw["vertices"][far] += np.float32(1e5)
    kw["instance_matrices"] = kw["instance_matrices"].copy()
    kw["instance_matrices"][-1][:3, 3] += 1e5
    scene = gw.Scene(**kw)
    assert scene.grid_info(INSTANCED)["kind"] == "adaptive grid"
    # (without the far copy the same copies are instanced)
    kw2 = scattered(n=2000, extent=10.0, mirrored_every=0)
    assert gw.Scene(**kw2).grid_info(INSTANCED)["kind"] == "instanced adaptive grid"
