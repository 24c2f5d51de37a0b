"""Small numpy helpers for Blender matrices (mathutils.Matrix -> float64 arrays)."""
import math

import numpy as np

BLOCK = 1 << 15     # vectors transformed per numpy pass over a stack of matrices


def to_numpy(matrix) -> np.ndarray:
    """A mathutils 4x4 Matrix as a (4, 4) float64 array (rows as in Blender)."""
    rows = tuple(matrix)
    return np.array([x for row in rows for x in row], dtype=np.float64).reshape(len(rows), -1)


def finite(values) -> bool:
    """Whether every float of a flat list is finite (their sum first: one check for most lists)."""
    return math.isfinite(sum(values)) or all(map(math.isfinite, values))


def transform_points(m: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply the affine 4x4 `m` to (N, 3) points; float64 result. A stack of
    matrices (K, 4, 4) gives (K, N, 3): the points under each."""
    return _apply(m, points, True)


def _apply(m: np.ndarray, vectors: np.ndarray, translate: bool) -> np.ndarray:
    """m's rows applied to each (N, 3) vector, term by term in the order the core's
    Affine::point / vector sum them (core/src/affine.h), so that an instance the
    core moves (Scene.moved) gets the bits a new export gives it; one pass per
    output axis over all of a stack's matrices (numpy's stacked matmul loops over
    them one small product at a time)."""
    stack = m[None] if m.ndim == 2 else m
    v = vectors.astype(np.float64, copy=False)
    x, y, z = v[:, 0], v[:, 1], v[:, 2]
    out = np.empty((stack.shape[0], v.shape[0], 3))
    step = max(1, BLOCK // max(v.shape[0], 1))     # matrices per pass: temporaries that stay in cache
    for first in range(0, stack.shape[0], step):
        block = stack[first:first + step]
        for r in range(3):
            row = block[:, r, :, None]
            axis = row[:, 0] * x + row[:, 1] * y + row[:, 2] * z
            out[first:first + step, :, r] = axis + row[:, 3] if translate else axis
    return out[0] if m.ndim == 2 else out


def normal_matrix(m: np.ndarray) -> np.ndarray:
    """The 3x3 map of object-space normals to world space: the inverse transpose of `m`'s 3x3
    part, as its cofactor matrix over its determinant, or, where that part is singular (an
    object scaled to zero along an axis), the cofactor matrix alone. The cofactors map a normal
    as they map the cross product of two edges, so a flattened object's normals follow its
    flattened triangles' winding, along the flattened surface's normal (without a mirror, each
    on the side of the surface it came from; a sphere scaled to zero along z becomes a disc
    whose normals point along z). Computed as Scene.moved computes it (core/src/scene_moved.cpp,
    affine.h), so both take the same branch and agree to rounding. A stack (K, 4, 4) gives (K, 3, 3)."""
    r0, r1, r2 = (m[..., i, :3] for i in range(3))
    cof = np.stack([np.cross(r1, r2), np.cross(r2, r0), np.cross(r0, r1)], axis=-2)
    det = np.sum(r0 * cof[..., 0, :], axis=-1)[..., None, None]
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        inverse_transpose = cof / np.where(det != 0, det, 1.0)
    usable = (det != 0) & np.isfinite(det) & np.isfinite(inverse_transpose).all(axis=(-2, -1), keepdims=True)
    return np.where(usable, inverse_transpose, cof)


def transform_normals(m: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Apply normal_matrix(m) to (N, 3) normals and renormalise (normals it maps to zero, of an
    object collapsed onto a line or a point, which no ray can hit, stay zero). A stack of
    matrices (K, 4, 4) gives (K, N, 3)."""
    n = _apply(normal_matrix(m), normals, False)
    return normalized(n)


def normalized(n: np.ndarray) -> np.ndarray:
    """The (..., 3) vectors scaled to unit length in place (zero ones stay zero).
    (Summed per component: a reduction along an axis of 3 is slow in numpy.)"""
    x, y, z = n[..., 0], n[..., 1], n[..., 2]
    length = np.sqrt(x * x + y * y + z * z)[..., None]
    np.divide(n, length, out=n, where=length > 0)
    return n


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """np.cross of (..., 3) vectors, per component (the same products, faster for many short vectors)."""
    ax, ay, az = a[..., 0], a[..., 1], a[..., 2]
    bx, by, bz = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx], axis=-1)


def axis(m: np.ndarray, column: int) -> np.ndarray:
    """Column `column` of the 3x3 part (the object's local X, Y or Z axis in world space)."""
    return m[:3, column].copy()


def unit(v: np.ndarray) -> np.ndarray:
    length = float(np.linalg.norm(v))
    return v / length if length > 0 else v
