"""The thread-scaling benchmark runs: core/bench/bench_threads.py at a tiny size.

Like test50 it never judges the timings, only that the script runs end to end,
renders every scene at every thread count it was given (it stops if the images
differ between thread counts) and writes a table whose speed-ups and
efficiencies are computed from its own times.
"""
import subprocess
import sys
from pathlib import Path

import pytest

from md_tables import table_rows

ROOT = Path(__file__).resolve().parents[1]
SPD_DIR = ROOT.parent / "shared" / "scenes" / "spd"


def seconds(cell: str) -> float:
    value, unit = cell.split()
    return float(value) * {"s": 1.0, "ms": 1e-3}[unit]


@pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")
def test_thread_scaling_table_covers_every_scene_and_thread_count(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "core" / "bench" / "bench_threads.py"), "--res", "48",
                           "--threads", "1,2,3", "--reps", "1", "--scenes", "balls_s4,distant",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    md = (tmp_path / "thread-scaling.md").read_text()
    rows = table_rows(md, "| scene | threads |")
    assert [(r["scene"].split(",")[0], int(r["threads"])) for r in rows] == \
        [(s, t) for s in ("Balls (size 4)", "Distant") for t in (1, 2, 3)]
    for scene in ("Balls", "Distant"):
        mine = [r for r in rows if r["scene"].startswith(scene)]
        one = seconds(mine[0]["render time"])
        assert mine[0]["speed-up"] == "1.00x"
        for r in mine:
            t, wall = int(r["threads"]), seconds(r["render time"])
            assert wall > 0 and float(r["Mrays/s"]) > 0
            assert float(r["speed-up"].rstrip("x")) == pytest.approx(one / wall, rel=0.02, abs=0.02)
            assert float(r["efficiency"].rstrip("%")) == pytest.approx(100 * one / wall / t, abs=1.5)
    assert (tmp_path / "images" / "benchmarks" / "thread_scaling.png").stat().st_size > 1000
