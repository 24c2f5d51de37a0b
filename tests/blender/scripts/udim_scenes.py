"""A scene of a UDIM (tiled) image (render_scene.py and export_dump.py build it by name)."""
import os

import bpy
import numpy as np

from scenes import link, reset, shader_material

# tile number -> (width, height) of its random 8-bit colours; 1003 and 1012 are left out
TILES = {1001: (8, 8), 1002: (8, 4), 1011: (4, 16), 1013: (6, 6)}
# the plane's UVs span u in [U0, U1] and v in [V0, V1]: every tile above, two missing ones,
# and (u, v) in (-0.5, 0), which Cycles' truncation puts in tile 1001
U0, U1, V0, V1 = -0.5, 3.5, -0.5, 1.5


def _write_tiles(folder, float_buffer):
    """The tiles' files folder/udim.<number>.png (or .exr): random colours, seeded by number."""
    os.makedirs(folder, exist_ok=True)
    ext = "exr" if float_buffer else "png"
    for number, (w, h) in TILES.items():
        pixels = np.random.default_rng(number).integers(0, 256, (h, w, 4)) / 255.0
        pixels[..., 3] = 1.0
        img = bpy.data.images.new(f"tile {number}", w, h, alpha=True, float_buffer=float_buffer)
        img.pixels.foreach_set(np.ascontiguousarray(pixels, np.float32).reshape(-1))
        img.filepath_raw = os.path.join(folder, f"udim.{number}.{ext}")
        img.file_format = "OPEN_EXR" if float_buffer else "PNG"
        img.save()
        bpy.data.images.remove(img)
    return os.path.join(folder, f"udim.1001.{ext}")


def udim_scene(folder, storage="files", extension="REPEAT", interpolation="Linear", non_color=False,
               remove_tile=None, resolution=(96, 48)):
    """An orthographic camera filling its view with a plane whose Emission colour is an Image
    Texture of the UDIM image TILES (8-bit PNG files in `folder`; storage "exr": float
    OpenEXR files; "packed": the PNG tiles packed into the .blend), its UVs spanning
    [U0, U1] x [V0, V1]; the texture's extension and interpolation as given; remove_tile: a tile
    whose file is deleted once Blender has listed it."""
    scene = reset(resolution=tuple(resolution))
    scene.camera.data.type = "ORTHO"
    scene.camera.data.ortho_scale = U1 - U0
    first = _write_tiles(folder, float_buffer=storage == "exr")
    img = bpy.data.images.load(first)
    img.source = "TILED"                 # (Blender finds the other tiles by their numbers)
    if non_color:
        img.colorspace_settings.name = "Non-Color"
    elif storage == "exr":     # (bpy 5.0 tags the files sRGB, which Cycles then decodes: linear, as they are)
        names = img.colorspace_settings.bl_rna.properties["name"].enum_items.keys()
        img.colorspace_settings.name = "Linear Rec.709" if "Linear Rec.709" in names else "Linear"   # (3.4: Linear)
    if storage == "packed":
        img.pack()
    if remove_tile is not None:
        os.remove(first.replace("1001", str(remove_tile)))
    # (a grid of half-unit quads: Cycles loads only the tiles that some UV corner lies in)
    mesh = bpy.data.meshes.new("Tiled")
    nu, nv = int(2 * (U1 - U0)), int(2 * (V1 - V0))
    us, vs = np.linspace(U0, U1, nu + 1), np.linspace(V0, V1, nv + 1)
    verts = [(u - (U0 + U1) / 2, 0.0, v - (V0 + V1) / 2) for v in vs for u in us]
    faces = [(j * (nu + 1) + i, j * (nu + 1) + i + 1, (j + 1) * (nu + 1) + i + 1, (j + 1) * (nu + 1) + i)
             for j in range(nv) for i in range(nu)]
    mesh.from_pydata(verts, [], faces)
    uv = mesh.uv_layers.new(name="UVMap")
    for loop, data in zip(mesh.loops, uv.data):
        x, _, z = verts[loop.vertex_index]
        data.uv = (x + (U0 + U1) / 2, z + (V0 + V1) / 2)
    plane = link(bpy.data.objects.new("Tiled", mesh))
    mat = shader_material("Tiled", "ShaderNodeEmission", [("Strength", 1.0)])
    tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image, tex.extension, tex.interpolation = img, extension, interpolation
    mat.node_tree.links.new(tex.outputs["Color"], mat.node_tree.nodes["Emission"].inputs["Color"])
    plane.data.materials.append(mat)
    bpy.context.view_layer.update()
    return {"tiles": sorted(int(t.number) for t in img.tiles), "packed": len(img.packed_files)}
