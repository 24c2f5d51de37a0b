"""Makes the `gridwalk` package importable.

Blender 4.2+ installs the wheels listed in blender_manifest.toml itself. A
legacy install (Blender 3.4 - 4.1) only copies this folder, so the bundled
wheel (./wheels/gridwalk-*.whl) is unpacked once into ./wheels/site and that
folder is put on sys.path. numpy must come from Blender's Python (Debian's
blender uses the system Python: `apt-get install python3-numpy`).
"""
import sys
import zipfile
from pathlib import Path

WHEELS = Path(__file__).resolve().parent / "wheels"


def add_bundled_wheels():
    """Unpack the bundled gridwalk wheel if gridwalk is not importable (no-op otherwise)."""
    import importlib.util
    if importlib.util.find_spec("gridwalk") is not None:
        return
    wheels = sorted(WHEELS.glob("gridwalk-*.whl"))
    if not wheels:
        return
    site = WHEELS / "site"
    stamp = site / (wheels[-1].name + ".unpacked")
    if not stamp.exists():
        with zipfile.ZipFile(wheels[-1]) as archive:
            archive.extractall(site)
        stamp.touch()
    if str(site) not in sys.path:
        sys.path.insert(0, str(site))


def import_gridwalk():
    """The gridwalk package, or ImportError with a message meant for the user."""
    try:
        import gridwalk
    except ImportError as exc:
        raise ImportError(f"The Gridwalk core cannot be loaded ({exc}). Install the add-on zip "
                          "that bundles the gridwalk wheel, or pip-install gridwalk into "
                          "Blender's Python (numpy is needed too).") from exc
    return gridwalk
