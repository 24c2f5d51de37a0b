"""Blender lights -> gridwalk.model.Light.

Units. Blender gives point/spot/area lights a power P in watts and sun lights an
irradiance S in W/m^2. Our core shades a diffuse surface as
    kd * color * light.color * cos(theta) / d^2     (local lights)
    kd * color * light.color * cos(theta)           (sun)
with no 1/pi in the BRDF. Cycles' diffuse BRDF is albedo/pi, so matching Cycles
means folding 1/pi into the light colour:
    point, sphere, spot : I = P / (4 pi)    [W/sr]   -> light.color = rgb * P / (4 pi^2)
    area (rect, disk, ellipse): I = P / pi on its axis     -> light.color = rgb * P / pi^2
                          (Blender before 4.0: I = P / 4, color = rgb * P / (4 pi))
    sun                 : E = S             [W/m^2]  -> light.color = rgb * S / pi
where rgb is the light colour (times the blackbody colour when "use temperature"
is on) and P or S is multiplied by 2^exposure (Blender 4.0+). With "normalize"
off (Blender 4.0+), an area or sphere light's power scales with its area, so
P is multiplied by that area. Area lights are one-sided Lambertian emitters in
both renderers (the core multiplies by the cosine at the emitter), so rect,
disk and ellipse lights match Cycles in every direction, not only on their axis.

Cast Shadow off: the light reaches every point facing it (casts_shadows).

Geometry. Lights point along their local -Z axis. A point light with radius
r > 0 becomes a "sphere" light. Sun "angle" is its angular diameter. Area
lights: SQUARE (size x size), RECTANGLE (size x size_y), DISK (diameter size),
ELLIPSE (diameters size x size_y; a disk scaled unevenly by its object is an
ellipse too); area sizes are scaled by the object's scale,
point/spot radii are not (as in Blender).
axis_u = local X, axis_v = -local Y, so u x v = -Z, the emitting side.
A sun, spot or area light whose object is scaled to zero (how artists switch
a light off by keyframes) points nowhere, and an area light of zero size has
no area: each gives no light, as in Cycles, and is skipped with a warning
naming it. An area light set as a Portal (Cycles' light.cycles.is_portal) gives no
light, as in Cycles, and is left out; a light object's Ray Visibility (Diffuse, Glossy,
Transmission) is read as Cycles reads it (Light.visible_diffuse and the others).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from gridwalk.model import Light

from ._matrix import axis, to_numpy, unit
from .meshes import shown

POINT_FACTOR = 1.0 / (4.0 * math.pi ** 2)
AREA_FACTOR = 1.0 / math.pi ** 2
SUN_FACTOR = 1.0 / math.pi


def _rgb(light) -> np.ndarray:
    rgb = np.array(tuple(light.color)[:3], dtype=np.float64)
    if getattr(light, "use_temperature", False):
        rgb *= np.array(tuple(light.temperature_color)[:3], dtype=np.float64)
    emission = _node_emission(light)
    if emission is not None:
        rgb *= emission
    return rgb


def _light_output(light):
    """The light's node tree's Light Output (the active one), or None without nodes."""
    tree = getattr(light, "node_tree", None)
    if not getattr(light, "use_nodes", False) or tree is None:
        return None
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_LIGHT"]
    return next((n for n in outputs if getattr(n, "is_active_output", False)), outputs[0] if outputs else None)


def _node_emission(light):
    """Colour x Strength of an Emission node with unlinked inputs feeding the
    light's node output (Cycles multiplies the light by it), 0 for an output
    fed nothing, None without nodes or for trees that are not that (warned)."""
    out = _light_output(light)
    if out is None:
        return None
    surface = out.inputs.get("Surface")
    if surface is None or not surface.is_linked:
        return np.zeros(3)
    node = surface.links[0].from_node
    if node.type != "EMISSION" or node.mute or any(i.is_linked for i in node.inputs if i.name in ("Color", "Strength")):
        return None
    return np.array(tuple(node.inputs["Color"].default_value)[:3], np.float64) * float(node.inputs["Strength"].default_value)


def _power(light, area: float) -> float:
    power = float(light.energy) * 2.0 ** float(getattr(light, "exposure", 0.0))
    if not getattr(light, "normalize", True) and area > 0:
        power *= area
    return power


def _sun_units(angle: float) -> float:
    """What the Blender running the export makes of a sun's Strength, against the core's
    irradiance on a facing surface: 1 from 4.0 on (Cycles' sun keeps it at any angle); before,
    Cycles spread the sun over a disc of radius tan(h) at unit distance (h half the angle), which
    gives a facing surface 2 cos h / (1 + cos h) of it (measured in 3.4: 0.93 at 60 degrees, 0.67
    at 120, none at 180; test_b57)."""
    import bpy
    if bpy.app.version >= (4, 0, 0) or not angle > 0:
        return 1.0
    h = 0.5 * min(angle, math.pi)
    return max(2.0 * math.cos(h) / (1.0 + math.cos(h)), 0.0)


def _area_units() -> float:
    """Blender before 4.0 converted an area light's power to radiance as P / (4 A), not
    P / (pi A) (Blender issue 109404, fixed in 4.0): its Cycles shows and lights with
    pi / 4 of 4.0's radiance, and so does this export there."""
    import bpy   # (the Blender running the export)
    return math.pi / 4.0 if bpy.app.version < (4, 0, 0) else 1.0


def _casts_shadows(light) -> bool:
    """Cast Shadow: Cycles' own setting in Blender 3.x (use_shadow is EEVEE's
    there), the shared use_shadow from 4.0 on."""
    cycles = getattr(light, "cycles", None)
    if cycles is not None and hasattr(cycles, "cast_shadow"):
        return bool(cycles.cast_shadow)
    return bool(getattr(light, "use_shadow", True))


def _area_shape(light, sx: float, sy: float):
    """(kind, size, radius, area) of an area light, scaled by the object's scale."""
    shape = light.shape
    w = light.size * sx
    h = (light.size_y if shape in ("RECTANGLE", "ELLIPSE") else light.size) * sy
    if shape in ("SQUARE", "RECTANGLE"):
        return "rect", (w, h), 0.0, w * h
    area = math.pi * w * h / 4.0
    if w == h:
        return "disk", (w, h), w / 2.0, area
    return "ellipse", (w, h), 0.0, area


def convert_light(light, matrix) -> Light:
    """One Blender light datablock at world transform `matrix` (mathutils or numpy 4x4).
    A negative power (a light that darkens, warned by _approximated) gives no
    light: its colour is 0, as the core takes no negative light."""
    out = _convert_light(light, matrix)
    if min(out.color) < 0:
        out = dataclasses.replace(out, color=tuple(max(float(c), 0.0) for c in out.color))
    return out


def _convert_light(light, matrix) -> Light:
    m = matrix if isinstance(matrix, np.ndarray) else to_numpy(matrix)
    position = tuple(m[:3, 3])
    nff = light.get("nff_intensity") if hasattr(light, "get") else None
    if nff is not None and light.type == "POINT":
        # Imported from NFF (blender_addon/nff_import.py): NFF's light has this
        # intensity and no distance falloff; Blender's power is only a preview.
        return Light(position=position, color=tuple(float(c) for c in nff), kind="point")
    x, y, z = (axis(m, i) for i in range(3))
    sx, sy = float(np.linalg.norm(x)), float(np.linalg.norm(y))
    if light.type in ("SUN", "SPOT", "AREA") and not np.linalg.norm(z) > 0:
        raise ValueError("its object is scaled to zero, so it points nowhere and gives no light")
    direction = tuple(unit(-z))
    rgb = _rgb(light)
    kind = light.type
    shadows = _casts_shadows(light)
    if kind == "SUN":
        color = rgb * float(light.energy) * 2.0 ** float(getattr(light, "exposure", 0.0)) * SUN_FACTOR
        color = color * _sun_units(float(light.angle))
        return Light(position=position, color=tuple(color), kind="sun",
                     direction=direction, angle=float(light.angle), casts_shadows=shadows)
    if kind == "AREA":
        shape, size, radius, area = _area_shape(light, sx, sy)
        if not area > 0:
            raise ValueError("its size (times its object's scale) is zero, so it gives no light")
        color = rgb * _power(light, area) * AREA_FACTOR * _area_units()
        return Light(position=position, color=tuple(color), kind=shape, size=size,
                     radius=radius, axis_u=tuple(unit(x)), axis_v=tuple(unit(-y)),
                     direction=direction, inverse_square=True, casts_shadows=shadows)
    radius = float(light.shadow_soft_size)   # Blender does not scale it with the object
    color = rgb * _power(light, 4.0 * math.pi * radius * radius) * POINT_FACTOR
    # Soft Falloff (Blender 4.0+, on by default): a disk facing the lit point, as every
    # point light with a radius was before 4.0; off, a sphere of uniform radiance.
    soft = bool(getattr(light, "use_soft_falloff", True))
    if kind == "SPOT":
        return Light(position=position, color=tuple(color), kind="spot", radius=radius,
                     direction=direction, spot_size=float(light.spot_size),
                     spot_blend=float(light.spot_blend), inverse_square=True, casts_shadows=shadows,
                     soft_falloff=soft)
    if kind == "POINT":
        return Light(position=position, color=tuple(color),
                     kind="sphere" if radius > 0 else "point", radius=radius,
                     inverse_square=True, casts_shadows=shadows, soft_falloff=soft)
    raise ValueError(f"unsupported light type {kind!r}")


def light_from_instance(inst, warnings: list):
    """The Light for one depsgraph object instance of a light object, or None. An instance
    shows when its instancer does (meshes.shown): a light scattered by Geometry Nodes or
    particles, or in an instanced collection, from a source hidden in renders, lights the
    scene as in Cycles (it was left out)."""
    obj = inst.object
    if not inst.show_self or not shown(inst, obj):
        return None
    if obj.data.type == "AREA" and getattr(getattr(obj.data, "cycles", None), "is_portal", False):
        return None     # (a portal guides Cycles' sampling of the world and gives no light of its own)
    matrix = to_numpy(inst.matrix_world)
    if not np.isfinite(matrix).all():
        warnings.append(f"Skipped light '{obj.name}': its transform is not finite (NaN or Inf)")
        return None
    try:
        light = convert_light(obj.data, matrix)
    except ValueError as exc:
        warnings.append(f"Skipped light '{obj.name}': {exc}")
        return None
    warnings.extend(f"Light '{obj.name}': {what}" for what in _approximated(obj.data, matrix))
    # (Ray Visibility, as Cycles reads it for a light; Camera and Volume Scatter have nothing to leave out here)
    return dataclasses.replace(light, **{attr: bool(getattr(obj, attr, True)) for attr in
                                         ("visible_diffuse", "visible_glossy", "visible_transmission")})


def _approximated(light, matrix) -> list[str]:
    """What Gridwalk renders otherwise than Cycles in this light's settings."""
    out = []
    if _light_output(light) is not None and _node_emission(light) is None:
        out.append("its nodes are not read (only an Emission node with unlinked Color and Strength "
                   "into the Light Output is): it gives the light's own colour and power")
    if light.type in ("POINT", "SPOT", "AREA", "SUN") and float(light.energy) < 0:
        out.append("negative power (a light that darkens) is not supported; it gives no light")
    spread = float(getattr(light, "spread", math.pi))
    if light.type == "AREA" and spread < math.pi - 1e-6:
        out.append(f"Spread {math.degrees(spread):.0f} degrees is not supported; it lights the whole "
                   "half-space in front of it")
    if light.type == "SPOT":
        sx, sy = (float(np.linalg.norm(matrix[:3, i])) for i in range(2))
        if abs(sx - sy) > 1e-4 * max(sx, sy):
            out.append("a non-uniform scale does not stretch its cone; the cone stays round")
    return out
