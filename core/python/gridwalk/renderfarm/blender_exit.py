"""Leaving a Blender process at once (inside Blender: a farm task's
in_blender.py, and blender_addon.scripting's scripts).

Scripts leave Blender with os._exit, because the bpy module can hang at
interpreter exit after image I/O. os._exit skips Blender's own clean-up,
which removes its session folder (blender_XXXXXX in the temporary folder of
the preferences, $TMPDIR or /tmp), so exit_now removes it first.

No gridwalk import: in_blender.py imports this as its sibling module,
whatever gridwalk that Blender has.
"""
import os
import re
import shutil
import sys


def session_folder(bpy):
    """Blender's session folder, or None where bpy.app.tempdir is not one:
    Blender falls back to the base folder when it cannot make its own, and
    that folder is the user's."""
    try:
        path = os.path.normpath(bpy.app.tempdir)
        base = bpy.context.preferences.filepaths.temporary_directory
    except Exception:
        return None
    if not re.fullmatch(r"blender_[A-Za-z0-9]{6}", os.path.basename(path)):
        return None
    if base and os.path.normpath(os.path.abspath(base)) == path:
        return None
    return path


def exit_now(code: int):
    """Flush the output and end the process with `code`, first removing
    Blender's session folder where bpy is loaded."""
    bpy = sys.modules.get("bpy")
    folder = session_folder(bpy) if bpy is not None else None
    if folder:
        shutil.rmtree(folder, ignore_errors=True)
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
