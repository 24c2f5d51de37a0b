"""One farm run on a Dask client: send the job, submit the missing tiles or
frames, keep each result on disk as it arrives, report, put together.

Faults:
- a worker that dies mid-task: Dask runs its tasks again elsewhere (or on the
  worker its nanny restarts); results are deterministic, so the output is
  the same;
- a task that fails: the others go on; then FarmError names every failed
  tile or frame and the worker, and says where the finished ones are kept;
- Ctrl-C (KeyboardInterrupt): the futures are cancelled, the workers stop the
  running tasks (the renderer's threads or Blender), and this returns only
  when no worker is running a task of this run (or after STOP_WAIT_SECONDS,
  saying which workers were still busy).
"""
from __future__ import annotations

import sys
import time
import uuid
from collections import defaultdict
from dataclasses import dataclass, field

from .blend_job import PROBE
from .cluster import FarmError
from .jobplugin import TaskFailed, busy_tasks, run_task
from .store import ResultStore, StoreBusy

STOP_WAIT_SECONDS = 15.0


@dataclass
class WorkerFigures:
    items: int = 0
    rays: int = 0
    seconds: float = 0.0          # time spent rendering
    scene_loads: int = 0          # times the worker built (or wrote) the scene: 1, sent once

    @property
    def rays_per_second(self) -> float:
        return self.rays / self.seconds if self.seconds > 0 else 0.0


@dataclass
class FarmReport:
    """What a farm run did: `output` (the image, or the frames' folder),
    `rendered` and `reused` (tile indices or frame numbers), `workers`
    (address -> WorkerFigures), `done_by` (item -> worker address), `seconds`."""
    output: object = None
    what: str = ""
    rendered: list = field(default_factory=list)
    reused: list = field(default_factory=list)
    workers: dict = field(default_factory=lambda: defaultdict(WorkerFigures))
    done_by: dict = field(default_factory=dict)
    seconds: float = 0.0

    def summary(self) -> str:
        lines = [f"  {len(self.rendered)} {self.what}s rendered, {len(self.reused)} kept from an earlier run, "
                 f"{self.seconds:.2f} s"]
        for address, w in sorted(self.workers.items()):
            lines.append(f"  worker {address}: {w.items} {self.what}s, {w.rays / 1e6:.3g} M rays in "
                         f"{w.seconds:.2f} s rendering, {w.rays_per_second / 1e6:.2f} Mrays/s")
        return "\n".join(lines)


class Progress:
    """A progress bar on stderr: tiles or frames done out of the total."""

    def __init__(self, total: int, what: str, quiet: bool):
        self.total, self.what, self.quiet = total, what, quiet
        self.start = time.perf_counter()
        self.done = self.failed = 0

    def step(self, failed: bool = False) -> None:
        self.done += 1
        self.failed += failed
        self.draw()

    def draw(self) -> None:
        if self.quiet:
            return
        filled = self.done * 30 // max(1, self.total)
        failed = f", {self.failed} failed" if self.failed else ""
        sys.stderr.write(f"\rfarm [{'#' * filled:<30}] {self.done}/{self.total} {self.what}s{failed}  "
                         f"{time.perf_counter() - self.start:6.1f} s")
        sys.stderr.flush()

    def close(self) -> None:
        if not self.quiet:
            sys.stderr.write("\n")


def _submit(client, run_id, what, items):
    return {client.submit(run_task, run_id, item, key=f"gridwalk-{what}-{run_id}-{item}", pure=False): item
            for item in items}


def wait_until_idle(client, run_id: str, limit: float = STOP_WAIT_SECONDS) -> None:
    """Return once no worker runs a task of `run_id`; FarmError after `limit` s."""
    deadline = time.monotonic() + limit
    while True:
        busy = {w: n for w, n in client.run(busy_tasks, run_id).items() if n}
        if not busy:
            return
        if time.monotonic() > deadline:
            raise FarmError(f"after {limit:g} s these workers still run cancelled tasks: {busy}")
        time.sleep(0.05)


def _collect(client, job, store, futures, report, progress, failures: dict) -> None:
    """Keeps each finished task's result; failed ones go into `failures` (item: message),
    which the caller reads however this ends."""
    from distributed import as_completed

    for future, result in as_completed(futures, loop=client.loop, with_results=True, raise_errors=False):
        item = futures[future]
        if future.status == "error":
            exc = result[1] if isinstance(result, tuple) else result       # (type, exception, traceback)
            failures[item] = str(exc) if isinstance(exc, TaskFailed) else \
                f"{job.what} {item}: {type(exc).__name__}: {exc}"
            progress.step(failed=True)
            continue
        job.keep(store, item, result)
        figures = report.workers[result["worker"]]
        figures.items += 1
        figures.rays += result.get("rays") or 0
        figures.seconds += result.get("seconds") or 0.0
        figures.scene_loads = max(figures.scene_loads, result["scene_loads"])
        report.done_by[item] = result["worker"]
        report.rendered.append(item)
        progress.step()
        future.release()


def run(client, job, threads: int = 0, quiet: bool = False) -> FarmReport:
    """Render `job` (a CoreJob or BlendJob) on `client`'s workers."""
    t0 = time.perf_counter()
    run_id = uuid.uuid4().hex[:12]
    plugin = job.plugin(run_id, threads)
    futures, store, failures = {}, None, {}
    try:
        client.register_plugin(plugin)
        if getattr(job, "needs_probe", False):
            futures = _submit(client, run_id, "probe", [PROBE])
            try:
                job.use_probe(next(iter(futures)).result())
            except TaskFailed as exc:
                raise FarmError(str(exc)) from None
        try:
            store = ResultStore(job.folder, job.digest)
        except StoreBusy as exc:
            raise FarmError(str(exc)) from None
        report = FarmReport(what=job.what)
        report.reused = [item for item in job.items if store.find(job.stem(item)) is not None]
        reused = set(report.reused)
        todo = [item for item in job.items if item not in reused]
        if not quiet:
            kept = f"; {len(report.reused)} {job.what}s kept from an earlier run" if report.reused else ""
            print(f"gridwalk farm: {job.describe()} on {len(client.scheduler_info()['workers'])} workers{kept}",
                  file=sys.stderr)
        progress = Progress(len(todo), job.what, quiet)
        progress.draw()
        futures = _submit(client, run_id, job.what, todo)
        try:
            _collect(client, job, store, futures, report, progress, failures)
        finally:
            progress.close()
    except BaseException as exc:
        if store is not None:
            store.close()
        if failures:   # (named nowhere else: the workers' own records of them are dropped, jobplugin.QuietFailures)
            named = "\n".join(f"  {failures[item]}" for item in sorted(failures))
            print(f"gridwalk farm: before the run stopped, {len(failures)} {job.what}s had failed:\n{named}",
                  file=sys.stderr)
        if isinstance(exc, KeyboardInterrupt):
            client.cancel(list(futures), force=True)
            wait_until_idle(client, run_id)
        raise
    finally:
        try:
            client.unregister_worker_plugin(plugin.name)
        except (KeyError, ValueError):      # it never reached the workers
            pass
    if failures:
        store.close()
        named = "\n".join(f"  {failures[item]}" for item in sorted(failures))
        raise FarmError(f"{len(failures)} of {len(todo)} {job.what}s failed:\n{named}\n"
                        f"{len(report.rendered) + len(report.reused)} finished {job.what}s are kept in "
                        f"{store.folder}; run the same command again to render only the missing ones")
    try:
        report.output = job.finish(store)
    finally:
        store.close()
    report.seconds = time.perf_counter() - t0
    return report
