"""Blender's tiled (UDIM) images -> one gridwalk.Image per tile, for Texture(tiles=...).

Image.pixels gives a tiled image's first tile only, so each tile is read from
its own file: the image's path with <UDIM> (1001, 1002, ...) or <UVTILE>
(u1_v1, u2_v1, ...) replaced by the tile's, or a packed tile's bytes written
to a temporary file. The file is loaded as an image of its own
(bpy.data.images.load), read as any image is, with the tiled image's colour
space, and removed at once; the loading runs on Blender's main thread
(main_thread.py). A tile filled in Blender and never saved (a generated tile)
is read as its Blank colour. A tile that cannot be read renders magenta, as a
missing image does, and is named in the image's warning.
"""
from __future__ import annotations

import os
import shutil
import tempfile

import numpy as np

from gridwalk import Image
from gridwalk.image import srgb_to_linear

from .main_thread import MainThreadTimeout, on_main_thread


def tile_token(path: str, number: int) -> str:
    """The path of tile `number` of a tiled image whose path holds <UDIM> or <UVTILE>."""
    column, row = (number - 1001) % 10, (number - 1001) // 10
    return path.replace("<UDIM>", str(number)).replace("<UVTILE>", f"u{column + 1}_v{row + 1}")


def tile_sizes(img) -> tuple[int, int]:
    """(bytes stored for all of a tiled image's tiles, bytes of the largest tile's float32
    read copy): for the memory estimate (textures.image_read_bytes' rule, tile by tile)."""
    stored = largest = 0
    for tile in img.tiles:
        w, h = (int(x) for x in tile.size)
        c = max(int(getattr(tile, "channels", 0) or getattr(img, "channels", 4)), 1)
        stored += w * h * c * (4 if img.is_float else 1)
        largest = max(largest, w * h * c * 4)
    return stored, largest


def _generated(tile, data: bool):
    """A generated tile's linear pixels (its Blank colour), or None for its other patterns. The
    colour is sRGB-encoded (a gamma-corrected property), which Blender decodes for a tile that is
    not data (Non-Color)."""
    if getattr(tile, "generated_type", "BLANK") != "BLANK":
        return None
    w, h = max(int(tile.generated_width), 1), max(int(tile.generated_height), 1)
    colour = np.array(tuple(tile.generated_color)[:4], np.float64)
    if not data:
        colour[:3] = srgb_to_linear(colour[:3])
    return np.tile(colour.astype(np.float32), (h, w, 1))


def _load(path: str, read_image, settings_of, notes: list):
    """(gridwalk.Image, problem) of the image file at `path`, loaded and removed again; a
    float tile left in its file's own colour space (Python's writes refused) is noted."""
    import bpy
    try:
        loaded = bpy.data.images.load(path, check_existing=False)
    except (RuntimeError, OSError) as exc:
        return None, f"it cannot be loaded ({exc})"
    try:
        space = settings_of.colorspace_settings.name
        if loaded.colorspace_settings.name != space:
            try:        # (a float image's pixels are decoded from its colour space as it loads)
                loaded.colorspace_settings.name = space
            except (AttributeError, TypeError, ValueError):    # (Python's writes refused: the file's own)
                if loaded.is_float:
                    notes.append(f"tiles of image '{settings_of.name}' are read in their files' colour space "
                                 f"{loaded.colorspace_settings.name}, not {space}: Blender refuses Python's "
                                 "writes just now (docs/blender.md)")
        return read_image(loaded, settings_of=settings_of)
    finally:
        bpy.data.images.remove(loaded)


def _read_all(img, read_image, problems: dict, notes: list) -> list:
    """[(tile number, gridwalk.Image or None)] for every tile, on the main thread."""
    import bpy
    packed = {int(getattr(p, "tile_number", 0)): p for p in getattr(img, "packed_files", ())}
    base = bpy.path.abspath(img.filepath_raw, library=img.library)
    scratch = None
    out = []
    try:
        for tile in img.tiles:
            number = int(tile.number)
            image, problem = None, None
            if number in packed and packed[number].packed_file is not None:
                scratch = scratch or tempfile.mkdtemp(prefix="gridwalk_udim_")
                path = os.path.join(scratch, f"{number}{os.path.splitext(base)[1] or '.png'}")
                with open(path, "wb") as f:
                    f.write(bytes(packed[number].packed_file.data))
                image, problem = _load(path, read_image, img, notes)
            elif getattr(tile, "is_generated_tile", False):
                pixels = _generated(tile, img.colorspace_settings.is_data)
                if pixels is None:
                    problem = f"its {tile.generated_type.replace('_', ' ').title()} pattern is not read"
                else:
                    image = Image(pixels, "linear", name=f"{img.name} {number}")
                    image.mean_rgb = image.mean_rgb_associated = tuple(float(c) for c in pixels[0, 0, :3])
            else:
                path = tile_token(base, number)
                if not os.path.isfile(path):
                    problem = f"its file {path!r} is missing"
                else:
                    image, problem = _load(path, read_image, img, notes)
            if problem is not None:
                problems[number] = problem
            out.append((number, image))
    finally:
        if scratch is not None:
            shutil.rmtree(scratch, ignore_errors=True)
    return out


def read_tiles(img, read_image, cancelled=lambda: False) -> tuple[list, dict, list]:
    """([(tile number, gridwalk.Image or None)], {tile number: why it is magenta}, [notes]) of a
    tiled image; read_image(loaded, settings_of=img) reads one loaded tile as textures.read_image
    does, in img's colour space."""
    problems: dict = {}
    notes: list = []
    if "<UDIM>" not in img.filepath_raw and "<UVTILE>" not in img.filepath_raw and not getattr(img, "packed_files", ()):
        if not all(getattr(tile, "is_generated_tile", False) for tile in img.tiles):
            return [], {0: f"its path {img.filepath_raw!r} names no <UDIM> or <UVTILE> tile"}, []
    try:
        tiles = on_main_thread(lambda: _read_all(img, read_image, problems, notes), cancelled=cancelled)
    except MainThreadTimeout as exc:
        return [], {0: f"its tiles could not be read ({exc})"}, []
    return tiles, problems, sorted(set(notes))
