"""Blender materials -> gridwalk.model.Material.

Supported surface shaders (the node linked to the active Material Output):
Principled BSDF, Diffuse BSDF, Glossy BSDF, Glass BSDF and Emission. Anything
else, and materials without nodes, use the viewport display settings
(diffuse_color, metallic, roughness). Linked (textured) inputs use their
unlinked default value. Unsupported graphs and textured inputs are reported
as ONE warning per export, naming the materials.

Principled BSDF -> Whitted model (our shading has no 1/pi in the BRDF: that
factor is folded into the light intensities, see lights.py):
  m = metallic, t = transmission * (1 - m), r = roughness
  color         = base color
  kd            = (1 - m) * (1 - t)                (diffuse albedo = kd * color)
  F0            = 0.08 * Specular (3.x) or ((ior-1)/(ior+1))^2 * 2 * Specular IOR Level (4.x)
  shininess     = 2 / a^2 - 2 with a = max(r^2, 1e-3), capped at 1000 (Blinn-Phong ~ GGX)
  ks            = ((1 - m) * F0 + m) * (shininess + 8) / 8   (normalised Blinn-Phong lobe)
  mirror        = m,  roughness = r  (glossy when r > 0)
  transmittance = t,  ior = IOR
  emission      = Emission Strength * max(Emission Color)
"""
from __future__ import annotations

from gridwalk.model import Material

# Custom property of a material holding gridwalk.Material fields; when present
# it is exported as is (NFF's Phong highlight has no Principled equivalent).
GRIDWALK_MATERIAL = "gridwalk_material"

SHININESS_CAP = 1000.0
DEFAULT_MATERIAL = Material(color=(0.8, 0.8, 0.8), kd=1.0, ks=0.0, shininess=32.0)


def _socket(node, *names):
    for name in names:
        socket = node.inputs.get(name)
        if socket is not None:
            return socket
    return None


def _value(node, names, default, textured):
    socket = _socket(node, *names) if isinstance(names, tuple) else _socket(node, names)
    if socket is None:
        return default
    if socket.is_linked:
        textured.append(socket.name)
    value = socket.default_value
    if hasattr(value, "__len__"):
        return tuple(float(c) for c in value)[:3]
    return float(value)


def principled_material(color, metallic, roughness, transmission, ior, f0, emission=0.0):
    """The documented Principled -> Whitted mapping (also used for viewport colours)."""
    m = min(max(metallic, 0.0), 1.0)
    t = min(max(transmission, 0.0), 1.0) * (1.0 - m)
    r = min(max(roughness, 0.0), 1.0)
    a = max(r * r, 1e-3)
    shininess = min(2.0 / (a * a) - 2.0, SHININESS_CAP)
    ks = ((1.0 - m) * f0 + m) * (shininess + 8.0) / 8.0
    return Material(color=tuple(color[:3]), kd=(1.0 - m) * (1.0 - t), ks=ks,
                    shininess=shininess, transmittance=t, ior=max(ior, 1e-3),
                    mirror=m, roughness=r, emission=max(emission, 0.0))


def _from_principled(node, textured):
    color = _value(node, "Base Color", (0.8, 0.8, 0.8), textured)
    metallic = _value(node, "Metallic", 0.0, textured)
    roughness = _value(node, "Roughness", 0.5, textured)
    transmission = _value(node, ("Transmission Weight", "Transmission"), 0.0, textured)
    ior = _value(node, "IOR", 1.45, textured)
    if _socket(node, "Specular IOR Level") is not None:          # Blender 4.0+
        level = _value(node, "Specular IOR Level", 0.5, textured)
        f0 = ((ior - 1.0) / (ior + 1.0)) ** 2 * 2.0 * level
    else:                                                       # Blender 3.x
        f0 = 0.08 * _value(node, "Specular", 0.5, textured)
    strength = _value(node, "Emission Strength", 1.0, textured)
    emission_color = _value(node, ("Emission Color", "Emission"), (0.0, 0.0, 0.0), textured)
    return principled_material(color, metallic, roughness, transmission, ior, f0,
                               strength * max(emission_color))


