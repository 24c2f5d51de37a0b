"""The Dask cluster a farm run uses: an existing one, or a LocalCluster.

    with connect(scheduler="tcp://host:8786") as (client, threads): ...
    with connect(local=4) as (client, threads): ...   # 4 worker processes here

A wrong scheduler address fails within seconds, with a message that says
what was tried: the address is parsed, the host looked up and the port
opened before Dask's client is made (Dask alone would retry for its whole
timeout and then report a bare timeout).
"""
from __future__ import annotations

import asyncio
import logging
import os
import signal
import socket
import threading
from contextlib import contextmanager

CONNECT_TIMEOUT = 10.0
START_HINT = ("start one with `dask scheduler` (it listens on tcp://HOST:8786) and workers with "
              "`dask worker tcp://HOST:8786`, or leave out --scheduler to run a local cluster")
NOT_A_SCHEDULER = ("check the port: a scheduler listens on 8786 by default (8787 is its dashboard, "
                   "which is HTTP)")


class FarmError(RuntimeError):
    """The farm could not run, or some of its tiles or frames failed."""


def check_scheduler(address: str, timeout: float) -> None:
    """FarmError unless a Dask scheduler answers at `address` within `timeout` s."""
    from distributed.comm import connect
    from distributed.comm.addressing import parse_address, parse_host_port

    try:
        scheme, location = parse_address(address)
        host, port = parse_host_port(location)
    except ValueError as exc:
        raise FarmError(f"--scheduler {address!r} is not a scheduler address ({exc}); "
                        "expected tcp://HOST:PORT") from None
    if scheme not in ("tcp", "tls"):
        raise FarmError(f"--scheduler {address!r}: unsupported scheme {scheme!r}; expected tcp://HOST:PORT")
    if not 0 < port < 65536:
        raise FarmError(f"--scheduler {address!r}: port {port} is not a TCP port (1-65535)")
    try:
        socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except socket.gaierror as exc:
        raise FarmError(f"cannot reach the Dask scheduler at {address}: unknown host {host!r} ({exc.strerror})") \
            from None
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as exc:
        reason = "connection refused: nothing listens on that port" if isinstance(exc, ConnectionRefusedError) \
            else (exc.strerror or str(exc) or type(exc).__name__)
        raise FarmError(f"cannot reach the Dask scheduler at {address}: {reason}; {START_HINT}") from None

    async def handshake():
        # Dask's connect() bounds the TCP connection by `timeout` but waits for
        # the peer's handshake without a limit: a server that is not Dask's
        # (an HTTP dashboard port, SSH, ...) would hang it, or send bytes that
        # it reads as a huge frame length.
        comm = await asyncio.wait_for(connect(address, timeout=timeout), timeout)
        await comm.close()

    try:
        asyncio.run(handshake())
    except (OSError, TimeoutError) as exc:
        raise FarmError(f"{address} accepts connections but no Dask scheduler answers there within "
                        f"{timeout:g} s{f' ({exc})' if str(exc) else ''}; {NOT_A_SCHEDULER}") from None
    except Exception as exc:      # garbage from another kind of server: MemoryError, decode errors, ...
        raise FarmError(f"{address} accepts connections but what answers is not a Dask scheduler "
                        f"({type(exc).__name__}); {NOT_A_SCHEDULER}") from None


# Dask settings of the local cluster. On one machine the scheduler, the
# nannies and this client share the cores with the workers, and Dask's
# housekeeping for a dashboard nobody opens cost about 0.15 cores of a 2-core
# machine when idle (measured with psutil over 4 s: 0.065 cores in this
# process, 0.045 in each worker), more while tiles come in: every server's
# event-loop watchdog ticks every 20 ms, each worker's statistical profiler
# samples the running task every 10 ms, the nannies poll their workers'
# memory every 100 ms. With these, about 0.02 cores. Work stealing stays on:
# the scheduler hands out the first 2 tasks per worker at once, and stealing
# is what moves a waiting tile from a worker still busy with a heavy one to an
# idle one (with few tiles per worker, or frames of unequal cost). A cluster
# started with `dask scheduler` / `dask worker` keeps its own settings
# (docs/distributed.md).
LOCAL_CLUSTER_CONFIG = {
    "distributed.admin.tick.interval": "1s",
    "distributed.worker.profile.enabled": False,
    "distributed.worker.memory.monitor-interval": "1s",
    "distributed.admin.system-monitor.interval": "2s",
}


def start_local_cluster(workers: int):
    """A LocalCluster of `workers` processes of one thread each, without a
    dashboard, with LOCAL_CLUSTER_CONFIG. Its worker processes ignore SIGINT:
    Ctrl-C in a terminal reaches the whole process group, and the workers must
    leave the cancel to the client (which stops their tasks) instead of dying
    with tracebacks. A process started with SIGINT ignored keeps it ignored
    (Python too)."""
    import dask
    from distributed import LocalCluster

    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        with dask.config.set(LOCAL_CLUSTER_CONFIG):   # the workers are started with the config of this moment
            # (The scheduler serves its HTTP routes even without a dashboard, by
            # default on port 8787, with a warning when that is taken: another
            # farm, or the user's own Dask. A free port on this machine instead.)
            return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                                scheduler_kwargs={"dashboard_address": "127.0.0.1:0"},
                                silence_logs=logging.ERROR)
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)


@contextmanager
def connect(scheduler: str | None = None, local: int | None = None, timeout: float = CONNECT_TIMEOUT):
    """Yield (client, render threads per task: 0 where each worker decides)."""
    from distributed import Client

    if scheduler and local:
        raise ValueError("give either a scheduler address or a number of local workers, not both")
    if scheduler:
        check_scheduler(scheduler, timeout)
        client = Client(scheduler, timeout=timeout, set_as_default=False)
        try:
            try:
                client.wait_for_workers(1, timeout=timeout)
            except TimeoutError:
                raise FarmError(f"the Dask scheduler at {scheduler} has no workers (waited {timeout:g} s): "
                                f"start some with `dask worker {scheduler}`") from None
            yield client, 0
        finally:
            client.close()
        return
    cores = os.cpu_count() or 1
    workers = cores if local is None else local
    if workers < 1:
        raise ValueError(f"--local must be at least 1 worker, got {workers}")
    cluster = start_local_cluster(workers)
    try:
        client = Client(cluster, set_as_default=False)
        try:
            yield client, max(1, cores // workers)
        finally:
            client.close()
    finally:
        cluster.close()
