"""The Scene's input checks and its box hold for large arrays, where the core checks them in
one vectorised pass first (core/src/scene.cpp: check_finite, check_ids, bounds_of) and looks
for the offending entry only when there is one: the first bad entry deep inside a large array
is still the one named, at every position of a vector's lanes and in the scalar tail; and the
box is the exact box of the triangles' corners (not of unused vertices)."""
import numpy as np
import pytest

import gridwalk as gw

N = 10_007   # (not a multiple of any vector width: the last entries are in the loop's tail)


def _mesh(seed=0):
    rng = np.random.default_rng(seed)
    vertices = rng.uniform(-5.0, 5.0, (N, 3)).astype(np.float32)
    triangles = rng.integers(0, N, (N, 3)).astype(np.int32)
    return vertices, triangles


@pytest.mark.parametrize("at", [0, 1, 2, 3, 4, 5, 6, 7, 4_321, N - 2, N - 1])
@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_a_non_finite_vertex_anywhere_is_named(at, value):
    vertices, triangles = _mesh()
    vertices[at, at % 3] = value
    with pytest.raises(ValueError, match=rf"vertices\[{at}\] has a non-finite value"):
        gw.Scene(vertices=vertices, triangles=triangles)


@pytest.mark.parametrize("at", [0, 5, 3_333, N - 1])
@pytest.mark.parametrize("value", [-1, N, N + 1, np.iinfo(np.int32).max, np.iinfo(np.int32).min])
def test_an_out_of_range_corner_anywhere_is_named(at, value):
    vertices, triangles = _mesh()
    triangles[at, (at + 1) % 3] = value
    with pytest.raises(ValueError, match=rf"triangles\[{at}\] = {value} is out of range: vertices has {N} entries"):
        gw.Scene(vertices=vertices, triangles=triangles)


def test_the_first_of_several_bad_entries_is_named():
    vertices, triangles = _mesh()
    triangles[9_000, 0] = -3
    triangles[700, 2] = N
    with pytest.raises(ValueError, match=rf"triangles\[700\] = {N} is out of range"):
        gw.Scene(vertices=vertices, triangles=triangles)


def test_every_corner_in_range_and_finite_builds():
    vertices, triangles = _mesh()
    triangles[0, 0], triangles[1, 1] = 0, N - 1          # (the ends of the range are in it)
    scene = gw.Scene(vertices=vertices, triangles=triangles)
    assert scene.num_primitives == N


@pytest.mark.parametrize("seed", range(4))
def test_the_box_is_the_exact_box_of_the_corners(seed):
    vertices, triangles = _mesh(seed)
    used = np.unique(triangles)
    unused = np.setdiff1d(np.arange(N), used)
    if len(unused):
        vertices[unused] = 1000.0                         # far away, and in no triangle
    for count in (1, 2, 3, 4, 5, N):                      # (the vector pass's tail alone, and the whole)
        lo, hi = gw.Scene(vertices=vertices, triangles=triangles[:count]).bounds
        corners = vertices[triangles[:count]].reshape(-1, 3)
        np.testing.assert_array_equal(np.asarray(lo, np.float32), corners.min(axis=0))
        np.testing.assert_array_equal(np.asarray(hi, np.float32), corners.max(axis=0))
