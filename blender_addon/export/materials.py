"""Blender materials -> gridwalk.model.Material.

Supported surface shaders (the node linked to the active Material Output):
Principled BSDF, Diffuse BSDF, Glossy BSDF, Glass BSDF and Emission, a
Mix Shader of one of these with a Transparent BSDF (an alpha cut-out: the
coverage becomes the material's alpha, Fac or 1 - Fac), and the mixes
shader_mix.py reads (a Diffuse and a Glossy BSDF by a constant Fac or by
Fresnel, a shader with an Emission). Anything else uses the viewport display
settings (diffuse_color, metallic, roughness); a material without nodes is a
Diffuse BSDF of its viewport colour, as Cycles renders it.

Linked inputs the core evaluates per hit (textures.py reads the images):
  Image Texture (Color or Alpha output) -> Principled Base Color, Roughness,
      Metallic, Alpha, and the Color of the other shaders; its Vector input
      unlinked (the mesh's active render UV map), linked from a UV Map node
      (that layer) or a Texture Coordinate's UV, through any Mapping nodes
      (uv_mapping.py: Texture.uv_transform);
  Color Attribute -> Base Color (the named layer, or the active render one),
      also multiplied (a Mix, Multiply, factor 1) by an image: both are read;
  Attribute (a mesh attribute by name; of the Object and Instancer types a value
      per instance: object_attributes.py) and Object Info (Random, Color, Alpha,
      Object Index: object_info.py) like an image, each instance's value in the
      corner colours (instance_values.py); one such colour source per material;
  an Image Texture through Separate Color, Math, Mix and Invert nodes with
      constant other inputs (value_nodes.py: Texture.channel, gain, bias, clamp);
  Bump fed by an Image Texture (its Height) -> the shader's Normal
      (bump_texture, bump_distance (negated by Invert), bump_strength), and
      a Normal Map into the Bump's own Normal as below;
  Normal Map (Tangent Space) fed by an Image Texture -> the shader's Normal
      (normal_texture, its Strength normal_strength; the tangent frame comes
      from the image's UV map).
Any other linked input (a procedural texture, a Color Ramp...) uses
the socket's unlinked default value; unsupported graphs and inputs are
reported as ONE warning per export, naming the materials and the nodes.

Principled BSDF -> Whitted model (our shading has no 1/pi in the BRDF: that
factor is folded into the light intensities, see lights.py):
  m = metallic, t = transmission * (1 - m), r = roughness
  color         = base color
  kd            = (1 - m) * (1 - t)      (diffuse albedo = kd * color)
  layered_diffuse = Blender 4.0+ only: its Principled BSDF puts the diffuse under
                  the specular layer, which takes its albedo seen from the viewer
                  out of the diffuse (the core: kd x (1 - Fresnel at the view's
                  angle x the lobe's albedo), 0.04 head-on at IOR 1.5 and level
                  0.5); 3.x's adds the specular on top
  F0            = 0.08 * Specular (3.x) or ((ior-1)/(ior+1))^2 * 2 * Specular IOR Level (4.x)
  shininess     = 2 / a^2 - 2 with a = max(r^2, 1e-3), capped at 1000 (a Phong lobe ~ GGX's)
  ks            = ((1 - m) * F0 + m) * (shininess + 8) / 8   (normalised Phong weight; the
                  core's GGX lobe, used where r > 0, takes ks * 8 / (shininess + 8) as its
                  reflectance at normal incidence)
  mirror        = m,  roughness = r  (glossy when r > 0)
  multiscatter  = the shader's distribution is Multiscatter GGX (Blender 4.0+'s default)
  dielectric_reflection = True: the specular layer (F0 on the share that is neither
                  metal nor transmission) reflects the scene by Fresnel, not only the
                  lamps (a glossy floor mirrors what stands on it, spheres get bright rims)
  metallic      = m   (the metal's share of the highlight and of the mirror
                  reflection takes the base colour: gold reflects gold)
  transmittance = t,  ior = IOR,  tints_refraction = t > 0 (the base colour
                  tints what passes, as Cycles' coloured glass: Blender 4.0+'s Principled
                  by its square root at each crossing, tint_sqrt; the Glass BSDF's
                  Color its reflection too: tints_reflection)
  emission_color = Emission Color * Emission Strength   (Emission shader: Color * Strength;
                  an Emission Color fed by an image: emission_texture, and
                  emission_color the strength)
  alpha         = Alpha
With a Metallic texture the record holds the metallic = 0 mapping and the
core blends towards the metal per hit; with a Roughness texture the core
recomputes shininess and ks per hit from the same formulas.
"""
from __future__ import annotations

import dataclasses

from gridwalk.model import Material

from .hair_color import hair_color
from .node_links import _socket, _source, input_value
from .object_attributes import ObjectAttribute
from .object_info import OUTPUTS as OBJECT_INFO_OUTPUTS, ObjectInfo
from .shader_mix import read_mix
from .color_ramp import ramp_stops
from .textures import plain_image
from .uv_mapping import CORNER_COORDINATES, texture_fields
from .value_nodes import TEXTURE_NODES, image_through_nodes, is_vector, mix_inputs

