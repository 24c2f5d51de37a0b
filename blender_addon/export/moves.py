"""Transform edits: when a new export differs from the last one only in some
instances' matrices, the scene is moved in the core (gridwalk.Scene.moved)
instead of being assembled again and copied in: moving a 1M-triangle object
then costs its vertices' transform, not the whole scene's round trip.
"""
from __future__ import annotations

import numpy as np

from .assemble import corner_order, mirrors


def instance_moves(before: tuple, layout, after: tuple, export, cache):
    """The gridwalk.InstanceMove list that turns the scene of signature `before`
    (Export.signature(), with its parts' `layout`) into that of `after`, or None
    when anything but instance matrices changed (or nothing did)."""
    import gridwalk

    if layout is None or before[1:] != after[1:] or not len(before[0]) == len(after[0]) == len(layout):
        return None
    moves = []
    for old, new, part, place in zip(before[0], after[0], export.meshes.parts, layout):
        if old[0] != new[0] or old[2] != new[2]:       # another mesh entry or other materials
            return None
        if old[1] == new[1]:
            continue
        key, data, matrix, _ = part
        previous = np.frombuffer(old[1], dtype=np.float64).reshape(4, 4)
        if mirrors(previous) != mirrors(matrix):     # (its corners' order changes: assembled again)
            return None
        if place.flat:
            positions, normals = cache.corners(key, data).reshape(-1, 3, 3)[:, corner_order(matrix)].reshape(-1, 3), None
        else:
            positions, normals = data.co, data.normals if place.normals else None
        cache.transforms += 1
        moves.append(gridwalk.InstanceMove(place.vertex_start, place.triangle_start, place.triangle_count,
                                           positions, matrix, normals=normals, flat=place.flat,
                                           previous_matrix=previous))
    return moves or None
