"""`python -m gridwalk farm SCENE -o OUT`: the farm subcommand (see gridwalk.cli)."""
from __future__ import annotations

import sys

from ..settings import BY_NAME


def add_parser(sub, add_settings_options, settings_from_args) -> None:
    p = sub.add_parser("farm", help="render on a Dask cluster: an NFF/PLY still in tiles, a .blend's frames or tiles",
                       description="Render on a Dask cluster (docs/distributed.md). The output is identical, bit "
                                   "for bit, to a render on one machine; finished tiles and frames are kept on disk "
                                   "and a run again renders only the missing ones.")
    p.add_argument("scene", help="an .nff or .ply scene (split into tiles), or a .blend file (frames, or --tiles)")
    p.add_argument("-o", "--output", required=True,
                   help="NFF/PLY: an image, .png or .npy; .blend frames: a folder (frame_NNNN files in the "
                        ".blend's format); a tiled .blend frame: .exr or .npy (linear float RGBA)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--scheduler", metavar="tcp://HOST:PORT", help="use this running Dask scheduler")
    where.add_argument("--local", type=int, metavar="N",
                       help="start a LocalCluster of N worker processes here (default: one per core)")
    p.add_argument("--tiles", type=int, default=None,
                   help="split the image into N tiles (NFF/PLY default: 16); for a .blend, one frame in N tiles")
    p.add_argument("--frames", default=None, metavar="A-B",
                   help=".blend: frames to render, e.g. 1-250 or 1-3,8 (default: the .blend's range; "
                        "with --tiles: one frame, default the current one)")
    p.add_argument("--width", type=int, default=None, help="NFF/PLY image width (default: the scene's)")
    p.add_argument("--height", type=int, default=None, help="NFF/PLY image height (default: the scene's)")
    p.add_argument("--blender", default=None,
                   help="the Blender command on the workers (default: $GRIDWALK_BLENDER there, else `blender`)")
    p.add_argument("--addon", default=None,
                   help="a Gridwalk add-on folder to register in Blender on the workers (default: "
                        "$GRIDWALK_ADDON there, else the add-on enabled in that Blender's preferences)")
    p.add_argument("--blender-pythonpath", default=None,
                   help="folders put in front of PYTHONPATH for Blender's Python on the workers "
                        "(default: $GRIDWALK_BLENDER_PYTHONPATH there)")
    p.add_argument("--connect-timeout", type=float, default=10.0,
                   help="seconds to wait for the scheduler and its first worker (default: 10)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_settings_options(p, leave_out=("region",))       # (the farm renders the whole image, its tiles the regions)
    p.set_defaults(func=lambda args: cmd_farm(args, settings_from_args))


def cmd_farm(args, settings_from_args) -> int:
    from . import FarmError, farm

    given = any(getattr(args, name, None) is not None for name in BY_NAME)
    try:
        report = farm(args.scene, args.output, settings=settings_from_args(args) if given else None,
                      tiles=args.tiles, frames=args.frames, scheduler=args.scheduler, local=args.local,
                      width=args.width, height=args.height, blender=args.blender, addon=args.addon,
                      blender_pythonpath=args.blender_pythonpath, connect_timeout=args.connect_timeout,
                      quiet=args.quiet)
    except FarmError as err:
        print(f"gridwalk: error: {err}", file=sys.stderr)
        return 1
    print(f"gridwalk farm: {args.scene} -> {report.output}")
    print(report.summary())
    return 0
