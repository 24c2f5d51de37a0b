"""Pictures for docs/materials.md: Sky Texture worlds rendered by GRIDWALK and by Cycles
(direct light only, as GRIDWALK renders) in bpy 4.5 and bpy 5.0, side by side, with the
normalized cross-correlation of their luminance (radiance clipped at 20 times the
median, which leaves the sun's pixel out). Each row is scaled by one exposure for both
engines (the sky's radiance is physical: a clear day's sky is 5-20 times brighter than 1).
A script that writes docs, not a test:

    .venv/bin/python core/bench/sky_pictures.py [--out docs/images/sky.png]
"""
from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import numpy as np

from material_pictures import ROOT, ncc, render, to_srgb, write_sheet

ROWS = (   # (Blender, scene options, label)
    ("bpy45", {"variant": "default"}, "Blender 4.5: the Sky Texture as added (Nishita, sun 15 degrees up)"),
    ("bpy45", {"variant": "evening"}, "Blender 4.5: sun 6 degrees up, turned 140 degrees; 2 km up, more air, dust, ozone"),
    ("bpy45", {"variant": "default", "panorama": True, "resolution": [256, 128]},
     "Blender 4.5: the default sky in every direction (equirectangular; the sun at the left quarter)"),
    ("bpy45", {"variant": "default", "sun_view": True, "resolution": [192, 128]},
     "Blender 4.5: the sun through a 500 mm lens (exposure for the disc: its darker limb, redder lower edge)"),
    ("bpy50", {"variant": "default"}, "Blender 5.0: the Sky Texture as added (Multiple Scattering)"),
    ("bpy50", {"variant": "evening"}, "Blender 5.0: Multiple Scattering, the evening settings"),
    ("bpy50", {"variant": "default", "panorama": True, "resolution": [256, 128]},
     "Blender 5.0: Multiple Scattering in every direction (light below the horizon too)"),
)
SIZE = [192, 128]


def main():
    import json
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "sky.png"))
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for blender, scene, label in ROWS:
            options = [f"scene={json.dumps(dict({'resolution': SIZE}, **scene))}", "transparent=false"]
            opts = {"GRIDWALK": options, "CYCLES": options}
            ours, cycles = (render("sky", e, opts[e], Path(tmp), blender) for e in ("GRIDWALK", "CYCLES"))
            exposure = 0.45 / np.median(cycles[..., :3].mean(-1))
            if scene.get("sun_view"):                              # (the disc, not the sky around it)
                exposure = 0.9 / cycles[..., :3].mean(-1).max()
            # (NCC with radiance clipped at 20 x the median: the sun, a third of a pixel wide, is a few
            # samples' noise in either engine and would weigh more than the rest of the picture)
            top = np.inf if scene.get("sun_view") else 20 * np.median(cycles[..., :3])
            rows.append((label, to_srgb(ours * exposure), to_srgb(cycles * exposure),
                         ncc(np.minimum(ours, top), np.minimum(cycles, top))))
            print(f"{label}: NCC of luminance {rows[-1][3]:.4f}")
    write_sheet(rows, args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
