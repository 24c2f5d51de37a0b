"""Running Blender on a worker: which binary, which add-on, and watching it.

Each worker machine finds Blender and the Gridwalk add-on the same way,
from the farm's options when given, else from its own environment:

    GRIDWALK_BLENDER             the Blender command (default: `blender` on PATH)
    GRIDWALK_ADDON               a Gridwalk add-on folder to register in each run
                                 (default: none; the add-on must then be enabled
                                 in that Blender's preferences, as after a normal install)
    GRIDWALK_BLENDER_PYTHONPATH  folders put in front of PYTHONPATH for Blender's
                                 Python (where numpy and gridwalk are, if not
                                 in Blender's own Python)
"""
from __future__ import annotations

import functools
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from .jobplugin import TaskStopped

SCRIPT = Path(__file__).resolve().parent / "in_blender.py"


def _dying_with_parent(argv: list) -> list:
    """argv run so that Linux kills it when the thread that started it dies (a worker process
    killed by its nanny or by the system left its Blender rendering for minutes beside the
    frame's rerun): through util-linux's `setpriv --pdeathsig KILL`, which sets the signal and
    then executes argv in the same process. Where setpriv is missing or has no --pdeathsig
    (util-linux before 2.33, BusyBox), or off Linux, argv as it is. (Not a preexec_fn calling
    prctl: that runs Python in the child between fork and exec, which the subprocess docs warn
    may deadlock in a threaded process, and a Dask worker is one.)"""
    setpriv = _setpriv_with_pdeathsig()
    return [setpriv, "--pdeathsig", "KILL", "--", *argv] if setpriv else list(argv)


@functools.lru_cache(maxsize=1)
def _setpriv_with_pdeathsig() -> str | None:
    """setpriv's path where `setpriv --pdeathsig KILL -- true` works (asked once), else None."""
    setpriv = shutil.which("setpriv") if sys.platform.startswith("linux") else None
    if setpriv is None:
        return None
    try:
        probe = subprocess.run([setpriv, "--pdeathsig", "KILL", "--", "true"], stdin=subprocess.DEVNULL,
                               capture_output=True, timeout=10)
    except (OSError, subprocess.TimeoutExpired):
        return None
    return setpriv if probe.returncode == 0 else None


# The engine's last line (blender_addon/engine.py): "Gridwalk: finished; export 0.012 s, build 0.003 s,
# render 0.41 s, total 0.43 s, Tiles 16/16 | 3.2 Mrays/s"; the stages before "render" may change.
FINISHED = re.compile(r"Gridwalk: finished;[^\n]*? render ([\d.]+) s,[^\n]*?\| ([\d.]+) Mrays/s")
STOP_GRACE_SECONDS = 5.0


class BlenderFailed(RuntimeError):
    """Blender did not render what it was asked to (the message says why)."""


@dataclass(frozen=True)
class BlenderSetup:
    """How workers run Blender; None: from the worker's environment (see above)."""
    binary: str | None = None
    addon: str | None = None
    pythonpath: str | None = None

    def command(self) -> str:
        binary = self.binary or os.environ.get("GRIDWALK_BLENDER") or "blender"
        found = shutil.which(binary)
        if found is None:
            raise BlenderFailed(f"Blender {binary!r} is not found on this worker: install it, or set "
                                "GRIDWALK_BLENDER (--blender) to the Blender executable")
        return found

    def addon_folder(self) -> str | None:
        return self.addon or os.environ.get("GRIDWALK_ADDON") or None

    def environment(self, task: dict) -> dict:
        env = dict(os.environ, GRIDWALK_FARM_TASK=json.dumps(task))
        extra = self.pythonpath or os.environ.get("GRIDWALK_BLENDER_PYTHONPATH")
        if extra:
            env["PYTHONPATH"] = os.pathsep.join(p for p in (extra, env.get("PYTHONPATH")) if p)
        return env


def _read_all(stream, lines: list):
    for line in stream:
        lines.append(line)


def run_blender(setup: BlenderSetup, blend: Path, task: dict, should_stop) -> tuple[dict, str]:
    """Run in_blender.py in Blender on `blend` for `task`; (its result, Blender's output).

    should_stop() is polled while Blender runs; when it turns true Blender is
    interrupted (SIGINT, as Ctrl-C: the engine stops its threads), killed if it
    has not left after STOP_GRACE_SECONDS, and TaskStopped is raised.
    """
    task = dict(task, addon=setup.addon_folder())
    argv = [setup.command(), "-b", str(blend), "-noaudio", "--python", str(SCRIPT)]
    proc = subprocess.Popen(_dying_with_parent(argv), env=setup.environment(task), cwd=blend.parent,
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            errors="replace")
    lines: list = []
    reader = threading.Thread(target=_read_all, args=(proc.stdout, lines), daemon=True)
    reader.start()
    try:
        while proc.poll() is None:
            if should_stop():
                _stop(proc)
                raise TaskStopped("Blender was stopped: the task was cancelled")
            time.sleep(0.1)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        reader.join(timeout=5)
    output = "".join(lines)
    return _result(proc.returncode, output, task["action"]), output


def _stop(proc):
    proc.send_signal(signal.SIGINT)
    try:
        proc.wait(timeout=STOP_GRACE_SECONDS)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


def _result(code: int, output: str, action: str) -> dict:
    errors = [line.split(" ", 1)[1].strip() for line in output.splitlines()
              if line.startswith("GRIDWALK-FARM-ERROR ")]
    results = [line.split(" ", 1)[1] for line in output.splitlines() if line.startswith("GRIDWALK-FARM-RESULT ")]
    if errors:
        raise BlenderFailed(errors[-1])
    if code != 0 or not results:
        tail = " | ".join(line.strip() for line in output.strip().splitlines()[-6:])
        raise BlenderFailed(f"Blender exited with status {code} without a result; its last lines: {tail}")
    result = json.loads(results[-1])
    if action != "probe":
        finished = FINISHED.findall(output)
        if not finished:
            raise BlenderFailed("Blender reported no finished Gridwalk render (was another engine used?)")
        seconds, mrays = (float(v) for v in finished[-1])
        result.update(seconds=seconds, rays=int(mrays * 1e6 * seconds))
    return result
