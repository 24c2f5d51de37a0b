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
    part, or, where that part is singular (an object scaled to zero along an axis), its cofactor
    matrix, which is the inverse transpose times the determinant where both exist and keeps
    mapping normals to the flattened surface's normal where the inverse does not (a sphere
    scaled to zero along z becomes a disc whose normals point along z)."""
    linear = m[:3, :3]
    try:
        return np.linalg.inv(linear).T
    except np.linalg.LinAlgError:
        r0, r1, r2 = linear
        return np.array([np.cross(r1, r2), np.cross(r2, r0), np.cross(r0, r1)])


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
