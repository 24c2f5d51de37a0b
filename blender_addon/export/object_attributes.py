"""The Attribute node's Object and Instancer types: a value per object instance.

Cycles looks such an attribute up by name, per instance (Blender's
BKE_object_dupli_find_rgba_attribute):
  Object     the object's custom property of that name, else the RNA property at
             that path ("color", "location", "scale"...), then the same on its
             data (the mesh);
  Instancer  for an instance, first a Geometry Nodes instance attribute of that
             name on its copy, then the property of the particle settings that
             instance it, then the instancer's property, then as Object;
             for an object that is no instance, as Object.
A number (or a true boolean, 1) is grey, an array of up to four numbers its
first three channels (missing ones 0); nothing found is black.

The export fills each instance's triangles' corner colours with the value, as
for Object Info (object_info.py). Geometry Nodes instance attributes are read
with the copies' matrices where a carrier's copies are read in bulk
(carrier_instances.py); copies read one by one take the instancer's and the
object's properties, and a carrier whose instance attribute they skip is named
in a warning (MeshCollector.unread_instance_attributes).
"""
from __future__ import annotations

import dataclasses
import numbers

import numpy as np

BLACK = (0.0, 0.0, 0.0)


def _rgb(value):
    """(r, g, b) of a property's value as Cycles converts it, or None for a value it does not read."""
    if isinstance(value, bool):
        return (1.0, 1.0, 1.0) if value else BLACK
    if isinstance(value, numbers.Real):
        return (float(value),) * 3
    try:
        items = list(value)
    except TypeError:
        return None
    if not 0 < len(items) <= 4 or not all(isinstance(v, numbers.Real) and not isinstance(v, bool) for v in items):
        return None                          # (Cycles reads no array of booleans)
    items = [float(v) for v in items[:3]] + [0.0] * (3 - min(len(items), 3))
    return tuple(items)


def property_rgb(id_, name: str):
    """The (r, g, b) of `id_`'s custom property `name`, else of its RNA property at the path
    `name`; None where it has neither (or one of another kind: a string, a pointer)."""
    if id_ is None or not name:
        return None
    try:
        if name in id_.keys():
            return _rgb(id_[name])
    except (TypeError, AttributeError):     # (an ID without custom properties)
        pass
    try:
        return _rgb(id_.path_resolve(name))
    except (ValueError, AttributeError, TypeError):
        return None


@dataclasses.dataclass(frozen=True)
class ObjectAttribute:
    """The colour layer (MaterialTable.layers) of a material reading an Attribute node of type
    `kind` ("OBJECT" or "INSTANCER") named `name`: the instance's value."""
    kind: str
    name: str
    per_instance = False       # (a Geometry Nodes instance attribute comes in bulk: instance_column)

    def __repr__(self) -> str:
        return f"{self.kind.title()} attribute {self.name!r}"

    def plan_value(self, parent, obj, color, particles=None) -> tuple:
        """The value every instance of `obj` instanced by `parent` (None: no instance; particles:
        the particle settings that instance it, or None) gets."""
        instancers = [particles, parent] if self.kind == "INSTANCER" else []
        sources = [s for s in instancers if s is not None] + [obj, obj.data]
        for source in sources:
            found = property_rgb(source, self.name)
            if found is not None:
                return found
        return BLACK

    @property
    def reads_instances(self) -> bool:
        """Whether a Geometry Nodes instance attribute comes first (instance_column)."""
        return self.kind == "INSTANCER"

    def instance_column(self, points) -> np.ndarray | None:
        """(N, 3) float64 per copy, the Geometry Nodes instance attribute of this name on a carrier's
        instances (`points`: its instances_pointcloud()), or None where it has none (or this type
        does not read it)."""
        if self.kind != "INSTANCER":
            return None
        return instance_attribute(points, self.name)

    def unread_by_rows(self, parent) -> bool:
        """Whether copies of `parent` read one by one miss an instance attribute of this name:
        it has one (Blender 4.3+ tells), or (before 4.3) it has a Geometry Nodes modifier."""
        if self.kind != "INSTANCER" or parent is None:
            return False
        evaluated = getattr(parent, "evaluated_geometry", None)
        if evaluated is None:
            return any(m.type == "NODES" for m in getattr(parent, "modifiers", ()))
        try:
            geometry = evaluated()
            points = geometry.instances_pointcloud()
            attr = points.attributes.get(self.name) if points is not None else None
            return attr is not None and attr.data_type in VALUE_FIELDS      # (one Cycles reads)
        except (AttributeError, RuntimeError, TypeError):
            return False


VALUE_FIELDS = {"FLOAT": ("value", 1), "INT": ("value", 1), "BOOLEAN": ("value", 1), "INT8": ("value", 1),
                "FLOAT_VECTOR": ("vector", 3), "FLOAT2": ("vector", 2), "FLOAT_COLOR": ("color", 4),
                "BYTE_COLOR": ("color", 4)}


def instance_attribute(points, name: str) -> np.ndarray | None:
    """(N, 3) float64 the instances' attribute `name` on a carrier's instances point cloud, as
    Cycles reads it (a number grey, a vector or colour its first three channels), or None."""
    attr = points.attributes.get(name) if points is not None else None
    field = VALUE_FIELDS.get(getattr(attr, "data_type", ""))
    if field is None or getattr(attr, "domain", "") != "POINT":
        return None
    n = len(points.points)
    dtype = {"INT": np.int32, "INT8": np.int32, "BOOLEAN": bool}.get(attr.data_type, np.float32)
    raw = np.empty(n * field[1], dtype)
    attr.data.foreach_get(field[0], raw)
    raw = raw.reshape(n, field[1]).astype(np.float64)
    if field[1] == 1:
        return np.repeat(raw, 3, axis=1)
    out = np.zeros((n, 3))
    out[:, :min(field[1], 3)] = raw[:, :3]
    return out