# Custom property of a material holding gridwalk.Material fields; when present
# it is exported as is (NFF's Phong highlight has no Principled equivalent).
GRIDWALK_MATERIAL = "gridwalk_material"

SHININESS_CAP = 1000.0
DEFAULT_MATERIAL = Material(color=(0.8, 0.8, 0.8), kd=1.0, ks=0.0, shininess=32.0)


def default_material(version) -> Material:
    """What an object without material renders as in Blender `version`: a
    grey diffuse surface, and from 5.0 on a default Principled BSDF (grey 0.8,
    roughness 0.5, IOR 1.5, Specular IOR Level 0.5), as Cycles renders it."""
    if tuple(version) < (5, 0, 0):
        return DEFAULT_MATERIAL
    f0 = ((1.5 - 1.0) / (1.5 + 1.0)) ** 2
    return principled_material((0.8, 0.8, 0.8), 0.0, 0.5, 0.0, 1.5, f0, layered=True, reflects=True)


class Links:
    """What a material's linked inputs turn into: texture indices, the UV and
    colour layers they need, and the inputs left at their default (`textured`)."""

    def __init__(self, textures):
        self.textures = textures
        self.fields = {}           # Material field -> value
        self.uv_layer = None       # None: no texture; "": the active render UV map; else a layer name
        self.uv_layers_read = []   # every UV map the textures name, in order ("": the render one)
        self.color_layer = None    # likewise for the colour attribute
        self.points = set()        # "generated", "object", "position", "normal": the corner points a texture reads
        self.textured = []         # "input (node)" left at its default value
        self.unmodelled = []       # "input value" of layers the Whitted model does not have

    def take(self, socket, field, colour: bool = True) -> bool:
        """Turn a linked input into `field` (a texture index); True if it did. Normal
        maps take images at the UV map only (their colours are a normal in its frame)."""
        node, out = _source(socket)
        if node is None:
            return False
        if field == "normal_texture":
            before = set(self.points), self.uv_layer, self.color_layer
            taken = self._take(socket, node, out, field, colour)
            texture = self.textures.textures[self.fields[field]] if taken else None
            if texture is not None and not plain_image(texture):
                del self.fields[field]
                self.points, self.uv_layer, self.color_layer = before     # (nothing reads what it would have read)
                self.textured.append(f"{socket.name} ({node.bl_idname}: normal maps read images "
                                     "at the UV map only)")
                return False
            return taken
        return self._take(socket, node, out, field, colour)

    def _take(self, socket, node, out, field, colour) -> bool:
        if node.type in TEXTURE_NODES and self.textures is not None and \
                (node.type != "OBJECT_INFO" or out.name in OBJECT_INFO_OUTPUTS):
            # (a vector straight into a number: its average, as Cycles converts it)
            average = {"channel": 4} if is_vector(node, out.name) and socket.type == "VALUE" else None
            self.fields[field] = self._texture(node, out.name, average)
            return True
        if colour and field == "color_texture" and node.type == "VERTEX_COLOR":
            self.fields["vertex_color"] = True
            self._read_colours(getattr(node, "layer_name", "") or "", "colour attribute")
            return True
        image, output, adjust, ramp = (image_through_nodes(socket) if self.textures is not None
                                       else (None, None, "", None))
        if image is not None:
            self.fields[field] = self._ramped(image, output, adjust, ramp)
            return True
        if colour and field == "color_texture" and self._image_times_attribute(node):
            return True
        self.textured.append(f"{socket.name} ({node.bl_idname}{': ' + adjust if adjust else ''})")
        return False

    def _image_times_attribute(self, node) -> bool:
        """A Mix multiplying, with factor 1, an image (through value_nodes.py's
        nodes) by a Color Attribute node: the glTF importer's base colour of a
        textured model with vertex colours. Sets color_texture and vertex_color."""
        sockets = mix_inputs(node) if node.type == "MIX_RGB" or getattr(node, "data_type", "") == "RGBA" else None
        if sockets is None:
            return False
        fac, a, b = sockets
        if node.blend_type != "MULTIPLY" or _source(fac)[0] is not None or input_value(fac) != 1.0 \
                or getattr(node, "clamp_result", False) or getattr(node, "use_clamp", False):
            return False
        for image_side, other in ((a, b), (b, a)):
            attribute, _ = _source(other)
            if attribute is None or attribute.type != "VERTEX_COLOR":
                continue
            image, output, adjust, ramp = image_through_nodes(image_side)
            if image is None or image.type in ("ATTRIBUTE", "OBJECT_INFO"):   # (a colour source of its own)
                return False
            self.fields["color_texture"] = self._ramped(image, output, adjust, ramp)
            self.fields["vertex_color"] = True
            self._read_colours(getattr(attribute, "layer_name", "") or "", "colour attribute")
            return True
        return False

    def _ramped(self, node, output, adjust, ramp) -> int:
        """The texture index of a texture node's output (_texture) with the steps before the
        Color Ramp `ramp`, then the ramp (Texture.ramp, color_ramp.py) and the steps after it
        (adjust's ramp_* fields); without a ramp, _texture's."""
        if ramp is None:
            return self._texture(node, output, adjust)
        before = {k: v for k, v in adjust.items() if not k.startswith("ramp_")}
        stops, interpolation, notes = ramp_stops(ramp.color_ramp, ramp.name)
        self.textured += notes
        after = {k: v for k, v in adjust.items() if k.startswith("ramp_")}
        return self.textures.with_ramp(self._texture(node, output, before), stops, interpolation, after)

    def _texture(self, node, output, adjust=None) -> int:
        """The texture index of an image or procedural texture node (value_nodes.TEXTURE_NODES)'s output."""
        if node.type == "ATTRIBUTE":
            return self._attribute(node, output, adjust)
        if node.type == "OBJECT_INFO":
            return self._object_info(output, adjust)
        if node.type != "TEX_IMAGE":
            return self.textures.procedural(node, output, self._coords(node, "generated", False), adjust,
                                            self.textured)
        # (a projected image reads its point in 3D, not (x, y) alone: the vector path; a box
        # projection the object-space normals too)
        flat = getattr(node, "projection", "FLAT") not in ("BOX", "SPHERE", "TUBE")
        if getattr(node, "projection", "FLAT") == "BOX":
            self.points.add("normal")
        return self.textures.texture(node, output, self._coords(node, "uv", flat), adjust)

    def _attribute(self, node, output, adjust=None) -> int:
        """An Attribute node's output as a texture of the mesh attribute it names (kind "attribute":
        the corner colours the export reads from that attribute; its Fac their mean, as Cycles
        averages a colour), or for the Object and Instancer types of the value each instance's
        object (or instancer) gives that name (object_attributes.py). A material reads one such
        attribute; others, and View Layer attributes, are named in the warning."""
        name = node.attribute_name
        kind = getattr(node, "attribute_type", "GEOMETRY")
        if kind not in ("GEOMETRY", "OBJECT", "INSTANCER"):
            self.textured.append(f"{node.name!r} ({kind.replace('_', ' ').title()} attribute {name!r}: the mesh's "
                                 "attribute of that name is read)")
        fac = output in ("Fac", "Factor")        # (5.0 names it Factor)
        if output not in ("Color", "Vector") and not fac:
            self.textured.append(f"the {output} output of {node.name!r} (its Color is read)")
        if kind in ("OBJECT", "INSTANCER"):
            self._read_colours(ObjectAttribute(kind, name), "")
        else:
            self._read_colours(name or " ", "attribute")      # (no name: none the mesh has, black as in Cycles)
        return self.textures.attribute(fac, adjust)

    def _object_info(self, output, adjust=None) -> int:
        """An Object Info output (object_info.OUTPUTS) as a texture of the corner colours the
        export fills with each instance's value (object_info.py); like an attribute, one per material."""
        self._read_colours(ObjectInfo(output), "")
        return self.textures.attribute(output not in ("Color", "Location"), adjust)

    def _read_colours(self, layer, what: str):
        """The corner colours the material reads: the named attribute ("": the render colour
        attribute), or an Object Info output (object_info.ObjectInfo). One per material: a second,
        different one is named in the warning."""
        if self.color_layer is not None and self.color_layer != layer:
            named = repr(layer) if isinstance(layer, (ObjectInfo, ObjectAttribute)) else f"{what} {layer!r}"
            self.textured.append(f"{named} (the material already reads "
                                 f"{self.color_layer or 'the render colour attribute'!r})")
            return
        self.color_layer = layer

    def _coords(self, node, default, image) -> dict:
        """The node's coordinate fields (uv_mapping.texture_fields); notes the UV
        layer it reads, or the Generated or Object coordinates (neither for a constant point)."""
        layer, fields, problems = texture_fields(node, default, image)
        self.textured += problems
        if layer is None:
            if fields.get("coordinates", "uv") in CORNER_COORDINATES:
                self.points.add(fields["coordinates"])
        else:
            # (one UV map per material: the first texture's, "" the render map, is read by every
            # texture; the mesh tells whether "" and a name are one map: MeshCollector.mixed_uv_maps)
            if layer not in self.uv_layers_read:
                self.uv_layers_read.append(layer)
            if self.uv_layer is None:
                self.uv_layer = layer
        return fields


