"""The package imports, the native module is private, and a Scene reports what it holds."""
import numpy as np
import pytest

import gridwalk as gw
from meshes import icosphere


def test_public_api_is_the_python_package():
    for name in ("Scene", "Material", "Light", "Camera", "RenderSettings", "RenderJob", "render"):
        assert hasattr(gw, name)
    assert gw._core.__name__ == "gridwalk._core"
    assert "_core" not in gw.__all__


def test_scene_counts_and_bounds():
    V, F = icosphere(1, radius=2.0, center=(1, 2, 3))
    sc = gw.Scene(vertices=V, triangles=F, sphere_centers=[[10, 0, 0]], sphere_radii=[0.5])
    assert (sc.num_triangles, sc.num_spheres, sc.num_cylinders) == (len(F), 1, 0)
    lo, hi = sc.bounds
    assert np.allclose(lo, [-1, -0.5, -0.5], atol=1e-5)
    assert np.allclose(hi, [10.5, 4, 5], atol=1e-5)


def test_python_lists_and_float64_are_converted():
    sc = gw.Scene(vertices=[[0, 0, 0], [1, 0, 0], [0, 1, 0]], triangles=[[0, 1, 2]],
                  sphere_centers=np.zeros((1, 3)), sphere_radii=np.array([1.0]))
    assert sc.num_triangles == 1 and sc.num_spheres == 1


def test_settings_reject_unknown_modes():
    with pytest.raises(ValueError, match="aa"):
        gw.RenderSettings(aa="supersample").to_core()
    with pytest.raises(ValueError, match="unknown render settings"):
        gw.RenderSettings().replace(samples=4)
    with pytest.raises(ValueError, match="tile_size"):
        gw.RenderSettings(tile_size=0).to_core()