def _from_other_bsdf(node, textured):
    kind = node.type
    color = _value(node, "Color", (0.8, 0.8, 0.8), textured)
    if kind == "BSDF_DIFFUSE":
        return principled_material(color, 0.0, 1.0, 0.0, 1.45, 0.0)
    if kind in ("BSDF_GLOSSY", "BSDF_ANISOTROPIC"):
        return principled_material(color, 1.0, _value(node, "Roughness", 0.5, textured), 0.0, 1.45, 0.0)
    if kind == "BSDF_GLASS":
        return principled_material(color, 0.0, _value(node, "Roughness", 0.0, textured), 1.0,
                                   _value(node, "IOR", 1.45, textured), 0.04)
    if kind == "EMISSION":
        strength = _value(node, "Strength", 1.0, textured)
        return Material(color=color, kd=0.0, ks=0.0, emission=strength)
    return None


def _output_node(tree):
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_MATERIAL"]
    for node in outputs:
        if node.is_active_output and node.target in ("ALL", "CYCLES"):
            return node
    return outputs[0] if outputs else None


def _surface_node(tree):
    out = _output_node(tree)
    if out is None or not out.inputs["Surface"].is_linked:
        return None
    node = out.inputs["Surface"].links[0].from_node
    while node.type == "REROUTE" and node.inputs[0].is_linked:
        node = node.inputs[0].links[0].from_node
    return node


def viewport_material(mat) -> Material:
    """The material's viewport display settings as a Principled-like material."""
    return principled_material(tuple(mat.diffuse_color)[:3], mat.metallic, mat.roughness,
                               0.0, 1.45, 0.08 * getattr(mat, "specular_intensity", 0.5))


def convert_material(mat):
    """(Material, problem) for one Blender material; problem is None or a short reason."""
    stored = mat.get(GRIDWALK_MATERIAL) if hasattr(mat, "get") else None
    if stored is not None:   # set by the NFF importer: the exact Whitted material
        fields = stored.to_dict() if hasattr(stored, "to_dict") else dict(stored)
        fields["color"] = tuple(float(c) for c in fields["color"])
        return Material(**fields), None
    tree = getattr(mat, "node_tree", None)
    use_nodes = getattr(mat, "use_nodes", True)
    if tree is None or not use_nodes:
        return viewport_material(mat), None
    node = _surface_node(tree)
    if node is None:
        return viewport_material(mat), "no surface shader"
    textured = []
    if node.type == "BSDF_PRINCIPLED":
        result = _from_principled(node, textured)
    else:
        result = _from_other_bsdf(node, textured)
    if result is None:
        return viewport_material(mat), f"unsupported shader {node.bl_idname}"
    if textured:
        return result, "linked inputs (" + ", ".join(sorted(set(textured))) + ") use default values"
    return result, None


class MaterialTable:
    """Collects the scene's materials; index 0 is the default (objects without material)."""

    def __init__(self):
        self.materials = [DEFAULT_MATERIAL]
        self._index = {None: 0}
        self._problems = {}

    def index_of(self, mat) -> int:
        key = None if mat is None else mat.original.name_full
        index = self._index.get(key)
        if index is None:
            material, problem = convert_material(mat)
            if problem:
                self._problems[key] = problem
            index = self._index[key] = len(self.materials)
            self.materials.append(material)
        return index

    def slot_indices(self, obj):
        """Global material index for each material slot of `obj` (at least one entry)."""
        slots = [self.index_of(slot.material) for slot in obj.material_slots]
        return slots or [0]

    def warnings(self) -> list[str]:
        if not self._problems:
            return []
        items = "; ".join(f"{name}: {why}" for name, why in sorted(self._problems.items()))
        return [f"{len(self._problems)} material(s) only partly supported, "
                f"approximated by their viewport/default values ({items})"]
