"""The world -> the background colour and a gridwalk.World.

With nodes: the Background node linked to the active World Output. Its
Color x Strength is
  - the background: what rays that miss everything see (camera rays, and
    mirror and refraction rays);
  - Whitted's ambient term: every surface adds base colour x diffuse weight x
    this colour, the light a diffuse surface gets from a uniform sky that it
    sees whole (Cycles' answer for an unoccluded surface; there is no
    occlusion, so creases are as bright as roofs).
A Color linked from an Environment Texture (equirectangular, HDR/EXR or 8-bit)
or a Sky Texture (export/sky.py: the image gridwalk.sky bakes of the sky Cycles
renders) makes the environment what missing rays see (times Strength), and its
irradiance on each surface's normal the ambient term (World.environment_light:
a table of the image's cosine integral over normals, so a sky over dark ground
lights tops and leaves undersides dark, as in Cycles; blocked by the scene
with World Shadows on). Any other
linked Color or Strength falls back to the world's viewport colour, with a
warning naming the node. Without nodes: world.color, both as background and
ambient. A Mix Shader whose Fac is Light Path's Is Camera Ray, between two
plain Background nodes (the NFF importer's world): the camera side is the
background and the other side the ambient term (Cycles' mirror rays would see
the other side; here they see the background). A world whose Ray Visibility
> Diffuse is off (Cycles' switch) gives no ambient term, as Cycles' diffuse
surfaces then get no light from it. Reroutes, muted nodes and links, and RGB
and Value nodes are followed as for materials (materials._follow). No world: black, as in Blender. Film Transparent (World.transparent, set by the
export) makes camera rays that miss see nothing: RGB 0 and alpha 0, as
Cycles writes them; mirror and refraction rays still see the world.
"""
from __future__ import annotations

import dataclasses

from gridwalk import World

from .environment_rotation import environment_rotation
from .sky import sky_world
from .node_links import _source, input_value


def _background_node(tree):
    """The shader node feeding the World Output Cycles renders, through
    reroutes and muted nodes and links as materials.py follows them."""
    out = tree.get_output_node("CYCLES")
    return None if out is None else _source(out.inputs["Surface"])[0]


def _camera_ray_mix(node):
    """(camera rays' node, other rays' node) of a Mix Shader whose Fac is Light
    Path's Is Camera Ray (a background that camera rays see and that lights
    nothing, or lights in another colour); None for any other node."""
    if node.type != "MIX_SHADER":
        return None
    fac, out = _source(node.inputs["Fac"])
    if fac is None or fac.type != "LIGHT_PATH" or out.name != "Is Camera Ray":
        return None
    other, camera = (_source(n)[0] for n in (node.inputs[1], node.inputs[2]))
    return camera, other


def _plain_background(world, node, warnings) -> tuple:
    """Color x Strength of an unlinked Background node; black for no node."""
    if node is None:
        return (0.0, 0.0, 0.0)
    if node.type != "BACKGROUND":
        warnings.append(f"World {world.name!r}: only a plain Background node is read on each side of the "
                        f"Is Camera Ray mix ({node.bl_idname} read as black)")
        return (0.0, 0.0, 0.0)
    linked = [(k, _source(node.inputs[k])[0]) for k in ("Color", "Strength")]
    linked = [(k, src) for k, src in linked if src is not None]
    if linked:
        what = ", ".join(f"its {k} from {src.bl_idname}" for k, src in linked)
        warnings.append(f"World {world.name!r}: a Background node on one side of the Is Camera Ray mix has {what}; "
                        "only constant colours and strengths are read there (read as black)")
        return (0.0, 0.0, 0.0)
    strength = input_value(node.inputs["Strength"])
    return tuple(c * strength for c in input_value(node.inputs["Color"])[:3])


def convert_world(world, textures, warnings: list) -> tuple:
    """(background RGB, gridwalk.World) of a Blender world (None: black, no light).
    A world made invisible to diffuse rays (World > Ray Visibility > Diffuse,
    Cycles' switch) lights nothing: its ambient term is 0."""
    background, out = _convert_world(world, textures, warnings)
    visibility = getattr(world, "cycles_visibility", None)
    if visibility is not None and not getattr(visibility, "diffuse", True):
        out = dataclasses.replace(out, ambient=(0.0, 0.0, 0.0), environment_light=False)
    ignored = [label for prop, label in (("camera", "Camera"), ("glossy", "Glossy"), ("transmission", "Transmission"))
               if visibility is not None and not getattr(visibility, prop, True)]
    if ignored:
        warnings.append(f"World {world.name!r}: Ray Visibility > {', '.join(ignored)} off is not supported "
                        "(camera, mirror and refraction rays that miss see the world)")
    return background, out


def _convert_world(world, textures, warnings: list) -> tuple:
    if world is None:
        return (0.0, 0.0, 0.0), World()
    viewport = tuple(float(c) for c in world.color)[:3]
    tree = getattr(world, "node_tree", None)
    if tree is None or not getattr(world, "use_nodes", True):
        return viewport, World(ambient=viewport)
    node = _background_node(tree)
    if node is None:
        return (0.0, 0.0, 0.0), World()
    camera_only = _camera_ray_mix(node)
    if camera_only is not None:
        seen, lit = (_plain_background(world, n, warnings) for n in camera_only)
        return seen, World(ambient=lit)
    if node.type != "BACKGROUND":
        warnings.append(f"World {world.name!r}: unsupported shader {node.bl_idname}, "
                        "using the world viewport colour")
        return viewport, World(ambient=viewport)
    color_in, strength_in = node.inputs["Color"], node.inputs["Strength"]
    if _source(strength_in)[0] is not None:
        warnings.append(f"World {world.name!r}: a linked Strength is not supported, using the world viewport colour")
        return viewport, World(ambient=viewport)
    strength = input_value(strength_in)
    source, _ = _source(color_in)
    if source is not None and source.type in ("TEX_ENVIRONMENT", "TEX_SKY") and textures is not None:
        if source.type == "TEX_SKY":
            fields, problem = sky_world(source, textures)
            if fields is None:
                warnings.append(f"World {world.name!r}: {problem}, using the world viewport colour")
                return viewport, World(ambient=viewport)
        else:
            if getattr(source, "projection", "EQUIRECTANGULAR") != "EQUIRECTANGULAR":
                warnings.append(f"World {world.name!r}: the {source.projection} projection is read as equirectangular")
            fields = dict(environment=textures.texture(source))
        rotation, problem = environment_rotation(source)
        if problem:
            warnings.append(f"World {world.name!r}: {problem}")
        mean = textures.mean_color(fields["environment"])
        return (tuple(c * strength for c in mean),
                World(environment_strength=strength, environment_light=True, environment_rotation=rotation, **fields))
    if source is not None:
        name = source.bl_idname
        warnings.append(f"World {world.name!r}: a Color from {name} is not supported, using the world viewport colour")
        return viewport, World(ambient=viewport)
    color = tuple(c * strength for c in input_value(color_in)[:3])
    return color, World(ambient=color)


def background_color(world, warnings: list) -> tuple:
    """The background colour alone (world previews)."""
    return convert_world(world, None, warnings)[0]
