"""Wave, Magic, White Noise and Brick Textures on a plane (render_scene.py and export_dump.py
build them by name)."""
from procedural_scenes import emissive_plane
from scenes import plain_world

# Variants: the node, how it is set, what feeds its Vector and which output feeds the Emission's
# Color. "object": Object coordinates through a Mapping node scaling them by `scale` and moving
# them by `at`; otherwise the Vector is unlinked (Generated).
#   wave          the Wave node as Blender adds it (bands along X, sine), Color
#   wave_rings    rings about Z, saw profile, Distortion 6 (Detail 3.5, Detail Scale 1.5), Phase 0.7, Fac
#   wave_diagonal diagonal bands, triangle profile, Scale 2, Color, at Object coordinates
#   magic         the Magic node as Blender adds it (depth 2, Scale 5, Distortion 1), Color
#   magic_far     depth 4, Scale 1.13, Distortion 1.6, Object coordinates moved 9 out (past 2 pi,
#                 where Cycles takes the point modulo 2 pi), Fac
#   white_noise   3D, its Vector a Mapping of Scale 1e-30 moved to (0.3, 1.7, -2.2): one point, one
#                 hashed colour
#   white_noise_4d  4D (W 0.37), the same point, its Value
#   white_noise_zero  the Mapping's Scale 0: Cycles folds it into the zero vector, Location and all
#   white_noise_unlinked  its Vector unlinked: the zero vector in Cycles (not Generated coordinates)
#   white_noise_constant  a Mapping of Scale 0 whose own Vector is unlinked: all its inputs are
#                 constants, which Cycles evaluates (the point is its Location)
#   brick         the Brick node as Blender adds it, Color
#   brick_custom  every setting moved (colours, mortar size and smoothness, bias, width, height,
#                 offset 0.3 every 3rd row, squash 0.6 every 2nd), Color, at Object coordinates
#   brick_fac     the custom bricks' Fac (the mortar)
#   brick_zero    Brick Width -0.4 (a script's value: the socket takes it): mortar (0.2, 0.4, 0.6) everywhere
#   musgrave_<type>  (Blender 3.x and 4.0 only: 4.1 made it a Noise Texture) the Musgrave Texture of that
#                 type (fbm, multifractal, ridged, hybrid, hetero), Detail 3.5 (0.6 for "fbm_low", -0.5 for
#                 "hybrid_negative": Cycles clamps it to 0, one octave times 0, flat),
#                 Dimension 1.2, Lacunarity 2.3, Offset 0.8 and Gain 1.3 for the types that take them,
#                 at Object coordinates, its Fac through a Multiply Add node (x 0.35 + 0.5: no negative light)
PATTERN_VARIANTS = ("wave", "wave_rings", "wave_diagonal", "magic", "magic_far", "white_noise", "white_noise_4d",
                    "white_noise_zero", "white_noise_unlinked", "white_noise_constant", "brick", "brick_custom",
                    "brick_fac", "brick_zero")
MUSGRAVE_VARIANTS = ("musgrave_fbm", "musgrave_fbm_low", "musgrave_multifractal", "musgrave_ridged",
                     "musgrave_hybrid", "musgrave_hetero", "musgrave_hybrid_negative")
MUSGRAVE_TYPES = {"fbm": "FBM", "multifractal": "MULTIFRACTAL", "ridged": "RIDGED_MULTIFRACTAL",
                  "hybrid": "HYBRID_MULTIFRACTAL", "hetero": "HETERO_TERRAIN"}
NODES = {"wave": "ShaderNodeTexWave", "magic": "ShaderNodeTexMagic", "white": "ShaderNodeTexWhiteNoise",
         "brick": "ShaderNodeTexBrick", "musgrave": "ShaderNodeTexMusgrave"}
POINT = (0.3, 1.7, -2.2)


def _mapped(nodes, links, texture, scale, at=(0.0, 0.0, 0.0)):
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = scale
    mapping.inputs["Location"].default_value = at
    links.new(nodes.new("ShaderNodeTexCoord").outputs["Object"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], texture.inputs["Vector"])


