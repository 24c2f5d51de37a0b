"""The asynchronous render: tiles stream out exactly once, progress reaches 1,
cancel returns within 100 ms and leaves no worker thread behind, statistics
report Havran & Sixta's measures."""
import os
import time

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls
from thread_names import thread_names


def thread_count():
    return len(os.listdir("/proc/self/task"))


def render_threads():
    """The core's render threads of this process (they are named "gridwalk")."""
    return thread_names().count("gridwalk")


def scene(size=2, res=128):
    kw = balls(size)
    kw["camera"].width = kw["camera"].height = res
    return gw.Scene(**kw)


def test_polled_tiles_cover_the_image_exactly_once():
    sc = scene()
    job = gw.RenderJob(sc, gw.RenderSettings(tile_size=16, threads=2)).start()
    seen = np.zeros((128, 128), int)
    canvas = np.zeros((128, 128, 4), np.float32)
    while True:
        done = job.finished
        for t in job.poll():
            seen[t.y:t.y + t.height, t.x:t.x + t.width] += 1
            canvas[t.y:t.y + t.height, t.x:t.x + t.width] = t.rgba
        if done:
            break
        time.sleep(0.005)
    final = job.wait()
    for t in job.poll():
        seen[t.y:t.y + t.height, t.x:t.x + t.width] += 1
        canvas[t.y:t.y + t.height, t.x:t.x + t.width] = t.rgba
    assert np.all(seen == 1)
    assert job.progress == 1.0 and job.tiles_done == job.tiles_total == 64
    assert np.array_equal(canvas, final)


def test_cancel_returns_within_100ms_and_stops_all_workers():
    sc = scene(size=3, res=512)
    before = thread_count()
    slow = gw.RenderSettings(aa="jittered", aa_samples=6, shadow="random", shadow_samples=4, threads=4)
    job = gw.RenderJob(sc, slow).start()
    deadline = time.time() + 30
    while job.tiles_done < 1 and time.time() < deadline:   # cancel mid-render, after some tiles
        time.sleep(0.01)
    assert thread_count() > before and render_threads() == 4
    t0 = time.perf_counter()
    job.cancel()
    elapsed = time.perf_counter() - t0
    assert elapsed < 0.1, f"cancel took {elapsed * 1000:.1f} ms"
    assert job.cancelled and thread_count() == before and render_threads() == 0
    assert 0 < job.tiles_done < job.tiles_total
    # A cancel after the end leaves a finished job, not a cancelled one.
    done = gw.RenderJob(scene(size=1, res=16)).start()
    done.wait()
    done.cancel()
    assert not done.cancelled and done.tiles_done == done.tiles_total
    # A new render after a cancel works and is complete.
    img = gw.render(scene(size=1, res=32))
    assert img.shape == (32, 32, 4) and np.all(np.isfinite(img))


def test_dropping_a_running_job_stops_its_threads():
    before = thread_count()
    job = gw.RenderJob(scene(size=3, res=256), gw.RenderSettings(aa="jittered", aa_samples=4)).start()
    time.sleep(0.05)
    del job
    # The destructor joins the threads; a joined thread's entry can linger in
    # /proc/self/task for a moment while the kernel reaps it (seen under ASan),
    # so the count is given a second to settle. A thread left running never does.
    deadline = time.monotonic() + 1.0
    while thread_count() != before and time.monotonic() < deadline:
        time.sleep(0.01)
    assert thread_count() == before


def test_statistics_report_rays_tests_and_cells():
    sc = scene(size=3, res=64)
    job = gw.RenderJob(sc, gw.RenderSettings(threads=2)).start()
    job.wait()
    s = job.stats
    assert s["primary_rays"] == 64 * 64
    assert s["shadow_rays"] > 0 and s["secondary_rays"] > 0
    assert s["rays"] == s["primary_rays"] + s["shadow_rays"] + s["secondary_rays"]
    assert 0 < s["tests_per_ray"] < 200 and s["cells_per_ray"] > 1
    g = s["grid"]
    assert g["cells"] >= np.prod(g["resolution"]) and g["refs"] >= sc.num_primitives   # root grid and the refining ones
    assert g["build_seconds"] >= 0 and g["bytes"] > 0
    assert s["seconds"] > 0 and s["mrays_per_second"] > 0


