"""A Voronoi Texture on a plane (render_scene.py and export_dump.py build it by name)."""
from procedural_scenes import emissive_plane, tinted
from scenes import plain_world

# Voronoi variants: how the node is set and which output feeds the Emission's Color. Object
# coordinates come through a Mapping node that scales them by 0.25 (cells of several pixels).
#   distance   the node as Blender adds it (3D F1, Euclidean, Scale 5), Vector unlinked
#              (Generated), its Distance output
#   color      its Color output, at Object coordinates
#   position   its Position output (the point moved by (1, 1, 1): every coordinate positive)
#   f2         F2 with the Manhattan metric, Distance
#   smooth     Smooth F1 (Smoothness 0.8), Color
#   minkowski  F1 with Minkowski exponent 1.5, Randomness 0.6, Distance
#   2d, 4d     2D; 4D with W 0.37: Color
#   1d         1D, W 1.37: one colour over the plane
#   fractal    (Blender 4.0 and later) Detail 2.5, Roughness 0.6, Lacunarity 2.2, Normalize, Distance
#   edge       Distance to Edge (Randomness 0.8), Distance
#   edge_fractal  (Blender 4.0 and later) Distance to Edge over Detail 1.5, Roughness 0.6, Normalize
#   radius     N-Sphere Radius, its Radius output
#   position_ramp  its Position into a Color Ramp's Fac (a vector read as a number: its average)
#   tinted_position_ramp  its Position through a Mix multiplying it by a colour, then into the
#              ramp (the Mix makes it a colour: read as a number, its luminance)
VORONOI_VARIANTS = ("distance", "color", "position", "f2", "smooth", "minkowski", "2d", "4d", "1d", "fractal",
                    "position_ramp", "tinted_position_ramp", "edge", "edge_fractal", "radius")
OUTPUTS = {"color": "Color", "position": "Position", "smooth": "Color", "2d": "Color", "4d": "Color", "1d": "Color",
           "radius": "Radius"}


def voronoi_scene(variant="distance", resolution=(96, 72)):
    """A plane facing the camera, its Emission's Color a Voronoi Texture set as `variant` says."""
    plane, mat = emissive_plane("Cellular", resolution)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    cells = nodes.new("ShaderNodeTexVoronoi")
    if variant != "distance":
        mapping = nodes.new("ShaderNodeMapping")
        mapping.inputs["Scale"].default_value = (0.25, 0.25, 0.25)
        if variant in ("position", "position_ramp", "tinted_position_ramp"):    # (moved to positive coordinates: no negative light)
            mapping.inputs["Location"].default_value = (1.0, 1.0, 1.0)
        links.new(nodes.new("ShaderNodeTexCoord").outputs["Object"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], cells.inputs["Vector"])
    if variant == "f2":
        cells.feature, cells.distance = "F2", "MANHATTAN"
    elif variant == "smooth":
        cells.feature = "SMOOTH_F1"
        cells.inputs["Smoothness"].default_value = 0.8
    elif variant == "minkowski":
        cells.distance = "MINKOWSKI"
        cells.inputs["Exponent"].default_value = 1.5
        cells.inputs["Randomness"].default_value = 0.6
    elif variant in ("2d", "4d", "1d"):
        cells.voronoi_dimensions = variant.upper()
        if variant != "2d":                                              # (a 2D node hides its W)
            cells.inputs["W"].default_value = 1.37 if variant == "1d" else 0.37
    elif variant in ("edge", "edge_fractal"):
        cells.feature = "DISTANCE_TO_EDGE"
        cells.inputs["Randomness"].default_value = 0.8
        if variant == "edge_fractal":
            cells.inputs["Detail"].default_value, cells.inputs["Roughness"].default_value = 1.5, 0.6
            cells.normalize = True
    elif variant == "radius":
        cells.feature = "N_SPHERE_RADIUS"
    elif variant == "fractal":
        cells.inputs["Detail"].default_value, cells.inputs["Roughness"].default_value = 2.5, 0.6
        cells.inputs["Lacunarity"].default_value = 2.2
        cells.normalize = True
    if variant in ("position_ramp", "tinted_position_ramp"):
        ramp = nodes.new("ShaderNodeValToRGB")
        ramp.color_ramp.elements[0].position, ramp.color_ramp.elements[1].position = 0.6, 1.4 / 1.5
        position = cells.outputs["Position"]
        if variant == "tinted_position_ramp":
            position = tinted(mat.node_tree, position, (0.35, 0.8, 1.1, 1.0))
        links.new(position, ramp.inputs["Fac"])
        links.new(ramp.outputs["Color"], nodes["Emission"].inputs["Color"])
    else:
        links.new(cells.outputs[OUTPUTS.get(variant, "Distance")], nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    plain_world("World", (0.0, 0.0, 0.0))
    return {}
