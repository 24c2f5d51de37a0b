"""A tile or frame that fails on a worker is reported by the client (driver.run names each one
with its message). The worker logged its own "Compute Failed" record of it too, a dozen lines
with a traceback of the task function, for every failed task and with --quiet as well. The job's
plugin now drops those records of its own run's tasks on the worker, and keeps every other one.

A real Dask cluster runs the tasks. Its worker runs in this process (processes=False), so that
the worker's log records reach pytest's caplog."""
import logging
import uuid

import numpy as np
import pytest
from distributed import Client, LocalCluster

from gridwalk import Camera, Light, RenderSettings
from gridwalk.renderfarm.core_job import CoreTiles
from gridwalk.renderfarm.jobplugin import TaskFailed, plugin_name, run_task


def plain_failure(x):
    raise ValueError(f"not a farm task {x}")


@pytest.fixture(scope="module")
def client():
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=None) as local, \
            Client(local, set_as_default=False) as c:
        yield c


def compute_failed(caplog):
    return [r.getMessage() for r in caplog.records if r.getMessage().startswith("Compute Failed")]


def test_a_failed_tile_is_not_logged_again_by_the_worker_while_other_failures_are(client, caplog):
    caplog.set_level(logging.ERROR, logger="distributed.worker")
    run_id = uuid.uuid4().hex[:12]
    scene = {"vertices": np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "triangles": np.int32([[0, 1, 2]]),
             "camera": Camera(eye=(0, 0, 3), target=(0, 0, 0), width=8, height=8), "lights": [Light(position=(0, 0, 5))]}
    # a tile outside the 8 x 8 image: the render refuses its region on the worker
    plugin = CoreTiles(run_id, 1, scene, RenderSettings(threads=1), [(4, 4, 64, 64)])
    client.register_plugin(plugin)
    try:
        ours = client.submit(run_task, run_id, 0, key=f"gridwalk-tile-{run_id}-0", pure=False)
        with pytest.raises(TaskFailed, match="tile 0 .* failed on worker"):
            ours.result(timeout=60)
        other = client.submit(plain_failure, 1, pure=False)
        with pytest.raises(ValueError, match="not a farm task 1"):
            other.result(timeout=60)
    finally:
        client.unregister_worker_plugin(plugin_name(run_id))
    records = compute_failed(caplog)
    assert any("plain_failure" in m for m in records), records       # other tasks' records are kept
    assert not any(run_id in m for m in records), records            # ours is reported by the client alone
    # and once the run's plugin is gone, its filter is gone with it
    again = client.submit(plain_failure, 2, pure=False)
    with pytest.raises(ValueError):
        again.result(timeout=60)
    assert len(compute_failed(caplog)) == len(records) + 1
    assert not [f for f in logging.getLogger("distributed.worker").filters if type(f).__name__ == "QuietFailures"]
