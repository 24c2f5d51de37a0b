"""The Blender exporter's assembly of instances (blender_addon/export/assemble.py) transforms
the instances of one mesh together, as stacks of matrices, in chunks. Every instance comes out
as its mesh under its matrix, checked against a plain per-instance reference written here:
mirrored instances with their corners reversed, flat meshes' face normals, smooth meshes'
normals, UVs, colours and each instance's own materials, meshes interleaved. Chunks give the
bits that instances one at a time give; those bits are the ones the core gives an instance it
moves (Scene.moved, the viewport's transform edits); a changed, added or deleted instance
transforms its own chunk again and no other."""
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


def scene_parts(seed=1, count=14):
    """A smooth mesh with UVs and a flat one with colours and two material slots, their
    instances interleaved, every third mirrored, the flat ones with two material lookups."""
    rng = np.random.default_rng(seed)
    t = len(F)
    smooth = MeshData(V.copy(), F.copy(), N.copy(), np.zeros(t, np.int32), uvs=rng.random((t, 3, 2)).astype(np.float32))
    flat = MeshData(V * 0.5, F[:, ::-1].copy(), None, (np.arange(t) % 2).astype(np.int32),
                    colors=rng.random((t, 3, 3)).astype(np.float32))
    one, two, three = (np.array(x, np.int32) for x in ([0], [1, 2], [2, 1]))
    parts = []
    for i in range(count):
        m = matrix(rng, mirror=i % 3 == 1)
        parts.append((("smooth",), smooth, m, one) if i % 2 == 0 or i > 10 else
                     (("flat",), flat, m, two if i < 6 else three))
    return parts


def check_against_reference(out, layout, parts):
    """Each part's slice of the assembled arrays is its mesh under its matrix."""
    assert len(layout) == len(parts)
    covered = np.zeros(len(out["triangles"]), int)
    for (key, data, m, lookup), place in zip(parts, layout):
        order = [0, 2, 1] if np.linalg.det(m[:3, :3]) < 0 else [0, 1, 2]
        first, count = place.triangle_start, place.triangle_count
        assert count == len(data.triangles)
        covered[first:first + count] += 1
        tris = out["triangles"][first:first + count] - place.vertex_start
        world = data.co.astype(np.float64) @ m[:3, :3].T + m[:3, 3]
        if place.flat:
            assert np.array_equal(tris, np.arange(3 * count).reshape(-1, 3))
            corners = world[data.triangles[:, order]]
            got = out["vertices"][place.vertex_start:place.vertex_start + 3 * count].reshape(-1, 3, 3)
            np.testing.assert_allclose(got, corners, rtol=1e-6, atol=1e-5)
            face = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
            length = np.linalg.norm(face, axis=1, keepdims=True)
            face = np.divide(face, length, out=np.zeros_like(face), where=length > 0)
            normals = out["normals"][place.vertex_start:place.vertex_start + 3 * count].reshape(-1, 3, 3)
            np.testing.assert_allclose(normals, np.repeat(face[:, None], 3, axis=1), atol=1e-5)
        else:
            assert np.array_equal(tris, data.triangles[:, order])
            np.testing.assert_allclose(out["vertices"][place.vertex_start:place.vertex_start + len(V)], world,
                                       rtol=1e-6, atol=1e-5)
            n = data.normals @ np.linalg.inv(m[:3, :3])
            np.testing.assert_allclose(out["normals"][place.vertex_start:place.vertex_start + len(V)],
                                       n / np.linalg.norm(n, axis=1, keepdims=True), atol=1e-6)
        assert np.array_equal(out["triangle_materials"][first:first + count], lookup[data.material_slot])
        uvs = data.uvs[:, order] if data.uvs is not None else np.zeros((count, 3, 2))
        colors = data.colors[:, order] if data.colors is not None else np.ones((count, 3, 3))
        assert np.array_equal(out["uvs"][first:first + count], uvs)
        assert np.array_equal(out["colors"][first:first + count], colors)
    assert (covered == 1).all()                           # every triangle is one instance's


def test_every_instance_is_its_mesh_under_its_matrix(monkeypatch):
    monkeypatch.setattr(asm, "CHUNK_INSTANCES", 1 << 30)            # no cut by matrix
    parts = scene_parts()
    out, layout = asm.assemble_triangles(parts, MeshCache())
    assert len(asm.chunks(parts)) == 2                   # the two meshes' instances, each in one chunk
    assert set(out) == {"vertices", "triangles", "normals", "triangle_materials", "uvs", "colors"}
    check_against_reference(out, layout, parts)


