"""The Blender exporter's assembly of instances (blender_addon/export/assemble.py) transforms
consecutive instances of one mesh together, as one stack of matrices. Chunks give the bits
that instances one at a time give, mirrored instances among them, flat meshes' face normals,
smooth meshes' normals, UVs, colours and materials included; those bits are the ones the core
gives an instance it moves (Scene.moved, the viewport's transform edits); a changed matrix
transforms its chunk again and nothing else."""
import numpy as np
import pytest

import gridwalk as gw
from blender_addon.export import assemble as asm
from blender_addon.export.mesh_cache import MeshCache
from blender_addon.export.meshes import MeshData
from meshes import uv_sphere

V, F = uv_sphere(6, 10, radius=1.0, center=np.zeros(3), seed=2)
V = V.astype(np.float32)
N = (V / np.linalg.norm(V, axis=1, keepdims=True)).astype(np.float32)


def matrix(rng, mirror=False):
    q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    q[:, 0] *= np.sign(np.linalg.det(q))                   # a rotation
    m = np.eye(4)
    m[:3, :3] = q * rng.uniform(0.3, 3.0, 3) * (np.array([-1, 1, 1]) if mirror else 1)
    m[:3, 3] = rng.normal(0, 20, 3)
    return m


def meshes(rng):
    """A smooth mesh with UVs, a flat one with colours and two material slots."""
    t = len(F)
    smooth = MeshData(V.copy(), F.copy(), N.copy(), np.zeros(t, np.int32),
                      uvs=rng.random((t, 3, 2)).astype(np.float32))
    flat = MeshData(V * 0.5, F[:, ::-1].copy(), None, (np.arange(t) % 2).astype(np.int32),
                    colors=rng.random((t, 3, 3)).astype(np.float32))
    return smooth, flat


def scene_parts(seed=1):
    """Runs of instances of two meshes: mirrored ones mixed in, two material lookups in one run."""
    rng = np.random.default_rng(seed)
    smooth, flat = meshes(rng)
    one, two, three = (np.array(x, np.int32) for x in ([0], [1, 2], [2, 1]))
    parts = [(("smooth",), smooth, matrix(rng, mirror=i % 3 == 1), one) for i in range(7)]
    parts += [(("flat",), flat, matrix(rng, mirror=i in (2, 3)), two if i < 4 else three) for i in range(6)]
    parts += [(("smooth",), smooth, matrix(rng), one)]
    return parts


def assembled(parts, chunk_vertices, monkeypatch):
    monkeypatch.setattr(asm, "CHUNK_VERTICES", chunk_vertices)
    return asm.assemble_triangles(parts, MeshCache())


def test_chunks_give_the_bits_of_instances_one_at_a_time(monkeypatch):
    parts = scene_parts()
    single, single_layout = assembled(parts, 1, monkeypatch)            # every chunk one instance
    chunked, chunked_layout = assembled(parts, 1 << 18, monkeypatch)    # three chunks
    assert len(asm.chunks(parts)) == 3
    assert set(single) == set(chunked) == {"vertices", "triangles", "normals", "triangle_materials", "uvs", "colors"}
    for name in single:
        assert single[name].dtype == chunked[name].dtype and np.array_equal(single[name], chunked[name]), name
    assert [vars(p) for p in single_layout] == [vars(p) for p in chunked_layout]
    # and what one instance should be: its mesh under its matrix, corners reversed where it mirrors
    key, data, m, lookup = parts[1]                                      # a mirrored smooth instance
    place = chunked_layout[1]
    start, count = place.vertex_start, len(V)
    np.testing.assert_allclose(chunked["vertices"][start:start + count], V @ m[:3, :3].T + m[:3, 3], rtol=1e-6,
                               atol=1e-5)
    tris = chunked["triangles"][place.triangle_start:place.triangle_start + place.triangle_count]
    assert np.array_equal(tris, F[:, [0, 2, 1]] + start)
    assert np.array_equal(chunked["uvs"][place.triangle_start], data.uvs[0][[0, 2, 1]])
    n = N @ np.linalg.inv(m[:3, :3])
    np.testing.assert_allclose(chunked["normals"][start:start + count], n / np.linalg.norm(n, axis=1)[:, None],
                               atol=1e-6)
    # the flat mesh's instances: unshared corners with face normals, each with its own lookup
    flat_place = chunked_layout[7]
    assert flat_place.flat and flat_place.triangle_count == len(F)
    first = flat_place.triangle_start
    assert np.array_equal(chunked["triangle_materials"][first:first + 4], [1, 2, 1, 2])
    last = chunked_layout[12].triangle_start
    assert np.array_equal(chunked["triangle_materials"][last:last + 4], [2, 1, 2, 1])
    assert np.array_equal(chunked["colors"][first], parts[7][1].colors[0])       # not mirrored: as given
    corners = chunked["vertices"][chunked["triangles"][first]].astype(np.float64)
    face = np.cross(corners[1] - corners[0], corners[2] - corners[0])
    assert np.allclose(chunked["normals"][chunked["triangles"][first]], face / np.linalg.norm(face), atol=1e-5)


