"""A glTF 2.0 model written here and imported by Blender's own glTF importer
(render_scene.py and export_dump.py build it by name): what the materials of
models from the web look like in Blender, node for node."""
import base64
import json
import math
import os
import struct
import tempfile
import zlib

import bpy
import numpy as np

from scenes import add_light, plain_world, reset

# The material's factors and its base colour's KHR_texture_transform.
FACTORS = {"baseColorFactor": [0.8, 0.6, 0.4, 0.9], "roughnessFactor": 0.7, "metallicFactor": 0.5}
TRANSFORM = {"offset": [0.1, 0.2], "rotation": 0.3, "scale": [2.0, 3.0]}


def png(pixels) -> bytes:
    """An 8-bit RGB or RGBA PNG of `pixels` ((h, w, 3 or 4) uint8, row 0 at the top)."""
    h, w, c = pixels.shape
    rows = b"".join(b"\x00" + pixels[y].astype(np.uint8).tobytes() for y in range(h))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    header = struct.pack(">IIBBBBB", w, h, 8, {3: 2, 4: 6}[c], 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b"")


def _data_uri(kind, data):
    return f"data:{kind};base64," + base64.b64encode(data).decode()


def write_gltf(path):
    """A 2 x 2 quad in the XY plane facing +Z, its material a base colour image (RGBA) with
    FACTORS and TRANSFORM, and a packed occlusion-roughness-metallic image; returns the images."""
    rng = np.random.default_rng(3)
    color, orm = rng.integers(0, 256, (8, 8, 4)), rng.integers(0, 256, (8, 8, 3))
    color[..., 3] = rng.integers(128, 256, (8, 8))
    positions = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    uvs = np.array([[0, 1], [1, 1], [1, 0], [0, 0]], np.float32)            # glTF's v runs down
    indices = np.array([0, 1, 2, 0, 2, 3], np.uint16)
    blob = positions.tobytes() + uvs.tobytes() + indices.tobytes()
    doc = {
        "asset": {"version": "2.0"}, "extensionsUsed": ["KHR_texture_transform"],
        "scenes": [{"nodes": [0]}], "scene": 0, "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1}, "indices": 2, "material": 0}]}],
        "materials": [{"name": "Model", "alphaMode": "BLEND", "pbrMetallicRoughness": {
            "baseColorTexture": {"index": 0, "extensions": {"KHR_texture_transform": TRANSFORM}},
            "metallicRoughnessTexture": {"index": 1}, **FACTORS}}],
        "textures": [{"source": 0}, {"source": 1}],
        "images": [{"uri": _data_uri("image/png", png(color))}, {"uri": _data_uri("image/png", png(orm))}],
        "buffers": [{"byteLength": len(blob), "uri": _data_uri("application/octet-stream", blob)}],
        "bufferViews": [{"buffer": 0, "byteOffset": 0, "byteLength": 48}, {"buffer": 0, "byteOffset": 48, "byteLength": 32},
                        {"buffer": 0, "byteOffset": 80, "byteLength": 12}],
        "accessors": [{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3",
                       "min": [-1, -1, 0], "max": [1, 1, 0]},
                      {"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"},
                      {"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}]}
    with open(path, "w") as f:
        json.dump(doc, f)
    return color, orm


def gltf_model_scene(resolution=(48, 48)):
    """The quad of write_gltf imported by Blender's glTF importer, facing the camera and filling
    its view, lit by a sun from the camera's side, under a grey world."""
    reset(resolution=tuple(resolution))
    if "io_scene_gltf2" not in bpy.context.preferences.addons:
        bpy.ops.preferences.addon_enable(module="io_scene_gltf2")
    folder = tempfile.mkdtemp(dir=bpy.app.tempdir)   # (removed with it by scripting.leave)
    path = os.path.join(folder, "model.gltf")
    color, orm = write_gltf(path)
    bpy.ops.import_scene.gltf(filepath=path)
    model = next(o for o in bpy.context.scene.objects if o.type == "MESH")
    model.scale = (3.5, 3.5, 3.5)          # (the importer turns glTF's +Y up to +Z: the quad faces -Y)
    add_light("Sun", "SUN", (0, -5, 0), (math.radians(80), 0, math.radians(10)), energy=3.0)
    plain_world("World", (0.2, 0.2, 0.2))
    bpy.context.view_layer.update()
    return {"factors": FACTORS, "transform": TRANSFORM}
