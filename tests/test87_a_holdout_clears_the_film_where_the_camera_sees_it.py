"""Material(holdout=True), Cycles' Holdout: camera rays that meet it see
black and leave the film clear there (RenderJob.holdout gives each pixel's
share; alpha leaves it out); it still casts shadows."""
import numpy as np
import pytest

import gridwalk as gw


def scene(holdout=True, mirror_floor=False):
    v = np.array([[-40, -40, 0], [40, -40, 0], [40, 40, 0], [-40, 40, 0],     # a floor filling the view
                  [-2, -1.5, 1], [0, -1.5, 1], [0, 1.5, 1], [-2, 1.5, 1]], np.float32)
    t = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]], np.int32)
    floor = gw.Material(color=(0.5, 0.5, 0.5), mirror=0.8 if mirror_floor else 0.0)
    materials = [floor, gw.Material(holdout=holdout, color=(0.9, 0.2, 0.2))]
    camera = gw.Camera(eye=(0, -3, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=48, height=48)
    return gw.Scene(vertices=v, triangles=t, triangle_materials=[0, 0, 1, 1], materials=materials, camera=camera,
                    lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])


def render(sc, **settings):
    job = gw.RenderJob(sc, gw.RenderSettings(**settings)).start()
    job.wait()
    return job


@pytest.mark.parametrize("mode", [dict(aa="jittered", aa_samples=3), dict(aa="adaptive", adaptive_threshold=0.0)])
def test_the_holdout_is_black_and_clear_and_its_share_is_reported(mode):
    job = render(scene(), **mode)
    image, held = job.image, job.holdout
    assert held.shape == (48, 48)
    inside = held > 0.999
    assert 100 < inside.sum() < 600
    assert np.all(image[inside] == 0)                             # black and alpha 0
    edge = (held > 0.05) & (held < 0.95)
    assert edge.sum() > 10
    # each sample either meets the holdout or something else: the shares add up to the coverage
    full = image[..., 3] + held
    assert np.all(full <= 1 + 1e-6)
    assert np.allclose(full, 1.0, atol=1e-6)                      # (every sample meets the floor or the holdout)
    assert not held[:, 36:].any() and not held[40:].any()        # away from the quad: no holdout


def test_a_holdout_still_casts_its_shadow_and_reflections_see_it_black():
    sc = scene(mirror_floor=True)
    held, plain = render(sc, aa="center"), render(scene(holdout=False, mirror_floor=True), aa="center")
    clear = held.holdout > 0.5
    # the floor beside the holdout (its shadow falls straight down: the light is overhead)
    shadowed = ~clear & (plain.image[..., 0] < 0.05) & (held.image[..., 3] > 0.99)
    assert shadowed.sum() > 0, "the holdout's shadow on the floor"
    assert np.array_equal(held.image[~clear][..., :3] <= plain.image[~clear][..., :3] + 1e-6,
                          np.ones_like(held.image[~clear][..., :3], bool))


def test_no_holdout_no_array():
    job = render(scene(holdout=False), aa="center")
    assert job.holdout is None
    assert np.all(job.image[..., 3] == 1.0)


def test_the_viewport_clears_an_opaque_film_where_a_holdout_is():
    import time
    sc = scene()
    final = render(sc, aa="center")
    r = gw.ProgressiveRenderer()
    try:
        rid, _ = r.submit(sc, [(1, gw.RenderSettings(aa="center"), sc.camera)], 48, 48, opaque=True)
        end = time.monotonic() + 60
        while r.status["finished"] != rid:
            assert time.monotonic() < end, r.status
            time.sleep(0.005)
        img = r.image()[1][::-1]                     # (rows come bottom-up, as Blender draws them)
    finally:
        r.stop()
    np.testing.assert_allclose(img[..., 3], 1.0 - final.holdout, atol=1e-6)
    assert (img[..., 3] == 0).sum() > 100


def test_an_object_held_out_from_the_camera_is_still_seen_by_other_rays():
    mirror = gw.Material(color=(0.9, 0.9, 0.9), kd=0.0, mirror=1.0)

    def with_quad(**flags):
        v = np.array([[-40, -40, 0], [40, -40, 0], [40, 40, 0], [-40, 40, 0],
                      [-2, -1.5, 1], [0, -1.5, 1], [0, 1.5, 1], [-2, 1.5, 1]], np.float32)
        t = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]], np.int32)
        quad = gw.Material(color=(0.9, 0.1, 0.1), emission=1.0, **flags)   # (its underside glows in the mirror)
        camera = gw.Camera(eye=(0, -3, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=48, height=48)
        sc = gw.Scene(vertices=v, triangles=t, triangle_materials=[0, 0, 1, 1], materials=[mirror, quad],
                      camera=camera, lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])
        return render(sc, aa="center")

    red = lambda job: ((job.image[..., 0] - job.image[..., 1]) > 0.3) & (job.holdout < 0.5)
    camera_only, everywhere = with_quad(holdout_camera=True), with_quad(holdout=True)
    assert camera_only.holdout.sum() == everywhere.holdout.sum() > 100     # the same pixels held out
    assert red(camera_only).sum() > 10 and not red(everywhere).any()      # the mirror shows it, or black
    # an alpha cut-out held out from the camera keeps its holes: the mirror floor shows through them
    cut = with_quad(holdout_camera=True, alpha=0.5)
    held = cut.holdout[cut.holdout > 0]
    np.testing.assert_allclose(held[held > 0.45].mean(), 0.5, atol=0.02)
