"""Geometry export: transforms, modifiers, collection instances, hidden objects, spheres."""
import numpy as np


def _as_set(points, decimals=4):
    return {tuple(np.round(p, decimals)) for p in np.asarray(points, dtype=np.float64)}


def test_cube_triangles_are_in_world_space(export):
    out = export("cube")
    assert out.triangles.shape == (12, 3)
    assert out.vertices.dtype == np.float32 and out.triangles.dtype == np.int32
    # every exported vertex is a transformed cube corner, and all corners are used
    assert _as_set(out.vertices[out.triangles.reshape(-1)]) == _as_set(out.expected["corners"])
    assert out.has_normals is False          # flat cube: geometric normals suffice
    assert np.all(out.triangle_materials == 0)


def test_hidden_for_render_objects_are_skipped(export):
    out = export("cube")
    assert len(out.triangles) == out.expected["triangles"]   # HiddenCube is not there


def test_modifiers_are_applied_and_smooth_normals_exported(export):
    out = export("suzanne", levels=2)
    assert len(out.triangles) == out.expected["triangles"]
    assert len(out.triangles) > 20 * out.expected["base_faces"]
    assert out.has_normals
    n = out.normals
    assert n.shape == out.vertices.shape
    np.testing.assert_allclose(np.linalg.norm(n, axis=1), 1.0, atol=1e-4)
    # smooth normals agree with the faces they shade
    tri = out.vertices[out.triangles]
    face_n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    face_n /= np.linalg.norm(face_n, axis=1, keepdims=True) + 1e-30
    corner_n = n[out.triangles].mean(axis=1)
    assert np.mean(np.sum(face_n * corner_n, axis=1) > 0.5) > 0.97


def test_both_instances_of_a_collection_are_exported(export):
    out = export("instances")
    assert len(out.triangles) == out.expected["triangles"]
    used = out.vertices[out.triangles.reshape(-1)]
    for corners in out.expected["instances"]:
        corners = np.asarray(corners)
        near = np.linalg.norm(used[:, None, :] - corners[None, :, :], axis=2).min(axis=0)
        assert near.max() < 1e-4, "an instance's corners are missing"
    centres = np.sort(used[:, 0])
    assert centres[0] < -2.0 and centres[-1] > 2.0


def test_render_as_sphere_gives_one_analytic_sphere(export):
    out = export("sphere")
    np.testing.assert_allclose(out.sphere_centers, [out.expected["center"]], atol=1e-5)
    np.testing.assert_allclose(out.sphere_radii, [out.expected["radius"]], rtol=1e-5)
    assert len(out.triangles) == 12          # only the cube stays a mesh