def _value(node, names, default, links: Links, field=None):
    """The input's value; a linked input becomes `field` (a texture) when the
    core can evaluate it, else its default value is used and named in `links`."""
    socket = _socket(node, *names) if isinstance(names, tuple) else _socket(node, names)
    if socket is None:
        return default
    src, _ = _source(socket)
    if src is not None and not (field and links.take(socket, field, True)) and not field:
        links.textured.append(f"{socket.name} ({src.bl_idname})")
    value = input_value(socket)
    return value[:3] if isinstance(value, tuple) else value


def principled_material(color, metallic, roughness, transmission, ior, f0, emission=0.0, layered=False,
                        reflects=False, tint_sqrt=False):
    """The documented Principled -> Whitted mapping (also used for viewport colours).
    emission: a strength (colour * emission) or an RGB emitted colour;
    layered: the diffuse lies under the specular layer (layered_diffuse);
    reflects: the specular layer reflects the scene (dielectric_reflection);
    tint_sqrt: each crossing of the transmission tints by the colour's square root (Material.tint_sqrt)."""
    m = min(max(metallic, 0.0), 1.0)
    t = min(max(transmission, 0.0), 1.0) * (1.0 - m)
    r = min(max(roughness, 0.0), 1.0)
    a = max(r * r, 1e-3)
    shininess = min(2.0 / (a * a) - 2.0, SHININESS_CAP)
    ks = ((1.0 - m) * f0 + m) * (shininess + 8.0) / 8.0
    return Material(color=tuple(max(float(c), 0.0) for c in color[:3]), kd=(1.0 - m) * (1.0 - t), ks=ks,
                    shininess=shininess, transmittance=t, ior=max(ior, 1e-3),
                    mirror=m, metallic=m, roughness=r, tints_refraction=t > 0, tint_sqrt=bool(tint_sqrt and t > 0),
                    layered_diffuse=bool(layered),
                    dielectric_reflection=bool(reflects),
                    **_emission(emission))


