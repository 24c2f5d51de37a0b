"""Distributed rendering on a real Dask LocalCluster with 2 worker processes:
NFF tiles put together equal the single-machine render bit for bit, the scene
reaches each worker once, a killed worker changes nothing, a bad scheduler
address fails in seconds, Ctrl-C stops every task and a re-run renders only
the missing tiles, and the command starts its own cluster."""
import logging
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import numpy as np
import pytest
from distributed import Client, LocalCluster

import gridwalk
from gridwalk import FarmError, RenderSettings
from gridwalk.renderfarm import plan
from gridwalk.renderfarm.core_job import load_scene
from test13_cli import SPD_DIR, gridwalk as run_cli, needs_spd

pytestmark = needs_spd

HEAVY_SCENE, HEAVY_SIZE = SPD_DIR / "balls_s3.nff", (160, 120)
HEAVY = RenderSettings(aa="jittered", aa_samples=5, shadow="area", shadow_samples=2)
HEAVY_OPTIONS = ["--width", 160, "--height", 120, "--aa", "jittered", "--aa-samples", 5, "--shadow", "area",
                 "--shadow-samples", 2]


@pytest.fixture(scope="module")
def cluster():
    """(scheduler address, client) of a LocalCluster: 2 worker processes, each with a nanny."""
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as local, Client(local, set_as_default=False) as client:
        yield local.scheduler_address, client


def single_render(scene_path, size, settings):
    kwargs, _ = load_scene(scene_path, *size)
    return gridwalk.render(gridwalk.Scene(**kwargs), settings)


@pytest.fixture(scope="module")
def heavy_reference():
    return single_render(HEAVY_SCENE, HEAVY_SIZE, HEAVY)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def test_tiles_cover_every_pixel_exactly_once():
    for width, height, count in [(160, 120, 16), (97, 61, 7), (5, 300, 6), (64, 64, 1), (10, 3, 30)]:
        rects = plan.tiles(width, height, count)
        assert len(rects) == count
        cover = np.zeros((height, width), int)
        for x, y, w, h in rects:
            assert w >= 1 and h >= 1
            cover[y:y + h, x:x + w] += 1
        assert np.all(cover == 1), (width, height, count)
    assert plan.tile_grid(100, 100, 7) == (7, 1)          # a prime count: strips
    assert plan.parse_frames("1-3,8, 10..11") == [1, 2, 3, 8, 10, 11]
    for bad in ("3-1", "a-b", "1-"):
        with pytest.raises(ValueError, match="--frames"):
            plan.parse_frames(bad)


def test_the_kept_tiles_digest_changes_with_any_pixel_value_or_field_of_the_scene():
    """A re-run keeps tiles only when the scene is the same: a texture's pixels,
    one value deep in a long array and a record's field all change the digest."""
    from gridwalk.renderfarm.core_job import _scene_digest
    pixels = np.zeros((64, 64, 3), np.uint8)
    base = {"images": [gridwalk.Image(pixels, name="tex")], "uvs": [np.zeros((2000, 3, 2), np.float32)],
            "materials": [gridwalk.Material(color=(0.5, 0.5, 0.5))]}
    edited_pixels = pixels.copy()
    edited_pixels[40, 40, 1] = 7
    edited_uvs = np.zeros((2000, 3, 2), np.float32)
    edited_uvs[1000, 1, 0] = 0.25
    variants = [{**base, "images": [gridwalk.Image(edited_pixels, name="tex")]},
                {**base, "images": [gridwalk.Image(pixels, colorspace="linear", name="tex")]},
                {**base, "uvs": [edited_uvs]},
                {**base, "materials": [gridwalk.Material(color=(0.5, 0.5, 0.6))]}]
    digest = _scene_digest(base)
    assert _scene_digest(dict(base)) == digest
    assert all(_scene_digest(v) != digest for v in variants)


def test_nff_tiles_put_together_equal_the_single_machine_render(cluster, tmp_path):
    address, _ = cluster
    settings = RenderSettings(aa="adaptive", shadow="area", shadow_samples=2)   # lattice points shared by tiles
    reference = single_render(SPD_DIR / "balls_s2.nff", (96, 72), settings)
    for tiles in (6, 7):
        out = tmp_path / f"tiles{tiles}.npy"
        report = gridwalk.farm(SPD_DIR / "balls_s2.nff", out, settings=settings, tiles=tiles, width=96, height=72,
                               scheduler=address)
        image = np.load(out)
        assert image.dtype == np.float32 and np.array_equal(image, reference), f"{tiles} tiles differ"
        assert sorted(report.rendered) == list(range(tiles)) and not report.reused
        assert not (tmp_path / f"tiles{tiles}.npy.parts").exists()        # the kept tiles are cleaned up
        # The scene reached each worker once: every worker that rendered built it exactly once.
        assert all(w.scene_loads == 1 for w in report.workers.values()), report.workers
        assert sum(w.items for w in report.workers.values()) == tiles


