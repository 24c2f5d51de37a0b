"""The compositor's Denoise node fed with GRIDWALK's Denoising Albedo and
Denoising Normal passes.

usage: <python with bpy> denoise.py OUT_DIR
Renders the glass pane scene under a soft sun (random shadow rays) three times:
  noisy.exr     4 samples per pixel, multilayer (Combined and the passes)
  denoised.exr  the same render through Render Layers -> Denoise -> output
  reference.exr 256 samples per pixel
and writes info.json (the Blender version).
"""
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))


def compositor_tree(bpy, scene):
    """Render Layers -> Denoise (Image, Denoising Albedo, Denoising Normal) -> the output."""
    if hasattr(scene, "compositing_node_group"):            # Blender 5.0+
        tree = bpy.data.node_groups.new("Denoise", "CompositorNodeTree")
        scene.compositing_node_group = tree
        tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        output = tree.nodes.new("NodeGroupOutput")
    else:
        scene.use_nodes = True
        tree = scene.node_tree
        tree.nodes.clear()
        output = tree.nodes.new("CompositorNodeComposite")
    layers = tree.nodes.new("CompositorNodeRLayers")
    denoise = tree.nodes.new("CompositorNodeDenoise")
    tree.links.new(layers.outputs["Image"], denoise.inputs["Image"])
    tree.links.new(layers.outputs["Denoising Albedo"], denoise.inputs["Albedo"])
    tree.links.new(layers.outputs["Denoising Normal"], denoise.inputs["Normal"])
    tree.links.new(denoise.outputs["Image"], output.inputs[0])
    return tree


def render(bpy, scene, path, samples, multilayer):
    settings = scene.render.image_settings
    if hasattr(settings, "media_type"):                     # Blender 5.0+
        settings.media_type = "MULTI_LAYER_IMAGE" if multilayer else "IMAGE"
    settings.file_format = "OPEN_EXR_MULTILAYER" if multilayer else "OPEN_EXR"
    settings.exr_codec, settings.color_depth = "NONE", "32"
    scene.gridwalk.aa_samples = samples
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)


def main(argv):
    import bpy

    import blender_addon
    import scenes

    out_dir = argv[0]
    blender_addon.register()
    scenes.BUILDERS["pane_shadow"](pane="glass")
    scene = bpy.context.scene
    scene.render.engine = "GRIDWALK"
    scene.render.film_transparent = False
    bpy.data.objects["Sun"].data.angle = math.radians(30)
    props = scene.gridwalk
    props.aa, props.shadow, props.shadow_samples = "RANDOM", "RANDOM", 1
    props.denoising_data = True
    scene.render.use_compositing = False
    render(bpy, scene, os.path.join(out_dir, "noisy.exr"), 2, True)
    render(bpy, scene, os.path.join(out_dir, "reference.exr"), 16, False)
    compositor_tree(bpy, scene)
    scene.render.use_compositing = True
    render(bpy, scene, os.path.join(out_dir, "denoised.exr"), 2, False)
    with open(os.path.join(out_dir, "info.json"), "w") as f:
        json.dump({"blender": list(bpy.app.version),
                   "oidn": bool(__import__("_cycles").with_openimagedenoise)}, f)   # Cycles' module


if __name__ == "__main__":
    from blender_addon.scripting import run_main
    run_main(main)
