"""Polygons and triangle strips to triangles.

polygons(points, counts): polygon k has the counts[k] corners that follow
those of polygon k-1 in `points`. Each polygon is projected onto the plane of
its dominant normal axis (Newell's normal). A convex polygon of up to
FAN_CORNERS corners becomes a fan (0, j, j+1), a larger one is clipped in
rounds (every other corner per round, as the ear clipper does along convex
runs: no corner is in more than about 2 log2(n) triangles, where a fan's
first corner is in all of them and crowds every grid cell around it); any
other polygon is ear-clipped (in the core, core/src/ear_clip.h),
so that a concave polygon (SPD's gears, an L-shaped scan face) is covered
exactly once. Triangles keep the polygon's winding. Non-convex polygons of
more than MAX_CLIPPED_CORNERS corners are refused (TooManyCorners): one of a
million corners takes up to about 10 s to clip (a self-intersecting outline
of random points; a gear of thin spikes 3 s, a spiral band 1.3 s).

strips(indices, restart): triangle strips in one index stream, a strip
ending wherever `restart` is set; triangle j of a strip is (s[j], s[j+1],
s[j+2]) for even j and (s[j+1], s[j], s[j+2]) for odd j (the winding
alternates), and triangles that repeat an index (the joins of stitched strips)
are dropped.
"""
from __future__ import annotations

import numpy as np

from .. import _core

MAX_CLIPPED_CORNERS = 1_000_000
# Larger convex polygons are clipped in rounds, not fanned: a 16,384-gon cap
# fanned from one corner cost rays that met it 282 triangle tests each in a
# scene of 200,000 small triangles (1.3 Mrays/s), in rounds 7 (2.9 Mrays/s).
FAN_CORNERS = 32
APEX_TRIES = 2   # corners tried as a fan's first corner where corner 0's fan has a triangle of no area


class TooManyCorners(ValueError):
    """A non-convex polygon too large to clip; `polygon` is its index."""

    def __init__(self, polygon: int, corners: int):
        super().__init__(f"{corners} corners and not convex: non-convex polygons are "
                         f"triangulated up to {MAX_CLIPPED_CORNERS} corners")
        self.polygon = polygon


