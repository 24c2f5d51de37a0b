"""The instruction-count benchmark runs: core/bench/bench_instructions.py on one
small scene (SPD mount, size 4) and a few rays, under valgrind's callgrind.

Like test50 it never judges the numbers' size, only that the script runs end to
end and writes its table: one row per ray kind, with counts for both engines
that are positive and finite, and Embree's traversal inside its whole call.
"""
import importlib.util
import math
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from md_tables import table_rows

ROOT = Path(__file__).resolve().parents[1]
SPD_DIR = ROOT.parent / "shared" / "scenes" / "spd"


@pytest.mark.skipif(shutil.which("callgrind_control") is None, reason="valgrind is not installed")
@pytest.mark.skipif(importlib.util.find_spec("embreex") is None, reason="embreex is not installed")
@pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")
def test_instruction_counts_are_written_for_every_ray_kind(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "core" / "bench" / "bench_instructions.py"),
                           "--scenes", "mount_s4", "--rays", "256", "--out", str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    md = (tmp_path / "instruction-counts.md").read_text()
    rows = table_rows(md, "| scene | ray kind |")
    assert [r["ray kind"] for r in rows] == ["primary", "shadow", "random"]
    for r in rows:
        gw, em = float(r["Gridwalk per ray"]), float(r["Embree per ray"])
        inside = float(r["Embree per ray inside rtcIntersect1 / rtcOccluded1"])
        assert 0 < gw < 1e6 and 0 < em < 1e6 and math.isfinite(gw)
        assert 0 < inside <= em   # the traversal is part of embreex's call
        assert float(r["Gridwalk / Embree"].strip("*")) == pytest.approx(gw / em, rel=0.01)
    summary = table_rows(md, "| ray kind | over Embree's whole call")
    assert [r["ray kind"] for r in summary] == ["primary", "shadow", "random"]
    for r, row in zip(summary, rows):   # one scene: the geometric mean is its own ratio
        assert float(r["over Embree's whole call"].strip("*")) == float(row["Gridwalk / Embree"].strip("*"))