def _emission(emission) -> dict:
    if hasattr(emission, "__len__"):
        rgb = tuple(max(float(c), 0.0) for c in emission[:3])
        return {"emission_color": rgb} if any(rgb) else {}
    return {"emission": max(float(emission), 0.0)}


def _from_principled(node, textured):
    color = _value(node, "Base Color", (0.8, 0.8, 0.8), textured, "color_texture")
    metallic = _value(node, "Metallic", 0.0, textured, "metallic_texture")
    if "metallic_texture" in textured.fields:
        metallic = 0.0                    # the core blends towards the metal per hit
    roughness = _value(node, "Roughness", 0.5, textured, "roughness_texture")
    transmission = _value(node, ("Transmission Weight", "Transmission"), 0.0, textured)
    ior = max(_value(node, "IOR", 1.45, textured), 1e-3)        # (a Value node may give any number)
    layered = _socket(node, "Specular IOR Level") is not None     # Blender 4.0+
    if layered:
        level = max(_value(node, "Specular IOR Level", 0.5, textured), 0.0)
        f0 = ((ior - 1.0) / (ior + 1.0)) ** 2 * 2.0 * level
    else:                                                       # Blender 3.x
        f0 = 0.08 * max(_value(node, "Specular", 0.5, textured), 0.0)
    strength = _value(node, "Emission Strength", 1.0, textured)
    emission_color = _value(node, ("Emission Color", "Emission"), (0.0, 0.0, 0.0), textured, "emission_texture")
    if "emission_texture" in textured.fields:
        emission_color = (1.0, 1.0, 1.0)       # the texture's colour x the strength, per hit
    # (Blender 4.0+'s Principled tints each crossing by the colour's square root: Cycles' transmission tint)
    material = principled_material(color, metallic, roughness, transmission, ior, f0,
                                   tuple(c * strength for c in emission_color), layered, reflects=True,
                                   tint_sqrt=layered)
    material.alpha = min(max(_value(node, "Alpha", 1.0, textured, "alpha_texture"), 0.0), 1.0)
    material.multiscatter = multiscatter(node)
    _name_unread(node, PRINCIPLED_UNREAD, textured)
    if strength < 0 and any(c > 0 for c in emission_color):   # (the core takes no negative light)
        textured.unmodelled.append(f"Emission Strength {strength:g}")
    return material


# Inputs of the shaders that the Whitted model has no term for, by the names
# they have had (4.x, then 3.x): where one is linked or set away from its
# neutral value (0, or white for a 4.x Specular Tint), the material is
# rendered as if it were not and the warning names it.
PRINCIPLED_UNREAD = (("Coat Weight", "Clearcoat"), ("Sheen Weight", "Sheen"), ("Subsurface Weight", "Subsurface"),
                     ("Specular Tint",), ("Anisotropic",), ("Thin Film Thickness",), ("Diffuse Roughness",))
OTHER_UNREAD = {"BSDF_DIFFUSE": (("Roughness",),), "BSDF_GLOSSY": (("Anisotropy",),),
                "BSDF_ANISOTROPIC": (("Anisotropy",),)}


def multiscatter(node) -> bool:
    """Whether the shader's glossy lobe is Multiscatter GGX (Blender 4.0+'s default;
    3.x's is GGX; Beckmann and Ashikhmin-Shirley are rendered as GGX)."""
    return getattr(node, "distribution", "GGX") == "MULTI_GGX"


def _name_unread(node, inputs, links: Links):
    """Appends each of `inputs` that would change Cycles' image to links.unmodelled."""
    for names in inputs:
        socket = _socket(node, *names)
        if socket is None:
            continue
        value = input_value(socket)
        if isinstance(value, tuple):   # a colour: neutral when white
            neutral, shown = min(value[:3]) >= 1.0, "(" + ", ".join(f"{c:g}" for c in value[:3]) + ")"
        else:
            neutral, shown = value == 0, f"{value:g}"
        if _source(socket)[0] is not None or not neutral:
            links.unmodelled.append(f"{socket.name} {shown}")


