"""An NFF file through File > Import > NFF in real Blender (tests/blender/scripts/nff_import_dump.py),
and the core's render of the same file to compare with."""
import json

import numpy as np

import exr
import gridwalk
from gridwalk.io import load_nff
from runner import run_script

SETTINGS = {"aa": "JITTERED", "aa_samples": 2}


def import_nff(kind, path, out, *options):
    """(import.json, exported arrays) of the import of `path` in Blender `kind`."""
    run_script(kind, "nff_import_dump.py", path, out, *options, timeout=300)
    info = json.loads((out / "import.json").read_text())
    arrays = out / "arrays.npz"
    return info, dict(np.load(arrays)) if arrays.exists() else {}


def import_and_render(kind, path, out) -> dict:
    """The import rendered by GRIDWALK in Blender (rgba) and the core's render of the file (core)."""
    info, arrays = import_nff(kind, path, out, "render=" + json.dumps(SETTINGS))
    nff = load_nff(path)
    # the import is rendered with Film Transparent (camera misses RGB 0, alpha 0, as Cycles)
    core = gridwalk.render(gridwalk.Scene(**nff, world=gridwalk.World(transparent=True)),
                           gridwalk.RenderSettings(**info["render_settings"]))
    rgba = exr.rgba(exr.read_exr(out / "gridwalk.exr"), "ViewLayer.Combined.")
    return {"kind": kind, "info": info, "arrays": arrays, "nff": nff, "core": core, "rgba": rgba, "out": out}


def imported_fixture(names, path_of):
    """A module-scoped fixture: import_and_render (plus "name") for each of
    `names` in bpy 4.5 and 5.0, the file given by path_of(name, out_dir)."""
    import pytest

    from runner import missing_reason

    @pytest.fixture(scope="module", params=[(k, s) for k in ("bpy45", "bpy50") for s in names],
                    ids=lambda p: f"{p[0]}-{p[1]}")
    def imported(request, tmp_path_factory):
        kind, name = request.param
        if missing_reason(kind):
            pytest.skip(missing_reason(kind))
        out = tmp_path_factory.mktemp(f"{kind}_{name}")
        return {**import_and_render(kind, path_of(name, out), out), "name": name}
    return imported
