"""Geometry Nodes instances read in bulk: a carrier's matrices from its instances component.

A Geometry Nodes carrier that scatters a mesh lists each copy in
depsgraph.object_instances, and reading a copy there (its object, what
decides its plan, its matrix) costs about 8 microseconds of Python: 0.72 s for
the 90,000 copies of core/bench/blender_bench.py, where the depsgraph's own
listing of them takes 0.07 s. Blender 4.3 and later give the carrier's
evaluated geometry (Object.evaluated_geometry()), whose instances component
holds every copy's transform and reference in two arrays that foreach_get
reads at once (2 ms for 45,000 copies).

So a carrier's copies are taken here instead of one by one (MeshCollector.add_instance):
  * the copies are listed in the depsgraph in the order of the component's points,
    one each; the first copy of each reference is read as before (its object and
    instance_key make its InstancePlan, the same plan the one-by-one path makes) and
    every copy after it costs the check of its instancer's address;
  * a carrier is read so (from MIN_POINTS copies; of any size where a material reads instance
    attributes, which come only this way) only where each of its references is one mesh copy (a mesh
    object, or Object Info's As Instance of one: one_mesh_copy) and it has no point
    cloud, curves or volume of its own (each listed as an instance too);
  * every SAMPLE-th copy, the last, and the first of each reference, is checked: its
    instance_key must be its reference's, or one whose plan exports alike (same_outcome:
    a geometry set's copies come through temporary objects that take turns), and its
    matrix_world the carrier's matrix times its transform (to float32 rounding);
  * where a copy's plan reads a value of its own (Object Info's Random: the copy's
    random_id), it is read with the copy; a Geometry Nodes instance attribute an
    Instancer attribute reads comes from the instances component with the matrices
    (instance_values.py);
  * when the depsgraph has listed them all, the copies go to MeshCollector as one
    block of matrices (add_block), in their order.
Whatever does not check out (a copy count other than the points', a reference that
becomes several instances or something other than a mesh with finite vertices, a
plan with particle hair, a key or matrix that differs) sends the carrier back to the
one-by-one path: its copies are read again from the depsgraph, by read_again().
Blender before 4.3 has no evaluated_geometry: every copy is read one by one there.
"""
from __future__ import annotations

import numpy as np

from ._matrix import to_numpy
from .instance_values import row_value
from .meshes import instance_key

MIN_POINTS = 64      # smaller carriers are read one by one (the bulk path's set-up, about 0.4 ms a carrier, outweighs
                     # what it saves), unless a material reads instance attributes, which come only in bulk
SAMPLE = 1024        # every SAMPLE-th copy is checked against the depsgraph's own
MISSING = object()
REALIZED = ("pointcloud", "curves", "volume", "grease_pencil")   # a geometry set's components besides mesh and instances


def _instance_points(geometry):
    points = geometry.instances_pointcloud()
    return 0 if points is None else len(points.points)


def one_mesh_copy(reference, depth: int = 0) -> bool:
    """Whether an instance reference (an Object, a Collection, a geometry set or None) becomes
    exactly one mesh instance in depsgraph.object_instances: a mesh object that instances
    nothing itself, a geometry set of a mesh alone, or a geometry set of nothing but one
    instance of such a reference (Object Info's As Instance gives that)."""
    if reference is None or depth > 4:
        return False
    if hasattr(reference, "instances_pointcloud"):              # a geometry set
        if any(getattr(reference, name, None) is not None for name in REALIZED):
            return False
        count = _instance_points(reference)
        if reference.mesh is not None:
            return count == 0
        return count == 1 and one_mesh_copy(reference.instance_references()[0], depth + 1)
    if getattr(reference, "type", None) != "MESH":             # (a collection has no type)
        return False
    if getattr(reference, "instance_type", "NONE") != "NONE" or len(getattr(reference, "particle_systems", ())):
        return False
    evaluated = getattr(reference, "evaluated_geometry", None)
    return evaluated is None or _instance_points(evaluated()) == 0


