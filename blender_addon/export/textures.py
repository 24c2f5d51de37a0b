"""Blender images and Image / Environment Texture nodes -> gridwalk.Image and gridwalk.Texture.

Each Blender image is read once (img.pixels.foreach_get, rows flipped to put
row 0 at the top) however many nodes use it:
  8-bit images stay 8-bit, tagged "srgb" (decoded to linear by the core)
  unless their colour space is data (Non-Color) or linear; float images
  (HDR, EXR) are already scene-linear in Blender and stay float32.
Packed and generated images read like any other. A missing or unreadable
image (size 0 x 0, no pixels), an image too large to read within
MAX_IMAGE_BYTES, and UDIM tiles become a 1 x 1 magenta image, as Blender
shows them, with one warning naming each.

Node settings: interpolation Closest stays closest, every other mode is
bilinear; extension REPEAT / EXTEND / CLIP / MIRROR as set (any other is read
as REPEAT, with a warning). A texture is (image, interpolation, extension, output,
premultiplied (8-bit images' colour, associated as Cycles gives it; not a
grey + alpha PNG's, which Cycles leaves straight),
unassociated (divided by alpha again where the node's Alpha output is used)):
the Color and Alpha outputs of one node are two textures of one image.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from gridwalk import Image, Texture
from gridwalk.image import srgb_to_linear

from .node_links import InGroup, _source, input_value, tree_nodes
from .object_info import OUTPUTS as INFO_OUTPUTS
from .udim import read_tiles, tile_sizes
from .uv_mapping import VECTOR_IDENTITY


MAGENTA = (1.0, 0.0, 1.0)
# The largest image read: foreach_get needs a float32 copy of every channel
# (4 bytes per value) besides the stored image. 16k x 16k RGBA is 4 GiB.
MAX_IMAGE_BYTES = 2 << 30
# The Image Texture node's projections the core has (gridwalk.Texture.projection)
PROJECTIONS = {"FLAT": "flat", "BOX": "box", "SPHERE": "sphere", "TUBE": "tube"}
INTERPOLATION = {"Closest": "closest"}
EXTENSION = {"REPEAT": "repeat", "EXTEND": "extend", "CLIP": "clip", "MIRROR": "mirror"}


def _alpha_used(node) -> bool:
    """Whether the node's Alpha output feeds a node that reaches the output
    Cycles renders (Cycles drops nodes that lead nowhere, and their links)."""
    alpha = node.outputs.get("Alpha")
    if alpha is None or not alpha.is_linked:
        return False
    if isinstance(node, InGroup):          # (inside a node group: a linked Alpha is taken as used)
        return True
    tree = node.id_data
    output = tree.get_output_node("CYCLES") if hasattr(tree, "get_output_node") else None
    if output is None:                     # (a node group's tree: taken as used)
        return True
    feeding, todo = {output.as_pointer()}, [output]
    while todo:                            # every node upstream of the output
        for socket in todo.pop().inputs:
            for link in socket.links:
                if link.is_valid and not link.is_muted and link.from_node.as_pointer() not in feeding:
                    feeding.add(link.from_node.as_pointer())
                    todo.append(link.from_node)
    return any(link.is_valid and not link.is_muted and link.to_node.as_pointer() in feeding
               for link in alpha.links)


def _png_grey_alpha(img) -> bool:
    """Whether the image is a PNG file on disk stored as grey + alpha (colour
    type 4 in its header; Blender reads it as RGBA, and its depth says 32 as
    for RGBA). Cycles reads such a file itself and leaves its colour as
    stored, straight; a packed one it takes from Blender, as RGBA, and
    associates. False where the header cannot be read."""
    if getattr(img, "file_format", "") != "PNG" or getattr(img, "source", "") != "FILE" or img.packed_file:
        return False
    try:
        import bpy   # (the Blender running the export)
        with open(bpy.path.abspath(img.filepath_raw, library=img.library), "rb") as f:
            head = f.read(26)
    except (OSError, AttributeError, TypeError, ValueError):
        return False
    return len(head) == 26 and head[:8] == b"\x89PNG\r\n\x1a\n" and head[12:16] == b"IHDR" and head[25] == 4


def image_read_bytes(img) -> int:
    """Memory to read and store one image: the float32 copy plus what is kept."""
    w, h = (int(x) for x in img.size)
    c = max(int(getattr(img, "channels", 4)), 1)
    return w * h * c * (4 + (4 if img.is_float else 1))


# 8-bit colour spaces whose decoding the core does as Blender does (sRGB's curve, or none); the
# others (Display P3, Rec.1886, AgX, Filmic, ACES...) are read as sRGB when their name says sRGB,
# else as linear, and named in a warning.
EXACT_SPACES = ("sRGB", "Linear", "Linear Rec.709", "Non-Color", "Raw")


def colorspace_note(img, settings_of=None) -> str | None:
    """Why an 8-bit image's colours differ from Blender's decoding, or None."""
    settings = (settings_of or img).colorspace_settings
    if img.is_float or settings.is_data or settings.name in EXACT_SPACES:
        return None
    return (f"image '{img.name}': its colour space {settings.name!r} is read as "
            f"{'sRGB' if _colorspace(img, settings_of) == 'srgb' else 'linear'} (Gridwalk decodes sRGB, "
            "Linear Rec.709 and Non-Color as Blender does)")


def _colorspace(img, settings_of=None) -> str:
    settings = (settings_of or img).colorspace_settings
    if settings.is_data:
        return "data"
    if img.is_float:
        return "linear"
    return "srgb" if "srgb" in settings.name.lower() else "linear"


def read_image(img, limit: int = MAX_IMAGE_BYTES, settings_of=None):
    """(gridwalk.Image, problem): problem is None, or why the image is magenta.
    settings_of: the image whose colour space the pixels are in (a UDIM tile's tiled image)."""
    if img is None:
        return None, "no image is set"
    if getattr(img, "source", "") == "TILED":
        return None, "an Environment Texture does not read UDIM tiles"
    if getattr(img, "source", "") in ("SEQUENCE", "MOVIE"):
        return None, f"image {img.source.lower()}s are not supported (use a single image)"
    try:
        w, h = (int(x) for x in img.size)
        if w == 0 or h == 0:
            return None, "it has no pixels (0 x 0: missing or unreadable file)"
        need = image_read_bytes(img)
        if need > limit:
            return None, (f"{w} x {h} pixels need an estimated {need / 2**30:.1f} GiB to read, "
                          f"more than the limit of {limit / 2**30:.1f} GiB")
        c = int(img.channels)
        px = np.empty(w * h * c, np.float32)
        img.pixels.foreach_get(px)
    except (RuntimeError, ValueError, MemoryError) as exc:
        return None, f"it cannot be read ({exc})"
    px = px.reshape(h, w, c)[::-1]
    non_finite = 0
    if img.is_float:                # (NaN and Inf, which broken HDR files hold, before the mean and the lighting)
        non_finite = int(px.size - np.count_nonzero(np.isfinite(px)))
        if non_finite:
            px = np.nan_to_num(px, nan=0.0, posinf=65504.0, neginf=0.0)
    space = _colorspace(img, settings_of)
    mean = _mean_rgb(px, space == "srgb")
    associated = mean
    if not img.is_float:
        px = np.rint(np.clip(px, 0.0, 1.0) * 255.0).astype(np.uint8)
        if c in (2, 4):                # the mean of the colour premultiplied as the core does it (in bytes)
            times_alpha = px[..., :c - 1].astype(np.uint32) * px[..., c - 1:] // 255
            associated = _mean_rgb(np.concatenate([times_alpha / 255.0, px[..., c - 1:] / 255.0], axis=2),
                                   space == "srgb")
    image = Image(px, space, name=img.name)
    image.mean_rgb, image.mean_rgb_associated = mean, associated
    image.non_finite = non_finite
    image.grey_alpha_file = _png_grey_alpha(img)   # (read once here: the image cache keeps it)
    image.colorspace_note = colorspace_note(img, settings_of)
    return image, None


def _mean_rgb(px, srgb: bool, step: int | None = None) -> tuple:
    """Average linear RGB of (h, w, c) float pixels in [0, 1] (sRGB-encoded when srgb),
    weighted by cos(latitude) as an equirectangular environment spreads over the sphere;
    every `step`-th row and column (by default about 65,536 of them)."""
    rgb = px[..., :3] if px.shape[2] >= 3 else np.repeat(px[..., :1], 3, axis=2)
    step = step or max(1, int(np.sqrt(rgb.shape[0] * rgb.shape[1] / 65536)))
    rgb = np.asarray(rgb[::step, ::step], np.float64)
    if srgb:
        rgb = srgb_to_linear(rgb)
    rows = rgb.shape[0]
    weight = np.cos((np.arange(rows) + 0.5) / rows * np.pi - np.pi / 2)[:, None, None]
    return tuple(float(x) for x in (rgb * weight).sum(axis=(0, 1)) / (weight.sum() * rgb.shape[1]))


def _stored_bytes(img) -> int:
    w, h = (int(x) for x in img.size)
    return w * h * max(int(getattr(img, "channels", 4)), 1) * (4 if img.is_float else 1)


def scene_texture_bytes(depsgraph) -> int:
    """Memory of the images the depsgraph's materials and world sample (each
    once; those too large to read count as the 1-pixel magenta stand-in), and
    the largest image's float32 read buffer: for the memory estimate, before
    anything is read."""
    seen, stored, largest = set(), 0, 0
    for id_ in depsgraph.ids:
        tree = getattr(id_, "node_tree", None)
        if tree is None or type(id_).__name__ not in ("Material", "World"):
            continue
        for node in tree_nodes(tree):
            img = getattr(node, "image", None) if node.type in ("TEX_IMAGE", "TEX_ENVIRONMENT") else None
            if img is None or img.name_full in seen:
                continue
            seen.add(img.name_full)
            if getattr(img, "source", "") == "TILED" and node.type == "TEX_IMAGE":
                tiles_stored, tile_read = tile_sizes(img)   # (tiles are read one at a time)
                stored, largest = stored + tiles_stored, max(largest, tile_read)
                seen.add(img.name_full)
                continue
            if 0 < image_read_bytes(img) <= MAX_IMAGE_BYTES:
                stored += _stored_bytes(img)
                largest = max(largest, image_read_bytes(img) - _stored_bytes(img))
    return stored + largest


def _material_nodes(depsgraph):
    """Every node of the depsgraph's materials' node trees and their node groups (what the
    memory estimate's questions below look at before the export)."""
    for id_ in depsgraph.ids:
        if type(id_).__name__ == "Material" and getattr(id_, "node_tree", None) is not None:
            yield from tree_nodes(id_.node_tree)


def uses_normal_maps(depsgraph) -> bool:
    """Whether a material of the depsgraph has a Normal Map node (the core then
    keeps a tangent per triangle corner): for the memory estimate."""
    return any(node.type == "NORMAL_MAP" for node in _material_nodes(depsgraph))


def reads_instance_attributes(depsgraph) -> bool:
    """Whether a material reads an Attribute node of the Instancer type (a Geometry Nodes instance
    attribute, read with the copies in bulk: carrier_instances.py)."""
    return any(node.type == "ATTRIBUTE" and getattr(node, "attribute_type", "") == "INSTANCER"
               for node in _material_nodes(depsgraph))


def plain_image(texture) -> bool:
    """Whether a gridwalk.Texture is an image read at the UV map, unmapped in 3-space and
    without a ramp: what the core's normal maps and environments take (texture.h's plain_image)."""
    return (texture.kind == "image" and texture.coordinates == "uv" and not texture.ramp
            and tuple(texture.vector_transform) == VECTOR_IDENTITY and texture.projection == "flat")


def corner_point_arrays(depsgraph) -> int:
    """How many per-corner point arrays (Generated, Object coordinates, object normals) the
    export may write, from the materials' nodes (a procedural texture reads Generated by
    default; a Texture Coordinate node's linked Generated, Object or Normal output): for the
    memory estimate."""
    reads = set()
    for node in _material_nodes(depsgraph):
        if node.type in PROCEDURAL_NODES:
            reads.add("Generated")
        elif node.type == "TEX_COORD":
            reads |= {name for name in ("Generated", "Object", "Normal") if node.outputs[name].is_linked}
        elif node.type == "TEX_IMAGE" and getattr(node, "projection", "FLAT") == "BOX":
            reads.add("Normal")        # (a box projection blends by the object-space normals)
    return len(reads)


def corner_arrays_read(depsgraph) -> dict:
    """Which per-corner arrays the export may write besides the points, from the materials'
    nodes: "uvs" (an image, a UV Map node, a Texture Coordinate node's linked UV output or a
    Normal Map, whose tangents follow the UVs) and "colors" (a Color Attribute or Attribute
    node, or an Object Info node's output: corner colours): for the memory estimate, which
    counts both per triangle."""
    reads = {"uvs": False, "colors": False}
    for node in _material_nodes(depsgraph):
        if node.type in ("TEX_IMAGE", "UVMAP", "NORMAL_MAP") or (
                node.type == "TEX_COORD" and node.outputs["UV"].is_linked):
            reads["uvs"] = True
        elif node.type in ("VERTEX_COLOR", "ATTRIBUTE") or (
                node.type == "OBJECT_INFO" and any(out.is_linked for out in node.outputs if out.name in INFO_OUTPUTS)):
            reads["colors"] = True
    return reads


PROCEDURAL_NODES = ("TEX_CHECKER", "TEX_GRADIENT", "TEX_NOISE", "TEX_VORONOI", "TEX_WAVE", "TEX_MAGIC",
                    "TEX_WHITE_NOISE", "TEX_BRICK", "TEX_MUSGRAVE")   # the patterns gridwalk.Texture models


def noise_wraps() -> bool:
    """Whether this Blender's Perlin noise wraps far coordinates (Texture.noise_wrap: 4.0 and later),
    for the Noise, Wave and Musgrave Textures."""
    import bpy
    return bpy.app.version >= (4, 0, 0)


def noise_fields(node, values: dict) -> dict:
    """gridwalk.Texture fields of a Noise Texture node whose inputs have the values
    `values` (by socket name). Blender before 4.0 has no Lacunarity (2) or Normalize (on)
    and does not wrap the coordinates; before 4.1 it has no type (fBM) and clamps
    Roughness to [0, 1]."""
    roughness = float(values["Roughness"])
    if not hasattr(node, "noise_type"):
        roughness = min(max(roughness, 0.0), 1.0)
    return dict(kind="noise", noise_type=getattr(node, "noise_type", "FBM").lower(),
                dimensions=int(node.noise_dimensions[0]), w=float(values.get("W", 0.0)),
                scale=float(values["Scale"]), detail=float(values["Detail"]), roughness=roughness,
                lacunarity=float(values.get("Lacunarity", 2.0)), distortion=float(values["Distortion"]),
                noise_offset=float(values.get("Offset", 0.0)), noise_gain=float(values.get("Gain", 1.0)),
                normalize=bool(getattr(node, "normalize", True)), noise_wrap=noise_wraps())


def voronoi_fields(node, values: dict) -> dict:
    """gridwalk.Texture fields of a Voronoi Texture node (any feature; values: its
    inputs' by socket name). Blender before 4.0 has no Detail (0: one octave), Roughness,
    Lacunarity or Normalize (off); 5.0 hashes the cells anew (voronoi_pcg)."""
    import bpy
    return dict(kind="voronoi", voronoi_feature=node.feature.lower(), voronoi_metric=node.distance.lower(),
                dimensions=int(node.voronoi_dimensions[0]), w=float(values.get("W", 0.0)),
                scale=float(values["Scale"]), detail=float(values.get("Detail", 0.0)),
                roughness=float(values.get("Roughness", 0.5)), lacunarity=float(values.get("Lacunarity", 2.0)),
                exponent=float(values.get("Exponent", 0.5)), randomness=float(values.get("Randomness", 1.0)),
                smoothness=float(values.get("Smoothness", 1.0)), normalize=bool(getattr(node, "normalize", False)),
                voronoi_pcg=bpy.app.version >= (5, 0, 0))


def musgrave_fields(node, values: dict) -> tuple[dict, float, float]:
    """(gridwalk.Texture fields, gain, bias) of a Musgrave Texture node (Blender 3.x; 4.1 made it
    a Noise Texture): its noise as the Noise Texture of 4.1 computes it after Blender's own
    conversion of the node (versioning_400.cc), unnormalized, Roughness = Lacunarity^-Dimension,
    Detail one less (at most 14); a Detail d below 1 keeps no more than the first octave, and
    fBM, Multifractal and Hybrid then take the value times d (Multifractal plus 1 - d): the
    gain and bias to apply."""
    kind = node.musgrave_type.lower()
    # (Cycles clamps the Detail to [0, 15] first: a negative one gives the first octave times 0)
    detail = min(max(float(values["Detail"]), 0.0), 15.0)
    lacunarity = max(float(values["Lacunarity"]), 1e-5)
    gain, bias = 1.0, 0.0
    if detail >= 1.0:
        detail = min(detail - 1.0, 14.0)
    elif kind not in ("ridged_multifractal", "hetero_terrain"):
        gain, bias, detail = detail, (1.0 - detail if kind == "multifractal" else 0.0), 0.0
    roughness = lacunarity ** -max(float(values["Dimension"]), 1e-5)
    return (dict(kind="noise", noise_type=kind, dimensions=int(node.musgrave_dimensions[0]), w=float(values["W"]),
                 scale=float(values["Scale"]), detail=detail, roughness=roughness, lacunarity=lacunarity,
                 distortion=0.0, noise_offset=float(values["Offset"]), noise_gain=float(values["Gain"]),
                 normalize=False, noise_wrap=noise_wraps()), gain, bias)


def wave_fields(node, values: dict) -> dict:
    """gridwalk.Texture fields of a Wave Texture node (values: its inputs' by socket name).
    Blender 3.4 clamps its Detail to [0, 15] and Detail Roughness to [0, 1] (4.0 and later
    take them as they are) and does not wrap the noise's coordinates."""
    bands = node.wave_type == "BANDS"
    old = not noise_wraps()
    detail, roughness = float(values["Detail"]), float(values["Detail Roughness"])
    if old:
        detail, roughness = min(max(detail, 0.0), 15.0), min(max(roughness, 0.0), 1.0)
    return dict(kind="wave", wave_type=node.wave_type.lower(),
                wave_direction=(node.bands_direction if bands else node.rings_direction).lower(),
                wave_profile={"SIN": "sine", "SAW": "saw", "TRI": "triangle"}[node.wave_profile],
                scale=float(values["Scale"]), distortion=float(values["Distortion"]), detail=detail,
                detail_scale=float(values["Detail Scale"]), roughness=roughness,
                phase=float(values["Phase Offset"]), noise_wrap=not old)


def magic_fields(node, values: dict) -> dict:
    """gridwalk.Texture fields of a Magic Texture node."""
    return dict(kind="magic", depth=int(node.turbulence_depth), scale=float(values["Scale"]),
                distortion=float(values["Distortion"]))


def brick_fields(node, values: dict) -> dict:
    """gridwalk.Texture fields of a Brick Texture node (its Fac: the mortar's share, as grey)."""
    colour = lambda name: tuple(float(c) for c in values[name][:3])
    return dict(kind="brick", color1=colour("Color1"), color2=colour("Color2"), mortar=colour("Mortar"),
                scale=float(values["Scale"]), mortar_size=float(values["Mortar Size"]),
                mortar_smooth=float(values["Mortar Smooth"]), brick_bias=float(values["Bias"]),
                brick_width=float(values["Brick Width"]), row_height=float(values["Row Height"]),
                offset_amount=float(node.offset), offset_frequency=int(node.offset_frequency),
                squash_amount=float(node.squash), squash_frequency=int(node.squash_frequency))


def _signature(img):
    """What an image's pixels depend on; None for an image being edited (always read)."""
    if img is None or getattr(img, "is_dirty", False):
        return None
    return (img.name_full, tuple(img.size), img.source, img.filepath, img.is_float,
            img.colorspace_settings.name, getattr(img, "generated_type", ""), img.packed_file is not None)


def _magenta(name: str):
    """The 1 x 1 magenta image that stands for one that cannot be read (as Blender shows it)."""
    image = Image(np.array([[MAGENTA]], np.float32), "linear", name=name)
    image.mean_rgb = MAGENTA
    return image


class TextureTable:
    """The scene's images (each once) and textures (each distinct node setting once).

    cache: a dict kept between exports (the viewport's MeshCache.images):
    images whose signature is unchanged are not read again."""

    def __init__(self, cache: dict | None = None):
        self.cache = cache if cache is not None else {}
        self._used: set = set()
        self.images: list = []
        self.textures: list = []
        self._image_index: dict = {}
        self._texture_index: dict = {}
        self.problems: dict = {}         # image name -> why it renders magenta
        self.notes: set = set()          # other one-line remarks
        self.cancelled = lambda: False   # (the export's cancel test, while tiles are read on the main thread)

    def _image(self, img) -> int:
        key = img.name_full if img is not None else None
        if key not in self._image_index:
            signature = _signature(img)
            image, problem = self.cache.get(signature) if signature is not None and signature in self.cache \
                else read_image(img)
            if signature is not None:
                self.cache[signature] = (image, problem)
                self._used.add(signature)
            if image is None:
                self.problems[key or "(none)"] = problem
                image = _magenta(f"missing {key}")
            elif getattr(image, "non_finite", 0):
                self.notes.add(f"image '{key}' has {image.non_finite} NaN or infinite values: "
                               "NaN and -Inf are read as 0, +Inf as 65504")
            if getattr(image, "colorspace_note", None):
                self.notes.add(image.colorspace_note)
            self._image_index[key] = len(self.images)
            self.images.append(image)
        return self._image_index[key]

    def _tiles(self, img, cancelled) -> list:
        """[(tile number, image index)] of a tiled (UDIM) image's tiles; a tile that cannot
        be read is the magenta stand-in, its problem noted under the image's name."""
        key = ("tiles", img.name_full)
        if key not in self._image_index:
            signature = _signature(img)
            cached = self.cache.get(("tiles", signature)) if signature is not None else None
            tiles, problems, notes = cached if cached is not None else \
                read_tiles(img, lambda loaded, settings_of: read_image(loaded, settings_of=settings_of), cancelled)
            if signature is not None and not notes:
                self.cache[("tiles", signature)] = (tiles, problems, notes)
                self._used.add(("tiles", signature))
            self.notes.update(notes)
            if problems:
                self.problems[img.name_full] = "; ".join(
                    why if number == 0 else f"tile {number}: {why}" for number, why in sorted(problems.items()))
            indices = []
            for number, image in tiles or [(1001, None)]:
                if getattr(image, "colorspace_note", None):
                    self.notes.add(image.colorspace_note.replace(f"image '{image.name}'", f"image '{img.name}'"))
                if image is None:
                    image = _magenta(f"missing {img.name_full} {number}")
                indices.append((number, len(self.images)))
                self.images.append(image)
            self._image_index[key] = indices
        return self._image_index[key]

    def generated(self, key, make, name: str) -> int:
        """Index of the texture of an image the export computes (a Sky Texture's): make()
        gives its float (H, W, 3) linear pixels, called only when `key` is not cached."""
        if key not in self._image_index:
            if key not in self.cache:
                pixels = make()
                image = Image(pixels, "linear", name=name)
                image.mean_rgb = image.mean_rgb_associated = _mean_rgb(pixels, False, step=1)
                self.cache[key] = (image, None)
            self._used.add(key)
            self._image_index[key] = len(self.images)
            self.images.append(self.cache[key][0])
        # (extend: a ray at the zenith reads the zenith's row, not a blend with the nadir's; the
        # seam behind the image reads its edge column, the same sky)
        return self._add(dict(image=self._image_index[key], interpolation="linear", extension="extend"))

    def texture(self, node, output: str = "Color", coords: dict | None = None, adjust: dict | None = None) -> int:
        """Index of the texture an Image or Environment Texture node's `output` gives,
        at the coordinates `coords` says (Texture's uv_transform, or coordinates and
        vector_transform: uv_mapping.texture_fields; the UV map by default), its value
        adjusted by `adjust` (Texture's channel, gain, bias and clamp: value_nodes.py)."""
        tiled = node.type == "TEX_IMAGE" and getattr(node.image, "source", "") == "TILED"
        tiles = self._tiles(node.image, self.cancelled) if tiled else ()
        image = tiles[0][1] if tiled else self._image(node.image)
        interpolation = INTERPOLATION.get(node.interpolation, "linear")
        extension = EXTENSION.get(getattr(node, "extension", "REPEAT"), "repeat")
        if getattr(node, "extension", "REPEAT") not in EXTENSION:
            self.notes.add(f"image extension {node.extension} is read as Repeat")
        projection = getattr(node, "projection", "FLAT") if node.type == "TEX_IMAGE" else "FLAT"
        if projection not in PROJECTIONS:
            self.notes.add(f"image projection {node.projection} is read as Flat")
        shape = {} if projection not in PROJECTIONS else \
            dict(projection=PROJECTIONS[projection], projection_blend=float(getattr(node, "projection_blend", 0.0)))
        # Cycles' Color output is associated (premultiplied); where the node's
        # Alpha output is used, Cycles divides the filtered colour by alpha again.
        # Data images and channel-packed alpha stay as stored. (Blender holds
        # float images associated already: only 8-bit ones are straight.)
        img = node.image
        has_alpha = (output != "Alpha" and img is not None and not img.colorspace_settings.is_data
                     and getattr(img, "alpha_mode", "STRAIGHT") in ("STRAIGHT", "PREMUL"))
        premultiply = has_alpha and not img.is_float and not getattr(self.images[image], "grey_alpha_file", False)
        unassociate = has_alpha and _alpha_used(node)
        return self._add(dict(image=image, tiles=tuple(tiles), interpolation=interpolation, extension=extension,
                              use_alpha=output == "Alpha", premultiply=premultiply, unassociate=unassociate,
                              **shape, **(coords or {}), **(adjust or {})))

    def attribute(self, fac: bool, adjust: dict | None = None) -> int:
        """Index of a texture of the mesh attribute the material reads (gridwalk.Texture kind
        "attribute": the corner colours at the hit; fac: their mean, an Attribute node's Fac)."""
        return self._add(dict(kind="attribute", use_alpha=fac, **(adjust or {})))

    def procedural(self, node, output: str = "Color", coords: dict | None = None, adjust: dict | None = None,
                   problems: list | None = None) -> int:
        """Index of the texture a procedural texture node's `output` (PROCEDURAL_NODES)
        gives (a Checker's Fac: white and black; a Gradient's Color and Fac are the same grey;
        a Noise's Fac its value, its Color three noises; a Voronoi's Distance, Color, Position
        or W (and Radius, for its N-Sphere Radius feature); a Wave's, Magic's or Brick's
        Fac and a White Noise's Value as use_alpha), as texture() takes coords and
        adjust. Linked inputs other than the Vector take their own values, noted in `problems`."""
        values = {}
        for socket in node.inputs:
            if socket.name == "Vector":
                continue
            source = _source(socket)[0]     # (None for constants: an RGB or Value node, a muted link)
            if source is not None and problems is not None and getattr(socket, "enabled", True):
                problems.append(f"{socket.name} of {node.name!r} ({source.bl_idname}: its own value is used)")
            values[socket.name] = input_value(socket)
        if node.type == "TEX_GRADIENT":
            return self._add(dict(kind="gradient", gradient=node.gradient_type.lower(), **(coords or {}),
                                  **(adjust or {})))
        if node.type == "TEX_NOISE":
            return self._add(dict(noise_fields(node, values), use_alpha=output in ("Fac", "Factor"),
                                  **(coords or {}), **(adjust or {})))
        if node.type == "TEX_VORONOI":
            return self._add(dict(voronoi_fields(node, values), voronoi_output=output.lower(),
                                  **(coords or {}), **(adjust or {})))
        fields = {"TEX_WAVE": wave_fields, "TEX_MAGIC": magic_fields, "TEX_BRICK": brick_fields}
        if node.type in fields:
            return self._add(dict(fields[node.type](node, values), use_alpha=output in ("Fac", "Factor"), **(coords or {}), **(adjust or {})))
        if node.type == "TEX_MUSGRAVE":
            fields, gain, bias = musgrave_fields(node, values)
            adjusted = dict(adjust or {})
            if (gain, bias) != (1.0, 0.0):
                # (its value x gain + bias first, then the adjustments after it: one map)
                g, b = adjusted.get("gain", (1.0, 1.0, 1.0)), adjusted.get("bias", (0.0, 0.0, 0.0))
                adjusted["gain"] = tuple(x * gain for x in g)
                adjusted["bias"] = tuple(x * bias + y for x, y in zip(g, b))
            return self._add(dict(fields, use_alpha=True, **(coords or {}), **adjusted))
        if node.type == "TEX_WHITE_NOISE":
            return self._add(dict(kind="white_noise", dimensions=int(node.noise_dimensions[0]),
                                  w=float(values.get("W", 0.0)), use_alpha=output == "Value",
                                  **(coords or {}), **(adjust or {})))
        if output in ("Fac", "Factor"):          # (5.0 names the output Factor)
            color1, color2 = (1.0, 1.0, 1.0), (0.0, 0.0, 0.0)
        else:
            color1, color2 = (tuple(float(c) for c in values[k][:3]) for k in ("Color1", "Color2"))
        return self._add(dict(kind="checker", color1=color1, color2=color2, scale=float(values["Scale"]),
                              **(coords or {}), **(adjust or {})))

    def with_ramp(self, index: int, stops: tuple, interpolation: str, after: dict | None = None) -> int:
        """Index of texture `index` with a colour ramp (Texture.ramp: (position, R, G, B, A)
        stops in increasing position; Texture.ramp_interpolation) and the steps after it
        (`after`: Texture's ramp_channel, ramp_gain, ramp_bias, ramp_clamp)."""
        base = self.textures[index]
        fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(base)}
        fields.update(ramp=stops, ramp_interpolation=interpolation, **(after or {}))
        return self._add(fields)

    def _add(self, fields: dict) -> int:
        """Index of the texture with these gridwalk.Texture fields (each distinct one once)."""
        key = tuple(sorted(fields.items()))
        if key not in self._texture_index:
            self._texture_index[key] = len(self.textures)
            self.textures.append(Texture(**fields))
        return self._texture_index[key]

    def prune(self):
        """Forget the cached images this export did not use."""
        for signature in [k for k in self.cache if k not in self._used]:
            del self.cache[signature]

    def mean_color(self, index: int) -> tuple:
        """The average colour a texture gives (linear RGB; premultiplied where the
        texture premultiplies): the background colour of an environment world."""
        image = self.images[self.textures[index].image]
        return getattr(image, "mean_rgb_associated", image.mean_rgb) if self.textures[index].premultiply \
            else image.mean_rgb

    def warnings(self) -> list[str]:
        out = [f"Image '{name}' renders magenta: {why}" for name, why in sorted(self.problems.items())]
        return out + sorted(self.notes)
