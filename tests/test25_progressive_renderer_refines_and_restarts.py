"""gridwalk.ProgressiveRenderer, the native controller behind Blender's
Rendered viewport: its image is exactly the average of the RenderJobs its
passes stand for, rows run bottom-up, a coarse pass paints blocks, values
stay below the half-float maximum the viewport's texture holds, a newer
request cancels the running one, and stop() joins its native thread."""
import dataclasses
import time

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls
from thread_names import thread_names

W, H = 48, 32


def wait_finished(r: gw.ProgressiveRenderer, request: int, timeout: float = 60) -> dict:
    end = time.monotonic() + timeout
    while r.status["finished"] != request:
        assert time.monotonic() < end, f"request {request} did not finish: {r.status}"
        time.sleep(0.005)
    return r.status


@pytest.fixture(scope="module")
def scene():
    sc = gw.Scene(**balls(2))
    return sc, dataclasses.replace(sc.camera, width=W, height=H)


def averaged_reference(sc, settings, camera, n):
    ref = np.zeros((camera.height, camera.width, 4), np.float32)
    for i in range(n):
        ref += gw.RenderJob(sc, settings.replace(seed=settings.seed + i), camera=camera).start().wait()
    ref /= n
    ref[..., 3] = 1
    return ref


def test_fine_passes_average_to_the_render_jobs_they_stand_for(scene):
    sc, cam = scene
    s = gw.RenderSettings(threads=2, aa="random", aa_samples=1, seed=7)
    r = gw.ProgressiveRenderer()
    try:
        rid, structures = r.submit(sc, [(1, s, cam, 3)], W, H)
        status = wait_finished(r, rid)
        assert status["error"] == "" and status["passes_done"] == 3 and structures == [0]
        version, img = r.image()
        assert img.shape == (H, W, 4) and version == status["version"]
        ref = averaged_reference(sc, s, cam, 3)
        assert np.abs(img[::-1] - ref).max() <= 1e-6     # rows come bottom-up, as Blender draws them
        assert img[..., :3].std() > 0.05                 # a picture, not a blank
    finally:
        r.stop()


