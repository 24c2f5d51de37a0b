"""The Object Info shader node: values that are the same over one object instance.

A material's Object Info output becomes the corner colours of the triangles of
every instance that uses it (one value per instance, each corner alike), read
by the core's "attribute" texture as an Attribute node's are
(materials.Links._object_info). The outputs read, as Cycles gives them:
  Random        Cycles' object random number: for an instance (Geometry Nodes,
                particles, a collection instance) the depsgraph instance's
                random_id, for an object that is no instance a hash of its name
                (Cycles' hash_uint2(hash_string(name), 0): Bob Jenkins' lookup3
                final mix over h = 37 h + c of the name's UTF-8 bytes), divided
                by 2^32 - 1;
  Color, Alpha  the object's Viewport Display colour (Object.color) and its alpha;
                an instance's are its instancer's (Blender gives the objects it
                lists as instances their instancer's colour; Cycles reads that);
  Object Index  the object's own Pass Index;
  Location      the instance's place in the world (its matrix's translation; a viewport
                move changes the export's signature then, so it is exported again).
Material Index is named in the material's warning; so is Object Info on
shapes the core draws itself (point clouds, hair).
"""
from __future__ import annotations

import dataclasses

OUTPUTS = ("Random", "Color", "Alpha", "Object Index", "Location")   # the outputs read
MASK = 0xFFFFFFFF
BLACK = (0.0, 0.0, 0.0)


@dataclasses.dataclass(frozen=True)
class ObjectInfo:
    """The colour layer (MaterialTable.layers) of a material reading Object Info's `output`:
    no mesh attribute, the instance's value. (object_attributes.ObjectAttribute is the other
    such layer: both give plan_value, per_instance, instance_value and instance_column.)"""
    output: str

    def __repr__(self) -> str:
        return f"Object Info's {self.output}"

    @property
    def per_instance(self) -> bool:
        """Whether each instance has its own value (Random, Location), read by instance_value."""
        return self.output in ("Random", "Location")

    def plan_value(self, parent, obj, color, particles=None) -> tuple:
        """The value every instance of `obj` instanced by `parent` gets (color: display_color's)."""
        return BLACK if self.per_instance else per_object(obj, self.output, color)

    def instance_value(self, inst, obj, place) -> tuple:
        """The instance's own value; place: its matrix's translation (Location)."""
        if self.output == "Location":
            return tuple(float(v) for v in place)
        return (random_of(inst, obj),) * 3

    reads_instances = False    # (no Geometry Nodes instance attribute: instance_column)

    def instance_column(self, points):
        return None

    def unread_by_rows(self, parent) -> bool:
        return False


def _rotate(x: int, k: int) -> int:
    return ((x << k) | (x >> (32 - k))) & MASK


def hash_uint2(kx: int, ky: int) -> int:
    """Cycles' hash of two unsigned 32-bit integers (util/hash.h: lookup3's final mix)."""
    a = b = c = (0xDEADBEEF + (2 << 2) + 13) & MASK
    a, b = (a + kx) & MASK, (b + ky) & MASK
    c ^= b; c = (c - _rotate(b, 14)) & MASK
    a ^= c; a = (a - _rotate(c, 11)) & MASK
    b ^= a; b = (b - _rotate(a, 25)) & MASK
    c ^= b; c = (c - _rotate(b, 16)) & MASK
    a ^= c; a = (a - _rotate(c, 4)) & MASK
    b ^= a; b = (b - _rotate(a, 14)) & MASK
    c ^= b; c = (c - _rotate(b, 24)) & MASK
    return c


def hash_string(text: str) -> int:
    """Cycles' string hash: h = 37 h + c over the UTF-8 bytes, modulo 2^32."""
    h = 0
    for byte in text.encode("utf-8"):
        h = (h * 37 + byte) & MASK
    return h


def random_of(inst, obj) -> float:
    """Object Info's Random of a depsgraph instance (see the module's note; obj, its object, is
    read only where it is no instance)."""
    random_id = (inst.random_id & MASK) if inst.is_instance else hash_uint2(hash_string(obj.name), 0)
    return random_id / MASK


def display_color(parent, obj) -> tuple:
    """The Viewport Display colour (RGBA) Object Info gives an instance of `obj` by `parent`
    (None: no instance; the module's note)."""
    return tuple(float(c) for c in (parent if parent is not None else obj).color)


def per_object(obj, output: str, color: tuple) -> tuple:
    """The (r, g, b) an output other than Random gives every instance of `obj` (color: display_color's)."""
    if output == "Color":
        return tuple(color[:3])
    if output == "Alpha":
        return (color[3],) * 3
    return (float(obj.original.pass_index),) * 3           # Object Index
