"""Build the installable add-on zip, with the gridwalk wheel inside.

    python blender_addon/build_zip.py [--wheel dist/gridwalk-*.whl] [--out dist]

Without --wheel, the wheel is built from this checkout (pip wheel --no-deps).
The zip holds one folder, gridwalk_blender/, so the same file installs as a
Blender 4.2+ extension (Preferences > Get Extensions > Install from Disk; its
manifest lists the wheel, which Blender installs) and as a legacy add-on in
Blender 3.4 - 4.1 (Preferences > Add-ons > Install; dependencies.py unpacks
the wheel on first use). Prints the zip's path.
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

ADDON = Path(__file__).resolve().parent
ROOT = ADDON.parent
FOLDER = "gridwalk_blender"
SKIP_NAMES = {"build_zip.py", "__pycache__", "wheels"}
SYSTEMS = {"linux": "linux", "manylinux": "linux", "musllinux": "linux", "win": "windows", "macosx": "macos"}
MACHINES = {"x86_64": "x64", "amd64": "x64", "aarch64": "arm64", "arm64": "arm64"}


def build_wheel(out_dir: Path) -> Path:
    subprocess.run([sys.executable, "-m", "pip", "wheel", "-q", "--no-deps", "-w", str(out_dir), str(ROOT)],
                   check=True)
    return max(out_dir.glob("gridwalk-*.whl"), key=lambda p: p.stat().st_mtime)


def blender_platform(wheel: Path) -> str:
    """Blender's platform name for a wheel ("linux_x86_64" -> "linux-x64")."""
    tag = wheel.stem.split("-")[-1]
    system = next((v for k, v in SYSTEMS.items() if tag.split("_")[0].rstrip("0123456789") == k), None)
    machine = next((v for k, v in MACHINES.items() if tag.endswith(k)), None)
    if system is None or machine is None:
        raise SystemExit(f"unsupported wheel platform tag {tag!r}")
    return f"{system}-{machine}"


def manifest_text(wheel: Path) -> str:
    text = (ADDON / "blender_manifest.toml").read_text()
    head, sep, tail = text.partition("\n[permissions]")
    extra = f'platforms = ["{blender_platform(wheel)}"]\nwheels = ["./wheels/{wheel.name}"]\n'
    return head.rstrip("\n") + "\n" + extra + sep + tail


def addon_files():
    for path in sorted(ADDON.rglob("*")):
        rel = path.relative_to(ADDON)
        if path.is_file() and not SKIP_NAMES & set(rel.parts) and path.suffix != ".pyc":
            yield path, rel


def build_zip(wheel: Path, out_dir: Path) -> Path:
    version = wheel.name.split("-")[1]
    out_dir.mkdir(parents=True, exist_ok=True)
    target = out_dir / f"gridwalk_blender-{version}-{blender_platform(wheel)}.zip"
    with zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as zf:
        for path, rel in addon_files():
            if rel.name == "blender_manifest.toml":
                zf.writestr(f"{FOLDER}/{rel.as_posix()}", manifest_text(wheel))
            else:
                zf.write(path, f"{FOLDER}/{rel.as_posix()}")
        zf.write(wheel, f"{FOLDER}/wheels/{wheel.name}")
    return target


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--wheel", type=Path, help="a built gridwalk wheel (default: build one)")
    parser.add_argument("--out", type=Path, default=ROOT / "dist", help="output folder (default: dist)")
    args = parser.parse_args(argv)
    if args.wheel is None:
        with tempfile.TemporaryDirectory() as tmp:
            wheel = build_wheel(Path(tmp))
            print(build_zip(wheel, args.out))
    else:
        print(build_zip(args.wheel.resolve(), args.out))


if __name__ == "__main__":
    main()
