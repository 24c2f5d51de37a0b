"""The farm's result store (gridwalk.renderfarm.store): what a re-run finds
after the client was killed mid-write, and what it must not find.

The farm itself (a real LocalCluster, Ctrl-C, re-runs) is tested in test60;
these are the store's edge cases, which a kill can only hit by chance there.
"""
import os

import numpy as np

from gridwalk.renderfarm.store import JOURNAL, ResultStore


def test_a_kept_tile_is_found_by_a_new_store_of_the_same_job_only(tmp_path):
    tile = np.arange(24, dtype=np.float32).reshape(2, 3, 4)
    ResultStore(tmp_path, "job-a").put("tile_0000", ".npy", tile)
    again = ResultStore(tmp_path, "job-a")
    assert np.array_equal(np.load(again.find("tile_0000")), tile)
    assert ResultStore(tmp_path, "job-b").find("tile_0000") is None        # another scene or settings


def test_a_line_cut_short_by_a_crash_is_skipped_and_the_next_line_is_read(tmp_path):
    store = ResultStore(tmp_path, "job")
    store.put("tile_0000", ".npy", np.zeros((1, 1, 4), np.float32))
    store.put("tile_0001", ".npy", np.ones((1, 1, 4), np.float32))
    journal = tmp_path / JOURNAL
    data = journal.read_bytes()
    journal.write_bytes(data[:-9])                      # the process died while appending tile_0001's line
    reopened = ResultStore(tmp_path, "job")
    assert reopened.find("tile_0000") is not None
    assert reopened.find("tile_0001") is None           # its file exists, but it was never entered whole
    reopened.put("tile_0002", ".npy", np.full((1, 1, 4), 2, np.float32))
    last = ResultStore(tmp_path, "job")                 # the new line did not run on from the cut one
    assert last.find("tile_0002") is not None and last.find("tile_0000") is not None
    assert last.find("tile_0001") is None


def test_a_result_kept_again_replaces_the_earlier_one(tmp_path):
    ResultStore(tmp_path, "old").put("frame_0001", ".png", b"old")
    ResultStore(tmp_path, "new").put("frame_0001", ".png", b"new")
    assert ResultStore(tmp_path, "old").find("frame_0001") is None
    assert ResultStore(tmp_path, "new").find("frame_0001").read_bytes() == b"new"


def test_remove_deletes_the_results_and_the_journal(tmp_path):
    folder = tmp_path / "out.npy.parts"
    store = ResultStore(folder, "job")
    store.put("tile_0000", ".npy", np.zeros((1, 1, 4), np.float32))
    store.remove()
    assert not folder.exists()


def test_a_journal_of_many_runs_is_compacted_and_keeps_the_latest_results(tmp_path):
    """A frames folder keeps its journal across runs: after 50 re-runs of 4 frames it holds at most
    2 x 4 + 64 lines from earlier runs and this run's 4, not 200."""
    for run in range(50):
        store = ResultStore(tmp_path, f"run-{run}")
        for frame in range(4):
            store.put(f"frame_{frame:04d}", ".png", f"{run}:{frame}".encode())
    reopened = ResultStore(tmp_path, "run-49")
    lines = (tmp_path / JOURNAL).read_bytes().splitlines()
    assert len(lines) <= 2 * 4 + 64 + 4
    assert [reopened.find(f"frame_{f:04d}").read_bytes() for f in range(4)] == [f"49:{f}".encode() for f in range(4)]
    assert ResultStore(tmp_path, "run-48").find("frame_0000") is None


def test_remove_also_deletes_a_manifest_written_by_an_older_version(tmp_path):
    folder = tmp_path / "out.npy.parts"
    folder.mkdir()
    (folder / ".gridwalk-farm.json").write_text("{}")
    store = ResultStore(folder, "job")
    store.put("tile_0000", ".npy", np.zeros((1, 1, 4), np.float32))
    store.remove()
    assert not folder.exists()