def render_killing_a_worker_mid_tile(address, client, out):
    """Renders the heavy scene on the cluster and SIGKILLs a worker while it runs a tile; returns
    the farm's report, the killed worker's address and the tile it was running."""
    outcome = {}

    def render():
        try:
            outcome["report"] = gridwalk.farm(HEAVY_SCENE, out, settings=HEAVY, tiles=8, width=HEAVY_SIZE[0],
                                              height=HEAVY_SIZE[1], scheduler=address)
        except BaseException as exc:           # handed to the test thread
            outcome["error"] = exc

    thread = threading.Thread(target=render)
    thread.start()
    busy = {}
    deadline = time.monotonic() + 60
    while not busy and time.monotonic() < deadline:       # a worker in the middle of a tile
        busy = {w: keys for w, keys in client.run(
            lambda dask_worker: [ts.key for ts in dask_worker.state.executing if "gridwalk-tile" in ts.key]).items()
            if keys}
        time.sleep(0.01)
    assert busy, "no worker ever ran a tile"
    victim, keys = next(iter(busy.items()))
    pid = client.run(os.getpid, workers=[victim])[victim]
    os.kill(pid, signal.SIGKILL)
    thread.join(timeout=120)
    assert not thread.is_alive()
    assert "error" not in outcome, outcome.get("error")
    client.wait_for_workers(2, timeout=60)                  # the nanny restarted it, for what follows
    return outcome["report"], victim, int(keys[0].rsplit("-", 1)[1])


def test_a_killed_worker_leaves_the_output_identical(cluster, heavy_reference, tmp_path):
    address, client = cluster
    # The tile seen running may finish in the moment before the kill lands (a loaded machine):
    # then it was not lost, and the kill is tried again on a new render.
    for attempt in range(3):
        out = tmp_path / f"killed{attempt}.npy"
        report, victim, killed_tile = render_killing_a_worker_mid_tile(address, client, out)
        assert np.array_equal(np.load(out), heavy_reference)
        if report.done_by[killed_tile] != victim:          # its tile was rendered again, elsewhere
            break
    else:
        pytest.fail("the killed worker's tile was never lost to the kill (it always finished first)")


def test_a_bad_scheduler_address_fails_within_seconds_with_a_clear_message(tmp_path):
    port = free_port()
    t0 = time.monotonic()
    run = run_cli("farm", SPD_DIR / "balls_s1.nff", "-o", tmp_path / "x.png", "--scheduler", f"tcp://127.0.0.1:{port}")
    elapsed = time.monotonic() - t0
    assert run.returncode == 1 and elapsed < 15, (run.returncode, elapsed)
    message = run.stderr.strip()
    assert message == (f"gridwalk: error: cannot reach the Dask scheduler at tcp://127.0.0.1:{port}: connection "
                       "refused: nothing listens on that port; start one with `dask scheduler` (it listens on "
                       "tcp://HOST:8786) and workers with `dask worker tcp://HOST:8786`, or leave out --scheduler "
                       "to run a local cluster"), message
    for address, expected in [("tcp://no-such-host.invalid:8786", "unknown host 'no-such-host.invalid'"),
                              ("tcp//farm", "is not a scheduler address"),
                              ("http://127.0.0.1:8786", "unsupported scheme 'http'"),
                              ("tcp://127.0.0.1:99999", "port 99999 is not a TCP port")]:
        t0 = time.monotonic()
        with pytest.raises(FarmError, match=expected):
            gridwalk.farm(SPD_DIR / "balls_s1.nff", tmp_path / "x.png", scheduler=address)
        assert time.monotonic() - t0 < 10


