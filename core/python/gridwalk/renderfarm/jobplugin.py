"""The job on the workers: a Dask worker plugin, sent once to every worker.

The client registers one JobPlugin per run. Dask pickles it once, sends it
to each worker (and to any worker that joins later, such as one a nanny
restarted after a crash) and calls setup() there, so the scene travels once
per worker; tasks carry only (run id, tile or frame number) and find the
plugin by name.

The plugin also lets tasks stop when they are no longer wanted. Dask cannot
interrupt a running Python function: when the client cancels a future (Ctrl-C)
or goes away, the worker moves the running task to the state "cancelled" and
tells its plugins. The plugin records the key and calls the stop function the
task registered (`with plugin.stoppable(key, job.cancel): job.wait()`); a task
may also poll stop_requested(). `running` counts the tasks still inside a task
function, so the client can wait until no worker is busy with its job.
"""
from __future__ import annotations

import logging
import os
import socket
import threading
from contextlib import contextmanager

from distributed import get_worker
from distributed.diagnostics.plugin import WorkerPlugin

STOPPED_STATES = ("cancelled", "released", "forgotten")


def plugin_name(run_id: str) -> str:
    return f"gridwalk-farm-{run_id}"


class TaskFailed(RuntimeError):
    """A tile or frame failed on a worker; the message names it and the worker."""


class TaskStopped(RuntimeError):
    """A task stopped because the client cancelled it."""


class JobPlugin(WorkerPlugin):
    """Base class of the jobs (core tiles, Blender frames and tiles).

    Subclasses set `what` ("tile" or "frame"), keep their payload in
    attributes, and implement run(item, key) -> dict, called in a worker
    thread (`key` is the task's key, for stop_requested).
    """
    what = "item"

    def __init__(self, run_id: str, threads: int):
        self.name = plugin_name(run_id)
        self.run_id = run_id
        self.threads = threads          # render threads per task; 0: the worker decides

    # -- on the worker ---------------------------------------------------------
    def setup(self, worker):
        self.worker = worker
        self.quiet_failures = QuietFailures(self.run_id)
        logging.getLogger("distributed.worker").addFilter(self.quiet_failures)
        self.lock = threading.Lock()
        self.stopped = set()
        self.running = set()
        self.stop_functions = {}
        self.scene_loads = 0            # times the scene was built or written on this worker

    def teardown(self, worker):
        logging.getLogger("distributed.worker").removeFilter(self.quiet_failures)

    def transition(self, key, start, finish, **kwargs):
        if finish in STOPPED_STATES and start in ("executing", "long-running", "cancelled", "resumed"):
            self.stopped.add(key)
            stop = self.stop_functions.get(key)
            if stop is not None:
                stop()
        elif finish == "executing":
            self.stopped.discard(key)

    def stop_requested(self, key) -> bool:
        return key in self.stopped

    @contextmanager
    def stoppable(self, key, stop):
        """Within the block, a cancel of task `key` calls stop() (from the worker's event loop)."""
        self.stop_functions[key] = stop
        try:
            if key in self.stopped:         # cancelled before the function was registered
                stop()
            yield
        finally:
            self.stop_functions.pop(key, None)

    def render_threads(self) -> int:
        """Threads one task renders with: the client's choice, else this
        machine's cores shared among the tasks this worker runs at once."""
        if self.threads > 0:
            return self.threads
        return max(1, (os.cpu_count() or 1) // max(1, self.worker.state.nthreads))

    def label(self, item) -> str:
        return f"{self.what} {item}"

    def run(self, item, key) -> dict:
        raise NotImplementedError

    def execute(self, item) -> dict:
        key = get_worker().get_current_task()
        self.running.add(key)
        try:
            result = self.run(item, key)
        except TaskStopped:
            raise
        except Exception as exc:
            where = f"{self.worker.address} ({socket.gethostname()}, pid {os.getpid()})"
            raise TaskFailed(f"{self.label(item)} failed on worker {where}: {exc}") from None
        finally:
            self.running.discard(key)
        result.update(worker=self.worker.address, scene_loads=self.scene_loads)
        return result


class QuietFailures(logging.Filter):
    """Drops the worker's "Compute Failed" record of this run's tasks that
    raised TaskFailed or TaskStopped: the client reports each failed tile or
    frame with that message already (driver.run), and the worker's copy, a
    dozen lines with a traceback of the task function, repeated per task,
    buried it (and printed with --quiet). Other records, and tasks failing any
    other way, are kept."""

    def __init__(self, run_id: str):
        super().__init__()
        self.key_part = f"-{run_id}-"

    def filter(self, record) -> bool:
        if not str(record.msg).startswith("Compute Failed"):
            return True
        text = record.getMessage()
        return not (self.key_part in text and ("TaskFailed(" in text or "TaskStopped(" in text))


def run_task(run_id: str, item):
    """The task function: what Dask runs for one tile or frame."""
    plugin = get_worker().plugins.get(plugin_name(run_id))
    if plugin is None:
        raise TaskFailed(f"worker {get_worker().address} has not received farm job {run_id}")
    return plugin.execute(item)


def busy_tasks(run_id: str, dask_worker=None) -> int:
    """How many tasks of run `run_id` are running on this worker (client.run)."""
    plugin = dask_worker.plugins.get(plugin_name(run_id)) if dask_worker is not None else None
    return len(plugin.running) if plugin is not None else 0