def polygons(points, counts) -> tuple[np.ndarray, np.ndarray]:
    """(triangles, polygon): (T, 3) int64 positions in `points`, and the
    polygon each triangle comes from; polygons appear in order."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 3)
    counts = np.asarray(counts, dtype=np.int64)
    starts = np.cumsum(counts) - counts
    tris, polys = [], []
    for n in np.unique(counts):
        which = np.flatnonzero(counts == n)
        if n == 3:
            tris.append(starts[which, None] + np.arange(3))
            polys.append(which)
            continue
        xy = _project(points[starts[which, None] + np.arange(n)])
        fan = _convex(xy) | _flat(xy)
        rounds = np.zeros(len(which), bool)
        if n > FAN_CORNERS:
            # (A polygon that passes as convex by its fan alone, a fine concave arc
            # seen from corner 0, may fold in rounds: it keeps its fan.)
            rounds[fan] = _unfolded(xy[fan], _rounds(n)) | _flat(xy[fan])
            tris.append((starts[which[rounds], None, None] + _rounds(n)).reshape(-1, 3))
            polys.append(np.repeat(which[rounds], n - 2))
        fanned = fan & ~rounds
        corners = points[starts[which[fanned], None] + np.arange(n)]
        local = (_fan_apexes(xy[fanned], corners)[:, None, None] + _fans(np.zeros(1, np.int64), n)[None]) % n
        tris.append((starts[which[fanned], None, None] + local).reshape(-1, 3))
        polys.append(np.repeat(which[fanned], n - 2))
        if n == 4:                       # a concave quad: split at its reflex corner
            t = _concave_quads(xy[~fan])
            tris.append((starts[which[~fan], None, None] + t).reshape(-1, 3))
            polys.append(np.repeat(which[~fan], 2))
            continue
        for k in which[~fan]:
            if n > MAX_CLIPPED_CORNERS:
                raise TooManyCorners(int(k), int(n))
            local = ear_clip(_project(points[starts[k]:starts[k] + n][None])[0])
            tris.append(starts[k] + local)
            polys.append(np.full(len(local), k))
    if not tris:
        return np.empty((0, 3), np.int64), np.empty(0, np.int64)
    tri, poly = np.concatenate(tris).reshape(-1, 3), np.concatenate(polys)
    if len(poly) > 1 and np.any(poly[1:] < poly[:-1]):
        order = np.argsort(poly, kind="stable")   # back to polygon order
        tri, poly = tri[order], poly[order]
    return tri, poly


def strips(indices, restart, positions=False):
    """(T, 3) triangles of the strips in `indices` (see the module docstring);
    with positions=True also the position in `indices` where each one starts."""
    s = np.asarray(indices, dtype=np.int64)
    restart = np.asarray(restart, dtype=bool)
    if len(s) < 3:
        empty = np.empty((0, 3), np.int64)
        return (empty, np.empty(0, np.int64)) if positions else empty
    j = np.arange(len(s) - 2)
    keep = ~(restart[j] | restart[j + 1] | restart[j + 2])
    last = np.maximum.accumulate(np.where(restart, np.arange(len(s)), -1))
    odd = (j - last[j] - 1) % 2 == 1
    a, b, c = s[j], s[j + 1], s[j + 2]
    tri = np.stack([np.where(odd, b, a), np.where(odd, a, b), c], axis=1)
    keep &= (a != b) & (b != c) & (a != c)
    return (tri[keep], j[keep]) if positions else tri[keep]


def _fan_apexes(xy, p):
    """The corner each of the (m, n, 2) fanned polygons (p: their (m, n, 3) corners) is
    fanned from: 0, or where a triangle of corner 0's fan has no area (corners on one line
    with it: a square with a midpoint on a side, fanned from a corner of that side), the
    first corner whose fan has none and does not fold, of APEX_TRIES tried: its straight
    corners first (the middle of a side of two edges works), then the others. The fan
    covers the polygon either way; a triangle of no area is one the scene checks name as
    invisible, and a grid lists."""
    m, n = xy.shape[:2]
    apex = np.zeros(m, np.int64)
    if not m or n > FAN_CORNERS:   # (a large fan, one that would fold in rounds, keeps 0)
        return apex
    pattern = _fans(np.zeros(1, np.int64), n)
    todo = np.flatnonzero(_degenerate(p, pattern))
    if not len(todo):
        return apex
    straight = _degenerate(p[todo], np.stack([np.arange(n) - 1, np.arange(n), (np.arange(n) + 1) % n], 1),
                           each=True)
    # each polygon's straight corners first, then the others in order, corner 0 last
    key = np.where(straight, 0, 1)
    key[:, 0] = 2
    order = np.argsort(key, axis=1, kind="stable")
    for k in range(min(APEX_TRIES, n - 1)):
        corner = order[:, k]
        turned = (corner[:, None] + np.arange(n)) % n
        rows = todo[:, None]
        ok = ~_degenerate(p[rows, turned], pattern)
        ok[ok] = _unfolded(xy[rows[ok], turned[ok]], pattern)
        apex[todo[ok]] = corner[ok]
        todo, order = todo[~ok], order[~ok]
        if not len(todo):
            break
    return apex


def _degenerate(p, local, each=False):
    """Which (m, n, 3) polygons have a triangle of `local` whose area is zero to float32
    precision, as gridwalk.mesh_checks counts them (each=True: per triangle, (m, T))."""
    a = p[:, local[:, 0]]
    ab, ac = p[:, local[:, 1]] - a, p[:, local[:, 2]] - a
    (bx, by, bz), (cx, cy, cz) = np.moveaxis(ab, -1, 0), np.moveaxis(ac, -1, 0)   # (per component: no np.cross)
    area2 = (by * cz - bz * cy) ** 2 + (bz * cx - bx * cz) ** 2 + (bx * cy - by * cx) ** 2
    scale = np.maximum(bx * bx + by * by + bz * bz, cx * cx + cy * cy + cz * cz)
    zero = area2 <= 1e-14 * scale * scale
    return zero if each else np.any(zero, axis=1)


def _fans(starts, n):
    j = np.arange(1, n - 1)
    first = np.repeat(starts, n - 2)
    return np.stack([first, first + np.tile(j, len(starts)), first + np.tile(j + 1, len(starts))], axis=1)


def _rounds(n):
    """(n - 2, 3) local triangles of a convex n-gon clipped in rounds: each round
    clips every other corner of what is left (1, 3, 5, ... never the first or
    the last), until one triangle remains. The corners keep their order, so
    every triangle keeps the polygon's winding."""
    corners, out = np.arange(n), []
    while len(corners) > 3:
        i = np.arange(1, len(corners) - 1, 2)
        out.append(np.stack([corners[i - 1], corners[i], corners[i + 1]], axis=1))
        corners = np.delete(corners, i)
    out.append(corners[None])
    return np.concatenate(out)


def _project(p):
    """(m, n, 3) polygons -> (m, n, 2) in the plane of each one's dominant normal
    axis, mirrored where needed so that every polygon winds counter-clockwise."""
    nxt = np.roll(p, -1, axis=1)
    normal = np.cross(p, nxt).sum(axis=1)                      # Newell's method
    axis = np.argmax(np.abs(normal), axis=1)
    keep = np.array([[1, 2], [2, 0], [0, 1]])[axis]            # the other two axes, cyclic
    xy = np.take_along_axis(p, keep[:, None, :], axis=2)
    flip = np.take_along_axis(normal, axis[:, None], axis=1)[:, 0] < 0
    xy[flip, :, 0] *= -1.0
    return xy


