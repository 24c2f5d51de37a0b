"""Picture for docs/blender.md: Cryptomatte Object, Material and Asset passes of
GRIDWALK and of Cycles (16 samples) on the Cryptomatte test's scene
(tests/blender/scripts/cryptomatte.py), rendered in bpy 4.5, each shown as the
compositor's Pick view shows it: a colour per id, weighted by its coverage. A
script that writes docs, not a test:

    .venv/bin/python core/bench/cryptomatte_pictures.py [--out docs/images/cryptomatte.png]
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


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "cryptomatte.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        subprocess.run([str(BPY_PYTHON), str(ROOT / "tests" / "blender" / "scripts" / "cryptomatte.py"), tmp],
                       env=env, check=True, capture_output=True, timeout=300)
        renders = {engine: exr.read_exr(Path(tmp) / f"{engine}.exr") for engine in ("gridwalk", "cycles")}
    fig = plt.figure(figsize=(12, 5.0))
    for row, engine in enumerate(("gridwalk", "cycles")):
        channels = renders[engine]
        panels = [("Combined", np.clip(exr.rgba(channels, "ViewLayer.Combined.")[..., :3], 0, 1) ** (1 / 2.2))]
        panels += [(f"Crypto{layer}", pick(channels, layer)) for layer in LAYERS]
        for col, (title, image) in enumerate(panels):
            ax = fig.add_subplot(2, 4, row * 4 + col + 1)
            ax.imshow(image, interpolation="nearest")
            ax.set_title(f"{'GRIDWALK' if engine == 'gridwalk' else 'Cycles'}: {title}", fontsize=9)
            ax.axis("off")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
