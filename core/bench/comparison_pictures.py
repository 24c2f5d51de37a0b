"""Pictures for docs/blender.md: test scenes rendered by GRIDWALK and by Cycles in bpy 4.5,
side by side, with the normalized cross-correlation of their luminance. One sheet per
feature: "texture_coordinates" (a Checker Texture at each output of the Texture Coordinate
and Geometry nodes that depends on the view; test_b47's scenes), "per_instance" (Object Info
and Instancer attributes, a value per object instance; test_b52's scenes) and "shadow_catcher" (a
floor set to Shadow Catcher under a cube and a sun; test_b49's scene, the transparent film
shown over green). A script that writes docs, not a test:

    .venv/bin/python core/bench/comparison_pictures.py [SHEET ...]   (writes docs/images/SHEET.png)
"""
from __future__ import annotations

import argparse
import json
import tempfile
from pathlib import Path

import numpy as np

from material_pictures import ROOT, ncc, render, to_srgb, write_sheet

SIZE = [192, 144]
CHECKER = "procedural_checker"
SHEETS = {   # sheet -> rows of (scene, scene options, transparent film, label)
    "texture_coordinates": (
        (CHECKER, {"variant": "object", "coordinates": "Normal", "smooth": True}, False,
         "Normal: the smooth normal in object space (a cube scaled 1.2 x 0.8 x 1, shaded smooth)"),
        (CHECKER, {"variant": "cube", "coordinates": "Camera"}, False, "Camera: the point in the camera's space"),
        (CHECKER, {"variant": "cube", "coordinates": "Window"}, False, "Window: the point's place in the image"),
        (CHECKER, {"variant": "object", "coordinates": "Reflection", "smooth": True}, False,
         "Reflection: the view mirrored about the smooth normal"),
    ),
    "per_instance": (
        ("object_info", {"output": "Random", "ramp": True}, False,
         "Object Info Random through a Color Ramp: twelve objects of one mesh"),
        ("object_info", {"output": "Color"}, False, "Object Info Color: each object's Viewport Display colour"),
        ("object_info", {"output": "Color", "attribute": "INSTANCER", "layout": "copies"}, False,
         "Attribute (Instancer) 'tint': a colour stored on each of 64 Geometry Nodes copies"),
    ),
    "shadow_catcher": (
        ("shadow_catcher", {"world": 0.0}, True, "Shadow Catcher, transparent film, black world (over green)"),
        ("shadow_catcher", {"world": 0.3}, True, "Shadow Catcher, transparent film, grey world: the shadow part way"),
        ("shadow_catcher", {"world": 0.3}, False, "Shadow Catcher, opaque film: the world, darkened by the shadow"),
    ),
}
GREEN = np.array([0.2, 0.6, 0.2])


def over_green(rgba) -> np.ndarray:
    """A transparent film's pixels over green (premultiplied), as RGBA for to_srgb."""
    out = rgba.copy()
    out[..., :3] = rgba[..., :3] + (1 - rgba[..., 3:4]) * GREEN
    return out


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("sheets", nargs="*", default=list(SHEETS))
    args = parser.parse_args()
    for sheet in args.sheets:
        rows = []
        with tempfile.TemporaryDirectory() as tmp:
            for scene, options, transparent, label in SHEETS[sheet]:
                opts = [f"scene={json.dumps(dict(options, resolution=SIZE))}",
                        f"transparent={'true' if transparent else 'false'}"]
                ours, cycles = (render(scene, e, opts, Path(tmp)) for e in ("GRIDWALK", "CYCLES"))
                if transparent:
                    ours, cycles = over_green(ours), over_green(cycles)
                rows.append((label, to_srgb(ours), to_srgb(cycles), ncc(ours, cycles)))
                print(f"{label}: NCC of luminance {rows[-1][3]:.4f}")
        out = ROOT / "docs" / "images" / f"{sheet}.png"
        write_sheet(rows, out)
        print("wrote", out)


if __name__ == "__main__":
    main()
