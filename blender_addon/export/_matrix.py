"""Small numpy helpers for Blender matrices (mathutils.Matrix -> float64 arrays)."""
import numpy as np


def to_numpy(matrix) -> np.ndarray:
    """A mathutils 4x4 Matrix as a (4, 4) float64 array (rows as in Blender)."""
    return np.array([tuple(row) for row in matrix], dtype=np.float64)


def transform_points(m: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply the affine 4x4 `m` to (N, 3) points; float64 result."""
    return points @ m[:3, :3].T + m[:3, 3]


def normal_matrix(m: np.ndarray) -> np.ndarray:
    """The 3x3 map of object-space normals to world space: the inverse transpose of `m`'s 3x3
    part, as its cofactor matrix over its determinant, or, where that part is singular (an
    object scaled to zero along an axis), the cofactor matrix alone. The cofactors map a normal
    as they map the cross product of two edges, so a flattened object's normals follow its
    flattened triangles' winding, along the flattened surface's normal (without a mirror, each
    on the side of the surface it came from; a sphere scaled to zero along z becomes a disc
    whose normals point along z). Computed as Scene.moved computes it (core/src/scene_moved.cpp,
    affine.h), so both take the same branch and agree to rounding."""
    r0, r1, r2 = m[:3, :3]
    cof = np.array([np.cross(r1, r2), np.cross(r2, r0), np.cross(r0, r1)])
    det = float(r0 @ cof[0])
    if det != 0 and np.isfinite(det):
        with np.errstate(over="ignore", invalid="ignore"):
            inverse_transpose = cof / det
        if np.isfinite(inverse_transpose).all():
            return inverse_transpose
    return cof


def transform_normals(m: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Apply normal_matrix(m) to (N, 3) normals and renormalise (normals it maps to zero, of an
    object collapsed onto a line or a point, which no ray can hit, stay zero)."""
    n = normals @ normal_matrix(m).T
    length = np.linalg.norm(n, axis=1, keepdims=True)
    np.divide(n, length, out=n, where=length > 0)
    return n


def axis(m: np.ndarray, column: int) -> np.ndarray:
    """Column `column` of the 3x3 part (the object's local X, Y or Z axis in world space)."""
    return m[:3, column].copy()


def unit(v: np.ndarray) -> np.ndarray:
    length = float(np.linalg.norm(v))
    return v / length if length > 0 else v