def _from_other_bsdf(node, textured):
    kind = node.type
    if kind == "BSDF_HAIR_PRINCIPLED":   # (its Color is one of three parametrizations: read by hair_color)
        hair = hair_color(getattr(node, "parametrization", "COLOR"),
                          lambda name, default: _value(node, name, default, textured))
        return principled_material(hair, 0.0, _value(node, "Roughness", 0.3, textured), 0.0,
                                   _value(node, "IOR", 1.55, textured), 0.04)
    color = _value(node, "Color", (0.8, 0.8, 0.8), textured, "color_texture")
    _name_unread(node, OTHER_UNREAD.get(kind, ()), textured)
    if kind == "BSDF_DIFFUSE":
        return principled_material(color, 0.0, 1.0, 0.0, 1.45, 0.0)
    if kind in ("BSDF_GLOSSY", "BSDF_ANISOTROPIC"):
        glossy = principled_material(color, 1.0, _value(node, "Roughness", 0.5, textured), 0.0, 1.45, 0.0)
        glossy.multiscatter = multiscatter(node)
        return glossy
    if kind == "BSDF_GLASS":   # (its Color tints what it reflects as well as what it refracts)
        glass = principled_material(color, 0.0, _value(node, "Roughness", 0.0, textured), 1.0,
                                    _value(node, "IOR", 1.45, textured), 0.04)
        glass.tints_reflection = True
        glass.multiscatter = multiscatter(node)   # (rough glass: Multiscatter GGX keeps its light)
        return glass
    if kind == "BSDF_HAIR":
        return principled_material(color, 0.0, 0.5, 0.0, 1.55, 0.04)
    if kind == "EMISSION":
        strength = _value(node, "Strength", 1.0, textured)
        color = tuple(max(float(c), 0.0) for c in color)   # (the core refuses negative light)
        if "color_texture" in textured.fields or textured.fields.get("vertex_color"):
            # (texture or colour attribute x strength: a colour attribute alone was lost, the
            # emission its own white)
            return Material(color=color, kd=0.0, ks=0.0, emission=max(strength, 0.0))
        return Material(color=color, kd=0.0, ks=0.0, emission_color=tuple(max(c * strength, 0.0) for c in color))
    return None


def _one_shader(node, links):
    """One shader node's Material (None: a shader the core does not model)."""
    return _from_principled(node, links) if node.type == "BSDF_PRINCIPLED" else _from_other_bsdf(node, links)


def _cut_shader(mix):
    """(the shader, the Transparent BSDF) a Mix Shader mixes (an alpha cut-out,
    as downloaded assets build leaves and decals), or (None, None)."""
    first, second = _source(mix.inputs[1])[0], _source(mix.inputs[2])[0]
    kinds = [n.type if n is not None else None for n in (first, second)]
    if kinds.count("BSDF_TRANSPARENT") != 1 or None in kinds:
        return None, None
    return (second, first) if kinds[0] == "BSDF_TRANSPARENT" else (first, second)


def _cut_out(mix, clear, material, links):
    """The coverage of a Transparent / shader mix as the material's alpha:
    Fac where the Transparent BSDF (`clear`) is the first shader (a texture
    where Fac is linked to one), 1 - Fac where it is the second (a constant only)."""
    fac = mix.inputs[0]
    if "alpha_texture" in links.fields or material.alpha < 1.0:
        links.textured.append(f"Fac ({mix.bl_idname}: the shader's own Alpha is kept, the mix is not read)")
        return
    tint = input_value(clear.inputs["Color"])
    if min(tint[:3]) < 1.0:
        links.textured.append(f"Color ({clear.bl_idname}: a tinted Transparent BSDF is read as clear)")
    if _source(mix.inputs[1])[0].type == "BSDF_TRANSPARENT":       # (the only one: see _cut_shader)
        material.alpha = min(max(_value(mix, "Fac", 0.5, links, "alpha_texture"), 0.0), 1.0)
        return
    if _source(fac)[0] is not None:        # (1 - a texture is not read: Fac's own value is used)
        links.textured.append(f"Fac ({mix.bl_idname}: a linked Fac with the Transparent BSDF second)")
    material.alpha = min(max(1.0 - input_value(fac), 0.0), 1.0)