def test_a_second_process_cannot_open_a_folder_another_run_holds(tmp_path):
    # (two farm runs writing one output mixed their tiles, and the first's cleanup deleted the
    # second's: the folder is locked by the run that holds it, until it closes or removes it)
    import os
    import subprocess
    import sys
    folder = tmp_path / "out.npy.parts"
    store = ResultStore(folder, "job-a")
    store.put("tile_0000", ".npy", np.zeros((1, 1, 4), np.float32))
    probe = ("import sys\nfrom gridwalk.renderfarm.store import ResultStore, StoreBusy\n"
             "try:\n    ResultStore(sys.argv[1], 'job-b')\nexcept StoreBusy as e:\n    print('busy:', e)\n"
             "else:\n    print('opened')\n")
    out = subprocess.run([sys.executable, "-c", probe, str(folder)], capture_output=True, text=True, timeout=60)
    assert out.stdout.startswith("busy:") and "another farm run" in out.stdout, out.stdout + out.stderr
    assert f"process {os.getpid()}" in out.stdout
    again = ResultStore(folder, "job-a")          # this process's own re-run shares the lock
    assert again.find("tile_0000") is not None
    again.close()
    store.close()
    out = subprocess.run([sys.executable, "-c", probe, str(folder)], capture_output=True, text=True, timeout=60)
    assert out.stdout.startswith("opened"), out.stdout + out.stderr


def test_a_setpriv_without_pdeathsig_is_left_out_not_blamed_on_blender(tmp_path, monkeypatch):
    # util-linux before 2.33 (RHEL 8, Ubuntu 18.04) and BusyBox have a setpriv without
    # --pdeathsig: run through it, every Blender task failed before Blender started
    from gridwalk.renderfarm import blender
    old = tmp_path / "setpriv"
    old.write_text("#!/bin/sh\necho \"setpriv: unrecognized option '$1'\" >&2\nexit 1\n")
    old.chmod(0o755)
    monkeypatch.setenv("PATH", f"{tmp_path}:{os.environ['PATH']}")
    blender._setpriv_with_pdeathsig.cache_clear()
    try:
        assert blender._dying_with_parent(["blender", "-b"]) == ["blender", "-b"]
    finally:
        blender._setpriv_with_pdeathsig.cache_clear()
    monkeypatch.undo()
    wrapped = blender._dying_with_parent(["blender", "-b"])
    blender._setpriv_with_pdeathsig.cache_clear()
    assert wrapped[-3:] == ["--", "blender", "-b"] and wrapped[1:3] == ["--pdeathsig", "KILL"], wrapped


def test_blender_started_by_a_worker_dies_with_the_worker(tmp_path):
    # (a worker SIGKILLed by its nanny left its `blender -b` rendering beside the frame's rerun):
    # a stand-in child started as run_blender starts Blender outlives no SIGKILL of its parent
    import os
    import signal
    import subprocess
    import sys
    import time
    parent = subprocess.Popen([sys.executable, "-c",
                               "import subprocess, sys, time\n"
                               "from gridwalk.renderfarm.blender import _dying_with_parent\n"
                               "child = subprocess.Popen(_dying_with_parent(['sleep', '120']))\n"
                               "print(child.pid, flush=True)\n"
                               "time.sleep(120)\n"], stdout=subprocess.PIPE, text=True)
    child = int(parent.stdout.readline())
    assert os.path.exists(f"/proc/{child}")
    os.kill(parent.pid, signal.SIGKILL)
    parent.wait(timeout=30)
    deadline = time.monotonic() + 10

    def alive():                  # (a zombie waiting for init to reap it is dead)
        try:
            with open(f"/proc/{child}/stat") as f:
                return f.read().rsplit(")", 1)[1].split()[0] != "Z"
        except FileNotFoundError:
            return False
    while alive() and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not alive(), "the child outlived its killed parent"
