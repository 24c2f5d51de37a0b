"""Batched ray queries (Scene.intersect / occluded) spread over threads by
what the rays cost, not only by how many there are (batch.cpp).

Brute force over a 37k-triangle sphere costs milliseconds a ray: 2,000 such
rays ran on one thread while the bound was one thread per 4,096 rays. Now the
calling thread times a first slice and hands the rest to worker threads
("gridwalk-rays"), with the same answers bit for bit.
"""
import threading
import time

import numpy as np

import gridwalk as gw
from meshes import uv_sphere
from thread_names import thread_names


def costly_case():
    vertices, faces = uv_sphere(96, 192, radius=1.0, center=np.zeros(3), seed=1)
    scene = gw.Scene(vertices=vertices, triangles=faces)
    rng = np.random.default_rng(3)
    n = 2000
    origins = rng.normal(0, 0.2, (n, 3)).astype(np.float32)
    directions = rng.normal(size=(n, 3)).astype(np.float32)
    return scene, origins, directions


def query_watching_workers(query):
    """query()'s result and the most "gridwalk-rays" threads seen while it ran
    (the core releases the GIL during a batch)."""
    result, most = {}, 0
    worker = threading.Thread(target=lambda: result.setdefault("value", query()))
    worker.start()
    while worker.is_alive():
        most = max(most, thread_names().count("gridwalk-rays"))
        time.sleep(0.002)
    worker.join()
    assert "value" in result, "the query raised (see the thread's traceback)"
    return result["value"], most


def test_costly_rays_run_on_every_thread_with_identical_answers():
    scene, o, d = costly_case()
    one = gw.RenderSettings(accel="none", threads=1)
    two = gw.RenderSettings(accel="none", threads=2)
    want, workers_one = query_watching_workers(lambda: scene.intersect(o, d, settings=one))
    got, workers_two = query_watching_workers(lambda: scene.intersect(o, d, settings=two))
    assert workers_one == 0
    assert workers_two == 1            # the calling thread and one worker
    assert np.isfinite(want.t).all()   # every ray starts inside the closed sphere
    assert np.array_equal(got.t, want.t) and np.array_equal(got.prim, want.prim)
    assert np.array_equal(got.normal, want.normal)
    blocked_one = scene.occluded(o, d, settings=one)
    blocked_two, workers = query_watching_workers(lambda: scene.occluded(o, d, settings=two))
    assert workers == 1
    assert np.array_equal(np.asarray(blocked_two), np.asarray(blocked_one)) and np.asarray(blocked_one).all()