def _bump(node, links) -> bool:
    """Reads the shader's Normal input into links.fields when a Bump node drives
    it: its Height from an Image Texture (also through value_nodes.py's nodes),
    and a Normal Map feeding the Bump's own Normal; True if it read either (an
    unlinked Height bends nothing: the Normal passes through)."""
    socket = _socket(node, "Normal")
    bump = _source(socket)[0] if socket is not None else None
    if bump is None or bump.type != "BUMP" or links.textures is None:
        return False
    below = _source(bump.inputs["Normal"])[0]
    mapped = below is not None and _normal_map(bump, links)
    if below is not None and not mapped:
        links.textured.append(f"Normal of {bump.name!r} ({below.bl_idname})")
    height = _source(bump.inputs["Height"])[0]
    if height is None or not links.take(bump.inputs["Height"], "bump_texture", colour=False):
        return mapped                      # (a Height not read is named by take())
    height_texture = links.textures.textures[links.fields["bump_texture"]]
    if height_texture.kind == "brick":
        links.textured.append(f"Height of {bump.name!r} (a Brick Texture: its mortar's edges are steps, whose "
                              "slope shows as speckle where Cycles shows lines)")
    if height_texture.coordinates == "window" or height_texture.projection == "box":
        how = "at Window coordinates" if height_texture.coordinates == "window" else "a Box projection"
        links.textured.append(f"Height of {bump.name!r} ({how}: its slope is not computed, "
                              "the surface is not bumped)")
    for name, field in (("Strength", "bump_strength"), ("Distance", "bump_distance")):
        fed = _source(bump.inputs[name])[0]
        if fed is not None:
            links.textured.append(f"{name} of {bump.name!r} ({fed.bl_idname})")
        links.fields[field] = float(input_value(bump.inputs[name]))
    links.fields["bump_strength"] = max(links.fields["bump_strength"], 0.0)
    if bump.invert:
        links.fields["bump_distance"] = -links.fields["bump_distance"]
    return True


def _normal_map(node, links) -> bool:
    """Reads the shader's Normal input into links.fields when a Tangent Space
    Normal Map node fed by an Image Texture drives it; True if it did."""
    socket = _socket(node, "Normal")
    nmap = _source(socket)[0] if socket is not None else None
    if nmap is None or nmap.type != "NORMAL_MAP" or getattr(nmap, "space", "") != "TANGENT" or links.textures is None:
        return False
    image = _source(nmap.inputs["Color"])[0]
    if image is None:   # a colour: the flat (0.5, 0.5, 1) leaves the normal as it is, nothing to read
        flat = (0.5, 0.5, 1.0)
        return all(abs(c - f) <= 1 / 255 for c, f in zip(input_value(nmap.inputs["Color"])[:3], flat))
    if image.type != "TEX_IMAGE":
        return False
    if not links.take(nmap.inputs["Color"], "normal_texture", colour=False):
        return False
    named = getattr(nmap, "uv_map", "")
    if named and links.uv_layer and named != links.uv_layer:
        links.textured.append(f"UV Map {named!r} of {nmap.name!r} (its tangents come from the image's UV map)")
    strength = nmap.inputs.get("Strength")
    if strength is not None:
        fed = _source(strength)[0]
        if fed is not None:
            links.textured.append(f"Strength ({fed.bl_idname})")
        links.fields["normal_strength"] = max(float(input_value(strength)), 0.0)
    return True


def _output_node(tree):
    """The Material Output Cycles renders: the active one of those for all
    renderers or for Cycles (an EEVEE-only output beside it is not it)."""
    return tree.get_output_node("CYCLES")


def _surface_node(tree):
    out = _output_node(tree)
    return None if out is None else _source(out.inputs["Surface"])[0]


# A material whose output has a Volume and no Surface: Cycles' surface is
# then clear (rays pass it), and the core renders no volume, so nothing shows.
VOLUME_SURFACE = Material(color=(0.0, 0.0, 0.0), kd=0.0, ks=0.0, alpha=0.0)
# No surface shader (the output's Surface unlinked, or no output node): Cycles renders it opaque black.
NO_SURFACE = Material(color=(0.0, 0.0, 0.0), kd=0.0, ks=0.0)
# Cycles' Holdout shader (an object or collection set to Holdout: Material.holdout_camera)
HOLDOUT = Material(color=(0.0, 0.0, 0.0), kd=0.0, ks=0.0, holdout=True)


def _volume_only(tree) -> bool:
    out = _output_node(tree)
    return out is not None and _source(out.inputs["Volume"])[0] is not None


def viewport_material(mat) -> Material:
    """The material's viewport display settings as a Principled-like material."""
    return principled_material(tuple(mat.diffuse_color)[:3], mat.metallic, mat.roughness,
                               0.0, 1.45, 0.08 * getattr(mat, "specular_intensity", 0.5))


