"""Register the add-on, record what it added, unregister, record what is left.

usage: <python with bpy> registration.py OUT_DIR   (writes OUT_DIR/registration.json)
"""
import json
import os
import sys


def panels_with(bpy, engine):
    return sorted(name for name in dir(bpy.types)
                  if isinstance(getattr(getattr(bpy.types, name, None), "COMPAT_ENGINES", None), set)
                  and engine in getattr(bpy.types, name).COMPAT_ENGINES)


def main(out_dir):
    import bpy

    import blender_addon
    import gridwalk
    from blender_addon.settings import render_settings

    blender_addon.register()
    scene = bpy.context.scene
    scene.render.engine = "GRIDWALK"
    settings = render_settings(gridwalk, scene.gridwalk)
    settings.to_core()                        # validates every value
    rna = bpy.types.Scene.gridwalk.keywords["type"].bl_rna.properties
    props = {}
    for name in rna.keys():
        p = rna[name]
        entry = {"type": p.type, "label": p.name, "description": p.description}
        if p.type in ("INT", "FLOAT"):
            entry.update(default=p.default, min=p.hard_min, max=p.hard_max)
        elif p.type == "BOOLEAN":
            entry.update(default=p.default)
        elif p.type == "ENUM":
            entry.update(default=p.default, items=[item.identifier for item in p.enum_items])
        props[name] = entry
    # Each number at the end of its slider (one at a time): the settings must still
    # validate (a float32 property's limits can round outside the table's doubles).
    refused = []
    for name in rna.keys():
        p = rna[name]
        if p.type not in ("INT", "FLOAT") or name == "rna_type":
            continue
        default = getattr(scene.gridwalk, name)
        for end in (p.hard_min, p.hard_max):
            setattr(scene.gridwalk, name, end)
            try:
                render_settings(gridwalk, scene.gridwalk).to_core()
            except (ValueError, TypeError) as e:
                refused.append(f"{name} = {getattr(scene.gridwalk, name)!r}: {e}")
        setattr(scene.gridwalk, name, default)
    from blender_addon.ui import SETTINGS_PANELS
    info = {
        "properties": props,
        "panel_groups": {panel.__name__: list(panel.groups) for panel in SETTINGS_PANELS},
        "engine": scene.render.engine,
        "panels": panels_with(bpy, "GRIDWALK"),
        "settings": {k: v for k, v in vars(settings).items()},
        "slider_ends_refused": refused,
        "object_option": hasattr(bpy.types.Object, "gridwalk")
        and "render_as_sphere" in bpy.types.Object.gridwalk.keywords["type"].bl_rna.properties,
    }
    scene.render.engine = "CYCLES"
    blender_addon.unregister()
    info["panels_after"] = panels_with(bpy, "GRIDWALK")
    try:
        scene.render.engine = "GRIDWALK"
        info["engine_after"] = True
    except TypeError:                         # no longer a valid engine
        info["engine_after"] = False
    info["scene_property_after"] = hasattr(bpy.types.Scene, "gridwalk")
    with open(os.path.join(out_dir, "registration.json"), "w") as f:
        json.dump(info, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main, spread=True)
