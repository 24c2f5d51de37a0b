"""For scripts that run inside Blender (the demo, benchmarks, tests):

run_main(main)           call main with the arguments after "--", print a
                         traceback and exit 1 on any error, and leave with
                         leave().
leave(code)              exit the process with os._exit (the bpy module can
                         hang at interpreter exit after image I/O; see GUIDE
                         §4), first removing Blender's session temp folder,
                         which a normal exit removes and os._exit skips.
principled_material(...) a node material whose Principled BSDF has the given
                         base colour and inputs.

No bpy import at module level: importing this never starts Blender.
"""
import os
import sys
import traceback


def script_args() -> list:
    """The script's own arguments: those after "--" (blender -b), else argv[1:] (bpy module)."""
    return sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]


def run_main(main, spread: bool = False):
    """Call main(argv) (or main(*argv) with spread=True), then exit the process."""
    code = 0
    try:
        main(*script_args()) if spread else main(script_args())
    except BaseException:
        traceback.print_exc()
        code = 1
    leave(code)


def leave(code: int):
    """Exit at once with `code`, leaving no /tmp/blender_XXXXXX folder behind
    (gridwalk.renderfarm.blender_exit, shared with the farm's Blender tasks)."""
    try:
        from gridwalk.renderfarm.blender_exit import exit_now
    except Exception:   # (gridwalk missing or broken: leave all the same, without the clean-up)
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(code)
    exit_now(code)


def principled_material(name: str, color, **inputs):
    """A new material whose Principled BSDF has base `color` (RGB) and `inputs`
    (socket name -> value; 3.x names work in 4.x, e.g. "Transmission" for
    "Transmission Weight"); the viewport colour follows the base colour."""
    import bpy

    mat = bpy.data.materials.new(name)
    if bpy.app.version < (5, 0, 0):
        mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    for key, value in inputs.items():
        socket = key if key in bsdf.inputs else f"{key} Weight"
        bsdf.inputs[socket].default_value = value
    mat.diffuse_color = (*color, 1.0)
    return mat