def convert_material(mat, textures=None):
    """(Material, problem, links) for one Blender material; problem is None or
    a short reason; links (a Links, or None) says which UV and colour layers
    its textures need. textures: the scene's TextureTable (None: every linked
    input uses its default value)."""
    stored = mat.get(GRIDWALK_MATERIAL) if hasattr(mat, "get") else None
    if stored is not None:   # set by the NFF importer: the exact Whitted material
        fields = stored.to_dict() if hasattr(stored, "to_dict") else dict(stored)
        fields["color"] = tuple(max(float(c), 0.0) for c in fields["color"])
        for key in ("kd", "ks", "transmittance", "mirror", "emission"):   # (the core refuses negative light)
            if key in fields:
                fields[key] = max(float(fields[key]), 0.0)
        return Material(**fields), None, None
    tree = getattr(mat, "node_tree", None)
    use_nodes = getattr(mat, "use_nodes", True)
    if tree is None or not use_nodes:
        # (Cycles renders a material without nodes as a Diffuse BSDF of its viewport colour: its
        # viewport Metallic, Roughness and Specular made it a metal or glossy here before)
        return principled_material(tuple(mat.diffuse_color)[:3], 0.0, 1.0, 0.0, 1.45, 0.0), None, None
    node = _surface_node(tree)
    if node is None and _volume_only(tree):
        return dataclasses.replace(VOLUME_SURFACE), "a volume shader without a surface: volumes are not rendered, its surface is clear " \
                               "(as Cycles' is)", None
    if node is None:
        return dataclasses.replace(NO_SURFACE), "no surface shader: it renders black, as in Cycles", None
    if node.type == "HOLDOUT":
        return dataclasses.replace(HOLDOUT), None, None
    links = Links(textures)
    mixed = None
    if node.type == "ADD_SHADER" or (node.type == "MIX_SHADER" and _cut_shader(node)[0] is None):
        mixed = read_mix(node, links, _one_shader, principled_material, multiscatter)
        if mixed is None:
            links = Links(textures)
    if mixed is not None:          # (shader_mix.py: mixes one record holds)
        mix, clear, (result, node) = None, None, mixed
    else:
        mix, (node, clear) = (node, _cut_shader(node)) if node.type == "MIX_SHADER" else (None, (node, None))
        result = None if node is None else _one_shader(node, links)
    if result is None:
        shader = node.bl_idname if node is not None else \
            f"{mix.bl_idname} (the mixes read: a Transparent BSDF with one shader, a Diffuse BSDF with a Glossy " \
            "BSDF or an Emission, by a constant Fac or a Diffuse and a Glossy BSDF by Fresnel)"
        return viewport_material(mat), f"unsupported shader {shader}: its viewport colour is used", None
    if mix is not None:
        _cut_out(mix, clear, result, links)
    mapped = node is not None and (_bump(node, links) or _normal_map(node, links))
    for field, value in links.fields.items():
        setattr(result, field, value)
    problems = []
    shaping = [f"{name} ({_source(socket)[0].bl_idname})" for name in ("Normal", "Coat Normal", "Clearcoat Normal")
               if node is not None and (socket := _socket(node, name)) is not None and _source(socket)[0] is not None
               and not (mapped and name == "Normal")]
    output = _output_node(tree)
    displacement = output.inputs.get("Displacement") if output is not None else None
    if displacement is not None and _source(displacement)[0] is not None:
        shaping.append(f"Displacement ({_source(displacement)[0].bl_idname})")
    if shaping:   # (bump and normal maps, displacement: the surface keeps its mesh's shape and normals)
        problems.append(", ".join(shaping) + " not read: the surface is shaded with the mesh's own normals")
    if links.textured:
        problems.append("inputs " + ", ".join(sorted(set(links.textured))) + " use their default values")
    if links.unmodelled:
        problems.append(", ".join(links.unmodelled) + " not modelled (rendered as if unset)")
    return result, "; ".join(problems) or None, links


