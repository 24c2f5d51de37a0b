"""The package imports, the native module is private, and a Scene reports what it holds."""
import numpy as np
import pytest

import gridwalk as gw
from meshes import icosphere


def test_public_api_is_the_python_package():
    for name in ("Scene", "Material", "Light", "Camera", "RenderSettings", "RenderJob", "render"):
        assert hasattr(gw, name)
    assert gw._core.__name__ == "gridwalk._core"
    assert "_core" not in gw.__all__


def test_scene_counts_and_bounds():
    V, F = icosphere(1, radius=2.0, center=(1, 2, 3))
    sc = gw.Scene(vertices=V, triangles=F, sphere_centers=[[10, 0, 0]], sphere_radii=[0.5])
    assert (sc.num_triangles, sc.num_spheres, sc.num_cylinders) == (len(F), 1, 0)
    lo, hi = sc.bounds
    assert np.allclose(lo, [-1, -0.5, -0.5], atol=1e-5)
    assert np.allclose(hi, [10.5, 4, 5], atol=1e-5)


def test_python_lists_and_float64_are_converted():
    sc = gw.Scene(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]],
                  sphere_centers=np.zeros((1, 3)), sphere_radii=np.array([1.0]))
    assert sc.num_triangles == 1 and sc.num_spheres == 1


def test_settings_reject_unknown_modes():
    with pytest.raises(ValueError, match="aa"):
        gw.RenderSettings(aa="supersample").to_core()
    with pytest.raises(ValueError, match="unknown render settings"):
        gw.RenderSettings().replace(samples=4)
    with pytest.raises(ValueError, match="tile_size"):
        gw.RenderSettings(tile_size=0).to_core()


def test_rays_in_any_form_give_the_same_hits_and_keep_the_callers_arrays():
    # float32 C-contiguous arrays are taken as they are (no copy); lists, float64 and
    # strided arrays are converted; tmin / tmax as numbers or per-ray arrays, including
    # inf, NaN (a miss) and numbers beyond float32 (inf).
    sc = gw.Scene(sphere_centers=[[0, 0, 0], [0, 0, 4]], sphere_radii=[1.0, 1.0])
    o = np.array([[0, 0, -5], [0, 0, 10], [3, 0, 0], [0.5, 0, -5]], np.float32)
    d = np.array([[0, 0, 1], [0, 0, -1], [0, 0, 1], [0, 0, 1]], np.float32)
    o_before, d_before = o.copy(), d.copy()
    ref = sc.intersect(o, d)
    assert np.allclose(ref.t[[0, 1]], [4, 5]) and np.isinf(ref.t[2])
    forms = [(o.tolist(), d.tolist()), (o.astype(np.float64), d.astype(np.float64)),
             (np.repeat(o, 2, axis=0)[::2], np.repeat(d, 2, axis=0)[::2]), (np.asfortranarray(o), np.asfortranarray(d))]
    for oo, dd in forms:
        h = sc.intersect(oo, dd)
        assert np.array_equal(h.t, ref.t) and np.array_equal(h.prim, ref.prim)
        assert np.array_equal(sc.occluded(oo, dd), sc.occluded(o, d))
    for scalar, per_ray in [(4.5, np.full(4, 4.5, np.float32)), (np.inf, np.full(4, np.inf)), (3, np.full(4, 3))]:
        assert np.array_equal(sc.intersect(o, d, tmax=scalar).t, sc.intersect(o, d, tmax=per_ray).t)
        assert np.array_equal(sc.occluded(o, d, tmax=scalar), sc.occluded(o, d, tmax=per_ray))
    assert np.all(np.isinf(sc.intersect(o, d, tmax=float("nan")).t))
    assert np.array_equal(sc.intersect(o, d, tmax=1e39).t, ref.t)   # beyond float32: inf
    assert np.array_equal(sc.intersect(o, d, tmin=4.5).t[[0, 1]], [6, 5])
    assert np.array_equal(o, o_before) and np.array_equal(d, d_before)


WORK = """
import threading, time
import numpy as np
import gridwalk as gw
from gridwalk import scenes

scene = gw.Scene(**scenes.balls(2))
hits = scene.intersect(np.zeros((4, 3), np.float32), np.tile(np.float32([0, 0, 1]), (4, 1)))
camera = gw.Camera(eye=(0, -5, 1), target=(0, 0, 0), width=16, height=12)
image = gw.RenderJob(scene, gw.RenderSettings(threads=2), camera=camera).start().wait()
if DAEMON:                                  # a render still running when the script ends
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1))
    threading.Thread(target=lambda: job.start().wait(), daemon=True).start()
    time.sleep(0.2)
print("done", image.shape)
"""


@pytest.mark.parametrize("daemon", [False, True])
def test_a_script_ends_without_nanobind_leak_reports(daemon):
    """A script that leaves nothing behind leaks nothing even with nanobind's
    report on (GRIDWALK_LEAK_WARNINGS=1: a reference-counting mistake in the
    bindings would show here); one that ends while a daemon thread holds a
    render printed ~180 lines of "leaked" objects, now none by default."""
    import os
    import subprocess
    import sys
    env = dict(os.environ, GRIDWALK_LEAK_WARNINGS="0" if daemon else "1")
    out = subprocess.run([sys.executable, "-c", f"DAEMON = {daemon}\n" + WORK], capture_output=True, text=True,
                         timeout=120, env=env)
    assert out.returncode == 0 and "done (12, 16, 4)" in out.stdout, out.stderr
    assert "leaked" not in out.stderr, out.stderr[:2000]