def test_chunks_give_the_bits_of_instances_one_at_a_time(monkeypatch):
    parts = scene_parts()
    chunked, chunked_layout = asm.assemble_triangles(parts, MeshCache())
    assert max(len(c) for c in asm.chunks(parts)) > 4
    monkeypatch.setattr(asm, "CHUNK_VERTICES", 1)                     # every instance a chunk of its own
    assert len(asm.chunks(parts)) == len(parts)
    single, single_layout = asm.assemble_triangles(parts, MeshCache())
    assert [vars(p) for p in single_layout] == [vars(p) for p in chunked_layout]
    for name in single:
        assert single[name].dtype == chunked[name].dtype and np.array_equal(single[name], chunked[name]), name


@pytest.mark.parametrize("index", [0, 1, 3, 4])     # smooth (plain, mirrored), flat (plain, mirrored)
def test_an_instance_moved_in_the_core_has_the_bits_a_new_assembly_gives(index):
    parts = scene_parts()
    kw, layout = asm.assemble_triangles(parts, MeshCache())
    scene = gw.Scene(vertices=kw["vertices"], triangles=kw["triangles"], normals=kw["normals"])
    key, data, old, lookup = parts[index]
    mirrored = np.linalg.det(old[:3, :3]) < 0
    assert mirrored == (index % 3 == 1)
    new = matrix(np.random.default_rng(10 + index), mirror=mirrored)
    place = layout[index]
    positions = data.co
    if place.flat:                                       # its corners, in world-space order
        positions = data.co[data.triangles[:, [0, 2, 1] if mirrored else [0, 1, 2]].reshape(-1)]
    move = gw.InstanceMove(place.vertex_start, place.triangle_start, place.triangle_count, positions, new,
                           normals=None if place.flat else data.normals, flat=place.flat, previous_matrix=old)
    moved = scene.moved([move]).geometry()
    parts[index] = (key, data, new, lookup)
    fresh, _ = asm.assemble_triangles(parts, MeshCache())
    for name in ("vertices", "triangles", "normals"):
        assert np.array_equal(moved[name], fresh[name]), name


def test_a_changed_added_or_deleted_instance_transforms_its_own_chunk_again(monkeypatch):
    monkeypatch.setattr(asm, "CHUNK_INSTANCES", 8)
    parts = scene_parts(count=400)
    chunks = asm.chunks(parts)
    assert len(chunks) > 40                               # about 400 / 8 (two meshes)

    def transformed(new_parts):
        """Instances transformed to assemble new_parts after parts (the viewport's next export)."""
        cache = MeshCache()
        asm.assemble_triangles(parts, cache)
        before = cache.transforms
        cache.prune({p[0] for p in new_parts})
        out, layout = asm.assemble_triangles(new_parts, cache)
        check_against_reference(out, layout, new_parts)
        return cache.transforms - before

    assert transformed(parts) == 0                        # every chunk reused
    # a chunk of the smooth mesh's, well inside its run, and the next one of the same mesh
    k = next(n for n, c in enumerate(chunks) if len(c) > 1 and c[0] > 100 and parts[c[0]][0] == ("smooth",)
             and parts[chunks[n + 1][0]][0] == ("smooth",))
    j, near = chunks[k][0], len(chunks[k]) + len(chunks[k + 1]) + 1
    key, data, m, lookup = parts[j]
    shifted = m.copy()
    shifted[:3, 3] += 1.0
    changed = parts[:j] + [(key, data, shifted, lookup)] + parts[j + 1:]
    deleted = parts[:j] + parts[j + 1:]
    added = parts[:j + 1] + [(key, data, shifted, lookup)] + parts[j + 1:]
    for edit in (changed, deleted, added):
        assert 0 < transformed(edit) <= near              # its chunk (and the next, if the cut moved)
    assert len(parts) > 10 * near


def test_a_mesh_larger_than_a_chunk_is_cut_by_size(monkeypatch):
    parts = scene_parts()
    monkeypatch.setattr(asm, "CHUNK_INSTANCES", 1 << 30)             # no cut by matrix
    monkeypatch.setattr(asm, "CHUNK_VERTICES", 2 * len(V))
    assert all(len(c) <= 2 for c in asm.chunks(parts))
    assert sorted(i for c in asm.chunks(parts) for i in c) == list(range(len(parts)))
    monkeypatch.setattr(asm, "CHUNK_VERTICES", 1 << 18)
    assert [len(c) for c in asm.chunks(parts)] == [9, 5]              # the smooth mesh's, then the flat one's
