"""A Noise Texture on a plane (render_scene.py and export_dump.py build it by name)."""
import math

import bpy

from procedural_scenes import emissive_plane
from scenes import plain_world

# Noise variants: how the node is set and what it feeds (an Emission's Color, so that the
# image is the texture's value). Object coordinates come through a Mapping node that scales them by 0.25.
#   color      the node as Blender adds it (3D fBM, Scale 5, Detail 2), its Vector unlinked
#              (Generated), its Color output
#   fac        its Fac output; Detail 4.5 (a fraction of an octave), Roughness 0.65, Distortion 0.8,
#              at Object coordinates
#   2d, 4d     2D; 4D with W 0.37: Color, at Object coordinates
#   1d         1D, W 1.37: one colour over the whole plane
#   ramp       Fac through a Color Ramp (black to orange), Scale 3, Detail 6
#   multifractal, ridged, hybrid, hetero   the other noise types (Blender 4.1 and later), Fac,
#              with their Offset and Gain, Lacunarity 2.2, at Object coordinates
#   far        Color, the Mapping moving the point 250000 out along x: times Scale 5 past a million
#              (Blender 4.0 and later wrap such coordinates; 3.4 keeps their few digits)
NOISE_VARIANTS = ("color", "fac", "2d", "4d", "1d", "ramp", "multifractal", "ridged", "hybrid", "hetero", "far")
TYPES = {"multifractal": ("MULTIFRACTAL", 0.0, 1.0), "ridged": ("RIDGED_MULTIFRACTAL", 1.0, 2.0),
         "hybrid": ("HYBRID_MULTIFRACTAL", 0.7, 1.2), "hetero": ("HETERO_TERRAIN", 0.5, 1.0)}


def procedural_noise_scene(variant="color", resolution=(96, 72)):
    """A plane facing the camera, its Emission's Color a Noise Texture set as `variant` says."""
    plane, mat = emissive_plane("Noisy", resolution)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    noise = nodes.new("ShaderNodeTexNoise")
    output = "Color"
    if variant != "color":
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Scale"].default_value = (0.25, 0.25, 0.25)   # (features of several pixels)
        if variant == "far":
            mapping.inputs["Location"].default_value = (250000.0, 0.0, 0.0)
        links.new(nodes.new("ShaderNodeTexCoord").outputs["Object"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], noise.inputs["Vector"])
    if variant == "fac":
        noise.inputs["Detail"].default_value, noise.inputs["Roughness"].default_value = 4.5, 0.65
        noise.inputs["Distortion"].default_value = 0.8
        output = "Fac"
    elif variant in ("2d", "4d", "1d"):
        noise.noise_dimensions = variant.upper()
        if variant != "2d":                                              # (a 2D node hides its W)
            noise.inputs["W"].default_value = 1.37 if variant == "1d" else 0.37
    elif variant == "ramp":
        noise.inputs["Scale"].default_value, noise.inputs["Detail"].default_value = 3.0, 6.0
        output = "Fac"
    elif variant in TYPES:
        noise.noise_type, offset, gain = TYPES[variant]
        for socket in noise.inputs:                                      # (a type hides what it does not use)
            if socket.name in ("Offset", "Gain"):
                socket.default_value = offset if socket.name == "Offset" else gain
        noise.inputs["Lacunarity"].default_value, noise.inputs["Detail"].default_value = 2.2, 3.0
        output = "Fac"
    source = noise.outputs[output if output in noise.outputs else "Factor"]   # (5.0 names Fac Factor)
    if variant == "ramp":
        ramp = nodes.new("ShaderNodeValToRGB")
        ramp.color_ramp.elements[0].position, ramp.color_ramp.elements[0].color = 0.35, (0.0, 0.0, 0.0, 1.0)
        ramp.color_ramp.elements[1].position, ramp.color_ramp.elements[1].color = 0.65, (1.0, 0.5, 0.1, 1.0)
        links.new(source, ramp.inputs["Fac"])
        source = ramp.outputs["Color"]
    links.new(source, nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    plain_world("World", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}


def noise_bump_scene(height="NOISE", resolution=(96, 72)):
    """A white diffuse plane facing the camera whose Normal is a Bump node (Distance 0.4) fed by
    a texture's Fac at Object coordinates (through a Mapping node scaling them by 0.25): `height`
    NOISE (3D fBM, Scale 5, Detail 1), GRADIENT (linear: one even slope) or BRICK (its Fac: the
    mortar, whose steps Gridwalk names in a warning); lit by a sun from the
    upper left, 40 degrees off the plane's normal, in a black world."""
    from scenes import add_light
    plane, mat = emissive_plane("Bumped", resolution)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.remove(nodes["Emission"])
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)
    links.new(diffuse.outputs["BSDF"], nodes["Material Output"].inputs["Surface"])
    texture = nodes.new({"NOISE": "ShaderNodeTexNoise", "GRADIENT": "ShaderNodeTexGradient",
                         "BRICK": "ShaderNodeTexBrick"}[height])
    if height == "NOISE":
        texture.inputs["Detail"].default_value = 1.0
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (0.25, 0.25, 0.25)
    links.new(nodes.new("ShaderNodeTexCoord").outputs["Object"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
    bump = nodes.new("ShaderNodeBump")
    bump.inputs["Distance"].default_value = 0.4
    links.new(texture.outputs[0], bump.inputs["Height"])
    links.new(bump.outputs["Normal"], diffuse.inputs["Normal"])
    plane.data.materials.append(mat)
    add_light("Sun", "SUN", rotation=(math.radians(90 - 40), 0.0, math.radians(-30)), energy=3.0)
    plain_world("World", (0.0, 0.0, 0.0))
    bpy.context.view_layer.update()
    return {}
