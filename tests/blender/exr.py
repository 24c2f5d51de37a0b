"""A minimal OpenEXR reader for the tests: uncompressed scanline files only.

Blender writes them with image_settings.file_format = "OPEN_EXR_MULTILAYER" (or
"OPEN_EXR"), exr_codec = "NONE" and color_depth = "32". Channels come back as
float32 (H, W) arrays, row 0 at the top, keyed by name ("ViewLayer.Depth.Z").
"""
from __future__ import annotations

import struct

import numpy as np

MAGIC = 20000630
PIXEL_TYPES = {0: np.dtype("<u4"), 1: np.dtype("<f2"), 2: np.dtype("<f4")}


def _cstring(data, pos):
    end = data.index(b"\0", pos)
    return data[pos:end].decode(), end + 1


def _channels(value):
    channels, pos = [], 0
    while value[pos] != 0:
        name, pos = _cstring(value, pos)
        pixel_type, = struct.unpack_from("<i", value, pos)
        channels.append((name, PIXEL_TYPES[pixel_type]))
        pos += 16
    return channels


def _header(data, pos, strings=None):
    """(attribute name -> raw value, position after the header); `strings`, a
    dict, also gets the attributes of type string, decoded (metadata)."""
    header = {}
    while data[pos] != 0:
        name, pos = _cstring(data, pos)
        kind, pos = _cstring(data, pos)
        size, = struct.unpack_from("<i", data, pos)
        header[name] = data[pos + 4:pos + 4 + size]
        if strings is not None and kind == "string":
            strings[name] = header[name].decode("utf-8")
        pos += 4 + size
    return header, pos + 1


def read_metadata(path) -> dict[str, str]:
    """The string attributes of a scanline EXR's headers (every part's): Blender's metadata."""
    strings = {}
    read_exr(path, strings)
    return strings


def read_exr(path, strings=None) -> dict[str, np.ndarray]:
    """Every channel of a single- or multi-part (Blender 5.0) scanline EXR."""
    data = open(path, "rb").read()
    magic, version = struct.unpack_from("<ii", data, 0)
    multipart = bool(version & 0x1000)
    if magic != MAGIC or version & 0x200:
        raise ValueError(f"{path}: not a scanline OpenEXR file")
    headers, pos = [], 8
    while True:
        header, pos = _header(data, pos, strings)
        headers.append(header)
        if not multipart or data[pos] == 0:
            break
    pos += 1 if multipart else 0
    out = {}
    for part, header in enumerate(headers):
        if header["compression"][0] != 0:
            raise ValueError(f"{path}: compressed EXR (write it with exr_codec = 'NONE')")
        channels = _channels(header["channels"])
        x0, y0, x1, y1 = struct.unpack("<iiii", header["dataWindow"])
        width, height = x1 - x0 + 1, y1 - y0 + 1
        offsets = np.frombuffer(data, "<u8", height, pos)
        pos += 8 * height
        planes = {name: np.empty((height, width), np.float32) for name, _ in channels}
        for offset in offsets:
            p = int(offset) + (4 if multipart else 0)        # multi-part chunks start with the part number
            y, _ = struct.unpack_from("<ii", data, p)
            p += 8
            for name, dtype in channels:
                planes[name][y - y0] = np.frombuffer(data, dtype, width, p)
                p += width * dtype.itemsize
        out.update(planes)
    return out


def rgba(channels: dict, prefix: str = "") -> np.ndarray:
    """(H, W, 4) from the R, G, B, A channels under `prefix` (e.g. "ViewLayer.Combined.")."""
    return np.stack([channels[prefix + c] for c in "RGBA"], axis=-1)


def luminance(rgba):
    """Rec. 709 luminance of linear RGB(A) pixels."""
    return rgba[..., :3] @ np.array([0.2126, 0.7152, 0.0722], np.float32)
