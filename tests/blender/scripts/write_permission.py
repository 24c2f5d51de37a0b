"""Running a GUI script's timer step where Blender lets Python write.

Blender's permission for Python to write to ID data is one process-wide
flag that each call of a Python class's method (a panel's draw, an engine's
render) saves, sets and restores. A render of a Python engine on a job's
thread (F12, a material preview) interleaving with a draw on the main
thread can restore it in the wrong order and leave it read-only for the rest
of the session (docs/blender.md): from then on a timer's writes to ID data
fail, and so does every bpy.ops call. Blender runs a Python property's
update callback with writes allowed whatever the flag says, and lets
Python write a window manager's properties while the flag is read-only, so
a step that cannot write runs inside such an update.
"""
import bpy

WRITE_REFUSED = "Writing to ID classes in this context is not allowed"
PROBE_NAME = "gwtest write probe"
PENDING = {}


def _run_pending(wm, context):
    try:
        PENDING["result"] = PENDING["fn"]()
    except Exception as exc:            # Blender prints and swallows what an update raises
        PENDING["error"] = exc


bpy.types.WindowManager.gwtest_step = bpy.props.IntProperty(update=_run_pending)


def run_allowing_writes(fn):
    """fn() inside WindowManager.gwtest_step's update; returns what fn
    returned, raises what it raised."""
    PENDING.clear()
    PENDING["fn"] = fn
    bpy.context.window_manager.gwtest_step += 1
    if "error" in PENDING:
        raise PENDING["error"]
    if "result" not in PENDING:
        raise RuntimeError("Blender did not call the update of WindowManager.gwtest_step")
    return PENDING["result"]


def writes_refused() -> bool:
    """Whether Blender refuses a script's writes to ID data just now (a write
    to a Text datablock nothing else uses; File > New drops it, so it is made
    again when missing)."""
    probe = bpy.data.texts.get(PROBE_NAME) or bpy.data.texts.new(PROBE_NAME)
    try:
        probe.use_fake_user = True
        return False
    except AttributeError as exc:
        if WRITE_REFUSED not in str(exc):
            raise
        return True


def run(fn, on_refused=None):
    """fn(), or fn() inside the update while writes are refused (then
    on_refused(fn) is called first, to record it)."""
    if not writes_refused():
        return fn()
    if on_refused is not None:
        on_refused(fn)
    return run_allowing_writes(fn)
