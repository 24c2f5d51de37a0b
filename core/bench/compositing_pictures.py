"""Pictures for docs/blender.md, GRIDWALK beside Cycles in bpy 4.5 on the test scenes
(tests/blender/scripts/): the Cryptomatte passes (cryptomatte.py) shown as the Cryptomatte
node's Pick view shows them, a colour per id weighted by its coverage; holdouts
(holdout.py) over a checkerboard, where the film is clear; and objects' ray visibility
(ray_visibility.py). A script that writes docs, not a test:

    .venv/bin/python core/bench/compositing_pictures.py [--out docs/images]
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from bench_common import BPY_PYTHON, ROOT, plt

sys.path.insert(0, str(ROOT / "tests" / "blender"))
import exr  # noqa: E402  (the tests' EXR reader)

LAYERS = ("Object", "Material", "Asset")
ENGINES = {"gridwalk": "GRIDWALK", "cycles": "Cycles"}


def run(script: str, out: Path):
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    subprocess.run([str(BPY_PYTHON), str(ROOT / "tests" / "blender" / "scripts" / script), str(out)],
                   env=env, check=True, capture_output=True, timeout=300)


def display(rgb):
    return np.clip(rgb, 0, 1) ** (1 / 2.2)


def pick(channels: dict, layer: str) -> np.ndarray:
    """(h, w, 3): every rank's id as a colour (from the id's bits) times its coverage, summed."""
    out = 0.0
    for p in range(3):
        for i, c in (("r", "g"), ("b", "a")):
            ids = channels[f"ViewLayer.Crypto{layer}{p:02d}.{i}"]
            bits = ids.astype(np.float32).view(np.uint32)
            colour = np.stack([(bits >> s) & 0xFF for s in (0, 8, 16)], -1).astype(np.float32) / 255 * 0.8 + 0.2
            out = out + colour * np.where(ids != 0, channels[f"ViewLayer.Crypto{layer}{p:02d}.{c}"], 0.0)[..., None]
    return np.clip(out, 0, 1)


def over_checks(rgba):
    """The image over a grey checkerboard, which shows where its alpha is below 1."""
    h, w = rgba.shape[:2]
    checks = np.where(((np.arange(h)[:, None] // 6 + np.arange(w)[None, :] // 6) % 2) == 0, 0.55, 0.8)
    a = rgba[..., 3:4]
    return display(rgba[..., :3]) * a + checks[..., None] * (1 - a)


def sheet(rows, path):
    """rows: [(title, [(label, image), ...]), ...] -> one figure, a row of panels each."""
    cols = max(len(panels) for _, panels in rows)
    fig = plt.figure(figsize=(3.0 * cols, 2.5 * len(rows)))
    for r, (_, panels) in enumerate(rows):
        for c, (label, image) in enumerate(panels):
            ax = fig.add_subplot(len(rows), cols, r * cols + c + 1)
            ax.imshow(image, interpolation="nearest")
            ax.set_title(label, fontsize=9)
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)
    print("wrote", path)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=str(ROOT / "docs" / "images"))
    out = Path(parser.parse_args().out)
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        for script in ("cryptomatte.py", "holdout.py", "ray_visibility.py"):
            (tmp / script).mkdir()
            run(script, tmp / script)
        crypto = {e: exr.read_exr(tmp / "cryptomatte.py" / f"{e}.exr") for e in ENGINES}
        held = {(e, f): exr.rgba(exr.read_exr(tmp / "holdout.py" / f"{e}_{f}.exr"), "ViewLayer.Combined.")
                for e in ENGINES for f in ("opaque", "transparent")}
        seen = {e: exr.rgba(exr.read_exr(tmp / "ray_visibility.py" / f"{e}.exr"), "ViewLayer.Combined.")
                for e in ENGINES}
    sheet([(e, [(f"{name}: Combined", display(exr.rgba(crypto[e], "ViewLayer.Combined.")[..., :3]))]
            + [(f"{name}: Crypto{layer}", pick(crypto[e], layer)) for layer in LAYERS])
           for e, name in ENGINES.items()], out / "cryptomatte.png")
    sheet([(e, [(f"{name}: film opaque", over_checks(held[e, "opaque"])),
                (f"{name}: film transparent", over_checks(held[e, "transparent"]))])
           for e, name in ENGINES.items()], out / "holdout.png")
    sheet([("visibility", [(f"{name}", display(seen[e][..., :3])) for e, name in ENGINES.items()])],
          out / "ray_visibility.png")


if __name__ == "__main__":
    main()