def _factor(texture):
    """The node's Fac output (named Factor in Blender 5.0)."""
    return texture.outputs["Factor"] if "Factor" in texture.outputs else texture.outputs["Fac"]


def pattern_scene(variant="wave", resolution=(96, 72)):
    """A plane facing the camera, its Emission's Color a texture set as `variant` says."""
    plane, mat = emissive_plane("Patterned", resolution)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    texture = nodes.new(NODES[variant.split("_")[0]])
    out = texture.outputs[0]
    if variant == "wave_rings":
        texture.wave_type, texture.rings_direction, texture.wave_profile = "RINGS", "Z", "SAW"
        for name, value in (("Distortion", 6.0), ("Detail", 3.5), ("Detail Scale", 1.5), ("Phase Offset", 0.7)):
            texture.inputs[name].default_value = value
        out = _factor(texture)
    elif variant == "wave_diagonal":
        texture.bands_direction, texture.wave_profile = "DIAGONAL", "TRI"
        texture.inputs["Scale"].default_value = 2.0
        _mapped(nodes, links, texture, (0.25, 0.25, 0.25))
    elif variant == "magic_far":
        texture.turbulence_depth = 4
        texture.inputs["Scale"].default_value, texture.inputs["Distortion"].default_value = 1.13, 1.6
        _mapped(nodes, links, texture, (0.4, 0.4, 0.4), (9.0, 9.0, 9.0))
        out = _factor(texture)
    elif variant == "white_noise_constant":
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Vector"].default_value = (0.5, 0.5, 0.5)
        mapping.inputs["Scale"].default_value, mapping.inputs["Location"].default_value = (0.0, 0.0, 0.0), POINT
        links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    elif variant.startswith("white_noise") and variant != "white_noise_unlinked":
        tiny = 0.0 if variant == "white_noise_zero" else 1e-30      # (1e-30 x 3.5 + 0.3 rounds to 0.3)
        _mapped(nodes, links, texture, (tiny, tiny, tiny), POINT)
        if variant == "white_noise_4d":
            texture.noise_dimensions = "4D"
            texture.inputs["W"].default_value = 0.37
            out = texture.outputs["Value"]
    elif variant in ("brick_custom", "brick_fac"):
        inputs = texture.inputs
        inputs["Color1"].default_value, inputs["Color2"].default_value = (0.9, 0.3, 0.1, 1.0), (0.1, 0.5, 0.9, 1.0)
        inputs["Mortar"].default_value = (1.0, 1.0, 0.6, 1.0)
        for name, value in (("Scale", 3.0), ("Mortar Size", 0.05), ("Mortar Smooth", 0.3), ("Bias", 0.2),
                            ("Brick Width", 0.7), ("Row Height", 0.3)):
            inputs[name].default_value = value
        texture.offset, texture.offset_frequency, texture.squash, texture.squash_frequency = 0.3, 3, 0.6, 2
        _mapped(nodes, links, texture, (0.3, 0.3, 0.3))
        if variant == "brick_fac":
            out = _factor(texture)
    elif variant.startswith("musgrave"):
        texture.musgrave_type = MUSGRAVE_TYPES[variant.split("_")[1]]
        detail = {"low": 0.6, "negative": -0.5}.get(variant.split("_")[-1], 3.5)
        for name, value in (("Detail", detail), ("Dimension", 1.2),
                            ("Lacunarity", 2.3), ("Offset", 0.8), ("Gain", 1.3)):
            texture.inputs[name].default_value = value
        _mapped(nodes, links, texture, (0.3, 0.3, 0.3))
        squeeze = nodes.new("ShaderNodeMath")
        squeeze.operation = "MULTIPLY_ADD"
        squeeze.inputs[1].default_value, squeeze.inputs[2].default_value = 0.35, 0.5
        links.new(texture.outputs["Fac"], squeeze.inputs[0])
        out = squeeze.outputs[0]
    elif variant == "brick_zero":
        texture.inputs["Brick Width"].default_value = -0.4
        texture.inputs["Mortar"].default_value = (0.2, 0.4, 0.6, 1.0)
    links.new(out, nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    plain_world("World", (0.0, 0.0, 0.0))
    return {}
