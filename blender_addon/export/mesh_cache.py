"""Exported meshes kept between exports (the viewport's incremental updates).

A mesh is read once per evaluated mesh datablock: objects sharing a mesh
(linked duplicates without modifiers) share the evaluated mesh, and so one
entry; an object with modifiers has its own. Entries are keyed by the
evaluated datablock's address and name plus a change counter: a geometry
update of an object (depsgraph.updates: is_updated_geometry), or of a mesh
datablock, bumps the counter of every address that object or mesh used, so
the next lookup reads it again. (An address freed and reused by a new mesh
belongs to an object that was just evaluated, so it is bumped too.)

Each chunk of instances' world-space arrays (assemble.py: a few dozen
instances of one mesh) is cached as well, keyed by its mesh entry and its
matrices, for the exports that assemble the scene again. The
viewport's transform edits assemble nothing: moves.instance_moves hands the
moved instances' object-space arrays (and, for flat meshes, their corners,
kept here) to the core.
"""
from __future__ import annotations

import numpy as np

from .assemble import world_chunk
from .meshes import read_object_mesh


class MeshCache:
    def __init__(self):
        self.entries = {}        # (address, name, counter) -> MeshData or None
        self.counter = {}        # address -> change counter
        self.names = {}          # address -> datablock name (for mesh updates)
        self.used_by = {}        # object name -> addresses it used
        self.world = {}          # (entry key, matrices' bytes, flat corners) -> world-space arrays
        self.world_used = set()  # the world keys the current export used
        self.reads = 0           # meshes read since the last reset_stats()
        self.transforms = 0      # instances transformed since the last reset_stats()
        self.images = {}         # image signature -> (gridwalk.Image, problem): textures.TextureTable
        self.object_corners = {}  # entry key -> a flat mesh's corners in object space (moves.instance_moves)
    def reset_stats(self):
        self.reads = self.transforms = 0

    def clear(self):
        self.__init__()

    def _bump(self, address):
        self.counter[address] = self.counter.get(address, 0) + 1

    def invalidate(self, updates) -> bool:
        """Forget the meshes that depsgraph `updates` changed; True if any geometry changed."""
        changed = False
        for update in updates:
            if not update.is_updated_geometry:
                continue
            changed = True
            id_ = update.id
            name = getattr(getattr(id_, "original", id_), "name_full", id_.name)
            for address in self.used_by.get(name, ()):
                self._bump(address)
            data = getattr(id_, "data", None)
            if data is not None and hasattr(data, "as_pointer"):
                self._bump(data.as_pointer())
            for address, data_name in self.names.items():   # a mesh datablock itself
                if data_name == name:
                    self._bump(address)
        return changed

    def key(self, obj, layers=(None, None)):
        address = obj.data.as_pointer() if obj.data is not None else id(obj)
        name = obj.data.name_full if obj.data is not None else obj.name_full
        return address, name, self.counter.get(address, 0), tuple(layers)

    def mesh(self, obj, layers=(None, None)):
        """(key, MeshData or None) of an evaluated object, read only when not cached;
        layers: the (uv, colour) layers its materials need (meshes.read_mesh)."""
        key = self.key(obj, layers)
        self.names[key[0]] = key[1]
        self.used_by.setdefault(obj.original.name_full, set()).add(key[0])
        if key not in self.entries:
            self.entries[key] = read_object_mesh(obj, layers)
            self.reads += 1
        return key, self.entries[key]

    def world_chunk(self, key, data, matrices, flat_corners):
        """World-space (vertices, triangles, normals, mirror flags) of a chunk of
        instances of one mesh (assemble.world_chunk), cached by their matrices."""
        wkey = (key, matrices.tobytes(), flat_corners)
        self.world_used.add(wkey)
        chunk = self.world.get(wkey)
        if chunk is None:
            chunk = self.world[wkey] = world_chunk(data, matrices, flat_corners)
            self.transforms += len(matrices)
        return chunk

    def corners(self, key, data):
        """A flat mesh's unshared corners in object space, (3T, 3) float32 (what a
        move of one of its instances transforms), kept while the entry is."""
        corners = self.object_corners.get(key)
        if corners is None:
            corners = self.object_corners[key] = np.ascontiguousarray(data.co[data.triangles.reshape(-1)])
        return corners

    def prune(self, used_keys):
        """Drop what the latest export did not use (deleted or changed objects)."""
        self.entries = {k: v for k, v in self.entries.items() if k in used_keys}
        self.object_corners = {k: v for k, v in self.object_corners.items() if k in used_keys}
        self.world = {k: v for k, v in self.world.items() if k in self.world_used}
        self.world_used = set()
        live = {k[0] for k in used_keys}
        self.names = {a: n for a, n in self.names.items() if a in live}
        self.used_by = {o: {a for a in s if a in live} for o, s in self.used_by.items()}
