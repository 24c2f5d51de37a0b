"""Values that are one per object instance, in the corner colours of its triangles.

Two kinds of material input give each instance one value: the Object Info
node (object_info.ObjectInfo) and the Attribute node's Object and Instancer
types (object_attributes.ObjectAttribute). Either is a material's colour
layer (MaterialTable.layers) in place of a mesh attribute's name; the mesh is
read without colours, and each part (an instance of it) gets its value:
  * the plan's value (plan_value: the same for every instance of one object by
    one instancer), found once per InstancePlan;
  * or, where the layer is per_instance (Object Info's Random), the value
    MeshCollector reads with each instance's matrix (instance_value);
  * or, for copies read in bulk, a column of values per copy (instance_column:
    a Geometry Nodes instance attribute), given with their matrices.
assemble_triangles then writes each part's value at every corner of its
triangles, and the core's "attribute" texture reads them.
"""
from __future__ import annotations

import numpy as np

from .object_attributes import ObjectAttribute
from .object_info import ObjectInfo


def is_instance_layer(layer) -> bool:
    """Whether a colour layer (MaterialTable.layers) is one value per instance, not a mesh attribute."""
    return isinstance(layer, (ObjectInfo, ObjectAttribute))


def row_value(plan, inst, obj, place):
    """An instance's own value (a tuple), where its plan's layer is per instance; else None
    (the plan's value applies). place: its matrix's translation, read already by the caller."""
    layer = plan.info
    return layer.instance_value(inst, obj, place) if layer is not None and layer.per_instance else None


def part_values(plans, which, rows) -> np.ndarray | None:
    """(P, 3) float32 each part's value, or None where no plan reads one. plans: the mesh plans
    (InstancePlan: info, info_value); which: each part's plan index; rows: (P, 3) float64 each
    part's own value, NaN where its plan's applies."""
    if not any(p.info is not None for p in plans):
        return None
    constants = np.array([p.info_value for p in plans], np.float64).reshape(-1, 3)
    out = np.asarray(rows, np.float64).reshape(-1, 3).copy()
    own = ~np.isnan(out).any(axis=1)
    out[~own] = constants[np.asarray(which)[~own]]
    return out.astype(np.float32)