def test_a_server_that_is_not_a_scheduler_fails_within_its_timeout_with_a_clear_message(tmp_path):
    """The dashboard's HTTP port, or a server that speaks first (SSH): Dask alone would wait
    for a handshake forever, or read the banner as a frame length and raise MemoryError."""
    http = ThreadingHTTPServer(("127.0.0.1", 0), BaseHTTPRequestHandler)
    banner = socket.create_server(("127.0.0.1", 0))

    def greet():
        while True:
            try:
                conn, _ = banner.accept()
            except OSError:               # closed at the end of the test
                return
            conn.sendall(b"SSH-2.0-OpenSSH_9.2p1 Debian-2\r\n")

    threading.Thread(target=http.serve_forever, daemon=True).start()
    threading.Thread(target=greet, daemon=True).start()
    try:
        for port, expected in [(http.server_address[1], "no Dask scheduler answers there within 2 s"),
                               (banner.getsockname()[1], "what answers is not a Dask scheduler")]:
            t0 = time.monotonic()
            with pytest.raises(FarmError, match=expected) as info:
                gridwalk.farm(SPD_DIR / "balls_s1.nff", tmp_path / "x.png", scheduler=f"tcp://127.0.0.1:{port}",
                              connect_timeout=2)
            assert "a scheduler listens on 8786 by default" in str(info.value)
            assert time.monotonic() - t0 < 8
    finally:
        http.shutdown()
        http.server_close()
        banner.close()


