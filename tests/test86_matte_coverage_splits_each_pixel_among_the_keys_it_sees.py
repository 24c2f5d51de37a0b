"""Matte coverage (RenderSettings.matte_ranks, Scene(matte_keys=...)): per
pixel and per layer of keys, the keys its camera samples meet, most first,
with the share of the pixel each covers: what the Blender add-on turns into
Cryptomatte passes (one layer for objects, one for materials, ...)."""
import numpy as np
import pytest

import gridwalk as gw


def two_quads(front_alpha=1.0, size=48):
    """A floor quad (key 0) filling the view, and a smaller quad (key 1) in
    front of its left half; a third key (2) on a sphere at the right."""
    v = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0],
                  [-2.5, -1.5, 1], [-0.3, -1.5, 1], [-0.3, 1.5, 1], [-2.5, 1.5, 1]], np.float32)
    t = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]], np.int32)
    materials = [gw.Material(color=(0.5, 0.5, 0.5)), gw.Material(color=(0.8, 0.2, 0.2), alpha=front_alpha)]
    camera = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=size, height=size)
    kw = dict(vertices=v, triangles=t, triangle_materials=[0, 0, 1, 1], sphere_centers=[[2.0, 0.0, 0.5]],
              sphere_radii=[1.0], materials=materials, camera=camera,
              lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])
    return kw, np.array([0, 0, 1, 1, 2], np.int32)


def render(scene, **settings):
    job = gw.RenderJob(scene, gw.RenderSettings(**settings))
    job.start()
    job.wait()
    return job


@pytest.mark.parametrize("mode", [dict(aa="jittered", aa_samples=4), dict(aa="sobol", aa_samples=3),
                                  dict(aa="adaptive", adaptive_depth=2, adaptive_threshold=0.0)])
def test_coverage_of_the_keys_adds_up_to_the_pixels_alpha(mode):
    kw, keys = two_quads()
    job = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=4, **mode)
    k, c = job.matte_keys[:, :, 0], job.matte_coverage[:, :, 0]
    assert job.matte_keys.shape == job.matte_coverage.shape == (48, 48, 1, 4) and k.dtype == np.int32
    np.testing.assert_allclose(c.sum(-1), job.image[..., 3], atol=1e-5)
    assert np.all(np.diff(c, axis=-1) <= 0), "ranks are ordered by coverage, most first"
    assert np.all((k >= 0) == (c > 0)), "a rank without coverage has no key"
    assert set(np.unique(k).tolist()) == {-1, 0, 1, 2}
    # inside each object its key alone, at full coverage
    for (y, x), key in (((24, 14), 1), ((24, 36), 2), ((3, 3), 0)):
        assert k[y, x, 0] == key and c[y, x, 0] == pytest.approx(1.0)
    covered = job.image[..., 3] > 0.999
    edges = (c[..., 0] > 0.05) & (c[..., 0] < 0.95) & covered
    assert edges.sum() > 20, "the quad's and the sphere's edges split their pixels"
    assert np.all(k[edges][:, 1] >= 0), "a pixel split between two objects has both keys"
    assert np.any((c[..., 0] > 0.05) & ~covered), "the floor's edge shares pixels with the background" 


def test_a_partly_covering_surface_shares_its_pixels_with_what_lies_behind():
    kw, keys = two_quads(front_alpha=0.25)
    job = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=2, aa="jittered", aa_samples=2)
    k, c = job.matte_keys[24, 14, 0], job.matte_coverage[24, 14, 0]
    assert k.tolist() == [0, 1]
    np.testing.assert_allclose(c, [0.75, 0.25], atol=1e-6)


def test_every_surface_behind_see_through_ones_keeps_its_share():
    kw, keys = two_quads(front_alpha=0.5)
    v = np.concatenate([kw["vertices"], kw["vertices"][4:] + [0, 0, 0.5]]).astype(np.float32)
    kw.update(vertices=v, triangles=np.concatenate([kw["triangles"], [[8, 9, 10], [8, 10, 11]]]).astype(np.int32),
              triangle_materials=[0, 0, 1, 1, 1, 1])
    keys = np.array([0, 0, 1, 1, 3, 3, 2], np.int32)
    for mode in (dict(aa="center"), dict(aa="adaptive", adaptive_depth=1)):
        job = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=3, **mode)
        k, c = job.matte_keys[24, 14, 0], job.matte_coverage[24, 14, 0]
        assert k.tolist() == [3, 0, 1]           # 0.5 the top quad, then 0.25 each (ties: the smaller key first)
        np.testing.assert_allclose(c, [0.5, 0.25, 0.25], atol=1e-6)


def test_depth_of_field_spreads_an_edge_over_more_pixels():
    kw, keys = two_quads()
    sharp = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=3, aa="jittered", aa_samples=2)
    kw["camera"] = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=48, height=48,
                             aperture=0.6, focus_distance=12.0)
    blurred = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=3, aa="jittered", aa_samples=2, dof_samples=8)
    mixed = lambda job: int(((job.matte_coverage[..., 0, 0] > 0.02) & (job.matte_coverage[..., 0, 0] < 0.98)).sum())
    assert mixed(blurred) > 2 * mixed(sharp)
    np.testing.assert_allclose(blurred.matte_coverage[:, :, 0].sum(-1), blurred.image[..., 3], atol=1e-5)
    # Whitted-adaptive sampling: every lens ray of every lattice point counts
    adaptive = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=3, aa="adaptive", adaptive_depth=2,
                      adaptive_threshold=0.0, dof_samples=8)
    np.testing.assert_allclose(adaptive.matte_coverage[:, :, 0].sum(-1), adaptive.image[..., 3], atol=1e-5)


