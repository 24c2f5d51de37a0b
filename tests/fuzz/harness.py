"""The fuzz target shared by the reader fuzzers (reader_fuzzer.py) and the regression tests.

One input: write the bytes to a scene file, load it. SceneFileError is the
expected refusal. A file that loads is turned into a gridwalk.Scene (the core
may refuse it with ValueError) and rendered at 8 x 8 pixels with one sample
per pixel, so the parsed garbage reaches the native core: grid build, DDA,
intersection, shading, secondary rays. Anything else that escapes -- another
exception type, a crash or sanitizer report in the core, a hang -- is a bug.

No atheris here: the regression tests import this module without it.
"""
from __future__ import annotations

import dataclasses
import os
import tempfile

import gridwalk as gw
from gridwalk.io import SceneFileError, load_nff, load_ply

# 8 x 8 (the file's camera is resized), one sample through each pixel centre,
# one worker thread: the fuzzer runs many small inputs one after another.
SIZE = 8
SETTINGS = gw.RenderSettings(threads=1, tile_size=SIZE, aa="center", aa_samples=1)
LOADERS = {".nff": load_nff, ".ply": load_ply}


def exercise(kwargs: dict):
    """Build a Scene from loader output and render it small. Returns the image,
    or None when the file's content is refused with ValueError."""
    camera = kwargs["camera"]
    try:
        camera.validate()          # the camera exactly as the file describes it
    except ValueError:
        pass
    kwargs = dict(kwargs, camera=dataclasses.replace(camera, width=SIZE, height=SIZE))
    try:
        scene = gw.Scene(**kwargs)
    except ValueError:
        return None
    image = gw.render(scene, SETTINGS)
    assert image.shape == (SIZE, SIZE, 4), image.shape
    return image


def run_file(path, suffix: str):
    """Load and render one scene file; SceneFileError counts as a clean refusal."""
    try:
        kwargs = LOADERS[suffix](path)
    except SceneFileError:
        return None
    return exercise(kwargs)


def run_bytes(data: bytes, suffix: str):
    """One input: a fresh temporary file (removed again at once, since
    libFuzzer ends the process without running Python's atexit hooks)."""
    fd, path = tempfile.mkstemp(prefix="gridwalk-fuzz-", suffix=suffix)
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        return run_file(path, suffix)
    finally:
        os.unlink(path)
