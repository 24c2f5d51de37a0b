"""Cancel at random moments 50 times, then render again; render 100 frames of an
animation in one session (issue 7, "Further checks"). See scripts/cancel_and_memory.py.

Cancels go through the engine's single cancel check (streaming.break_requested,
which calls RenderEngine.test_break): the script makes it return True once a
random delay has passed, so cancels land before the export, between export,
grid build and render, and while the worker threads render. One more render
gets a real SIGINT while its workers run. Threads are
counted from /proc/self/task; memory is the resident set from /proc/self/statm
(read after freed heap pages are handed back to the system, at frames 10 and 100).
"""
import json
from collections import Counter

import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, missing_reason, run_script

WORKERS = 4
CANCEL_SETTINGS = f'settings={{"aa": "JITTERED", "aa_samples": 5, "threads": {WORKERS}}}'


def _run(kind, tmp_path_factory, mode, *options):
    reason = missing_reason(kind)
    if reason:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp(f"{mode}_{kind}")
    run_script(kind, "cancel_and_memory.py", mode, out, *options, timeout=240)   # exit 0: no crash
    return out, json.loads((out / f"{mode}.json").read_text())


@pytest.fixture(scope="module", params=list(ALL_BLENDERS))
def cancels(request, tmp_path_factory):
    return _run(request.param, tmp_path_factory, "cancel", "cancels=50", CANCEL_SETTINGS)


@pytest.fixture(scope="module", params=list(ALL_BLENDERS))
def animation(request, tmp_path_factory):
    return _run(request.param, tmp_path_factory, "animation", "frames=100", "levels=1")


def test_fifty_random_cancels_leave_no_thread_and_the_next_render_is_intact(cancels):
    out, info = cancels
    renders = info["renders"]
    assert info["first"] == "finished" and len(renders) == 50
    assert not any(r["traceback"] for r in renders)
    stages = Counter(r["stage"] for r in renders)
    assert "unknown" not in stages, stages
    assert stages["while rendering"] >= 5, stages                      # the workers were running
    assert sum(n for s, n in stages.items() if s not in ("while rendering", "finished")) >= 5, stages
    idle = info["tasks_idle"]
    for r in renders:
        assert r["tasks_after"] <= idle, r                              # no worker outlives a render
    while_rendering = [r for r in renders if r["stage"] == "while rendering"]
    assert max(r["peak_tasks"] for r in while_rendering) >= idle + WORKERS   # and they were counted
    assert max(r["join_ms"] for r in while_rendering) < 100.0
    # Ctrl-C (SIGINT) while rendering: the real test_break in `blender -b`, KeyboardInterrupt in bpy
    interrupted = info["interrupted"]
    assert not interrupted["traceback"] and interrupted["tasks_after"] <= idle
    assert interrupted["stage"] in ("while rendering", "interrupted"), interrupted
    # rendering again after all that: complete, no thread left, the same image bit for bit
    assert info["last"] == "finished" and info["tasks_end"] <= idle
    first = exr.read_exr(out / "first.exr")
    last = exr.read_exr(out / "last.exr")
    assert first.keys() == last.keys()
    for name in first:
        np.testing.assert_array_equal(first[name], last[name], err_msg=name)
    assert exr.rgba(last, "ViewLayer.Combined.")[..., 3].mean() > 0.05


TRIMMED = range(10, 101, 10)     # the frames whose memory is read after the allocator's trim


def trend_growth(rss: dict) -> float:
    """Growth from frame 10 to 100 along the trend of the trimmed samples: the
    median of the slopes between every two of them (Theil-Sen), times 90 frames,
    over frame 10's memory. A leak raises every later sample and so the trend;
    a single sample caught before Blender frees a frame's buffers (+7% at one
    frame, back to the baseline at the next, seen on Blender 3.4) does not."""
    frames = np.array(TRIMMED, float)
    values = np.array([rss[int(f)] for f in frames], float)
    i, j = np.triu_indices(len(frames), k=1)
    slope = np.median((values[j] - values[i]) / (frames[j] - frames[i]))
    return slope * (frames[-1] - frames[0]) / values[0]


def test_memory_trend_ignores_one_high_sample_but_not_a_leak():
    flat = {f: 100.0 for f in TRIMMED}
    assert trend_growth({**flat, 70: 107.0}) == 0.0
    assert trend_growth({**flat, 100: 107.0}) == 0.0
    leak = {f: 100.0 + 0.06 * (f - 10) for f in TRIMMED}          # 5.4% over 90 frames
    assert trend_growth(leak) == pytest.approx(0.054)
    assert trend_growth({**leak, 40: 90.0}) == pytest.approx(0.054)


def test_hundred_frames_in_one_session_grow_memory_less_than_five_percent(animation):
    out, info = animation
    assert info["finished"] == 100 and not info["traceback"]
    rss = {int(frame): value for frame, value in info["rss"].items()}
    assert sorted(rss) == list(range(1, 101))
    growth = trend_growth(rss)
    trimmed = {f: round(rss[f] / 2**20, 1) for f in TRIMMED}
    assert growth < 0.05, f"resident memory grew {growth:.1%} from frame 10 to 100 (MiB: {trimmed})"
    tasks = {int(frame): n for frame, n in info["tasks"].items()}          # after each frame
    assert max(tasks[f] for f in range(10, 101)) <= tasks[10] and info["tasks_after"] <= tasks[10]
    first = exr.rgba(exr.read_exr(out / "frame_0001.exr"), "ViewLayer.Combined.")
    last = exr.rgba(exr.read_exr(out / "frame_0100.exr"), "ViewLayer.Combined.")
    assert first[..., 3].mean() > 0.05 and last[..., 3].mean() > 0.05
    assert not np.array_equal(first[..., 3], last[..., 3])             # the objects moved


@pytest.mark.parametrize("kind", ["bpy45"])
def test_cancel_during_the_export_takes_effect_within_100ms(kind, tmp_path_factory):
    """1500 separate mesh objects; the cancel lands after the export has read
    500 of them: the engine's render returns within 100 ms (Blender's own
    saving of the empty result afterwards is not counted), without reading the rest."""
    out, info = _run(kind, tmp_path_factory, "export", "objects=1500", "at=500")
    assert info["full"] == "finished", info["log"]
    assert info["full_seconds"] > 0.3, info                   # the export is long enough to cancel inside
    assert info["stage"] == "during the export", info["log"]
    assert not info["traceback"], info["log"]
    assert info["added"] < 510, info                         # it stopped reading objects at once
    assert info["latency_ms"] < 100.0, info
