"""Build a test scene, export it, and write the result for the test to check.

usage: <python with bpy> export_dump.py SCENE OUT_DIR [key=value ...]
   or: blender -b --factory-startup --python export_dump.py -- SCENE OUT_DIR ...
Writes OUT_DIR/arrays.npz (the numpy arrays) and OUT_DIR/export.json (records,
warnings, the scene's expected values, or the ExportError message).
"""
import dataclasses
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def _image_record(image) -> dict:
    pixels = image.pixels()          # a copy: taken once
    return {"name": image.name, "shape": list(pixels.shape), "dtype": str(pixels.dtype),
            "colorspace": image.colorspace, "memory_bytes": image.memory_bytes}


def main(argv):
    import bpy  # noqa: F401  (the bpy module, or Blender's own)
    import numpy as np

    import blender_addon
    import scenes
    from blender_addon.export import Export, ExportError
    from blender_addon.export.textures import corner_arrays_read, corner_point_arrays, scene_texture_bytes

    name, out_dir, *options = argv
    kwargs = dict(option.split("=", 1) for option in options)
    kwargs = {k: json.loads(v) for k, v in kwargs.items()}
    blender_addon.register()
    expected = scenes.BUILDERS[name](**kwargs)
    result = {"expected": expected, "blender": list(bpy.app.version)}
    depsgraph = bpy.context.evaluated_depsgraph_get()
    before = {image.name for image in bpy.data.images}
    try:
        export = Export(depsgraph)
        scene_kwargs, warnings = export.kwargs()
        result["bulk_copies"] = export.bulk_copies
    except ExportError as exc:
        result["error"] = str(exc)
    else:
        arrays = {k: v for k, v in scene_kwargs.items() if isinstance(v, np.ndarray)}
        for i, image in enumerate(scene_kwargs.get("images", [])):     # small images' pixels (row 0 at the top)
            if image.pixels().size <= 1 << 16:
                arrays[f"image_{i}"] = image.pixels()
        np.savez(os.path.join(out_dir, "arrays.npz"), **arrays)
        result["has_normals"] = scene_kwargs["normals"] is not None
        result["materials"] = [dataclasses.asdict(m) for m in scene_kwargs["materials"]]
        result["lights"] = [dataclasses.asdict(light) for light in scene_kwargs["lights"]]
        result["camera"] = dataclasses.asdict(scene_kwargs["camera"])
        result["background"] = list(scene_kwargs["background"])
        result["world"] = dataclasses.asdict(scene_kwargs["world"])
        result["warnings"] = warnings
        result["images"] = [_image_record(im) for im in scene_kwargs.get("images", [])]
        result["textures"] = [dataclasses.asdict(t) for t in scene_kwargs.get("textures", [])]
        result["texture_bytes"] = scene_texture_bytes(depsgraph)
        result["corner_point_arrays"] = corner_point_arrays(depsgraph)
        result["corner_arrays_read"] = corner_arrays_read(depsgraph)
    result["leftover_images"] = sorted(image.name for image in bpy.data.images if image.name not in before)
    with open(os.path.join(out_dir, "export.json"), "w") as f:
        json.dump(result, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main)
