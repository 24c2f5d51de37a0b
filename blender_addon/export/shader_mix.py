"""Mix and Add Shaders whose result one Whitted material record holds.

Cycles mixes closures: a Mix Shader weighs its first shader by 1 - Fac and its
second by Fac (Fac clamped to [0, 1]); an Add Shader sums them. The core's
record is one material, so these mixes are read (anything else: None, and the
caller falls back to the viewport colour and names the shader):

- Add Shader of a shader and an Emission of constant colour and strength: the
  shader with that emission added (exact).
- Mix Shader of a Diffuse BSDF and a Glossy BSDF by a constant Fac: the
  diffuse's colour (textured or not) with kd its weight, the glossy as the
  metal share of its weight, reflecting in its own colour
  (Material.own_metal_color, metal_color).
- Mix Shader of a Diffuse BSDF (first) and a Glossy BSDF (second) by a Fresnel
  node's Fac, or a Layer Weight's Fresnel (its IOR 1 / (1 - Blend)): the glossy
  is the diffuse's dielectric layer of that IOR, reflecting the scene by its
  exact Fresnel, the diffuse under it getting the rest
  (dielectric_reflection, layered_diffuse), as the mix weighs them. The
  layer reflects white: a Glossy colour other than white is named.
- Mix Shader of a Diffuse or Glossy BSDF and an Emission by a constant Fac:
  the BSDF weighed by its share, the emission by its own.
- Mix Shader of two Diffuse BSDFs of constant colours: one of the mixed colour.
"""
from __future__ import annotations

from .node_links import _socket, _source, input_value

DIFFUSE, GLOSSY = ("BSDF_DIFFUSE",), ("BSDF_GLOSSY", "BSDF_ANISOTROPIC")
WHITE_TOLERANCE = 1e-3


def read_mix(node, links, one, principled_material, multiscatter):
    """(Material, the shader whose Normal input shapes the surface) for the Mix or Add Shader
    `node`, or None where its mix is none of the module's. one(shader, links): a single shader's
    Material (filling links, as the export reads it); principled_material, multiscatter: the
    export's mapping helpers."""
    first, second = (_source(node.inputs[k])[0] for k in ((0, 1) if node.type == "ADD_SHADER" else (1, 2)))
    if first is None or second is None:
        return None
    if node.type == "ADD_SHADER":
        for shader, emission in ((first, second), (second, first)):
            material = _added_emission(shader, emission, links, one)
            if material is not None:
                return material, shader
        return None
    fac_node, fac_out = _source(node.inputs[0])
    if fac_node is None:
        f = min(max(float(input_value(node.inputs[0])), 0.0), 1.0)
        return _constant_mix(first, second, 1.0 - f, f, links, one, principled_material, multiscatter)
    ior = _fresnel_ior(fac_node, fac_out, links)
    if ior is not None and first.type in DIFFUSE and second.type in GLOSSY:
        material = _fresnel_layer(first, second, ior, links, one, principled_material, multiscatter)
        return None if material is None else (material, first)
    return None


def _added_emission(shader, emission, links, one):
    if emission.type != "EMISSION" or shader.type == "EMISSION":
        return None
    glow = _constant_emission(emission)
    if glow is None:
        return None
    material = one(shader, links)
    if material is None or "emission_texture" in links.fields or material.emission:
        return None
    material.emission_color = tuple(a + b for a, b in zip(material.emission_color, glow))
    return material


def _constant_emission(node):
    """An Emission's emitted colour (Color x Strength) where neither input is linked, else None."""
    color, strength = _socket(node, "Color"), _socket(node, "Strength")
    if any(s is not None and _source(s)[0] is not None for s in (color, strength)):
        return None
    rgb = tuple(max(float(c), 0.0) for c in input_value(color)[:3]) if color is not None else (1.0, 1.0, 1.0)
    k = max(float(input_value(strength)), 0.0) if strength is not None else 1.0
    return tuple(c * k for c in rgb)