class MaterialTable:
    """Collects the scene's materials; index 0 is the default (objects without material)."""

    def __init__(self, textures=None, override=None):
        """override: the view layer's Material Override, which every object's
        slots then use (as Cycles renders it), or None."""
        import bpy   # (the Blender running the export)

        self.materials = [default_material(bpy.app.version)]
        self.textures = textures
        self.links = [None]          # per material: Links (UV / colour layers it needs) or None
        self._index = {None: 0}
        self._problems = {}
        self.override = override
        self._names = {}             # index -> material name
        # per material: the Blender material's name (Cryptomatte's: "default_surface" for none, as
        # Cycles names its default shader) and Pass Index
        self.matte_names = [("default_surface", 0)]
        self.shape_notes = set()     # materials whose Generated / Object textures spheres and cylinders dropped
        self.colour_conflicts = set()  # (colour sources an object's materials read, the one read) (layers())
        self._layers = {}            # layers()' answers, by the slots' indices

    def index_of(self, mat) -> int:
        key = None if mat is None else mat.original.name_full
        index = self._index.get(key)
        if index is None:
            material, problem, links = convert_material(mat, self.textures)
            if mat is not None and (mat.get(GRIDWALK_MATERIAL) if hasattr(mat, "get") else None) is None:
                # (an NFF material's self-lit colour lights nothing; every other emission does,
                material.emits_light = _emits(material)   # as Cycles' mesh lights)
            if problem:
                self._problems[key] = problem
            index = self._index[key] = len(self.materials)
            self._names[index] = key or "(none)"
            self.materials.append(material)
            self.links.append(links)
            self.matte_names.append(("default_surface", 0) if mat is None else
                                    (mat.original.name, int(mat.original.pass_index)))
        return index

    def mixed_uv_maps(self, indices, mesh) -> list:
        """[(material name, the UV maps its textures read)] of the materials `indices` (an object's
        slots) whose textures name maps that are not one map of `mesh` (the render map for "" and a
        name the mesh lacks): every texture of such a material reads the first."""
        out = []
        layers = getattr(mesh, "uv_layers", None)
        if layers is None or not len(layers):
            return out
        render = next((l.name for l in layers if l.active_render), None) or layers[0].name
        for i in sorted(set(int(k) for k in indices)):
            links = self.links[i]
            if links is None or len(links.uv_layers_read) < 2:
                continue
            resolved = [name if name and layers.get(name) is not None else render for name in links.uv_layers_read]
            if len(set(resolved)) > 1:
                out.append((self.matte_names[i][0], list(dict.fromkeys(resolved))))
        return out

    def layers(self, indices) -> tuple:
        """(uv, colour layer, corner points) the materials `indices` (an object's
        slots) need; the last a sorted tuple of "generated", "object", "position" and "normal",
        those coordinates its textures read.
        The colour layer: None when none does, "" for the active render layer,
        else the first layer named. The UV layer likewise, or, where the slots'
        materials name different UV maps, a tuple of each slot's (None for a
        material without textures): meshes.read_mesh then reads each
        triangle's corners from its own material's map."""
        key = tuple(indices.tolist()) if hasattr(indices, "tolist") else tuple(int(i) for i in indices)
        found = self._layers.get(key)
        if found is None:      # (a material's links never change once added: one answer per set of slots)
            found = self._layers[key] = self._read_layers(indices)
        return found

    def _read_layers(self, indices) -> tuple:
        uvs, color, points, colours = [], None, set(), []
        for i in indices:
            links = self.links[i]
            uvs.append(None if links is None else links.uv_layer)
            if links is not None:
                color = color if color else links.color_layer if links.color_layer is not None else color
                points |= links.points
                if links.color_layer is not None and links.color_layer not in colours:
                    colours.append(links.color_layer)
        if len(colours) > 1:          # (one set of corner colours per mesh: the others read it too)
            self.colour_conflicts.add(tuple(sorted(_colour_source(c) for c in colours)) + (_colour_source(color),))
        named = {uv for uv in uvs if uv is not None}
        if len(named) > 1:
            return tuple(uvs), color, tuple(sorted(points))
        return (named.pop() if named else None), color, tuple(sorted(points))

    def shape_material(self, index: int) -> int:
        """`index`, or where that material's textures read Generated, Object, Position or Normal
        coordinates, which spheres and cylinders (point clouds, hair) do not have,
        the index of a copy without those textures (their inputs' own values), noted."""
        links = self.links[index]
        if links is None or not links.points:
            return index
        key = ("without corner points", index)
        if key not in self._index:
            material = self.materials[index]
            fields = {f.name: -1 for f in dataclasses.fields(material)
                      if f.name.endswith("_texture") and getattr(material, f.name) >= 0
                      and (self.textures.textures[getattr(material, f.name)].coordinates in CORNER_COORDINATES
                           or self.textures.textures[getattr(material, f.name)].projection == "box")}
            self._index[key] = len(self.materials)
            self.materials.append(dataclasses.replace(material, **fields))
            self.links.append(None)
            self.matte_names.append(self.matte_names[index])
            self.shape_notes.add(self._names.get(index, "?"))
        return self._index[key]

    def slot_indices(self, obj, holdout: bool = False, hidden: tuple = (), catcher: bool = False):
        """Global material index for each material slot of `obj` (at least one entry);
        holdout: the object is a holdout (each slot a copy held out from camera rays); hidden:
        the Material visibility fields the object turns off (each slot a copy with them off);
        catcher: the object is a Shadow Catcher (each slot a copy that is one)."""
        if self.override is not None:
            slots = [self.index_of(self.override)] * max(len(obj.material_slots), 1)
        else:
            slots = [self.index_of(slot.material) for slot in obj.material_slots] or [0]
        changes = tuple((field, False) for field in hidden) + ((("holdout_camera", True),) if holdout else ()) + \
            ((("shadow_catcher", True),) if catcher else ())
        return [self._variant(i, changes) for i in slots] if changes else slots

    def _variant(self, index: int, changes: tuple) -> int:
        """The index of material `index`'s copy with the (field, value) `changes`."""
        key = ("variant", index, changes)
        if key not in self._index:
            self._index[key] = len(self.materials)
            self.materials.append(dataclasses.replace(self.materials[index], **dict(changes)))
            self.links.append(self.links[index])
            self.matte_names.append(self.matte_names[index])
            self._names[self._index[key]] = self._names.get(index, "?")
        return self._index[key]

    def warnings(self) -> list[str]:
        out = []
        if self._problems:
            items = "; ".join(f"{name}: {why}" for name, why in sorted(self._problems.items()))
            out.append(f"{len(self._problems)} material(s) only partly supported ({items})")
        for *sources, read in sorted(self.colour_conflicts):
            out.append(f"An object's materials read different corner colours ({', '.join(sources)}); a mesh "
                       f"has one set, and all of them read {read}")
        if self.shape_notes:
            out.append("Generated, Object, Position and Normal texture coordinates are not read on point clouds and hair "
                       f"(their textures' inputs take their own values): {', '.join(sorted(self.shape_notes))}")
        return out


def _colour_source(layer) -> str:
    """A colour layer (MaterialTable.layers) in words."""
    if isinstance(layer, (ObjectInfo, ObjectAttribute)):
        return repr(layer)
    return f"colour attribute {layer!r}" if layer else "the render colour attribute"


def _emits(material) -> bool:
    return (material.emission > 0 and any(c > 0 for c in material.color)) or any(
        c > 0 for c in material.emission_color)
