"""Pictures for docs/blender.md: a Checker Texture through a Mapping node at each output of
Blender's Texture Coordinate node that depends on the view (Normal, Camera, Window,
Reflection), rendered by GRIDWALK and by Cycles in bpy 4.5, side by side, with the
normalized cross-correlation of their luminance. The scenes are test_b47's. A script that
writes docs, not a test:

    .venv/bin/python core/bench/texture_coordinate_pictures.py [--out docs/images/texture_coordinates.png]
"""
from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

from material_pictures import ROOT, compared, write_sheet

ROWS = (   # (scene options, label)
    ({"variant": "object", "coordinates": "Normal", "smooth": True},
     "Normal: the smooth normal in object space (a cube scaled 1.2 x 0.8 x 1, shaded smooth)"),
    ({"variant": "cube", "coordinates": "Camera"}, "Camera: the point in the camera's space"),
    ({"variant": "cube", "coordinates": "Window"}, "Window: the point's place in the image"),
    ({"variant": "object", "coordinates": "Reflection", "smooth": True},
     "Reflection: the view mirrored about the smooth normal"),
)
SIZE = [192, 144]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "texture_coordinates.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        rows = [compared(label, "procedural_checker",
                         [f"scene={json.dumps(dict(scene, resolution=SIZE))}", "transparent=false"], Path(tmp))
                for scene, label in ROWS]
    write_sheet(rows, args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
