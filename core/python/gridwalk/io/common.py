"""Pieces shared by the scene readers and generators."""
from __future__ import annotations

import re
from pathlib import Path

import numpy as np


class SceneFileError(ValueError):
    """A scene file is malformed. The message names the file and, where one
    applies, the line (NFF) or the element and record (PLY), and what was
    expected. It quotes at most a short excerpt of the file."""


# Geometry keywords of gridwalk.Scene: dtype and shape of one row.
_ARRAYS = {
    "vertices": (np.float32, (3,)), "triangles": (np.int32, (3,)),
    "triangle_materials": (np.int32, ()),
    "sphere_centers": (np.float32, (3,)), "sphere_radii": (np.float32, ()),
    "sphere_materials": (np.int32, ()),
    "cylinder_base": (np.float32, (3,)), "cylinder_apex": (np.float32, (3,)),
    "cylinder_base_radius": (np.float32, ()), "cylinder_apex_radius": (np.float32, ()),
    "cylinder_materials": (np.int32, ()),
}
EXCERPT = 40                    # characters of the file an error message quotes at most


def scene_kwargs(*, materials, lights, camera, background, normals=None, **arrays) -> dict:
    """Keyword arguments for gridwalk.Scene with every geometry key present:
    given arrays converted to float32 / int32, absent ones empty; normals
    (per vertex, float32) stay None unless given."""
    unknown = set(arrays) - set(_ARRAYS)
    if unknown:
        raise TypeError(f"not a Scene array: {sorted(unknown)}")
    kwargs = {}
    for key, (dtype, row) in _ARRAYS.items():
        value = arrays.get(key)
        kwargs[key] = (np.empty((0, *row), dtype) if value is None
                       else np.ascontiguousarray(value, dtype=dtype).reshape(-1, *row))
    kwargs["normals"] = None if normals is None else np.ascontiguousarray(normals, np.float32)
    kwargs.update(materials=list(materials), lights=list(lights), camera=camera,
                  background=tuple(float(c) for c in background))
    return kwargs


def excerpt(token: bytes | str, limit: int = EXCERPT) -> str:
    """A short, printable ASCII quotation of `token`: "'abc'", "'\\x00\\x00'", or
    "'abc'... (5000 characters)" for a long one."""
    text = token.decode("latin-1") if isinstance(token, bytes) else str(token)
    if len(text) <= limit:
        return ascii(text)
    return f"{ascii(text[:limit])}... ({len(text)} characters)"


def open_scene_file(path: Path):
    """open(path, "rb"), with a SceneFileError for a folder (OSError otherwise)."""
    if Path(path).is_dir():
        raise SceneFileError(f"{path}: is a folder, not a scene file")
    return open(path, "rb")


_INDEXED = re.compile(r"(?P<name>[a-z_]+)\[(?P<index>\d+)\](?P<rest>.*)", re.S)
_FIELD = re.compile(r"(?P<name>Camera\.[a-z_]+)(?P<rest>.*)", re.S)


def core_refusal(kwargs) -> tuple[str, int | None, str] | None:
    """Build the scene in the core (its own checks, in its own float32
    precision); None if the core accepts it, else (name, index, rest) from the
    core's ValueError "name[index] rest", or ("Camera.field", None, rest), or
    ("", None, message) for one naming no array."""
    from ..scene import Scene
    try:
        Scene(**kwargs)
    except ValueError as err:
        message = str(err)
        m = _INDEXED.match(message)
        if m:
            return m["name"], int(m["index"]), m["rest"].lstrip(": ")
        m = _FIELD.match(message)
        if m:
            return m["name"], None, m["rest"].strip()
        return "", None, message
    return None
