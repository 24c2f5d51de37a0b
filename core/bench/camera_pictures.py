"""Pictures for docs/blender.md: Blender's panoramic cameras (the camera tests' scene,
tests/blender/scripts/scenes.py PANORAMA_KINDS) rendered by GRIDWALK and by Cycles in
bpy 4.5, side by side, with the normalized cross-correlation of their luminance, under
a blue world (black where a fisheye or the mirror ball shows nothing).
A script that writes docs, not a test:

    .venv/bin/python core/bench/camera_pictures.py [--out docs/images/panoramas.png]
"""
from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from material_pictures import ROOT, compared, write_sheet

ROWS = (   # (camera kind, label)
    ("fisheye_equidistant", "Fisheye Equidistant, 149 degrees, shifted right"),
    ("fisheye_equisolid", "Fisheye Equisolid, 10.5 mm lens, 172 degrees, shifted down"),
    ("fisheye_polynomial", "Fisheye Lens Polynomial (Blender's 50 mm fit), cut at 34 degrees; vertical sensor fit"),
    ("mirror_ball", "Mirror Ball"),
    ("cubemap_face", "Equiangular Cubemap Face, shifted left"),
    ("central_cylindrical", "Central Cylindrical (Blender 4.3+)"),
)
SIZE = [192, 144]
SKY = [0.25, 0.4, 0.7]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "panoramas.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        rows = [compared(label, "camera_kinds", [f"scene={json.dumps(dict(kind=kind, resolution=SIZE, sky=SKY))}",
                                                 "transparent=false"], Path(tmp))
                for kind, label in ROWS]
    write_sheet(rows, args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
