"""A Color Ramp node as gridwalk.Texture's ramp: stops of (position, R, G, B, A).

Cycles bakes a Color Ramp into a table of Blender's own evaluation at 256
evenly spaced values of [0, 1] (ColorRamp.evaluate) and reads it between
entries; the core reads its stops the same way (core/src/texture.cpp,
ramp_color). A ramp in RGB mode whose stops are in order and finite, with
Linear, Ease or Constant interpolation, goes out as its own stops, which the
core evaluates as Blender does; any other (B-Spline or Cardinal
interpolation, HSV or HSL mode, stops a script left out of order, NaN
values) goes out as that table of 256 stops, Blender's evaluation, so that
it renders as in Cycles too.
"""
from __future__ import annotations

import math

import numpy as np

INTERPOLATIONS = {"LINEAR": "linear", "EASE": "ease", "CONSTANT": "constant"}   # Blender -> Texture
TABLE = 256                                     # Cycles' RAMP_TABLE_SIZE
FLOAT_MAX = float(np.finfo(np.float32).max)


def ramp_stops(ramp, name: str) -> tuple[tuple, str, list[str]]:
    """(stops, Texture.ramp_interpolation, notes to warn about) of a ColorRamp."""
    stops = [(float(e.position), *(float(c) for c in e.color)) for e in ramp.elements]
    finite = all(math.isfinite(x) for stop in stops for x in stop)
    ordered = all(a[0] <= b[0] for a, b in zip(stops, stops[1:]))
    interpolation = INTERPOLATIONS.get(ramp.interpolation)
    if interpolation is not None and ramp.color_mode == "RGB" and ordered and finite:
        return tuple(stops), interpolation, []
    table = np.array([tuple(ramp.evaluate(i / (TABLE - 1))) for i in range(TABLE)], np.float64)
    notes = []
    if not np.isfinite(table).all():
        notes.append(f"{name!r} has NaN or infinite colours (read as 0 and the largest float)")
        table = np.nan_to_num(table, nan=0.0, posinf=FLOAT_MAX, neginf=-FLOAT_MAX)
    stops = tuple((i / (TABLE - 1), *map(float, table[i])) for i in range(TABLE))
    return stops, "constant" if ramp.interpolation == "CONSTANT" else "linear", notes
