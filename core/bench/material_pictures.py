"""Pictures for docs/blender.md: the materials test scenes (issue 13) rendered
by GRIDWALK and by Cycles in bpy 4.5, side by side, with the normalized
cross-correlation of their luminance. A script that writes docs, not a test:

    .venv/bin/python core/bench/material_pictures.py [--out docs/images/materials.png]
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tests" / "blender"))
import exr  # noqa: E402
from runner import run_script  # noqa: E402

AA = '{"aa": "JITTERED", "aa_samples": 4, "shadow_samples": 8}'
SCENES = (   # (scene, label, options for both engines)
    ("checker", "Image Texture on UVs", ["resolution"]),
    ("environment", "HDR Environment, mirror sphere", ["transparent=false"]),
    ("environment", "HDR Environment lighting a matte sphere",
     ['scene={"matte": true, "resolution": [128, 96]}', "transparent=false"]),
    ("emission_mirror", "Emission seen in a mirror", ["transparent=false"]),
    ("chrome_ball", "A rectangle light in a chrome ball", ["transparent=false"]),
    ("emission_panel", "An Emission panel lighting a floor (no lamps)",
     ['scene={"resolution": [128, 96]}', "transparent=false"]),
    ("panel_floor", "A small Emission panel over a rough metal floor (Roughness 0.3)",
     ['scene={"floor": "metal", "resolution": [128, 96]}', "transparent=false"]),
    ("panel_floor", "A 1 m area light over a glossy metal floor (Roughness 0.15): its reflection's glow",
     ['scene={"floor": "lamp", "resolution": [128, 96]}', "transparent=false"]),
    ("near_sphere", "A point light of radius 0.5 cutting through a floor, Soft Falloff on (the default)",
     ['scene={"height": 0.3, "energy": 3.0, "resolution": [96, 96]}', "transparent=false"]),
    ("near_sphere", "The same light with Soft Falloff off: a sphere of uniform radiance",
     ['scene={"height": 0.3, "soft": false, "energy": 3.0, "resolution": [96, 96]}', "transparent=false"]),
    ("world_shadow", "A white world's light blocked by a ball (no lamps)",
     ['scene={"resolution": [128, 96]}', "transparent=false"]),
    ("sunny_monkey", "An HDRI with a sun and an Emission panel light Suzanne (no lamps)",
     ['scene={"resolution": [128, 96]}', "transparent=false"]),
    ("pane_shadow", "Glass pane: transparent shadow", ['scene={"pane": "glass", "resolution": [128, 128]}',
                                                      "transparent=false"]),
    ("cutout", "Transparent BSDF cut-out (left); image alpha (right)",
     ['scene={"resolution": [128, 64]}', "transparent=false"]),
    ("rough_glass", "Glass, Roughness 0 (left) and 0.4 (right), before stripes", ["transparent=false"]),
    ("rough_metal", "Metal, Roughness 0.2 / 0.35 / 0.5 / 0.8, under a sun (GGX)", ["transparent=false"]),
    ("rough_metal", "Metal, Roughness 0.2 / 0.35 / 0.5 / 0.8, in a grey world (GGX)",
     ['scene={"lit": "world"}', "transparent=false"]),
    ("dielectric", "Dielectric (Metallic 0), Roughness 0 / 0.2 / 0.5 / 0.8, in a grey world",
     ['scene={"lit": "world"}', "transparent=false"]),
    ("dielectric", "The same on a black glossy floor (Roughness 0.1) that mirrors them",
     ['scene={"lit": "floor"}', "transparent=false"]),
    ("particle_hair", "Particle hair: 40 tilted strands with 3 children each",
     ['scene={"random": 0.6, "children": true, "resolution": [128, 96]}', "transparent=false"]),
    ("normal_map", "Normal Map: stripes leaning 30 degrees either way",
     ['scene={"resolution": [128, 64]}', "transparent=false"]),
    ("normal_map", "Normal Map on a 16 x 8 UV sphere, leaning 30 degrees",
     ['scene={"sphere": true, "resolution": [128, 96]}', "transparent=false"]),
    ("mapped_texture", "Image Texture through two Mapping nodes, turned about every axis",
     ['scene={"chain": "chain", "source": "uvmap", "resolution": [128, 96]}', "transparent=false"]),
    ("gltf_model", "A glTF model: tint, packed roughness / metallic, texture transform",
     ['scene={"resolution": [128, 128]}', "transparent=false"]),
    ("emission_map", "Principled Emission Color from an image, lighting the floor (no lamps)",
     ['scene={"resolution": [128, 96]}', "transparent=false"]),
    ("bump", "Bump node: height stripes over a Normal Map leaning 30 degrees",
     ['scene={"tilt": 30.0, "resolution": [128, 64]}', "transparent=false"]),
    ("procedural_checker", "Checker Texture at Generated coordinates through a Mapping node, into a lit Principled BSDF",
     ['scene={"variant": "principled", "resolution": [128, 96]}', "transparent=false"]),
    ("procedural_gradient", "Gradient Texture (Radial) through a Color Ramp of three stops",
     ['scene={"gradient": "RADIAL", "ramp": "LINEAR", "resolution": [128, 96]}', "transparent=false"]),
    ("procedural_noise", "Noise Texture (3D fBM, Detail 6), its Fac through a Color Ramp",
     ['scene={"variant": "ramp", "resolution": [128, 96]}', "transparent=false"]),
    ("noise_bump", "Bump node fed by a Noise Texture, a sun from the upper left",
     ['scene={"height": "NOISE", "resolution": [128, 96]}', "transparent=false"]),
    ("voronoi", "Voronoi Texture (3D F1): its Color output",
     ['scene={"variant": "color", "resolution": [128, 96]}', "transparent=false"]),
    ("pattern", "Brick Texture with every setting moved (offset, squash, mortar, bias)",
     ['scene={"variant": "brick_custom", "resolution": [128, 96]}', "transparent=false"]),
    ("pattern", "Wave Texture (rings, saw profile, Distortion 6): its Fac",
     ['scene={"variant": "wave_rings", "resolution": [128, 96]}', "transparent=false"]),
    ("pattern", "Magic Texture (depth 2, as Blender adds it)",
     ['scene={"variant": "magic", "resolution": [128, 96]}', "transparent=false"]),
)
SIZE = '[128, 96]'


def render(scene, engine, options, out: Path, blender: str = "bpy45") -> np.ndarray:
    folder = out / f"{scene}_{engine}_{len(list(out.iterdir()))}"
    folder.mkdir()
    opts = [o if o != "resolution" else f'scene={{"resolution": {SIZE}}}' for o in options]
    if scene in ("environment", "emission_mirror") and not any(o.startswith("scene=") for o in options):
        opts.append(f'scene={{"resolution": {SIZE}}}')
    opts += [f"settings={AA}"] if engine == "GRIDWALK" else ["samples=128"]
    run_script(blender, "render_scene.py", scene, folder, engine, *opts, timeout=600)
    return exr.rgba(exr.read_exr(folder / f"{engine.lower()}.exr"), "ViewLayer.Combined.")


def to_srgb(rgba) -> np.ndarray:
    c = np.clip(rgba[..., :3], 0.0, 1.0)
    c = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    return (c * 255 + 0.5).astype(np.uint8)


def ncc(a, b) -> float:
    w = np.array([0.2126, 0.7152, 0.0722])
    a, b = a[..., :3] @ w, b[..., :3] @ w
    a, b = a - a.mean(), b - b.mean()
    return float((a * b).sum() / np.sqrt((a * a).sum() * (b * b).sum()))


def compared(label, scene, options, tmp: Path, blender: str = "bpy45"):
    """A sheet row (label, ours, cycles, ncc): `scene` rendered by both engines with `options`."""
    ours, cycles = (render(scene, e, options, tmp, blender) for e in ("GRIDWALK", "CYCLES"))
    row = (label, to_srgb(ours), to_srgb(cycles), ncc(ours, cycles))
    print(f"{label}: NCC of luminance {row[3]:.4f}")
    return row


def write_sheet(rows, out):
    """One picture of (label, ours, cycles, ncc) rows, GRIDWALK left and Cycles right, doubled in size."""
    scale, pad, head = 2, 8, 18
    width = max(r[1].shape[1] for r in rows) * scale
    sheet = Image.new("RGB", (2 * width + 3 * pad, sum(r[1].shape[0] * scale + head + pad for r in rows) + pad),
                      (255, 255, 255))
    draw, y = ImageDraw.Draw(sheet), pad
    for label, ours, cycles, score in rows:
        draw.text((pad, y), f"{label}   (left GRIDWALK, right Cycles; NCC {score:.3f})", fill=(0, 0, 0))
        y += head
        for i, img in enumerate((ours, cycles)):
            pic = Image.fromarray(img).resize((img.shape[1] * scale, img.shape[0] * scale), Image.NEAREST)
            sheet.paste(pic, (pad + i * (width + pad), y))
        y += ours.shape[0] * scale + pad
    sheet.save(out)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", default=str(ROOT / "docs" / "images" / "materials.png"))
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        rows = [compared(label, scene, options, Path(tmp)) for scene, label, options in SCENES]
    write_sheet(rows, args.out)
    print("wrote", args.out)


if __name__ == "__main__":
    main()
