"""Draw Gridwalk's camera, light and object panels with a recording layout, on real
cameras, lights and a mesh object: which properties each panel shows, and whether each is a
real property of the datablock it is drawn from in this Blender.

usage: <python with bpy> panels_draw.py OUT_DIR   (writes OUT_DIR/panels.json)
"""
import json
import os
import sys
from types import SimpleNamespace

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


class Recorder:
    """Stands in for bpy.types.UILayout (a panel's layout exists only in the GUI):
    records the properties drawn and the labels."""

    def __init__(self, log):
        self.log = log
        self.use_property_split = False

    def prop(self, owner, name, **_):
        self.log.append({"prop": name, "real": name in owner.bl_rna.properties})

    def label(self, text="", **_):
        self.log.append({"label": text})

    def row(self, **_):
        return self

    def column(self, **_):
        return self


def draw(panel, context):
    log = []
    panel.draw(SimpleNamespace(layout=Recorder(log)), context)
    return log


def main(out_dir):
    import bpy

    import blender_addon
    import scenes
    from blender_addon import ui

    blender_addon.register()
    scenes.reset()
    cam = bpy.context.scene.camera.data
    cam.type = "PANO"
    out = {}
    holder = cam if hasattr(cam, "panorama_type") else cam.cycles
    for item in holder.bl_rna.properties["panorama_type"].enum_items:     # every type this Blender has
        kind = item.identifier
        holder.panorama_type = kind
        context = SimpleNamespace(engine="GRIDWALK", camera=cam)
        out[f"panorama {kind}"] = {"poll": ui.GRIDWALK_CAMERA_PT_panorama.poll(context),
                                   "drawn": draw(ui.GRIDWALK_CAMERA_PT_panorama, context)}
    cam.type = "PERSP"
    out["perspective poll"] = ui.GRIDWALK_CAMERA_PT_panorama.poll(SimpleNamespace(engine="GRIDWALK", camera=cam))
    for kind in ("POINT", "SPOT", "SUN", "AREA"):
        light = bpy.data.lights.new(kind, kind)
        out[f"light {kind}"] = draw(ui.GRIDWALK_LIGHT_PT_light, SimpleNamespace(engine="GRIDWALK", light=light))
    cube = scenes.link(scenes.cube_object())
    out["object"] = draw(ui.GRIDWALK_OBJECT_PT_settings, SimpleNamespace(engine="GRIDWALK", object=cube))
    with open(os.path.join(out_dir, "panels.json"), "w") as f:
        json.dump(out, f, indent=1)


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main, spread=True)