def carrier_transforms(carrier, min_points=MIN_POINTS):
    """((N, 4, 4) float64 transforms relative to the carrier, (N,) reference indices,
    reference count) of an evaluated object's Geometry Nodes instances, or None where
    it has fewer than min_points, a reference that is not one mesh copy (one_mesh_copy),
    components the depsgraph lists as instances of their own (point clouds, curves,
    volumes), or where this Blender cannot tell."""
    evaluated = getattr(carrier, "evaluated_geometry", None)
    if evaluated is None:
        return None
    try:
        geometry = evaluated()
        points = geometry.instances_pointcloud()
        if points is None or len(points.points) < min_points:
            return None
        if any(getattr(geometry, name, None) is not None for name in REALIZED):
            return None
        references = geometry.instance_references()
        if not references or not all(one_mesh_copy(r) for r in references):
            return None
        count = len(references)
        n = len(points.points)
        transforms = np.empty(16 * n, np.float32)
        points.attributes["instance_transform"].data.foreach_get("value", transforms)
        indices = np.empty(n, np.int32)
        points.attributes[".reference_index"].data.foreach_get("value", indices)
    except (AttributeError, KeyError, RuntimeError, TypeError, IndexError):
        return None
    if indices.min() < 0 or indices.max() >= count:
        return None
    # (stored column by column, as Blender's float4x4)
    return transforms.reshape(n, 4, 4).transpose(0, 2, 1).astype(np.float64), indices, count


def same_outcome(plan, other) -> bool:
    """Whether instances of two plans export alike: shown or not, the same mesh entry
    (MeshCache key), materials, flags and Cryptomatte names, neither with particle hair."""
    if plan.renders != other.renders or plan.hair or other.hair:
        return False
    if not plan.renders:
        return True
    return (plan.kind == other.kind == "mesh" and plan.flags == other.flags and plan.names == other.names
            and plan.known[2] == other.known[2] and np.array_equal(plan.known[1], other.known[1]))


def copy_values(carrier, references, plans, own=None):
    """(N, 3) each copy's own value, NaN where its plan's applies (instance_values.py): `own`
    (those read with each copy: CarrierRun.own), and the Geometry Nodes instance attributes its
    plan's layer reads (instance_column); None for none."""
    layers = {}          # layer -> the references whose plans read it
    for r, plan in enumerate(plans):
        if plan is not None and plan.info is not None and plan.info.reads_instances:
            layers.setdefault(plan.info, []).append(r)
    if not layers:
        return own
    references = np.asarray(references)
    values = np.full((len(references), 3), np.nan) if own is None else own
    try:
        geometry = carrier.evaluated_geometry()      # (kept while its points are read)
        points = geometry.instances_pointcloud()
        for layer, which in layers.items():
            column = layer.instance_column(points)   # (once per layer, however many references read it)
            if column is not None and len(column) == len(references):
                rows = np.isin(references, which)
                values[rows] = column[rows]
    except (AttributeError, RuntimeError, TypeError):
        pass
    return values if own is not None or not np.isnan(values).all() else None


