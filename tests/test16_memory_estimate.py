"""gridwalk.memory: the estimate from counts alone, its caps, the refusal, and
how it compares with the memory a real render uses."""
import json
import subprocess
import sys
import textwrap

import pytest

import gridwalk as gw
from gridwalk import memory


def test_estimate_adds_up_and_scales_with_the_counts():
    s = gw.RenderSettings(threads=2, accel="grid")
    small = memory.estimate(1000, 600, width=64, height=48, settings=s)
    big = memory.estimate(10_000, 6000, width=64, height=48, settings=s)
    assert small.total == small.scene_arrays + small.grid + small.mailboxes + small.images
    assert big.scene_arrays == 10 * small.scene_arrays
    assert small.images == 64 * 48 * memory.PIXEL_BYTES == big.images
    assert big.mailboxes == 10_000 * 4 * 2
    assert memory.estimate(1000, settings=s).scene_arrays > small.scene_arrays    # 3 vertices per triangle
    assert memory.estimate(1000, 600, settings=s, normals=False).scene_arrays < small.scene_arrays
    none = memory.estimate(1000, 600, settings=s.replace(accel="none"))
    assert none.grid == 0 and none.mailboxes == 0
    adaptive = memory.estimate(10_000, 6000, settings=s.replace(accel="adaptive"))
    assert adaptive.mailboxes == 0 and adaptive.grid == 10_000 * (
        memory.ADAPTIVE_CELLS * memory.ADAPTIVE_CELL_BYTES + memory.ADAPTIVE_REFS * memory.REF_BYTES
        + memory.ADAPTIVE_BUILD_BYTES)
    assert memory.estimate(0, 0).total == memory.PIXEL_BYTES         # one pixel, nothing else


def test_grid_is_capped_by_max_cells_and_the_reference_cap():
    s = gw.RenderSettings(threads=1, mailboxes=False, accel="grid")
    capped = memory.estimate(10**9, settings=s.replace(max_cells=1000))
    refs = max(memory.MAX_REFS, 10**9)   # as in the core: every primitive keeps at least one reference
    assert capped.grid == 1000 * memory.CELL_BYTES + 4 + refs * memory.REF_BYTES
    assert memory.grid_refs(10**6, 50.0) == memory.MAX_REFS
    assert memory.grid_cells(10**6, 2.0, 1 << 24) == (2 * 100 + 1) ** 3
    assert memory.grid_refs(100, 2.0) == 500


def test_check_refuses_with_the_estimate_and_the_limit():
    est = memory.estimate(100_000, settings=gw.RenderSettings(threads=1))
    memory.check(est, None)
    memory.check(est, est.total)
    with pytest.raises(memory.SceneTooLarge) as info:
        memory.check(est, 4 << 20, "This scene", "set by a test")
    message = str(info.value)
    assert f"needs an estimated {memory.format_bytes(est.total)} of memory (scene arrays" in message
    assert message.endswith("more than the limit of 4 MiB (set by a test)")
    assert isinstance(info.value, MemoryError)
    assert memory.format_bytes(1536) == "1.5 KiB" and memory.format_bytes(3 << 30) == "3 GiB"
    total = memory.physical_memory()
    assert total and memory.default_limit() == int(total * 0.75)


MEASURE = textwrap.dedent("""
    import ctypes, gc, json, sys
    import numpy as np
    import gridwalk as gw
    from gridwalk import memory
    def rss():
        gc.collect(); ctypes.CDLL(None).malloc_trim(0)
        return int(open("/proc/self/statm").read().split()[1]) * 4096
    n = int(sys.argv[1])
    th = np.linspace(0, np.pi, n + 1); ph = np.linspace(0, 2 * np.pi, 2 * n + 1)
    t, p = np.meshgrid(th, ph, indexing="ij")
    v = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3).astype(np.float32)
    i = np.arange((n + 1) * (2 * n + 1)).reshape(n + 1, 2 * n + 1)
    a, b, c, d = i[:-1, :-1], i[1:, :-1], i[1:, 1:], i[:-1, 1:]
    tris = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    tris = tris.astype(np.int32)
    del th, ph, t, p, i, a, b, c, d
    base = rss()
    s = gw.RenderSettings(threads=2, accel=sys.argv[2])
    cam = gw.Camera(eye=(0, -3, 0), target=(0, 0, 0), width=320, height=240)
    scene = gw.Scene(vertices=v, triangles=tris, normals=v.copy(), camera=cam,
                     lights=[gw.Light(position=(0, -5, 5))])
    job = gw.RenderJob(scene, s)
    job.start().wait(); image, depth, normal = job.image, job.depth, job.normal
    used = rss() - base + v.nbytes + tris.nbytes      # the input arrays were made before `base`
    est = memory.estimate(len(tris), len(v), width=320, height=240, settings=s)
    print(json.dumps({"used": used, "estimate": est.total - est.mailboxes - 32 * 320 * 240}))
""")


@pytest.mark.parametrize("accel", ["adaptive", "grid"])
def test_estimate_is_close_to_the_memory_a_render_uses(tmp_path, accel):
    """A 1M-triangle sphere: resident memory grown while the scene, grid, job and
    images are alive (the mailboxes are freed when the workers end, and the host
    result buffers are not allocated here, so both are left out of the estimate)."""
    script = tmp_path / "measure.py"
    script.write_text(MEASURE)
    out = subprocess.run([sys.executable, str(script), "500", accel], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    figures = json.loads(out.stdout)
    ratio = figures["estimate"] / figures["used"]
    assert 0.8 < ratio < 1.6, figures
