"""What a farm job is split into: tiles of one image, or frames of an animation.

Both are plain numbers: a task carries a tile index or a frame number, and
every worker derives the same tile rectangles from (width, height, count).
"""
from __future__ import annotations

import hashlib
import math
import re


def tile_grid(width: int, height: int, count: int) -> tuple[int, int]:
    """(columns, rows) with columns * rows == count, the tiles as square as
    the image allows (a prime count gives strips)."""
    if count < 1:
        raise ValueError(f"--tiles must be at least 1, got {count}")
    if count > width * height:
        raise ValueError(f"--tiles {count} is more than the {width} x {height} image has pixels")
    best = None
    for rows in range(1, count + 1):
        if count % rows:
            continue
        cols = count // rows
        if cols > width or rows > height:
            continue
        squareness = abs(math.log((width / cols) / (height / rows)))
        if best is None or squareness < best[0]:
            best = (squareness, cols, rows)
    if best is None:
        raise ValueError(f"--tiles {count} cannot be laid out as a grid on a {width} x {height} image")
    return best[1], best[2]


def tiles(width: int, height: int, count: int) -> list[tuple[int, int, int, int]]:
    """`count` rectangles (x, y, w, h), row 0 at the top, covering the image
    exactly once; tile i is row i // columns, column i % columns."""
    cols, rows = tile_grid(width, height, count)
    xs = [width * c // cols for c in range(cols + 1)]
    ys = [height * r // rows for r in range(rows + 1)]
    return [(xs[c], ys[r], xs[c + 1] - xs[c], ys[r + 1] - ys[r]) for r in range(rows) for c in range(cols)]


MAX_FRAME = 1048574        # Blender's last frame (MAXFRAME; the first is -MAXFRAME): frame_set clamps to it


def parse_frames(text: str) -> list[int]:
    """'1-10', '7', '1-3,8,10-12' -> sorted frame numbers (no repeats)."""
    frames = set()
    for part in str(text).replace(" ", "").split(","):
        match = re.fullmatch(r"(-?\d+)(?:(?:-|\.\.)(-?\d+))?", part)
        if not match:
            raise ValueError(f"--frames: {part!r} is not a frame or a range A-B (e.g. 1-10 or 1-3,8)")
        first = int(match.group(1))
        last = int(match.group(2)) if match.group(2) is not None else first
        if last < first:
            raise ValueError(f"--frames: the range {part!r} ends before it starts")
        if first < -MAX_FRAME or last > MAX_FRAME:
            raise ValueError(f"--frames: {part!r} lies outside Blender's frames ({-MAX_FRAME} to {MAX_FRAME})")
        if last - first > 1_000_000:
            raise ValueError(f"--frames: the range {part!r} has more than a million frames")
        frames.update(range(first, last + 1))
    return sorted(frames)


def digest(*parts) -> str:
    """A hex digest of bytes and reprs: what a stored result was rendered from."""
    h = hashlib.sha256()
    for part in parts:
        h.update(part if isinstance(part, bytes) else repr(part).encode())
        h.update(b"\0")
    return h.hexdigest()
