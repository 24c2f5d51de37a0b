"""A refining grid of fewer than 32 primitives starts its search at one cell per primitive, not at the
refining density of two: on a mesh's surface most such grids failed at two (too many references) and
paid a full pass over their primitives' cells for nothing (Suzanne PLY: 204 of 272 small grids; its
build 0.83-0.87x the time since). Larger grids still start at two."""
import numpy as np
import pytest

from gridwalk import RenderSettings, Scene


def specks_centres(n, seed=3):
    rng = np.random.default_rng(seed)
    far = np.array([[x, y, z] for x in (0, 10) for y in (0, 10) for z in (0, 10)], float)
    return np.vstack([far, 5 + rng.random((n, 3)) * 0.5])


def specks_scene(n):
    """Eight specks at the corners of a 10-unit box (the root's extent) and a cluster of n specks
    within half a unit of (5, 5, 5): the cluster crowds one root cell, which gets a grid of its own."""
    centres = specks_centres(n)
    corners = np.concatenate([centres, centres + [1e-3, 0, 0], centres + [0, 1e-3, 0]])
    k = len(centres)
    triangles = np.stack([np.arange(k), np.arange(k) + k, np.arange(k) + 2 * k], axis=1)
    return Scene(vertices=corners.astype(np.float32), triangles=triangles.astype(np.int32))


def child_cells(info):
    nx, ny, nz = info["resolution"]
    assert info["grids"] == 2, info   # the root and the cluster's grid
    return info["cells"] - nx * ny * nz


@pytest.mark.parametrize("n", [12, 20, 31])
def test_a_small_refining_grid_gets_about_one_cell_per_primitive(n):
    cells = child_cells(specks_scene(n).grid_info())
    # Two cells per speck would give the cluster's grid 2n cells or more (rounded up per axis).
    assert n * 0.5 <= cells < 1.5 * n, cells


@pytest.mark.parametrize("n", [32, 40])
def test_a_larger_refining_grid_still_starts_at_two_cells_per_primitive(n):
    cells = child_cells(specks_scene(n).grid_info())
    assert cells >= 1.5 * n, cells


@pytest.mark.parametrize("n", [20, 40])
def test_the_specks_are_found_as_brute_force_finds_them(n):
    scene = specks_scene(n)
    rng = np.random.default_rng(n)
    # From anywhere in the box towards points on and around the specks (within 1e-3 of a corner).
    o = (rng.random((20000, 3)) * 12 - 1).astype(np.float32)
    target = specks_centres(n)[rng.integers(0, n + 8, 20000)] + rng.random((20000, 3)) * 1.2e-3
    d = (target - o).astype(np.float32)
    grid = scene.intersect(o, d)
    brute = scene.intersect(o, d, settings=RenderSettings(accel="none"))
    assert (grid.kind > 0).sum() > 2000   # (the rays are aimed: a good share of them hit)
    np.testing.assert_array_equal(grid.prim, brute.prim)
    np.testing.assert_array_equal(grid.t, brute.t)
