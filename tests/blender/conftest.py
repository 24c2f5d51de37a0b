"""Fixtures for the real-Blender tests (see runner.py)."""
import json

import numpy as np
import pytest

from runner import ALL_BLENDERS, BPY_VENVS, missing_reason, run_script


@pytest.fixture(params=list(BPY_VENVS))
def bpy_kind(request):
    """Each bpy-from-PyPI Blender (4.5 LTS, 5.0)."""
    reason = missing_reason(request.param)
    if reason:
        pytest.skip(reason)
    return request.param


@pytest.fixture(params=list(ALL_BLENDERS))
def any_blender(request):
    """Each Blender: bpy 4.5, bpy 5.0 and Debian's blender 3.4 binary."""
    reason = missing_reason(request.param)
    if reason:
        pytest.skip(reason)
    return request.param


@pytest.fixture(scope="module", params=list(ALL_BLENDERS))
def module_blender(request):
    """Each Blender, once per test module (for module fixtures that render once)."""
    reason = missing_reason(request.param)
    if reason:
        pytest.skip(reason)
    return request.param


class Export:
    """The exporter's output for one test scene (see scripts/export_dump.py)."""

    def __init__(self, out_dir):
        with open(out_dir / "export.json") as f:
            self.info = json.load(f)
        path = out_dir / "arrays.npz"
        self.arrays = dict(np.load(path)) if path.exists() else {}

    def __getattr__(self, name):
        if name in self.arrays:
            return self.arrays[name]
        return self.info[name]


@pytest.fixture
def export(any_blender, tmp_path):
    """export(scene_name, **builder_options) -> Export, run in each Blender."""
    def run(name, **options):
        args = [f"{k}={json.dumps(v)}" for k, v in options.items()]
        run_script(any_blender, "export_dump.py", name, tmp_path, *args)
        return Export(tmp_path)
    return run