def test_depth_and_normal_passes():
    sc = scene(size=1, res=48)
    job = gw.RenderJob(sc).start()
    job.wait()
    depth, normal, alpha = job.depth, job.normal, job.image[..., 3]
    hit = alpha > 0
    assert np.all(np.isfinite(depth[hit])) and np.all(np.isinf(depth[~hit]))
    assert np.allclose(np.linalg.norm(normal[hit], axis=-1), 1.0, atol=1e-4)


def test_region_renders_only_that_part():
    sc = scene(size=1, res=64)
    full = gw.render(sc)
    part = gw.render(sc, gw.RenderSettings(region=(10, 20, 17, 5)))
    assert np.array_equal(part[20:25, 10:27], full[20:25, 10:27])
    mask = np.ones((64, 64), bool); mask[20:25, 10:27] = False
    assert np.all(part[mask] == 0)
    for bad in [(0, 0, 0, 5), (70, 0, 5, 5), (-1, 0, 5, 5)]:
        try:
            gw.render(sc, gw.RenderSettings(region=bad))
        except ValueError:
            continue
        raise AssertionError(f"region {bad} accepted")


def test_a_region_job_holds_only_its_pixels_and_gives_every_pass_of_the_whole_image():
    """A farm tile of a large image allocates its own pixels, not the image's; the
    whole-image passes put the region where it lies (depth inf, the rest 0, outside)."""
    sc = scene(size=1, res=64)
    whole = gw.RenderJob(sc).start()
    whole.wait()
    job = gw.RenderJob(sc, gw.RenderSettings(region=(10, 20, 60, 5), tile_size=4)).start()   # clipped at x = 64
    job.wait()
    assert job.area == (10, 20, 54, 5)
    assert job._job.rgba.shape == (5, 54, 4) and job._job.depth.shape == (5, 54)
    assert np.array_equal(job.area_image, whole.image[20:25, 10:64])
    for name, outside in (("image", 0), ("depth", np.inf), ("normal", 0), ("albedo", 0)):
        got, ref = getattr(job, name), getattr(whole, name)
        assert got.shape == ref.shape
        assert np.array_equal(got[20:25, 10:], ref[20:25, 10:]), name
        assert np.all(got[:20] == outside) and np.all(got[25:] == outside) and np.all(got[:, :10] == outside), name
    tiles = gw.RenderJob(sc, gw.RenderSettings(region=(10, 20, 60, 5), tile_size=4)).start()
    tiles.wait()
    polled = tiles.poll()
    assert sum(t.width * t.height for t in polled) == 54 * 5
    for t in polled:                                 # polled tiles are in image coordinates
        rows, cols = slice(t.y, t.y + t.height), slice(t.x, t.x + t.width)
        assert np.array_equal(t.rgba, whole.image[rows, cols])
        for name in ("depth", "normal", "albedo"):
            assert np.array_equal(t.passes[name], getattr(whole, name)[rows, cols]), name


def test_wait_for_returns_at_each_finished_tile_and_at_once_at_the_end():
    # A slow render of 64 tiles on one thread: wait_for(30) returns when the next tile is done,
    # long before 30 s and before the job ends; once it has ended, at once, True. Before
    # start() it refuses; a NaN or negative wait is no wait.
    sc = scene(size=3, res=128)
    slow = gw.RenderSettings(aa="jittered", aa_samples=3, tile_size=16, threads=1)
    job = gw.RenderJob(sc, slow)
    with pytest.raises(RuntimeError, match="before start"):
        job.wait_for(0.1)
    job.start()
    woke = []
    while True:
        before = job.tiles_done
        t0 = time.perf_counter()
        ended = job.wait_for(30)
        woke.append(time.perf_counter() - t0)
        if ended:
            break
        assert job.tiles_done > before   # (woken by a tile, not by the timeout)
    assert job.tiles_done == 64 and len(woke) >= 2 and max(woke) < 10
    t0 = time.perf_counter()
    assert job.wait_for(30) and job.wait_for(float("nan")) and job.wait_for(-1)
    assert time.perf_counter() - t0 < 0.1
    job.wait()


