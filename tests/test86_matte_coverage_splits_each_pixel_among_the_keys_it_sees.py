"""Matte coverage (RenderSettings.matte_ranks, Scene(matte_keys=...)): per
pixel the keys its camera samples meet, most first, with the share of the
pixel each covers: what the Blender add-on turns into Cryptomatte passes."""
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
    k, c = job.matte_keys, job.matte_coverage
    assert k.shape == c.shape == (48, 48, 4) and k.dtype == np.int32
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
    k, c = job.matte_keys[24, 14], job.matte_coverage[24, 14]
    assert k.tolist() == [0, 1]
    np.testing.assert_allclose(c, [0.75, 0.25], atol=1e-6)


def test_depth_of_field_spreads_an_edge_over_more_pixels():
    kw, keys = two_quads()
    sharp = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=3, aa="jittered", aa_samples=2)
    kw["camera"] = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=48, height=48,
                             aperture=0.6, focus_distance=12.0)
    blurred = render(gw.Scene(**kw, matte_keys=keys), matte_ranks=3, aa="jittered", aa_samples=2, dof_samples=8)
    mixed = lambda job: int(((job.matte_coverage[..., 0] > 0.02) & (job.matte_coverage[..., 0] < 0.98)).sum())
    assert mixed(blurred) > 2 * mixed(sharp)
    np.testing.assert_allclose(blurred.matte_coverage.sum(-1), blurred.image[..., 3], atol=1e-5)


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
    assert job.matte_keys.shape == (48, 48, 0)
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


@pytest.mark.parametrize("keys, message", [([0, 0, 1], "matte_keys must have one entry per primitive (5"),
                                           ([0, 0, 1, 1, -2], "matte_keys[4] is -2"),
                                           ([0.5, 0, 1, 1, 2], "matte_keys must be an integer array")])
def test_bad_keys_are_refused_naming_the_array(keys, message):
    kw, _ = two_quads()
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("(", r"\(")):
        gw.Scene(**kw, matte_keys=keys)