def test_each_layer_merges_its_keys_before_keeping_the_ranks():
    # twelve thin slats side by side under one pixel: twelve objects (layer 0), one material (layer 1)
    slats = 12
    x = np.linspace(-0.004, 0.004, slats + 1)     # (the middle pixel is 0.005 wide: 7-8 slats)
    v = np.array([[[x[i], -0.5, 1], [x[i + 1], -0.5, 1], [x[i + 1], 0.5, 1], [x[i], 0.5, 1]] for i in range(slats)],
                 np.float32).reshape(-1, 3)
    t = np.array([[[4 * i, 4 * i + 1, 4 * i + 2], [4 * i, 4 * i + 2, 4 * i + 3]] for i in range(slats)],
                 np.int32).reshape(-1, 3)
    camera = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=0.1, width=3, height=3)
    keys = np.stack([np.repeat(np.arange(slats), 2), np.zeros(2 * slats, int)], axis=1)
    job = render(gw.Scene(vertices=v, triangles=t, camera=camera, matte_keys=keys), matte_ranks=4,
                 aa="jittered", aa_samples=8)
    k, c = job.matte_keys[1, 1], job.matte_coverage[1, 1]
    assert job.image[1, 1, 3] == 1.0
    assert (c[0] > 0).all() and c[0].sum() < 0.6      # four of twelve slats kept in the object layer
    assert k[1].tolist() == [0, -1, -1, -1] and c[1, 0] == pytest.approx(1.0)   # the material whole


def test_mattes_are_the_same_on_any_number_of_threads():
    kw, keys = two_quads()
    scene = gw.Scene(**kw, matte_keys=keys)
    one = render(scene, matte_ranks=3, aa="jittered", aa_samples=3, threads=1, tile_size=8)
    three = render(scene, matte_ranks=3, aa="jittered", aa_samples=3, threads=3, tile_size=16)
    assert np.array_equal(one.matte_keys, three.matte_keys)
    assert np.array_equal(one.matte_coverage, three.matte_coverage)


def test_without_ranks_or_keys_nothing_is_recorded():
    kw, keys = two_quads()
    job = render(gw.Scene(**kw, matte_keys=keys), aa="jittered", aa_samples=2)
    assert job.matte_keys.shape == (48, 48, 1, 0)
    tiles = gw.RenderJob(gw.Scene(**kw), gw.RenderSettings(tile_size=48)).start()
    tiles.wait()
    assert "matte_keys" not in (tiles.poll()[0].passes or {})
    unkeyed = render(gw.Scene(**kw), matte_ranks=2)          # no keys: every rank empty
    assert np.all(unkeyed.matte_keys == -1) and not unkeyed.matte_coverage.any()


def test_tiles_carry_their_mattes():
    kw, keys = two_quads()
    job = gw.RenderJob(gw.Scene(**kw, matte_keys=keys), gw.RenderSettings(matte_ranks=2, tile_size=16)).start()
    job.wait()
    tiles = job.poll()
    assert len(tiles) == 9
    for tile in tiles:
        part = (slice(tile.y, tile.y + tile.height), slice(tile.x, tile.x + tile.width))
        assert np.array_equal(tile.passes["matte_keys"], job.matte_keys[part])
        assert np.array_equal(tile.passes["matte_coverage"], job.matte_coverage[part])


@pytest.mark.parametrize("keys, message", [([0, 0, 1], "matte_keys must have one row per primitive (5"),
                                           ([0, 0, 1, 1, -2], "matte_keys[4] is -2"),
                                           ([[0, 1]] * 4 + [[2, -3]], "matte_keys[4, 1] is -3"),
                                           ([[0] * 5] * 5, "matte_keys must have 1 to 4 keys per primitive"),
                                           ([0.5, 0, 1, 1, 2], "matte_keys must be an integer array")])
def test_bad_keys_are_refused_naming_the_array(keys, message):
    kw, _ = two_quads()
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("(", r"\(")):
        gw.Scene(**kw, matte_keys=keys)


@pytest.mark.parametrize("mode", [dict(aa="center"), dict(aa="adaptive", adaptive_depth=1)])
def test_many_triangles_of_one_object_under_many_lens_rays_keep_their_coverage(mode):
    # a 120 x 120-quad floor of one key: 64 lens rays a sample each meet a different triangle
    n = 120
    g = np.linspace(-4, 4, n + 1, dtype=np.float32)
    x, y = np.meshgrid(g, g)
    v = np.stack([x, y, np.zeros_like(x)], -1).reshape(-1, 3)
    i = (np.arange(n)[:, None] * (n + 1) + np.arange(n)[None, :]).reshape(-1)
    t = np.concatenate([np.stack([i, i + 1, i + n + 2], 1), np.stack([i, i + n + 2, i + n + 1], 1)]).astype(np.int32)
    camera = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=30, width=8, height=8,
                       aperture=0.3, focus_distance=3.0)
    scene = gw.Scene(vertices=v, triangles=t, camera=camera, matte_keys=np.zeros(len(t), np.int32))
    job = render(scene, matte_ranks=2, dof_samples=64, **mode)
    assert job.image[..., 3].min() > 0.99
    np.testing.assert_allclose(job.matte_coverage[:, :, 0, 0], job.image[..., 3], atol=1e-5)
    assert np.all(job.matte_keys[:, :, 0, 0] == 0)