CTRL_C_SCRIPT = """
import sys, time
import gridwalk as gw
from gridwalk.scenes import balls
kw = balls(2)
kw["camera"].width = kw["camera"].height = 256
scene = gw.Scene(**kw)
settings = gw.RenderSettings(aa="jittered", aa_samples=40, threads=1)
blocking = gw.render if sys.argv[1] == "render" else (lambda sc, st: gw.RenderJob(sc, st).start().wait())
print("rendering", flush=True)
t0 = time.perf_counter()
try:
    blocking(scene, settings)
    print("finished", flush=True)
except KeyboardInterrupt:
    print(f"interrupted {time.perf_counter() - t0:.3f}", flush=True)
"""


@pytest.mark.parametrize("call", ["render", "wait"])
def test_ctrl_c_interrupts_a_blocking_render_at_once(call, tmp_path):
    # render() and RenderJob.wait() block in native code; they came back to Python only
    # when the render ended, so Ctrl-C (SIGINT) waited for the whole image (19 s in the report).
    import signal
    import subprocess
    import sys
    script = tmp_path / "ctrl_c.py"
    script.write_text(CTRL_C_SCRIPT)
    child = subprocess.Popen([sys.executable, str(script), call], stdout=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "rendering"
    time.sleep(0.5)                                   # (inside the render: it takes about 20 s)
    sent = time.perf_counter()
    child.send_signal(signal.SIGINT)
    out, _ = child.communicate(timeout=60)
    assert time.perf_counter() - sent < 2.0, out
    assert out.startswith("interrupted"), out


def glossy_scene(size=256):
    """A rough mirror floor filling the view under a ball, a sphere light, a lens with depth of field."""
    floor = gw.Material(kd=0.5, mirror=0.5, roughness=0.3)
    return gw.Scene(vertices=[[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], triangles=[[0, 1, 2], [0, 2, 3]],
                    sphere_centers=[[0, 0, 1]], sphere_radii=[1.0], materials=[floor],
                    lights=[gw.Light(position=(4, -4, 6), kind="sphere", radius=0.5)],
                    camera=gw.Camera(eye=(0, -6, 4), target=(0, 0, 0), width=size, height=size, aperture=0.1,
                                     focus_distance=7))


@pytest.mark.parametrize("costly", [
    # an adaptive tile's corners are traced before its first pixel (seconds for a 128-pixel tile)
    dict(aa="adaptive", dof_samples=32, glossy_samples=32, shadow="area", shadow_samples=2, tile_size=128),
    # one pixel of 4096 lens samples, each with 256 glossy rays
    dict(aa="center", dof_samples=4096, glossy_samples=256, tile_size=256),
])
def test_cancel_returns_within_100ms_from_inside_a_costly_tile_or_pixel(costly):
    # (cancel was asked between pixels only: 2.4-4.3 s with adaptive anti-aliasing, 4.6 s for a
    # pixel of thousands of samples)
    job = gw.RenderJob(glossy_scene(), gw.RenderSettings(threads=2, **costly)).start()
    time.sleep(0.5)
    assert job.tiles_done == 0                          # inside the first tile
    t0 = time.perf_counter()
    job.cancel()
    elapsed = time.perf_counter() - t0
    assert elapsed < 0.1, f"cancel took {elapsed * 1000:.1f} ms"
    assert job.cancelled and render_threads() == 0


def test_a_cancelled_render_publishes_only_whole_pixels():
    # (a tile's last pixel, cut short by the cancel between its lens samples, was published as
    # finished: darker and partly transparent)
    scene_ = glossy_scene(size=4)
    settings = dict(aa="center", dof_samples=1024, glossy_samples=16, tile_size=1, threads=2)
    t0 = time.perf_counter()
    full = gw.RenderJob(scene_, gw.RenderSettings(**settings)).start()
    full.wait()
    whole = time.perf_counter() - t0
    published = 0
    for trial in range(5):
        job = gw.RenderJob(scene_, gw.RenderSettings(**settings)).start()
        time.sleep(whole * (0.2 + 0.15 * trial))
        job.cancel()
        for tile in job.poll():
            published += 1
            assert np.array_equal(tile.rgba[0, 0], full.image[tile.y, tile.x]), (trial, tile.x, tile.y)
    assert published > 0
