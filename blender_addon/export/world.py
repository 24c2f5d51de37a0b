"""The world -> a constant background colour.

With nodes: the Background node linked to the active World Output gives
Color * Strength (a linked Color, e.g. a sky or HDRI texture, falls back to the
world's viewport colour with a warning). Without nodes: world.color. No world:
black, as in Blender. The background is what camera rays that miss see; it does
not light the scene (Whitted ray tracing has no environment lighting).
"""
from __future__ import annotations


def _background_node(tree):
    outputs = [n for n in tree.nodes if n.type == "OUTPUT_WORLD"]
    active = [n for n in outputs if n.is_active_output] or outputs
    if not active or not active[0].inputs["Surface"].is_linked:
        return None
    return active[0].inputs["Surface"].links[0].from_node


def background_color(world, warnings: list) -> tuple:
    if world is None:
        return (0.0, 0.0, 0.0)
    viewport = tuple(float(c) for c in world.color)[:3]
    tree = getattr(world, "node_tree", None)
    if tree is None or not getattr(world, "use_nodes", True):
        return viewport
    node = _background_node(tree)
    if node is None:
        return (0.0, 0.0, 0.0)
    if node.type != "BACKGROUND":
        warnings.append(f"World {world.name!r}: unsupported shader {node.bl_idname}, "
                        "using the world viewport colour as background")
        return viewport
    color_in, strength_in = node.inputs["Color"], node.inputs["Strength"]
    if color_in.is_linked or strength_in.is_linked:
        warnings.append(f"World {world.name!r}: textured background is not supported, "
                        "using the world viewport colour")
        return viewport
    strength = float(strength_in.default_value)
    return tuple(float(c) * strength for c in tuple(color_in.default_value)[:3])