def _turns(xy):
    """Cross product of the edges in and out of each corner of (m, n, 2) polygons."""
    e = np.roll(xy, -1, axis=1) - xy
    ep = np.roll(e, 1, axis=1)
    return ep, e, ep[..., 0] * e[..., 1] - ep[..., 1] * e[..., 0]


def _flat(xy):
    """Polygons of no area (collinear or coincident corners): any split is as good."""
    x, y = xy[..., 0], xy[..., 1]
    area = (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)
    size = np.ptp(xy, axis=1).max(axis=1)
    return ~(np.abs(area) > 1e-12 * size * size)


def _concave_quads(xy):
    """(m, 2, 3) local triangles of quads with one reflex corner r: (r, r+1, r+2),
    (r, r+2, r+3). A bow-tie (two reflex corners) has no right answer: its fan is kept."""
    _, _, cross = _turns(xy)
    r = np.where((cross < 0).sum(axis=1) == 1, np.argmin(cross, axis=1), 0)[:, None]
    return np.stack([np.concatenate([r, r + 1, r + 2], axis=1),
                     np.concatenate([r, r + 2, r + 3], axis=1)], axis=1) % 4


# A corner that lies off the line of its neighbours' edges by less than this
# fraction of the polygon's size, on the wrong side, still counts as convex:
# a regular polygon of many corners written with six significant digits (C's
# %g) has that much noise, more than its turns (a 10,000-gon took 11 s to
# ear-clip, and one of 1,000,000 corners was refused as not convex). A fan
# of such a polygon overlaps itself by slivers of that relative size.
CONVEX_TOLERANCE = 1e-5


def _convex(xy):
    """Which (m, n, 2) counter-clockwise polygons are convex: no right turn
    beyond the coordinates' noise (CONVEX_TOLERANCE), and a total turn of one
    revolution (a pentagram turns left everywhere, twice)."""
    ep, e, cross = _turns(xy)
    dot = (ep * e).sum(axis=-1)
    length = np.maximum(np.linalg.norm(ep, axis=-1), np.linalg.norm(e, axis=-1))
    size = np.ptp(xy, axis=1).max(axis=1)[:, None]
    turn = np.arctan2(cross, dot).sum(axis=1)
    # (cross / length: how far a corner's next edge leaves the line of the one before, at most)
    corners = np.all(cross >= -CONVEX_TOLERANCE * size * length, axis=1) & (np.abs(turn - 2 * np.pi) < 1e-6)
    # The tolerance is per corner: a concave arc of many fine corners passes
    # it everywhere, so the fan itself must not fold either (no fan triangle
    # (0, j, j + 1) turning the wrong way by more than the tolerance).
    return corners & _unfolded(xy, _fans(np.zeros(1, np.int64), xy.shape[1]))


def _unfolded(xy, local):
    """Which (m, n, 2) counter-clockwise polygons have no triangle of `local`
    ((T, 3) corner indices, corners in polygon order) turning the wrong way by
    more than the coordinates' noise (CONVEX_TOLERANCE).
    A triangle (a, b, c)'s doubled area is its side bc times a's distance from
    that side's line; moving the side's ends by the noise tilts the line by
    noise / side, which moves that distance by up to noise x spoke / side: so
    the tolerance scales with side + spoke (with the side alone, thin fan
    triangles next to corner 0 failed it on a 50,000-corner circle written
    with six digits)."""
    size = np.ptp(xy, axis=1).max(axis=1)[:, None]
    a, b, c = xy[:, local[:, 0]], xy[:, local[:, 1]], xy[:, local[:, 2]]
    ab, ac = b - a, c - a
    doubled = ab[..., 0] * ac[..., 1] - ab[..., 1] * ac[..., 0]
    side = np.linalg.norm(c - b, axis=-1)
    reach = np.maximum(np.linalg.norm(ab, axis=-1), np.linalg.norm(ac, axis=-1))
    return np.all(doubled >= -CONVEX_TOLERANCE * size * (side + reach), axis=1)


def ear_clip(xy) -> np.ndarray:
    """Triangles (n-2, 3) of local corner indices covering the counter-clockwise
    polygon `xy` (n, 2). An ear is a convex corner whose triangle holds no other
    reflex corner; after each clip only the two neighbours change. Where no
    ear is left (a self-intersecting or degenerate outline) the most convex
    corner is clipped anyway, so the result always has n - 2 triangles. In the
    core (core/src/ear_clip.h), with a grid of the corners, so that a clip
    costs about as much as the corners near it."""
    return _core.ear_clip(np.ascontiguousarray(xy, dtype=np.float64))
