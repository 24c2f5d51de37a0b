"""Small numpy helpers for Blender matrices (mathutils.Matrix -> float64 arrays)."""
import numpy as np


def to_numpy(matrix) -> np.ndarray:
    """A mathutils 4x4 Matrix as a (4, 4) float64 array (rows as in Blender)."""
    return np.array([tuple(row) for row in matrix], dtype=np.float64)


def transform_points(m: np.ndarray, points: np.ndarray) -> np.ndarray:
    """Apply the affine 4x4 `m` to (N, 3) points; float64 result."""
    return points @ m[:3, :3].T + m[:3, 3]


def transform_normals(m: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """Apply the inverse transpose of `m`'s 3x3 part to (N, 3) normals and renormalise.

    Correct under non-uniform scale; a degenerate matrix leaves normals unscaled.
    """
    linear = m[:3, :3]
    try:
        normal_matrix = np.linalg.inv(linear).T
    except np.linalg.LinAlgError:
        normal_matrix = linear
    n = normals @ normal_matrix.T
    length = np.linalg.norm(n, axis=1, keepdims=True)
    np.divide(n, length, out=n, where=length > 0)
    return n


def axis(m: np.ndarray, column: int) -> np.ndarray:
    """Column `column` of the 3x3 part (the object's local X, Y or Z axis in world space)."""
    return m[:3, column].copy()


def unit(v: np.ndarray) -> np.ndarray:
    length = float(np.linalg.norm(v))
    return v / length if length > 0 else v
