"""Anti-aliasing strategies on a hard-edged scene: stratification beats random
sampling at equal sample counts, and adaptive supersampling spends its rays on
edges only."""
import numpy as np
import pytest

import gridwalk as gw


def edge_scene(res=64):
    """Self-lit shapes with hard edges on black: a tilted triangle and a sphere."""
    V = np.array([[-2, 0, -1.5], [2.2, 0, -0.4], [-0.5, 0, 2.0]], np.float32)
    white = gw.Material(color=(1, 1, 1), kd=0.0, emission=1.0)
    red = gw.Material(color=(1, 0.2, 0.1), kd=0.0, emission=1.0)
    cam = gw.Camera(eye=(0, -6, 0), target=(0, 0, 0), fov=40, width=res, height=res)
    return gw.Scene(vertices=V, triangles=[[0, 1, 2]], triangle_materials=[0], sphere_centers=[[1.0, -1, 1.0]],
                    sphere_radii=[0.8], sphere_materials=[1], materials=[white, red], camera=cam)


@pytest.fixture(scope="module")
def reference():
    return gw.render(edge_scene(), gw.RenderSettings(aa="jittered", aa_samples=32))[..., :3]


def rmse(img, ref):
    return float(np.sqrt(np.mean((img[..., :3] - ref) ** 2)))


def mean_rmse(mode, n, ref, seeds=6):
    return np.mean([rmse(gw.render(edge_scene(), gw.RenderSettings(aa=mode, aa_samples=n, seed=s)), ref)
                    for s in range(seeds)])


def test_jittered_beats_random_at_equal_samples(reference):
    for n in (2, 4):
        assert mean_rmse("jittered", n, reference) < 0.8 * mean_rmse("random", n, reference)


def test_owen_scrambled_sobol_beats_random(reference):
    assert mean_rmse("sobol", 4, reference) < 0.8 * mean_rmse("random", 4, reference)


def test_more_samples_converge_to_the_reference(reference):
    errs = [mean_rmse("jittered", n, reference, seeds=3) for n in (1, 2, 4, 8)]
    assert all(a > b for a, b in zip(errs, errs[1:])), errs


def test_adaptive_subdivides_only_at_edges(reference):
    sc = edge_scene()
    job = gw.RenderJob(sc, gw.RenderSettings(aa="adaptive", adaptive_depth=3, adaptive_threshold=0.02)).start()
    img = job.wait()
    rays = job.stats["primary_rays"]
    corners = 65 * 65
    assert corners < rays < 0.25 * 64 * 64 * 81   # far fewer than subdividing every pixel fully
    center = gw.render(sc, gw.RenderSettings(aa="center"))
    assert rmse(img, reference) < 0.5 * rmse(center, reference)
    # Flat regions keep the corner average: a pixel far from any edge equals the reference.
    assert np.allclose(img[2, 2, :3], reference[2, 2], atol=1e-6)


def test_adaptive_shares_corners_between_tiles():
    a = gw.render(edge_scene(), gw.RenderSettings(aa="adaptive", tile_size=64, threads=1))
    b = gw.render(edge_scene(), gw.RenderSettings(aa="adaptive", tile_size=5, threads=3))
    assert np.array_equal(a, b)


def test_adaptive_error_keeps_falling_with_depth(reference):
    """Every lattice point is jittered within the finest cell, so an edge that
    crosses a pixel is always detected by its corners: no error floor."""
    errs = [np.mean([rmse(gw.render(edge_scene(), gw.RenderSettings(aa="adaptive", adaptive_depth=d,
                                                                    adaptive_threshold=0.02, seed=s)), reference)
                     for s in range(3)]) for d in (1, 2, 3, 4)]
    assert all(a > b for a, b in zip(errs, errs[1:])), errs
