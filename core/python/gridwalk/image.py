"""gridwalk.Image: the pixels a texture samples.

pixels: (H, W) or (H, W, C) with C = 1 (grey), 2 (grey, alpha), 3 (RGB) or
4 (RGBA); row 0 is the TOP of the image (as image files and imageio give
them; texture coordinate v = 0 is the bottom edge). uint8 pixels stay 8-bit
in memory; any other real dtype is stored as float32.

colorspace: "srgb" (colour channels are sRGB-encoded, decoded to linear at
lookup; the default for uint8), "linear" (scene-linear colour, the default
for floats) or "data" (values used as they are: roughness, metallic, alpha
maps; Blender's Non-Color). Alpha is never decoded.
"""
from __future__ import annotations

import numpy as np

from . import _core

COLORSPACES = ("srgb", "linear", "data")


class Image:
    def __init__(self, pixels, colorspace: str | None = None, name: str = ""):
        a = np.asarray(pixels)
        self.name = name or "Image"
        where = f"Image {self.name!r}"
        if a.dtype == object or not np.issubdtype(a.dtype, np.number) or np.issubdtype(a.dtype, np.complexfloating):
            raise ValueError(f"{where}: pixels must be a real numeric array, got dtype {a.dtype}")
        if a.ndim == 2:
            a = a[:, :, None]
        if a.ndim != 3 or not 1 <= a.shape[2] <= 4:
            raise ValueError(f"{where}: pixels must have shape (H, W) or (H, W, C) with C in 1..4, "
                             f"got {np.shape(pixels)}")
        if a.shape[0] == 0 or a.shape[1] == 0:
            raise ValueError(f"{where} is {a.shape[1]} x {a.shape[0]} pixels: an image needs at least one pixel")
        if colorspace is None:
            colorspace = "srgb" if a.dtype == np.uint8 else "linear"
        if colorspace not in COLORSPACES:
            raise ValueError(f"{where}: colorspace must be one of {list(COLORSPACES)}, got {colorspace!r}")
        self.colorspace = colorspace
        dtype = np.uint8 if a.dtype == np.uint8 else np.float32
        with np.errstate(over="ignore", invalid="ignore"):
            data = np.ascontiguousarray(a, dtype=dtype)
        self._native = _core.Image(data, colorspace == "srgb", where)

    @property
    def width(self) -> int:
        return self._native.width

    @property
    def height(self) -> int:
        return self._native.height

    @property
    def channels(self) -> int:
        return self._native.channels

    @property
    def memory_bytes(self) -> int:
        return self._native.memory_bytes

    def pixels(self) -> np.ndarray:
        """A copy of the stored pixels, (H, W, C) uint8 or float32, row 0 at the top."""
        return self._native.pixels()

    def __reduce__(self):   # pickled with its pixels (render farms ship scenes to workers)
        return (Image, (self.pixels(), self.colorspace, self.name))

    def __repr__(self) -> str:
        return f"gridwalk.Image({self.name!r}, {self.width} x {self.height} x {self.channels}, {self.colorspace})"


def srgb_to_linear(c):
    """sRGB-encoded values (a numpy array) decoded to linear, as the core decodes an 8-bit image."""
    c = np.asarray(c, np.float64)
    return np.where(c <= 0.04045, c / 12.92, ((np.maximum(c, 0.0) + 0.055) / 1.055) ** 2.4)

