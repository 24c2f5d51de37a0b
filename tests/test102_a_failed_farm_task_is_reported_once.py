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


def test_a_failed_tile_is_not_logged_again_by_the_worker_while_other_failures_are(client, caplog, monkeypatch):
    caplog.set_level(logging.ERROR, logger="distributed.worker")

    def run(self, index, key):
        raise RuntimeError(f"tile {index} cannot be rendered here")

    monkeypatch.setattr(CoreTiles, "run", run)   # (the worker runs in this process)
    run_id = uuid.uuid4().hex[:12]
    scene = {"vertices": np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "triangles": np.int32([[0, 1, 2]]),
             "camera": Camera(eye=(0, 0, 3), target=(0, 0, 0), up=(0, 1, 0), width=8, height=8), "lights": [Light(position=(0, 0, 5))]}
    plugin = CoreTiles(run_id, 1, scene, RenderSettings(threads=1), [(0, 0, 8, 8)])
    client.register_plugin(plugin)
    try:
        ours = client.submit(run_task, run_id, 0, key=f"gridwalk-tile-{run_id}-0", pure=False)
        with pytest.raises(TaskFailed, match="tile 0 .* failed on worker .*: tile 0 cannot be rendered here"):
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


def test_failures_before_a_run_stops_are_still_named(client, monkeypatch, capsys, tmp_path):
    """With the workers' records dropped, the client's report is the only trace of a failed
    tile: a run that ends by an exception (a full disk as a tile is kept, Ctrl-C) names the
    tiles that had failed before it stopped, then raises."""
    from gridwalk.renderfarm import core_job, driver

    def run(self, index, key):
        if index == 0:
            raise RuntimeError("tile 0 broke for a reason only the worker knows")
        import time
        time.sleep(0.3)                       # (tile 0's failure reaches the client first)
        return original(self, index, key)

    original = core_job.CoreTiles.run
    monkeypatch.setattr(core_job.CoreTiles, "run", run)
    scene = {"vertices": np.float32([[0, 0, 0], [1, 0, 0], [0, 1, 0]]), "triangles": np.int32([[0, 1, 2]]),
             "camera": Camera(eye=(0, 0, 3), target=(0, 0, 0), up=(0, 1, 0), width=8, height=8), "lights": [Light(position=(0, 0, 5))]}
    job = core_job.CoreJob(scene, tmp_path / "out.png", tiles=2)

    def keep(store, index, result):
        raise OSError("No space left on device")

    monkeypatch.setattr(job, "keep", keep)
    with pytest.raises(OSError, match="No space left"):
        driver.run(client, job, quiet=True)
    err = capsys.readouterr().err
    assert "before the run stopped, 1 tiles had failed" in err and "only the worker knows" in err, err