class CarrierRun:
    """One carrier's copies as the depsgraph lists them (CarrierInstances.take)."""

    def __init__(self, carrier, world, transforms, references, count):
        self.carrier = carrier                     # the evaluated carrier object
        self.world = world @ transforms            # (N, 4, 4) each copy's world matrix
        self.references = references.tolist()
        self.plans = [None] * count                # InstancePlan per reference, from its first copy
        self.keys = [None] * count                 # instance_key per reference
        self.seqs = []                             # each copy's instance number (MeshCollector.next_seq)
        self.own = None                            # (N, 3) the copies' own values (Random, Location), or None
        self.failed = False

    def _read_own(self, k, plan, inst):
        """Copy k's own value where its plan's layer is per instance (instance_values.row_value,
        at the copy's matrix, known already)."""
        if plan.info is None or not plan.info.per_instance:
            return
        value = row_value(plan, inst, None, self.world[k, :3, 3])   # (an instance: its random_id, not its name)
        if self.own is None:
            self.own = np.full((len(self.references), 3), np.nan)
        self.own[k] = value

    def take(self, inst, meshes):
        k = len(self.seqs)
        self.seqs.append(meshes.next_seq())
        if self.failed:
            return
        if k >= len(self.references):
            self.failed = True
            return
        r = self.references[k]
        plan = self.plans[r]
        if plan is not None:
            self._read_own(k, plan, inst)
        if plan is not None and k % SAMPLE and k != len(self.references) - 1:
            return
        obj = inst.object
        key = instance_key(inst, obj)
        if plan is None:
            if obj.type != "MESH":     # (lights, curves, point clouds...: their own paths)
                self.failed = True
                return
            plan = meshes.plan_of(inst, obj, key)
            if plan.hair or (plan.renders and not (plan.kind == "mesh" and plan.known[3].finite)):
                self.failed = True
                return
            self.plans[r], self.keys[r] = plan, key
            self._read_own(k, plan, inst)
        elif key != self.keys[r] and not same_outcome(meshes.plan_of(inst, obj, key), plan):
            # (copies of a geometry set come through temporary objects, which take turns:
            # another key, the same mesh, materials, flags and names)
            self.failed = True
            return
        matrix = to_numpy(inst.matrix_world)
        scale = max(float(np.abs(matrix).max()), 1.0)
        if not np.allclose(matrix, self.world[k], rtol=1e-5, atol=1e-6 * scale, equal_nan=True):
            self.failed = True


class CarrierInstances:
    """The Geometry Nodes carriers whose copies are read in bulk in one export."""

    def __init__(self, meshes, every_carrier: bool = False):
        """every_carrier: read carriers of any size in bulk (a material reads instance attributes:
        textures.reads_instance_attributes)."""
        self.meshes = meshes
        self.min_points = 1 if every_carrier else MIN_POINTS
        self.runs = {}      # carrier address -> CarrierRun, or None (its copies are read one by one)
        self.copies = 0     # after finish(): the copies read in bulk
        self._again = {}    # carrier address -> copies met again on the second pass (read_again)

    def take(self, inst) -> bool:
        """Whether the depsgraph instance `inst` is a carrier's copy, taken here (else the
        caller reads it as before)."""
        if not inst.is_instance:
            return False
        parent = inst.parent
        if parent is None:
            return False
        address = parent.as_pointer()
        run = self.runs.get(address, MISSING)
        if run is MISSING:
            found = carrier_transforms(parent, self.min_points)
            run = self.runs[address] = None if found is None else CarrierRun(parent, to_numpy(parent.matrix_world),
                                                                            *found)
        if run is None:
            return False
        run.take(inst, self.meshes)
        return True

    def finish(self) -> set:
        """Hands each run whose copies checked out to MeshCollector as one block; returns
        the addresses of the carriers whose copies must be read again, one by one."""
        again = set()
        for address, run in self.runs.items():
            if run is None:
                continue
            if run.failed or len(run.seqs) != len(run.references):
                again.add(address)
                continue
            plans = [plan if plan is not None and plan.renders else None for plan in run.plans]
            which = np.array([-1 if plans[r] is None else plans[r].index for r in run.references], np.int64)
            shown = which >= 0
            values = copy_values(run.carrier, run.references, plans, run.own)
            self.meshes.add_block(run.world[shown], which[shown], np.array(run.seqs, np.int64)[shown],
                                  None if values is None else values[shown])
            self.copies += len(run.seqs)
        return again

    def read_again(self, inst, again):
        """The instance number `inst` had on the first pass where, met on a second pass over the
        depsgraph, it is a copy of a carrier in `again` (finish()); else None. (Read again under
        their first numbers, the copies take their places among the others: MeshCollector.finish.)"""
        if not inst.is_instance or inst.parent is None:
            return None
        address = inst.parent.as_pointer()
        if address not in again:
            return None
        k = self._again.get(address, 0)
        self._again[address] = k + 1
        seqs = self.runs[address].seqs
        return seqs[k] if k < len(seqs) else None