def test_ctrl_c_stops_every_task_and_a_rerun_renders_only_the_missing_tiles(cluster, heavy_reference, tmp_path):
    address, client = cluster
    out = tmp_path / "interrupted.npy"
    argv = [sys.executable, "-m", "gridwalk", "farm", HEAVY_SCENE, "-o", out, "--tiles", 16, "--scheduler", address,
            *HEAVY_OPTIONS]
    proc = subprocess.Popen([str(a) for a in argv], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    seen = ""
    try:
        while " 2/16 tiles" not in seen and proc.poll() is None:
            seen += proc.stderr.read(1)
        proc.send_signal(signal.SIGINT)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130 and "gridwalk: cancelled" in err, seen + err
    running = client.run(lambda dask_worker: dask_worker.state.executing_count)
    assert set(running.values()) == {0}, f"tasks still running after Ctrl-C: {running}"
    kept = sorted((tmp_path / "interrupted.npy.parts").glob("tile_*.npy"))
    assert 2 <= len(kept) < 16

    report = gridwalk.farm(HEAVY_SCENE, out, settings=HEAVY, tiles=16, width=HEAVY_SIZE[0], height=HEAVY_SIZE[1],
                           scheduler=address)
    assert sorted(report.reused) == [int(p.stem[5:]) for p in kept]
    assert sorted(report.reused + report.rendered) == list(range(16))
    assert np.array_equal(np.load(out), heavy_reference)


def test_farm_command_starts_a_local_cluster_and_reports_progress_and_rays_per_worker(tmp_path):
    out = tmp_path / "local.npy"
    run = run_cli("farm", SPD_DIR / "balls_s1.nff", "-o", out, "--local", 2, "--tiles", 8, "--width", 64,
                  "--height", 48, "--aa", "jittered", "--aa-samples", 2)
    assert run.returncode == 0, run.stderr
    reference = single_render(SPD_DIR / "balls_s1.nff", (64, 48), RenderSettings(aa="jittered", aa_samples=2))
    assert np.array_equal(np.load(out), reference)
    assert "8/8 tiles" in run.stderr and "farm [" in run.stderr           # the progress bar
    per_worker = [line for line in run.stdout.splitlines() if line.strip().startswith("worker tcp://")]
    assert len(per_worker) == 2 and all(line.endswith("Mrays/s") for line in per_worker), run.stdout
    assert sum(int(line.split(": ")[1].split(" tiles")[0]) for line in per_worker) == 8


def test_the_local_cluster_keeps_its_housekeeping_quiet_and_the_global_config_untouched():
    """`--local` clusters run with LOCAL_CLUSTER_CONFIG in every worker process (on a 2-core machine
    Dask's default watchdog ticks, task profiler and memory polls took about 0.15 cores from the
    workers), and starting one leaves this process's Dask config as it was."""
    import dask

    from gridwalk.renderfarm.cluster import LOCAL_CLUSTER_CONFIG, start_local_cluster

    for key in LOCAL_CLUSTER_CONFIG:                 # each is one of Dask's own settings (a typo would be ignored)
        dask.config.get(key)
    before = dask.config.get("distributed.worker.profile.enabled")
    local = start_local_cluster(2)
    try:
        with Client(local, set_as_default=False) as client:
            seen = client.run(lambda: {key: dask.config.get(key) for key in LOCAL_CLUSTER_CONFIG})
            assert len(seen) == 2 and all(config == LOCAL_CLUSTER_CONFIG for config in seen.values()), seen
            assert client.submit(sum, [1, 2, 3]).result(timeout=30) == 6
    finally:
        local.close()
    assert dask.config.get("distributed.worker.profile.enabled") == before


def test_a_local_cluster_starts_without_warnings_when_the_dask_dashboard_port_is_taken():
    # Another farm, or the user's own Dask, on port 8787: the scheduler's HTTP routes once
    # defaulted to it and warned ("Port 8787 is already in use") on the farm's output.
    import socket
    import warnings

    from gridwalk.renderfarm.cluster import start_local_cluster

    taken = socket.socket()
    try:
        taken.bind(("", 8787))
    except OSError:
        pass                                         # already taken by something else: as good
    taken.listen()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            local = start_local_cluster(1)
        try:
            with Client(local, set_as_default=False) as client:
                assert client.submit(sum, [1, 2]).result(timeout=30) == 3
        finally:
            local.close()
    finally:
        taken.close()


def test_a_run_writing_an_output_another_run_writes_is_refused_before_any_tile(cluster, tmp_path):
    # (two runs writing one output mixed their tiles in it, and the first's cleanup deleted the
    # second's: the output's .parts folder is locked by the run writing it)
    from gridwalk.renderfarm.store import ResultStore
    address, _ = cluster
    out, parts = tmp_path / "shared.npy", tmp_path / "shared.npy.parts"
    holder = ResultStore(parts, "another job")            # a run of this process holds the folder
    call = (f"gridwalk.farm({str(SPD_DIR / 'balls_s2.nff')!r}, {str(out)!r}, "
            f"settings=gridwalk.RenderSettings(aa='center'), tiles=4, width=96, height=72, scheduler={address!r})")
    probe = subprocess.run([sys.executable, "-c", "import gridwalk\ntry:\n    " + call +
                            "\nexcept gridwalk.FarmError as e:\n    print('refused:', e)\n"],
                           capture_output=True, text=True, timeout=120)
    assert probe.stdout.startswith("refused:") and "another farm run" in probe.stdout, probe.stdout + probe.stderr
    assert f"process {os.getpid()}" in probe.stdout
    assert not out.exists() and [p.name for p in parts.iterdir()] == [".gridwalk-farm.lock"]   # no tile written
    holder.close()
    gridwalk.farm(SPD_DIR / "balls_s2.nff", out, settings=RenderSettings(aa="center"), tiles=4, width=96,
                  height=72, scheduler=address)
    assert np.array_equal(np.load(out), single_render(SPD_DIR / "balls_s2.nff", (96, 72), RenderSettings(aa="center")))
    assert not parts.exists()


def test_a_blend_jobs_tiles_and_frames_are_checked_before_any_blender_runs(tmp_path):
    from gridwalk.renderfarm.blend_job import BlendJob
    blend = tmp_path / "scene.blend"
    blend.write_bytes(b"BLENDER-v304" + bytes(64))
    for tiles in (0, -3, 2.5, True):
        with pytest.raises(ValueError, match="--tiles must be at least 1"):
            BlendJob(blend, tmp_path / "out.exr", tiles=tiles)
    job = BlendJob(blend, tmp_path / "out.exr", tiles=100000)
    assert job.needs_probe                          # the size comes from Blender: the probe checks the tiles
    with pytest.raises(ValueError, match="more than the 64 x 48 image has pixels"):
        job.use_probe({"frame_start": 1, "frame_end": 1, "width": 64, "height": 48})
    fits = BlendJob(blend, tmp_path / "out.exr", tiles=6)
    fits.use_probe({"frame_start": 1, "frame_end": 1, "width": 64, "height": 48})
    assert not fits.needs_probe and fits.items == list(range(6))
    assert plan.parse_frames("1048573-1048574") == [1048573, 1048574]
    text = tmp_path / "notes.blend"
    text.write_text("not a scene")
    with pytest.raises(ValueError, match="not a .blend file"):
        BlendJob(text, tmp_path / "frames")
    for text in ("1048575", "1048574,2000000", "-1048575--1048570"):
        with pytest.raises(ValueError, match="outside Blender's frames"):
            plan.parse_frames(text)
