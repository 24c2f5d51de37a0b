"""Writing an OpenEXR image: one part, scanlines, no compression, float32 RGBA.

The farm writes a tiled Blender frame this way: linear values exactly as
Blender's own float EXR holds them (Blender's PNG would add its view
transform, which the farm cannot reproduce outside Blender).
"""
from __future__ import annotations

import os
import struct
from pathlib import Path

import numpy as np

MAGIC, VERSION = 20000630, 2
FLOAT = 2


def _attribute(name: str, kind: str, value: bytes) -> bytes:
    return name.encode() + b"\0" + kind.encode() + b"\0" + struct.pack("<i", len(value)) + value


def write_exr(path, rgba: np.ndarray) -> None:
    """(H, W, 4) values, row 0 at the top, to `path` as float32 R, G, B, A."""
    rgba = np.asarray(rgba, dtype="<f4")
    height, width = rgba.shape[:2]
    names = "ABGR"                                   # channels are listed (and stored) by name
    channels = b"".join(n.encode() + b"\0" + struct.pack("<i4xii", FLOAT, 1, 1) for n in names) + b"\0"
    window = struct.pack("<iiii", 0, 0, width - 1, height - 1)
    header = b"".join([
        struct.pack("<ii", MAGIC, VERSION),
        _attribute("channels", "chlist", channels),
        _attribute("compression", "compression", b"\0"),
        _attribute("dataWindow", "box2i", window),
        _attribute("displayWindow", "box2i", window),
        _attribute("lineOrder", "lineOrder", b"\0"),
        _attribute("pixelAspectRatio", "float", struct.pack("<f", 1.0)),
        _attribute("screenWindowCenter", "v2f", struct.pack("<ff", 0.0, 0.0)),
        _attribute("screenWindowWidth", "float", struct.pack("<f", 1.0)),
        b"\0",
    ])
    planes = [rgba[..., "RGBA".index(n)] for n in names]
    line_bytes = 4 * width * len(names)
    first = len(header) + 8 * height
    offsets = struct.pack(f"<{height}Q", *(first + y * (8 + line_bytes) for y in range(height)))
    # (to a temporary name, then renamed: Ctrl-C or a full disk leaves what was there, not a part)
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as f:
            f.write(header + offsets)
            for y in range(height):
                f.write(struct.pack("<ii", y, line_bytes))
                for plane in planes:
                    f.write(plane[y].tobytes())
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