@pytest.mark.parametrize("index", [1, 3, 9, 10])     # smooth (mirrored, plain), flat (plain, mirrored)
def test_an_instance_moved_in_the_core_has_the_bits_a_new_assembly_gives(index, monkeypatch):
    parts = scene_parts()
    kw, layout = asm.assemble_triangles(parts, MeshCache())
    scene = gw.Scene(vertices=kw["vertices"], triangles=kw["triangles"], normals=kw["normals"])
    rng = np.random.default_rng(10 + index)
    key, data, old, lookup = parts[index]
    new = matrix(rng, mirror=asm.mirrors(old))
    place = layout[index]
    positions = data.co[data.triangles.reshape(-1)] if place.flat else data.co
    positions = positions.reshape(-1, 3, 3)[:, asm.corner_order(new)].reshape(-1, 3) if place.flat else positions
    move = gw.InstanceMove(place.vertex_start, place.triangle_start, place.triangle_count, positions, new,
                           normals=None if place.flat else data.normals, flat=place.flat, previous_matrix=old)
    moved = scene.moved([move]).geometry()
    parts[index] = (key, data, new, lookup)
    fresh, _ = asm.assemble_triangles(parts, MeshCache())
    for name in ("vertices", "triangles", "normals"):
        assert np.array_equal(moved[name], fresh[name]), name


def test_a_changed_matrix_transforms_its_chunk_again_and_nothing_else():
    parts = scene_parts()
    cache = MeshCache()
    first, _ = asm.assemble_triangles(parts, cache)
    assert cache.transforms == len(parts)
    cache.prune({p[0] for p in parts})
    again, _ = asm.assemble_triangles(parts, cache)
    assert cache.transforms == len(parts)                               # every chunk reused
    assert all(np.array_equal(first[k], again[k]) for k in ("vertices", "triangles", "normals"))
    key, data, m, lookup = parts[9]
    shifted = m.copy()
    shifted[:3, 3] += 1.0
    parts[9] = (key, data, shifted, lookup)
    moved, layout = asm.assemble_triangles(parts, cache)
    assert cache.transforms == len(parts) + 6                            # the flat mesh's chunk of six
    place = layout[9]
    span = slice(place.vertex_start, place.vertex_start + 3 * place.triangle_count)
    np.testing.assert_allclose(moved["vertices"][span], first["vertices"][span] + 1.0, atol=1e-4)
    rest = np.ones(len(first["vertices"]), bool)
    rest[span] = False
    assert np.array_equal(moved["vertices"][rest], first["vertices"][rest])


def test_a_mesh_larger_than_a_chunk_is_a_chunk_of_its_own(monkeypatch):
    parts = scene_parts()
    monkeypatch.setattr(asm, "CHUNK_VERTICES", 2 * len(V))
    spans = asm.chunks(parts)
    assert all(end - first <= 2 for first, end in spans) and spans[0] == (0, 2)
    assert sum(end - first for first, end in spans) == len(parts)
    monkeypatch.setattr(asm, "CHUNK_VERTICES", len(V) - 1)
    assert asm.chunks(parts) == [(i, i + 1) for i in range(len(parts))]
