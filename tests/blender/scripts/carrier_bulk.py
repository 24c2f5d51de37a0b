"""Export each carrier_scene variant twice, with a Geometry Nodes carrier's copies read in
bulk (export/carrier_instances.py) and one by one (carrier_transforms patched to find
nothing), and write how the two exports compare.

usage: <python with bpy> carrier_bulk.py OUT_DIR VARIANT...
(a carrier_scene variant, or "tampered": "object" with one checked copy's transform moved
in what the bulk path reads, which must send the carrier back to the one-by-one path)
Writes OUT_DIR/carrier_bulk.json: per variant, the copies read in bulk, the arrays that
differ between the two exports (name: largest difference, or a shape), both warning
lists and the lights each found.
"""
import json
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def compare(first, second) -> dict:
    import numpy as np
    differ = {}
    for name in sorted(set(first) | set(second)):
        a, b = first.get(name), second.get(name)
        if not isinstance(a, np.ndarray) and not isinstance(b, np.ndarray):
            continue
        if a is None or b is None or a.shape != b.shape:
            differ[name] = f"shape {getattr(a, 'shape', None)} against {getattr(b, 'shape', None)}"
        elif a.size:
            gap = float(np.abs(a.astype(np.float64) - b.astype(np.float64)).max())
            if not gap <= 1e-4 * max(1.0, float(np.abs(b).max())):
                differ[name] = gap
    return differ


def tampered(found):
    """carrier_transforms' result with copy SAMPLE (a copy checked against the depsgraph, not the
    first of its reference) moved by one unit."""
    from blender_addon.export.carrier_instances import SAMPLE
    if found is None:
        return None
    transforms, references, count = found
    transforms = transforms.copy()
    transforms[SAMPLE, 0, 3] += 1.0
    return transforms, references, count


def main(out_dir, *variants):
    import bpy

    import blender_addon
    import scenes
    from blender_addon.export import Export, carrier_instances

    blender_addon.register()
    found = carrier_instances.carrier_transforms
    result = {"blender": list(bpy.app.version), "bulk_api": hasattr(bpy.types.Object, "evaluated_geometry")}
    for variant in variants:
        scenes.carrier_scene("object" if variant == "tampered" else variant)
        depsgraph = bpy.context.evaluated_depsgraph_get()
        if variant == "tampered":      # a sampled copy's transform moved: the check must catch it
            carrier_instances.carrier_transforms = lambda carrier, *more: tampered(found(carrier, *more))
        try:
            bulk = Export(depsgraph)
            bulk_kwargs, bulk_warnings = bulk.kwargs()
        finally:
            carrier_instances.carrier_transforms = found
        carrier_instances.carrier_transforms = lambda carrier, *more: None
        try:
            single = Export(depsgraph)
            single_kwargs, single_warnings = single.kwargs()
        finally:
            carrier_instances.carrier_transforms = found
        result[variant] = {"bulk_copies": bulk.bulk_copies, "single_copies": single.bulk_copies,
                           "triangles": len(bulk_kwargs["triangles"]),
                           "differ": compare(bulk_kwargs, single_kwargs),
                           "warnings": [bulk_warnings, single_warnings],
                           "lights": [len(bulk.lights), len(single.lights)]}
    with open(os.path.join(out_dir, "carrier_bulk.json"), "w") as f:
        json.dump(result, f, indent=1)


if __name__ == "__main__":
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    code = 0
    try:
        main(*argv)
    except Exception:
        import traceback
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    os._exit(code)
