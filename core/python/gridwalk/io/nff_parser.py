"""NFF entities from a token stream into arrays (used by gridwalk.io.nff).

Each part of the file (a TokenStream segment) is parsed in one go: the
keywords are found, each entity's number count checked against its keyword
(`p n` against n), all the numbers converted at once, and each kind of
primitive gathered with numpy. The entity that is still open at the end of a
part is carried into the next one: its few tokens, or, for a polygon, what is
read of it so far (so a polygon of any size streams through). When the fast
check finds anything wrong, `_explain` walks the part entity by entity to
name the first mistake and where it is.

Positions are token indices in the file; errors are _Refusal(index, message)
and gridwalk.io.nff turns the index into a line number.
"""
from __future__ import annotations

import math

import numpy as np

from .common import excerpt

V, FROM, AT, UP, ANGLE, HITHER, RESOLUTION, B, L, F, C, S, P, PP = range(14)
KINDS = {b"v": V, b"from": FROM, b"at": AT, b"up": UP, b"angle": ANGLE, b"hither": HITHER,
         b"resolution": RESOLUTION, b"b": B, b"l": L, b"f": F, b"c": C, b"s": S, b"p": P, b"pp": PP}
NAMES = {kind: word.decode() for word, kind in KINDS.items()}
SIZE = np.array([0, 3, 3, 3, 1, 1, 2, 3, 3, 8, 8, 4, 0, 0])      # numbers after each keyword
WHAT = {V: "", FROM: "x y z", AT: "x y z", UP: "x y z", ANGLE: "degrees", HITHER: "distance",
        RESOLUTION: "width height", B: "r g b", L: "x y z [r g b]", F: "r g b Kd Ks Shine T ior",
        C: "base x y z radius, apex x y z radius", S: "x y z radius", P: "x y z per vertex",
        PP: "x y z nx ny nz per vertex"}
ENTITIES = "v, from, at, up, angle, hither, resolution, b, l, f, c, s, p, pp or #"
MAX_CORNERS = 1_000_000           # no NFF polygon has more corners
_NUMBER_CHARS = b"0123456789+-.eE"
_F32_MAX = float(np.finfo(np.float32).max)


class Refusal(Exception):
    """A malformed entity at token `index`; "{also}" in the message stands for
    the line of token `also`."""

    def __init__(self, index, message, also=None):
        self.index, self.message, self.also = index, message, also


def numeric(token: bytes | None) -> bool:
    return token is not None and token[:1] in (b"0", b"1", b"2", b"3", b"4", b"5", b"6", b"7", b"8",
                                                b"9", b"+", b"-", b".")


def _numbers(tokens) -> np.ndarray | None:
    """float64 values of plain decimal tokens within float32 range, or None."""
    if b" ".join(tokens).translate(None, _NUMBER_CHARS + b" "):
        return None
    try:
        values = np.fromiter(map(float, tokens), np.float64, len(tokens))
    except ValueError:
        return None
    return values if not len(values) or np.abs(values).max() <= _F32_MAX else None