def _constant_mix(first, second, w1, w2, links, one, principled_material, multiscatter):
    """(Material, shader) of a mix by a constant Fac (weights w1, w2), or None."""
    kinds = (first.type, second.type)
    material, shader = None, first
    if kinds[0] in DIFFUSE and kinds[1] in GLOSSY:
        material = _diffuse_and_glossy(first, second, w1, w2, links, one, principled_material, multiscatter)
    elif kinds[0] in GLOSSY and kinds[1] in DIFFUSE:
        material, shader = _diffuse_and_glossy(second, first, w2, w1, links, one, principled_material,
                                               multiscatter), second
    elif "EMISSION" in kinds and kinds[0] != kinds[1]:
        (bsdf, wb), (emission, we) = ((first, w1), (second, w2)) if kinds[1] == "EMISSION" else ((second, w2), (first, w1))
        material, shader = _with_emission(bsdf, wb, emission, we, links, one), bsdf
    elif kinds[0] in DIFFUSE and kinds[1] in DIFFUSE:
        colors = [_constant_color(n) for n in (first, second)]
        if None not in colors:
            material = one(first, links)
            material.color = tuple(w1 * a + w2 * b for a, b in zip(*colors))
    return None if material is None else (material, shader)


def _constant_color(node):
    """A shader's Color, or None where a node feeds it."""
    socket = _socket(node, "Color")
    return None if socket is not None and _source(socket)[0] is not None else _color_value(socket)


def _glossy_color(glossy, links):
    """The Glossy BSDF's colour, a constant: a linked one is named and its own value used."""
    socket = _socket(glossy, "Color")
    fed = _source(socket)[0] if socket is not None else None
    if fed is not None:
        links.textured.append(f"Color of {glossy.name!r} ({fed.bl_idname}: a Glossy BSDF in a mix reflects "
                              "one colour)")
    return _color_value(socket)


def _color_value(socket):
    """The Color input's own value (Blender's default grey where the shader has none)."""
    return (0.8, 0.8, 0.8) if socket is None else tuple(max(float(c), 0.0) for c in input_value(socket)[:3])


def _roughness(node, links):
    socket = _socket(node, "Roughness")
    if socket is None:
        return 0.5
    fed = _source(socket)[0]
    if fed is not None:
        links.textured.append(f"Roughness of {node.name!r} ({fed.bl_idname})")
    return float(input_value(socket))


def _diffuse_and_glossy(diffuse, glossy, wd, wg, links, one, principled_material, multiscatter):
    base = one(diffuse, links)
    if base is None:
        return None
    material = principled_material(base.color, wg, _roughness(glossy, links), 0.0, 1.45, 0.0)
    material.kd = wd          # (principled_material gives 1 - metallic: the same, kept exact)
    material.own_metal_color = True
    material.metal_color = _glossy_color(glossy, links)
    material.multiscatter = multiscatter(glossy)
    return material


def _with_emission(bsdf, wb, emission, we, links, one):
    glow = _constant_emission(emission)
    if glow is None or bsdf.type not in DIFFUSE + GLOSSY:
        return None
    material = one(bsdf, links)
    if material is None:
        return None
    material.kd *= wb
    material.ks *= wb
    material.mirror *= wb
    material.metallic *= wb
    material.emission_color = tuple(c * we for c in glow)
    return material


def _fresnel_ior(node, out, links):
    """The IOR of a Fresnel node's Fac, or of a Layer Weight's Fresnel output (1 / (1 - Blend), as
    Cycles computes it); None for any other Fac. A linked IOR, Blend or Normal is named."""
    if node.type == "FRESNEL":
        socket = node.inputs.get("IOR")
        value = float(input_value(socket)) if socket is not None else 1.45
    elif node.type == "LAYER_WEIGHT" and out is not None and out.name == "Fresnel":
        socket = node.inputs.get("Blend")
        blend = min(max(float(input_value(socket)), 0.0), 1.0) if socket is not None else 0.5
        value = 1.0 / max(1.0 - blend, 1e-5)
    else:
        return None
    for name in ("IOR", "Blend", "Normal"):
        s = node.inputs.get(name)
        fed = _source(s)[0] if s is not None else None
        if fed is not None:
            links.textured.append(f"{name} of {node.name!r} ({fed.bl_idname})")
    return max(value, 1.0 + 1e-4)


def _fresnel_layer(diffuse, glossy, ior, links, one, principled_material, multiscatter):
    base = one(diffuse, links)
    if base is None:
        return None
    f0 = ((ior - 1.0) / (ior + 1.0)) ** 2
    material = principled_material(base.color, 0.0, _roughness(glossy, links), 0.0, ior, f0, layered=True,
                                   reflects=True)
    material.multiscatter = multiscatter(glossy)
    tint = _glossy_color(glossy, links)
    if max(abs(c - 1.0) for c in tint) > WHITE_TOLERANCE:
        links.unmodelled.append(f"Color {tuple(round(c, 3) for c in tint)} of {glossy.name!r} (a Glossy BSDF "
                                "mixed by Fresnel reflects white here)")
    return material
