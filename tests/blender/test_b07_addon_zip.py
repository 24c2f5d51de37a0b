"""The user-facing zip: built by blender_addon/build_zip.py with the gridwalk
wheel inside, installed as an extension (Blender 4.5, 5.0; Blender installs the
wheel) or as a legacy add-on (Blender 3.4; the add-on unpacks the wheel),
enabled, and rendering."""
import json
import os
import subprocess
import sys
import zipfile

import pytest

import exr
from runner import BLENDER34_SITE, ROOT, SCRIPTS, command, run


@pytest.fixture(scope="module")
def addon_zip(tmp_path_factory):
    """The zip, around the newest wheel in dist/ (built from this checkout if none)."""
    out = tmp_path_factory.mktemp("zip")
    wheels = sorted((ROOT / "dist").glob("gridwalk-*.whl"), key=os.path.getmtime)
    args = ["--wheel", str(wheels[-1])] if wheels else []
    proc = subprocess.run([sys.executable, str(ROOT / "blender_addon" / "build_zip.py"), *args,
                           "--out", str(out)], capture_output=True, text=True, timeout=900, check=True)
    return proc.stdout.strip().splitlines()[-1]


def test_zip_holds_one_folder_with_manifest_and_wheel(addon_zip):
    names = zipfile.ZipFile(addon_zip).namelist()
    assert {n.split("/")[0] for n in names} == {"gridwalk_blender"}
    wheel = [n for n in names if n.endswith(".whl")]
    assert len(wheel) == 1 and wheel[0].startswith("gridwalk_blender/wheels/gridwalk-")
    manifest = zipfile.ZipFile(addon_zip).read("gridwalk_blender/blender_manifest.toml").decode()
    assert f'wheels = ["./wheels/{wheel[0].rsplit("/", 1)[1]}"]' in manifest
    assert "gridwalk_blender/build_zip.py" not in names
    assert not any("__pycache__" in n for n in names)


def _numpy_only(tmp_path):
    """A PYTHONPATH folder with Debian blender's numpy and nothing else (no gridwalk)."""
    site = tmp_path / "numpy_only"
    site.mkdir()
    for path in BLENDER34_SITE.glob("numpy*"):
        os.symlink(path, site / path.name)
    return str(site)


def test_zip_installs_enables_and_renders(any_blender, addon_zip, tmp_path):
    argv, env = command(any_blender, SCRIPTS / "install_zip.py", [addon_zip, tmp_path])
    env["BLENDER_USER_RESOURCES"] = str(tmp_path / "user")
    env["PYTHONPATH"] = _numpy_only(tmp_path) if any_blender == "blender34" else ""
    run(argv, env, timeout=300)
    info = json.loads((tmp_path / "install.json").read_text())
    assert info["enabled"] and info["engine_registered"]
    if any_blender == "blender34":
        assert info["module"] == "gridwalk_blender"
        assert "/gridwalk_blender/wheels/site/" in info["gridwalk_file"]   # unpacked by the add-on
    else:
        assert info["module"] == "bl_ext.user_default.gridwalk"
        assert (tmp_path / "user" / "extensions" / ".local" / "lib" / "python3.11"
                / "site-packages" / "gridwalk").is_dir()                 # installed by Blender
    rgba = exr.rgba(exr.read_exr(tmp_path / "gridwalk.exr"), "ViewLayer.Combined.")
    assert rgba.shape == (72, 96, 4) and rgba[..., :3].std() > 0.05