class Parser:
    """Entities into arrays, one TokenStream segment at a time (`feed`, then `finish`)."""

    def __init__(self):
        self.view, self.background = {}, None            # view: kind -> (value, index)
        self.lights, self.materials = [], []             # (position, colour, index), (Material, index)
        self.spheres, self.cones = [], []                # chunks (rows, material, index)
        self.polygons = []                               # chunks (corners, normals, counts, material, index)
        self.patches = False                             # a pp was read: normals are kept
        self.carry, self.carry_base = [], 0              # tokens of the entity still open
        self.open = None                                 # a polygon still open: [kind, index, count, values]
        self.last = None                                 # (kind, index) of the last entity read

    # -- segments --------------------------------------------------------------
    def feed(self, tokens: list, base: int, final: bool = False) -> None:
        if self.open is not None:
            used = self._continue_polygon(tokens, base, final)
            tokens, base = tokens[used:], base + used
        if self.carry:
            tokens, base, self.carry = self.carry + tokens, self.carry_base, []
        if not tokens:
            return
        keys = [j for j, t in enumerate(tokens) if t[0] > 57]        # words start with a letter
        if not keys or keys[0] != 0:
            self._explain(tokens, base, len(tokens), final)
        if final:
            self._entities(tokens, base, keys, len(tokens), final)
            return
        last = keys.pop()                                # the entity that may go on in the next part
        if keys:
            self._entities(tokens, base, keys, last, final)
        kind = KINDS.get(tokens[last])
        if kind in (P, PP) and len(tokens) - last > 2:
            self._open_polygon(tokens, base, last)
        elif len(tokens) - last > 1 + SIZE.max():        # more numbers than any entity takes
            self._explain(tokens, base, len(tokens), True)
        else:
            self.carry, self.carry_base = tokens[last:], base + last

    def finish(self) -> None:
        """The end of the file: close what is still open."""
        if self.open is not None:
            kind, index, count, values = self.open
            width = 6 if kind == PP else 3
            raise Refusal(index, f"'{NAMES[kind]}' needs {count * width} numbers ({WHAT[kind]}), "
                                 f"but the file ends after {sum(map(len, values))}: truncated?")
        self.feed([], 0, final=True)

    # -- the fast path ------------------------------------------------------------
    def _entities(self, tokens, base, keys, stop, final):
        """Complete entities starting at tokens[keys[i]]; the last one ends at stop."""
        codes = np.array([KINDS.get(tokens[k], -1) for k in keys])
        keys = np.asarray(keys)
        if (codes < 0).any():
            self._explain(tokens, base, stop, final)
        gap = np.diff(np.append(keys, stop)) - 1
        need = SIZE[codes].copy()
        lit = codes == L
        need[lit] = np.where(gap[lit] == 6, 6, 3)
        poly = (codes == P) | (codes == PP)
        counts = np.zeros(0, np.int64)
        if poly.any():
            count_tokens = [tokens[k + 1] if k + 1 < stop else b"" for k in keys[poly]]
            if not all(t.isdigit() and len(t) <= 10 for t in count_tokens):
                self._explain(tokens, base, stop, final)
            counts = np.array(list(map(int, count_tokens)), dtype=np.int64)
            if counts.min() < 3 or counts.max() > MAX_CORNERS:
                self._explain(tokens, base, stop, final)
            need[poly] = 1 + np.where(codes[poly] == PP, 6, 3) * counts
        if not np.array_equal(gap, need):
            self._explain(tokens, base, stop, final)
        mask = np.ones(stop, dtype=bool)
        mask[keys] = False
        mask[keys[poly] + 1] = False
        values = _numbers([tokens[j] for j in np.flatnonzero(mask).tolist()])
        if values is None:
            self._explain(tokens, base, stop, final)
        size = need - poly                               # numbers, the vertex count left out
        offset = np.cumsum(size) - size
        index = base + keys
        first_material = len(self.materials) - 1
        material = first_material + np.cumsum(codes == F)
        for kind in (S, C):
            sel = codes == kind
            if sel.any():
                rows = values[offset[sel, None] + np.arange(SIZE[kind])]
                (self.spheres if kind == S else self.cones).append((rows, material[sel], index[sel]))
        if poly.any():
            self._polygons(values, offset[poly], counts, codes[poly] == PP, material[poly], index[poly])
        few = np.flatnonzero(~((codes == S) | (codes == C) | poly))
        for e in few.tolist():                            # views, lights, materials: few of them
            self._entity(codes[e], values[offset[e]:offset[e] + size[e]].tolist(), int(index[e]))
        self.last = (int(codes[-1]), int(index[-1]))

    def _polygons(self, values, offset, counts, patch, material, index):
        width = np.where(patch, 6, 3)
        corner = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
        at = np.repeat(offset, counts) + corner * np.repeat(width, counts)
        corners = values[at[:, None] + np.arange(3)]
        normals = None
        if patch.any() or self.patches:
            normals = np.full_like(corners, math.nan)
            is_patch = np.repeat(patch, counts)
            normals[is_patch] = values[at[is_patch, None] + 3 + np.arange(3)]
            if not self.patches:
                self.patches = True
                for k, chunk in enumerate(self.polygons):          # the p corners read before
                    self.polygons[k] = (chunk[0], np.full_like(chunk[0], math.nan), *chunk[2:])
        self.polygons.append((corners, normals, counts, material, index))

    def _entity(self, kind, v, index):
        """A view entity, the background, a light or a material."""
        from ..model import Material
        if kind == ANGLE and not 0.0 < v[0] < 180.0:
            raise Refusal(index, f"'angle' must be between 0 and 180 degrees, got {v[0]:g}")
        if kind == HITHER and v[0] < 0:
            raise Refusal(index, f"'hither' must be >= 0, got {v[0]:g}")
        if kind == RESOLUTION:
            if not all(1 <= x < 2 ** 31 and x == int(x) for x in v):
                raise Refusal(index, f"'resolution' expects two positive integers, got {v[0]:g} {v[1]:g}")
            v = [int(x) for x in v]
        if kind == B:
            self.background = (tuple(v), index)
        elif kind == L:
            self.lights.append((tuple(v[:3]), tuple(v[3:]) or None, index))
        elif kind == F:
            r, g, b, kd, ks, shine, t, ior = v
            if shine < 0:
                raise Refusal(index, f"'f': Shine must be >= 0, got {shine:g}")
            if ior <= 0:
                if t > 0:
                    raise Refusal(index, f"'f': a transparent surface (T > 0) needs ior > 0, got {ior:g}")
                ior = 1.0
            self.materials.append((Material(color=(r, g, b), kd=kd, ks=ks, shininess=shine,
                                            transmittance=t, ior=ior, mirror=ks), index))
        elif kind == V:
            if V in self.view:             # its from / at / up / angle would replace the first's
                raise Refusal(index, "a second 'v' view block (the first is on line {also}); an NFF "
                                     "file has one view", also=self.view[V][1])
            self.view[V] = (None, index)
        else:
            self.view[kind] = (v[0] if kind in (ANGLE, HITHER) else v, index)

    # -- a polygon across segments --------------------------------------------------
    def _open_polygon(self, tokens, base, k):
        """Start the polygon at tokens[k], whose numbers run past the segment's end."""
        count = tokens[k + 1]
        if not (count.isdigit() and len(count) <= 10 and 3 <= int(count) <= MAX_CORNERS):
            self._explain(tokens, base, len(tokens), True)
        self.open = [KINDS[tokens[k]], base + k, int(count), []]
        self._continue_polygon(tokens[k + 2:], base + k + 2, False)

    def _continue_polygon(self, tokens, base, final) -> int:
        """Add the open polygon's numbers from the start of tokens; how many were used."""
        kind, index, count, parts = self.open
        width = 6 if kind == PP else 3
        have = sum(len(p) for p in parts)
        take = min(len(tokens), count * width - have)
        end = next((j for j in range(take) if not numeric(tokens[j])), take)
        values = _numbers(tokens[:end])
        if values is None:
            self.last = (kind, index)
            self._explain_numbers(kind, index, tokens[:end], base, count * width, have)
        parts.append(values)
        if end < take:                                   # an entity before the polygon is complete
            raise Refusal(index, f"'{NAMES[kind]}' needs {count * width} numbers ({WHAT[kind]}), but "
                                 f"only {have + end} follow before {excerpt(tokens[end])} on line {{also}}",
                          also=base + end)
        if have + end == count * width:
            self.open = None
            values = np.concatenate(parts)
            self._polygons(values, np.zeros(1, np.int64), np.array([count]), np.array([kind == PP]),
                           np.array([len(self.materials) - 1]), np.array([index]))
            self.last = (kind, index)
        return end

    # -- errors ------------------------------------------------------------------------
    def _explain(self, tokens, base, stop, final):
        """Walk tokens[:stop] entity by entity and raise the first mistake."""
        i = 0
        while i < stop:
            word, at = tokens[i], base + i
            kind = KINDS.get(word)
            if kind is None:
                if numeric(word) and self.last is not None:
                    raise Refusal(at, f"unexpected number {excerpt(word)}: the '{NAMES[self.last[0]]}' "
                                      f"on line {{also}} has all its numbers; expected an entity "
                                      f"({ENTITIES})", also=self.last[1])
                what = (f"a number, {excerpt(word)}, before any entity" if numeric(word)
                        else f"unknown entity {excerpt(word)}")
                raise Refusal(at, f"{what}; expected an entity ({ENTITIES})")
            i += 1
            k = int(SIZE[kind])
            if kind in (P, PP):
                count = tokens[i] if i < len(tokens) else None
                if count is None or not (count.isdigit() and len(count) <= 10
                                         and 3 <= int(count) <= MAX_CORNERS):
                    got = "the end of the file" if count is None else excerpt(count)
                    raise Refusal(at, f"'{NAMES[kind]}' expects a vertex count (an integer from 3 to "
                                      f"{MAX_CORNERS}), got {got}")
                k, i = int(count) * (6 if kind == PP else 3), i + 1
            elif kind == L and i + 3 < len(tokens) and numeric(tokens[i + 3]):
                k = 6
            self._explain_numbers(kind, at, tokens[i:i + k], base + i, k, 0, final or i + k <= stop)
            self.last = (kind, at)
            i += k
        raise Refusal(base, "malformed entities (the reader could not say where): please report")

    def _explain_numbers(self, kind, at, tokens, first, k, done, complete=True):
        need = f"'{NAMES[kind]}' needs {k} numbers ({WHAT[kind]})"
        for j, token in enumerate(tokens):
            if token in KINDS:
                raise Refusal(at, f"{need}, but only {done + j} follow before the entity "
                                  f"{excerpt(token)} on line {{also}}", also=first + j)
            if _numbers([token]) is not None:
                continue
            if not token.translate(None, _NUMBER_CHARS):
                try:
                    float(token)
                except ValueError:
                    pass
                else:
                    raise Refusal(first + j, f"'{NAMES[kind]}': {excerpt(token)} is beyond the float32 "
                                             f"range (+-3.4e38)")
            if token.lstrip(b"+-").lower() in (b"nan", b"inf", b"infinity"):
                raise Refusal(first + j, f"'{NAMES[kind]}': {excerpt(token)} is NaN or infinite; "
                                         f"expected a finite number")
            raise Refusal(first + j, f"'{NAMES[kind]}': bad number {excerpt(token)} (expected a decimal "
                                     f"number such as 1, -0.5 or 2e-3)")
        if len(tokens) < k and complete:
            raise Refusal(at, f"{need}, but the file ends after {done + len(tokens)}: truncated?")