def test_a_coarse_pass_paints_each_pixel_over_a_block(scene):
    sc, cam = scene
    s = gw.RenderSettings(threads=2, aa="center")
    small = dataclasses.replace(cam, width=-(-W // 5), height=-(-H // 5))
    r = gw.ProgressiveRenderer()
    try:
        rid, _ = r.submit(sc, [(5, s, small)], W, H)
        wait_finished(r, rid)
        _, img = r.image()
        coarse = gw.RenderJob(sc, s, camera=small).start().wait()
        coarse[..., 3] = 1
        expected = np.repeat(np.repeat(coarse, 5, 0), 5, 1)[:H, :W]
        np.testing.assert_array_equal(img[::-1], expected)
    finally:
        r.stop()


def test_values_stay_below_the_half_float_maximum(scene):
    sc, cam = scene
    data = balls(2)
    data["lights"] = [dataclasses.replace(light, color=tuple(1e9 * c for c in light.color)) for light in data["lights"]]
    blinding = gw.Scene(**data)
    s = gw.RenderSettings(threads=2, aa="center")
    r = gw.ProgressiveRenderer()
    try:
        rid, _ = r.submit(blinding, [(1, s, cam)], W, H)
        wait_finished(r, rid)
        img = r.image()[1]
        raw = gw.RenderJob(blinding, s, camera=cam).start().wait()
        assert raw[..., :3].max() > 1e6                               # the unclamped render is far above it
        limit = img.max()
        assert np.isfinite(img).all() and 60000 < limit < np.finfo(np.float16).max
        assert np.isfinite(img.astype(np.float16)).all()               # what the RGBA16F texture holds
        assert (img[..., :3] == limit).sum() == (raw[..., :3] >= limit).sum()   # bright pixels stay bright
        dim = raw[::-1] < limit                                        # ordinary values pass untouched
        np.testing.assert_array_equal(img[..., :3][dim[..., :3]], raw[::-1][..., :3][dim[..., :3]])
    finally:
        r.stop()


def test_a_newer_request_cancels_the_running_one(scene):
    sc, cam = scene
    s = gw.RenderSettings(threads=2, aa="random", aa_samples=1)
    r = gw.ProgressiveRenderer()
    try:
        endless, _ = r.submit(sc, [(1, s, cam, 10**6)], W, H)      # would run for hours
        while r.status["passes_done"] < 2:
            time.sleep(0.005)
        for _ in range(30):                                          # a storm of edits, none waited for
            r.submit(sc, [(1, s, cam, 10**6)], W, H)
        last, _ = r.submit(sc, [(1, s, cam, 2)], W, H)
        status = wait_finished(r, last, timeout=30)
        assert status["error"] == "" and status["request"] == last and status["passes_done"] == 2
        assert endless != last
        np.testing.assert_allclose(r.image()[1][::-1], averaged_reference(sc, s, cam, 2), atol=1e-6)
    finally:
        r.stop()


def test_stop_joins_the_native_thread_and_refuses_later_work(scene):
    sc, cam = scene
    r = gw.ProgressiveRenderer()
    assert "gridwalk-view" in thread_names()
    r.submit(sc, [(1, gw.RenderSettings(threads=2), cam, 10**6)], W, H)
    time.sleep(0.05)
    r.stop()
    r.stop()                                                         # a second stop is harmless
    # A joined thread's /proc/self/task entry can outlive the join by a moment (the kernel
    # wakes the joiner as the thread exits, then removes the task): give it 1 s.
    end = time.monotonic() + 1.0
    while {"gridwalk-view", "gridwalk"} & set(thread_names()) and time.monotonic() < end:
        time.sleep(0.01)
    assert "gridwalk-view" not in thread_names()
    assert "gridwalk" not in thread_names()                          # nor any render thread
    with pytest.raises(RuntimeError, match="stopped"):
        r.submit(sc, [(1, gw.RenderSettings(), cam)], W, H)


def test_no_scene_clears_the_image(scene):
    sc, cam = scene
    r = gw.ProgressiveRenderer()
    try:
        rid, _ = r.submit(sc, [(1, gw.RenderSettings(threads=2), cam)], W, H)
        wait_finished(r, rid)
        assert r.image()[1][..., :3].max() > 0
        rid, _ = r.submit(None, [], W, H)
        wait_finished(r, rid)
        assert not r.image()[1].any()
    finally:
        r.stop()


def test_bad_passes_are_refused_with_a_reason(scene):
    sc, cam = scene
    s = gw.RenderSettings()
    r = gw.ProgressiveRenderer()
    try:
        with pytest.raises(ValueError, match="block must be at least 1"):
            r.submit(sc, [(0, s, cam)], W, H)
        with pytest.raises(ValueError, match="repeat must be at least 1"):
            r.submit(sc, [(1, s, cam, 0)], W, H)
        with pytest.raises(ValueError, match=r"needs a 49 x 32 camera, got 48 x 32"):
            r.submit(sc, [(1, s, cam)], W + 1, H)
        with pytest.raises(ValueError, match=r"\(block, gridwalk.RenderSettings, gridwalk.Camera"):
            r.submit(sc, [(1, cam, s)], W, H)
        with pytest.raises(ValueError, match="gridwalk.Scene or None"):
            r.submit("scene", [(1, s, cam)], W, H)
        with pytest.raises(ValueError, match="at least 1 x 1"):
            r.submit(sc, [], 0, H)
        # (an infinite delay overflowed the wait's deadline: stop() never returned)
        for delay in (float("inf"), 1e20, -1.0, float("nan")):
            with pytest.raises(ValueError, match="delay must be between 0 and 3600 seconds"):
                r.submit(sc, [(1, s, cam)], W, H, delay=delay)
        for limit in (-1.0, 0.0, float("nan")):
            with pytest.raises(ValueError, match="limit must be a positive number"):
                r.submit(sc, [(1, s, cam)], W, H, limit=limit)
    finally:
        t0 = time.perf_counter()
        r.stop()
        assert time.perf_counter() - t0 < 5.0


OUT_OF_MEMORY = """
import dataclasses, resource, sys, time
import gridwalk as gw
from gridwalk.scenes import balls

sc = gw.Scene(**balls(1))
n = 16384                                             # 2^28 pixels: allowed, 4 GiB of RGBA floats
camera = dataclasses.replace(sc.camera, width=n, height=n)
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
r = gw.ProgressiveRenderer()
rid, _ = r.submit(sc, [(1, gw.RenderSettings(), camera)], n, n)
end = time.monotonic() + 60
while not r.status["error"] and r.status["finished"] != rid and time.monotonic() < end:
    time.sleep(0.01)
print(r.status["error"])
r.stop()
sys.stdout.flush()
"""


def test_a_viewport_image_larger_than_memory_reports_out_of_memory():
    """A 16384 x 16384 viewport under a 3 GiB address-space limit: the
    controller reports what ran out (the status said only "std::bad_alloc")."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", OUT_OF_MEMORY], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == ("out of memory for a 16384 x 16384 image of this scene (its structure, its "
                                  "passes' images and their threads' buffers)"), out.stdout
