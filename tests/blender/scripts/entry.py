"""The entry point every Blender test script shares: arguments after "--",
a traceback and exit code 1 on any error, and os._exit at the end (the bpy
module can hang at interpreter exit after image I/O)."""
import os
import sys
import traceback


def run(main, spread=False):
    """Call main(argv) (or main(*argv) with spread=True), then exit the process."""
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]
    code = 0
    try:
        main(*argv) if spread else main(argv)
    except BaseException:
        traceback.print_exc()
        code = 1
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)
