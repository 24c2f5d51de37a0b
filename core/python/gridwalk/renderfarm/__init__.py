"""Distributed rendering on Dask: big stills split into tiles, animations into frames.

    gridwalk.farm("balls.nff", "balls.png", tiles=16)                    # a LocalCluster here
    gridwalk.farm("shot.blend", "frames/", frames="1-250", scheduler="tcp://farm:8786")
    python -m gridwalk farm SCENE -o OUT [--scheduler tcp://HOST:PORT | --local N] ...

Modules: plan (tiles and frames), store (results on disk), cluster (the Dask
client), jobplugin (the job on the workers), core_job (NFF/PLY tiles through
the core), blend_job, blender and in_blender (.blend frames and tiles through
`blender -b`), driver (a run: submit, progress, faults, report), exr, cli.
Dask (`pip install gridwalk[farm]`) is imported only when a farm runs.
See docs/distributed.md.
"""
from __future__ import annotations

from .cluster import FarmError


def farm(scene, output, *, settings=None, tiles=None, frames=None, scheduler=None, local=None,
         width=None, height=None, blender=None, addon=None, blender_pythonpath=None,
         connect_timeout=10.0, quiet=True):
    """Render `scene` on a Dask cluster; the output is the single-machine render, bit for bit.

    scene     an .nff or .ply path (or a dict of gridwalk.Scene keywords): split
              into `tiles` tiles (default 16), rendered by the core with
              `settings` (a RenderSettings) at the camera's size or width x height;
              output: .png or .npy;
              or a .blend path: its `frames` ("1-250", "1-3,8"; default the
              .blend's range), each rendered by `blender -b` with GRIDWALK,
              output: a folder of frame_NNNN files in the .blend's format; or,
              with `tiles`, one frame (`frames`="N", default the current one)
              as border tiles, output: .exr or .npy (linear float RGBA).
    scheduler "tcp://HOST:PORT" of a running Dask scheduler, or None for a
              LocalCluster of `local` worker processes (default: one per core).
    blender, addon, blender_pythonpath
              the Blender command, a Gridwalk add-on folder and extra PYTHONPATH
              for Blender on the workers (None: each worker's GRIDWALK_BLENDER,
              GRIDWALK_ADDON, GRIDWALK_BLENDER_PYTHONPATH; see renderfarm.blender).

    Finished tiles and frames are kept on disk as they arrive; a run again
    renders only the missing ones. Returns a driver.FarmReport; raises
    FarmError naming each failed tile or frame.
    """
    from . import cluster, driver

    job = make_job(scene, output, settings=settings, tiles=tiles, frames=frames, width=width, height=height,
                   blender=blender, addon=addon, blender_pythonpath=blender_pythonpath)
    with cluster.connect(scheduler, local, connect_timeout) as (client, threads):
        if settings is not None and settings.threads > 0:
            threads = settings.threads
        return driver.run(client, job, threads, quiet)


def make_job(scene, output, *, settings=None, tiles=None, frames=None, width=None, height=None,
             blender=None, addon=None, blender_pythonpath=None):
    """The CoreJob or BlendJob for `scene` (checks everything that can be checked here)."""
    from pathlib import Path

    if not isinstance(scene, dict) and Path(scene).suffix.lower() == ".blend":
        from .blend_job import BlendJob
        from .blender import BlenderSetup

        if settings is not None or width is not None or height is not None:
            raise ValueError("a .blend file's render settings and size come from the file: "
                             "set them in Blender, not here")
        setup = BlenderSetup(blender, None if addon is None else str(Path(addon).resolve()), blender_pythonpath)
        return BlendJob(scene, output, frames=frames, tiles=tiles, blender=setup)
    if frames is not None:
        raise ValueError("--frames applies to .blend files; an NFF or PLY scene is one still")
    from .core_job import CoreJob

    return CoreJob(scene, output, settings, 16 if tiles is None else tiles, width, height)


__all__ = ["farm", "make_job", "FarmError"]
