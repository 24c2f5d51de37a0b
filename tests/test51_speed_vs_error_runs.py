"""The speed-vs-error benchmark script runs end to end at a tiny size and
writes every section (the full run regenerates docs/speed-vs-error.md)."""
import subprocess
import sys
from pathlib import Path

from md_tables import table_rows

SCRIPT = Path(__file__).resolve().parents[1] / "core" / "bench" / "bench_speed_vs_error.py"


def test_quick_run_writes_every_scene(tmp_path):
    proc = subprocess.run([sys.executable, str(SCRIPT), "--quick", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    md = (tmp_path / "speed-vs-error.md").read_text()
    for scene in ("edges", "penumbra", "dof", "glossy"):
        assert f"images/speed-vs-error/{scene}-rmse.png" in md
        assert (tmp_path / "images" / "speed-vs-error" / f"{scene}-rmse.png").stat().st_size > 1000
    assert "| strategy | samples |" in md and "RMSE" in md and "slope" in md.lower()
    # What the tables measure must hold even at the quick sizes: for each
    # jittered / stratified strategy, more samples per pixel give a smaller
    # error against the reference (the renders are real, so this can fail).
    rows = table_rows(md, "| strategy | samples | wall (ms)")
    by_strategy = {}
    for row in rows:
        by_strategy.setdefault(row["strategy"], []).append((float(row["rays/px"]), float(row["RMSE"])))
    checked = 0
    for strategy, points in by_strategy.items():
        if "jittered" not in strategy or len(points) < 2:
            continue
        points.sort()
        assert points[-1][1] < points[0][1], (strategy, points)
        checked += 1
    assert checked >= 1, by_strategy
