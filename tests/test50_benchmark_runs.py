"""The benchmark command runs: core/bench/bench_all.py --quick at tiny sizes.

Benchmarks are scripts, not timed tests: this only checks that the one command
writing docs/benchmarks.md runs end to end (Blender and Embree included) and
writes every section, table and plot. It never judges the timings.
"""
import importlib.util
import re
import subprocess
import sys
from pathlib import Path

import pytest

from md_tables import table_rows

ROOT = Path(__file__).resolve().parents[1]
SPD_DIR = ROOT.parent / "shared" / "scenes" / "spd"
HAVE_BPY = (ROOT / ".venv-bpy45" / "bin" / "python").exists()
HAVE_EMBREE = importlib.util.find_spec("embreex") is not None
SECTIONS = ("## Headline", "## 1. The seed's table", "## 2. Embree", "## 3. Cycles",
            "## 4. Havran & Sixta (1999)", "## Gaps")


@pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")
def test_quick_benchmark_writes_every_section(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "core" / "bench" / "bench_all.py"), "--quick",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    md = (tmp_path / "benchmarks.md").read_text()
    for heading in SECTIONS:
        assert heading in md, f"missing section {heading!r}"
    positions = [md.index(h) for h in SECTIONS]
    assert positions == sorted(positions), "sections out of order"
    assert "This section failed" not in md, md[md.index("This section failed"):][:3000]
    needles = ["speed-up no grid/grid", "seed's speed-up", "core-s", "tests/ray", "cells/ray", "Thread scaling",
               "bytes per triangle", "`nproc` = "]
    needles += ["Gridwalk Mrays/s", "hit/miss agree"] if HAVE_EMBREE else []
    needles += ["Equal-error time", "Suzanne PLY"] if HAVE_BPY else []
    for needle in needles:
        assert needle in md, f"missing {needle!r}"
    if HAVE_EMBREE:
        # Every compared scene and ray kind: the two engines agree on hit/miss
        # (to 99.99%) and on the primitive hit, so the speeds compare like with like.
        rows = table_rows(md, "| scene | ray kind |")
        compared = [r for r in rows if r["hit/miss agree %"] != "-"]
        assert len(compared) >= 6, rows
        for r in compared:
            assert float(r["hit/miss agree %"]) >= 99.99, r
            assert r["same prim %"] == "-" or float(r["same prim %"]) >= 99.9, r
    images = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", md)
    assert len(images) >= 3 + HAVE_EMBREE + 2 * HAVE_BPY, images
    for image in images:
        path = tmp_path / image
        assert path.is_file() and path.stat().st_size > 1000, f"plot {image} missing or empty"


@pytest.mark.skipif(not HAVE_EMBREE, reason="embreex is not installed")
def test_layouts_benchmark_writes_a_row_per_layout_and_ray_kind(tmp_path):
    proc = subprocess.run([sys.executable, str(ROOT / "core" / "bench" / "bench_layouts.py"), "--quick",
                           "--out", str(tmp_path)], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-4000:]
    md = (tmp_path / "layouts.md").read_text()
    sys.path.insert(0, str(ROOT / "core" / "bench"))
    from layout_scenes import LAYOUTS
    rows = table_rows(md, "| layout | rays |")
    assert [(r["layout"], r["rays"]) for r in rows] == \
        [(label, kind) for label, _ in LAYOUTS.values() for kind in ("primary", "random")]
    for r in rows:
        assert float(r["agree %"]) >= 99.9, r
        assert float(r["ratio"].strip("*")) > 0 and float(r["tests/ray"]) >= 0, r
    builds = table_rows(md, "| layout | triangles | grids |")
    assert len(builds) == len(LAYOUTS)
