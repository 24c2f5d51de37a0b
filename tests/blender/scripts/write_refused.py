"""What a script can do while Blender refuses Python's writes to ID data
(write_permission.py relies on it, docs/blender.md tells users): inside an
operator's poll, where Blender sets its read-only flag as a stuck flag
leaves it, record whether a plain write, an operator call and
write_permission.run_allowing_writes (a write and an operator call inside a
window-manager property's update) go through, and whether the flag is
read-only again after them.

usage: <python with bpy> write_refused.py OUT_DIR   (writes OUT_DIR/write_refused.json)
"""
import json
import os
import sys


def main(out_dir):
    import bpy

    import write_permission

    info = {}
    world = bpy.data.worlds.new("Probe world")

    class Noop(bpy.types.Operator):
        bl_idname = "gwtest.noop"
        bl_label = "Nothing"

        def execute(self, context):
            info["operator_ran"] = info.get("operator_ran", 0) + 1
            return {"FINISHED"}

    def write_and_call():
        world.color = (0.5, 0.25, 0.125)
        bpy.ops.gwtest.noop()
        return "done"

    class ReadOnly(bpy.types.Operator):
        """Its poll runs with Python's writes refused."""
        bl_idname = "gwtest.read_only"
        bl_label = "Read-only"

        @classmethod
        def poll(cls, context):
            if "refused_in_poll" in info:        # (Blender polls twice per call: the probe runs once)
                return True
            info["refused_in_poll"] = write_permission.writes_refused()
            try:
                world.color = (0.1, 0.1, 0.1)
                info["plain_write"] = "allowed"
            except AttributeError as exc:
                info["plain_write"] = str(exc)
            try:
                bpy.ops.gwtest.noop()
                info["plain_operator"] = "allowed"
            except RuntimeError as exc:
                info["plain_operator"] = str(exc)
            info["in_update"] = write_permission.run_allowing_writes(write_and_call)
            info["color_after_update"] = list(world.color)
            info["refused_after_update"] = write_permission.writes_refused()
            try:
                write_permission.run_allowing_writes(lambda: 1 / 0)
            except ZeroDivisionError:
                info["error_raised"] = True
            return True

        def execute(self, context):
            return {"FINISHED"}

    bpy.utils.register_class(Noop)
    bpy.utils.register_class(ReadOnly)
    info["refused_outside"] = write_permission.writes_refused()
    bpy.ops.gwtest.read_only()
    with open(os.path.join(out_dir, "write_refused.json"), "w") as f:
        json.dump(info, f, indent=1)


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    from blender_addon.scripting import run_main as run
    run(main, spread=True)
