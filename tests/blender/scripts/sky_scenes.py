"""A world lit by a Sky Texture (test_b42): a grey sphere and a white cube on a grey floor
(Diffuse BSDFs),
seen from above the horizon, with the sun low enough to cast long shadows.

sky_scene(variant): "default" is the node as Blender adds it (Nishita in 3.x-4.x, Multiple
Scattering in 5.0); "single" is 5.0's Single Scattering (the default type elsewhere);
"evening" turns the sun round and lowers it (rotation 140 degrees, elevation 6), with
altitude, air, dust / aerosol and ozone changed and a Sun Intensity of 0.5; "mapped" turns
the sky 90 degrees about Z with a Mapping node (without the sun's disc: Blender then has no
Vector input; "mapped_disc" keeps the disc, so the Mapping node is not read); "no_disc" hides the sun's disc;
"preetham" is the Preetham type with its sun low in the back left and a turbidity of 3; "hosek"
is an unread type (Hosek / Wilkie: the viewport colour, with a warning)."""
import math

import bpy

from scenes import reset, shader_material

SKY_VARIANTS = ("default", "single", "evening", "mapped", "mapped_disc", "no_disc", "preetham", "hosek")


def _sky_world(variant):
    world = bpy.data.worlds.new("Sky")
    bpy.context.scene.world = world
    if bpy.app.version < (5, 0, 0):
        world.use_nodes = True
    world.color = (0.2, 0.3, 0.4)
    nodes, links = world.node_tree.nodes, world.node_tree.links
    sky = nodes.new("ShaderNodeTexSky")
    new = bpy.app.version >= (5, 0, 0)
    if variant == "single":
        sky.sky_type = "SINGLE_SCATTERING" if new else "NISHITA"
    elif variant == "preetham":
        sky.sky_type = "PREETHAM"
        sky.sun_direction, sky.turbidity = (-0.5, 0.6, 0.35), 3.0
    elif variant == "hosek":
        sky.sky_type = "HOSEK_WILKIE"
    elif variant in ("no_disc", "mapped"):
        sky.sun_disc = False
    elif variant == "evening":
        sky.sun_rotation, sky.sun_elevation = math.radians(140), math.radians(6)
        sky.altitude, sky.air_density, sky.ozone_density, sky.sun_intensity = 2000.0, 1.6, 3.0, 0.5
        setattr(sky, "aerosol_density" if new else "dust_density", 2.5)
    if variant.startswith("mapped"):
        coords, mapping = nodes.new("ShaderNodeTexCoord"), nodes.new("ShaderNodeMapping")
        mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(90))
        links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
        links.new(mapping.outputs["Vector"], next(s for s in sky.inputs if s.identifier == "Vector"))
    links.new(sky.outputs["Color"], nodes["Background"].inputs["Color"])
    return sky


def _diffuse(name, grey):
    """Lambert in every Blender (3.x's Principled BSDF has Disney's diffuse, which Gridwalk does not model)."""
    return shader_material(name, "ShaderNodeBsdfDiffuse", [("Color", (grey, grey, grey, 1.0))])


def sky_scene(resolution=(96, 64), variant="default", panorama=False, sun_view=False):
    """panorama: the sky alone through an equirectangular panorama, looking along +X (every
    direction, the sun's disc included). sun_view: the sky alone through a 500 mm lens aimed
    at the default sun (15 degrees up, along +Y): its disc 13 pixels of 96 across."""
    scene = reset(resolution=tuple(resolution))
    scene.cycles.max_bounces = 0        # (direct light only in Cycles too: Gridwalk has no diffuse interreflection)
    _sky_world(variant)
    if sun_view:
        scene.camera.location = (0.0, 0.0, 1.0)
        scene.camera.rotation_euler = (math.radians(105), 0.0, 0.0)
        scene.camera.data.lens = 500.0
        bpy.context.view_layer.update()
        return {}
    if panorama:
        data = scene.camera.data
        data.type = "PANO"
        pano = data if hasattr(data, "panorama_type") else data.cycles      # Blender 4.x / 3.x
        pano.panorama_type = "EQUIRECTANGULAR"
        scene.camera.location = (0.0, 0.0, 0.0)
        scene.camera.rotation_euler = (math.radians(90), 0.0, math.radians(-90))
        bpy.context.view_layer.update()
        return {}
    scene.camera.location = (0.0, -9.0, 2.6)
    scene.camera.rotation_euler = (math.radians(80), 0.0, 0.0)
    bpy.ops.mesh.primitive_plane_add(size=40.0)
    bpy.context.object.data.materials.append(_diffuse("Floor", 0.5))
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(-1.3, 0.0, 1.0), segments=48, ring_count=24)
    ball = bpy.context.object
    ball.data.polygons.foreach_set("use_smooth", [True] * len(ball.data.polygons))
    ball.data.materials.append(_diffuse("Ball", 0.6))
    bpy.ops.mesh.primitive_cube_add(size=1.4, location=(1.5, 0.8, 0.7))
    bpy.context.object.data.materials.append(_diffuse("Cube", 0.8))
    bpy.context.view_layer.update()
    return {}
