"""Scene description records: materials, lights and the camera.

Each is a dataclass whose fields are the fields of the core's record of the
same name (gridwalk._core.Material, Light, Camera, declared in
core/src/material.h, lights.h and camera.h). `to_core()` fills the core's
record field by field: there is no packed layout and no column index. The
defaults are the core's own. Values are validated once, by the core, when
the record enters it (gridwalk.Scene, or `validate()`): ValueError names the
record and the field.
"""
from __future__ import annotations

import numbers
from dataclasses import dataclass, fields, replace

import numpy as np

from . import _core

LIGHT_KINDS = tuple(kind for kind, _, _ in _core.light_kinds())
PROJECTIONS = tuple(kind for kind, _, _ in _core.projections())
INTERPOLATIONS = tuple(kind for kind, _, _ in _core.interpolations())
EXTENSIONS = tuple(kind for kind, _, _ in _core.extensions())
TEXTURE_KINDS = tuple(kind for kind, _, _ in _core.texture_kinds())
TEXTURE_COORDS = tuple(kind for kind, _, _ in _core.texture_coords())
IMAGE_PROJECTIONS = tuple(kind for kind, _, _ in _core.image_projections())
GRADIENTS = tuple(kind for kind, _, _ in _core.gradients())
RAMP_INTERPOLATIONS = tuple(kind for kind, _, _ in _core.ramp_interpolations())
NOISE_TYPES = tuple(kind for kind, _, _ in _core.noise_types())
VORONOI_FEATURES = tuple(kind for kind, _, _ in _core.voronoi_features())
VORONOI_METRICS = tuple(kind for kind, _, _ in _core.voronoi_metrics())
VORONOI_OUTPUTS = tuple(kind for kind, _, _ in _core.voronoi_outputs())
WAVE_TYPES = tuple(kind for kind, _, _ in _core.wave_types())
WAVE_DIRECTIONS = tuple(kind for kind, _, _ in _core.wave_directions())
WAVE_PROFILES = tuple(kind for kind, _, _ in _core.wave_profiles())

_MAT, _LIGHT, _CAM = _core.Material(), _core.Light(), _core.Camera()
_TEX, _WORLD = _core.Texture(), _core.World()


def _f32(x: float) -> float:
    """The shortest decimal of a float32 default (0.8, not 0.800000011920929)."""
    return float(str(np.float32(x)))


def as_floats(value, n: int, where: str) -> tuple:
    """`value` as n floats, or ValueError naming the field (shape and type only)."""
    try:
        v = np.asarray(value, dtype=np.float64).reshape(-1)
    except (TypeError, ValueError):
        raise ValueError(f"{where} must be {n} numbers, got {value!r}") from None
    if v.shape != (n,):
        raise ValueError(f"{where} must have {n} components, got shape {np.shape(value)}")
    return tuple(float(x) for x in v)


def _scalar(value, kind, where: str):
    if isinstance(value, (bool, np.bool_)) and kind is not bool:
        raise ValueError(f"{where} must be a number, got {value!r}")
    if kind is bool:
        if not isinstance(value, (bool, np.bool_)):
            raise ValueError(f"{where} must be True or False, got {value!r}")
        return bool(value)
    if kind is int:
        if not isinstance(value, numbers.Integral):
            raise ValueError(f"{where} must be an integer, got {value!r}")
        if not -2**31 <= int(value) < 2**31:
            raise ValueError(f"{where} = {value} does not fit the core's 32-bit integer")
        return int(value)
    if not isinstance(value, numbers.Real):
        raise ValueError(f"{where} must be a number, got {value!r}")
    return float(value)


def to_core(record, core_type, convert=None):
    """A core record filled from the dataclass `record`, field by field.
    `convert` maps a field name to a function giving the core's value."""
    core = core_type()
    name = type(record).__name__
    for f in fields(record):
        value, where = getattr(record, f.name), f"{name}.{f.name}"
        if convert and f.name in convert:
            value = convert[f.name](value, where)
        elif isinstance(getattr(core, f.name), (tuple, list)):
            value = as_floats(value, len(getattr(core, f.name)), where)
        else:
            value = _scalar(value, type(getattr(core, f.name)), where)
        setattr(core, f.name, value)
    return core


class Record:
    """A dataclass mirroring a core record: CORE is the core's type; converters()
    maps fields to functions giving the core's value where a plain copy won't do."""
    CORE = None

    def converters(self) -> dict:
        return {}

    def to_core(self):
        """The core's record, field by field (shapes and types checked here)."""
        return to_core(self, self.CORE, self.converters())

    def validate(self) -> None:
        """Raise ValueError naming the field if the core would refuse this record."""
        self.to_core().validate()


@dataclass
class Material(Record):
    """Whitted / NFF material. NFF's `f r g b Kd Ks Shine T ior` maps to
    color, kd, ks, shininess, transmittance, ior, with mirror = Ks.
    roughness: 0 = exact mirror and Phong highlights of the shininess
    exponent; > 0 glossy: highlights and mirror reflection take a GGX
    microfacet lobe of alpha = roughness^2 (shininess unused), Fresnel rising
    from ks * 8 / (shininess + 8) at normal incidence (metallic's share: the
    colour) to white at grazing; with transmittance (rough glass) a GGX
    microfacet dielectric reflecting and refracting through each microfacet by
    the exact Fresnel of ior; multiscatter: that lobe keeps the energy
    single scattering loses (Cycles' Multiscatter GGX). emission: self-lit strength
    (color * emission is added to the shaded colour); emission_color: emitted
    radiance added as it is. alpha: coverage in [0, 1] (< 1 lets camera,
    secondary and shadow rays through the uncovered part). metallic in [0, 1]:
    the share of the surface that is metal, whose part of the highlight
    (metallic * (shininess + 8) / (8 ks)) and of the mirror reflection takes
    the colour (a gold Principled BSDF reflects gold); with own_metal_color it
    takes metal_color instead (a Mix Shader of a Diffuse BSDF and a Glossy BSDF
    of another colour: color is the diffuse's, metal_color the glossy's).

    Textures (indices into Scene(textures=...), -1 = none) replace an input
    per hit, sampled at the triangle's corner UVs (Scene(uvs=...)):
    color_texture the colour; roughness_texture the roughness (shininess and
    ks follow, as the Principled mapping does); metallic_texture the metallic
    weight (give the record's non-metal values: kd, ks, transmittance are
    scaled towards a mirror); alpha_texture the alpha; normal_texture a
    tangent-space normal map (Blender's Normal Map node: RGB in [0, 1] is the
    normal in the frame of the triangle's UV tangent dp/du, the bitangent
    following dp/dv, and the shading normal; give it a linear, Non-Color
    image), blended from the shading normal by normal_strength (0 none, 1 the
    map, more exaggerates, as Cycles' Strength); emission_texture the
    emitted colour, times emission_color (Principled's Emission Color fed by
    an image, emission_color its Emission Strength); bump_texture a height
    map (Blender's Bump node): the normal (after any normal map) becomes
    normalize(n - bump_distance x the height's gradient along the surface,
    its part along n removed along the geometric normal), blended with n by
    bump_strength; a negative distance bumps inwards (any texture: an image at
    the UV map by its texels' slopes, a procedural one or one at other
    coordinates by central differences of its pattern). A
    texture feeding a scalar gives its alpha channel when its use_alpha is set, else its
    luminance. vertex_color: the colour is the triangle's corner colours
    (Scene(colors=...)) interpolated; with a color_texture, the texture's
    colour times them (an image multiplied by a colour attribute).
    emits_light: the material's triangles also light other surfaces with what
    they emit (color * emission + emission_color, textures applied), from both
    sides, sampled as area lights are (Cycles' mesh lights); spheres and
    cylinders do not. tints_refraction: the colour tints what the surface
    refracts, also along shadow rays through it (coloured glass: Cycles'
    Principled transmission and Glass BSDF); tints_reflection: and what it
    reflects (the Glass BSDF). tint_sqrt: with tints_refraction, each crossing
    tints by the colour's square root, so that light entering and leaving a
    closed object is tinted by the colour (Cycles 4.0+'s Principled BSDF).
    NFF's transmission is untinted.
    dielectric_reflection: the share of the surface that is neither mirror nor
    transmittance reflects the scene (not only the lamps) by its specular
    layer: rays along the roughness's lobe (the mirror direction at 0),
    weighted by the exact Fresnel of the IOR whose reflectance at normal
    incidence is (ks * 8 / (shininess + 8) - metallic) / (1 - metallic), as Cycles'
    Principled BSDF reflects; NFF's Phong highlight reflects only lamps.
    layered_diffuse: the diffuse lies under that specular layer and gets kd
    times 1 - the layer's albedo seen from the viewer (what its rays return
    from a white world: 0.04 head-on at F0 0.04, more at grazing),
    as Blender 4.0+'s Principled BSDF; without it the layer adds to kd.
    holdout: a holdout (Cycles' Holdout shader): camera rays that meet it see
    black and leave the film clear there (RenderJob.holdout gives the share of
    each pixel; alpha excludes it); other rays see it black; it casts shadows.
    holdout_camera: held out from camera rays only (Blender's object and
    collection Holdout): other rays see the material, and its cut-outs stay.
    shadow_catcher: Blender's object Shadow Catcher: camera rays see what lies
    behind the surface darkened by the share of light the scene keeps from it
    (a white diffuse surface's light there with shadows over without, per
    channel); on a transparent film that shadow is black coverage (alpha 1 -
    the share), for compositing over footage; other rays see the material.
    visible_camera, visible_glossy, visible_transmission: camera rays,
    glossy reflection rays and refraction rays see the surface (off: they
    pass through it, as through an alpha cut-out); visible_shadow: it casts
    shadows (off: shadow rays pass) — Blender's object Visibility."""
    color: tuple = _MAT.color
    kd: float = _f32(_MAT.kd)
    ks: float = _MAT.ks
    shininess: float = _MAT.shininess
    transmittance: float = _MAT.transmittance
    ior: float = _MAT.ior
    mirror: float = _MAT.mirror
    metallic: float = _MAT.metallic
    own_metal_color: bool = _MAT.own_metal_color
    metal_color: tuple = _MAT.metal_color
    roughness: float = _MAT.roughness
    emission: float = _MAT.emission
    emission_color: tuple = _MAT.emission_color
    alpha: float = _MAT.alpha
    color_texture: int = _MAT.color_texture
    roughness_texture: int = _MAT.roughness_texture
    metallic_texture: int = _MAT.metallic_texture
    alpha_texture: int = _MAT.alpha_texture
    normal_texture: int = _MAT.normal_texture
    normal_strength: float = _MAT.normal_strength
    emission_texture: int = _MAT.emission_texture
    bump_texture: int = _MAT.bump_texture
    bump_distance: float = _MAT.bump_distance
    bump_strength: float = _MAT.bump_strength
    vertex_color: bool = _MAT.vertex_color
    emits_light: bool = _MAT.emits_light
    tints_refraction: bool = _MAT.tints_refraction
    tint_sqrt: bool = _MAT.tint_sqrt
    tints_reflection: bool = _MAT.tints_reflection
    multiscatter: bool = _MAT.multiscatter
    dielectric_reflection: bool = _MAT.dielectric_reflection
    layered_diffuse: bool = _MAT.layered_diffuse
    holdout: bool = _MAT.holdout
    holdout_camera: bool = _MAT.holdout_camera
    shadow_catcher: bool = _MAT.shadow_catcher
    visible_camera: bool = _MAT.visible_camera
    visible_glossy: bool = _MAT.visible_glossy
    visible_transmission: bool = _MAT.visible_transmission
    visible_shadow: bool = _MAT.visible_shadow
    CORE = _core.Material


def _choice(choices, enum):
    def convert(value, where):
        if value not in choices:
            raise ValueError(f"{where} must be one of {list(choices)}, got {value!r}")
        return getattr(enum, value)
    return convert


@dataclass
class Texture(Record):
    """How a material (or the world) samples an image or a procedural pattern.
    kind: image | attribute (Blender's Attribute node: the triangles' corner colours,
    Scene(colors=...), at the hit; use_alpha: their mean, its Fac; no image) |
    checker (Blender's Checker Texture: color1 and color2, RGB,
    in alternating cubes of side 1 / scale, as Cycles lays them; no image) |
    gradient (Blender's Gradient Texture, grey: gradient = linear | quadratic
    | easing | diagonal | spherical | quadratic_sphere | radial; no image) |
    noise (Blender's Noise Texture as Cycles evaluates it; no image):
    Perlin noise of the point x scale in dimensions 1 (w x scale), 2
    (x, y), 3 (the point) or 4 (the point and w x scale), first moved by
    distortion x noise, summed over 1 + detail octaves (detail in [0, 15]; a
    fraction blends the last octave in), each lacunarity times finer and
    roughness times as strong, as noise_type = fbm | multifractal |
    hybrid_multifractal | ridged_multifractal | hetero_terrain says
    (noise_offset, noise_gain: the multifractals' Offset and Gain); fbm with
    normalize maps the sum into about [0, 1]; noise_wrap: the coordinates wrap
    every 100000 and move by 1/2 from a million on (Blender 4.0 and later;
    3.4 takes them as they are). Its colour is Blender's Color output;
    use_alpha gives its Fac (the value, as grey); a value that overflows is 0.
    | voronoi (Blender's Voronoi Texture as Cycles evaluates it; no image): one
    point per unit cell of the point x scale (in `dimensions`, w as for
    noise) moved off the cell's corner by randomness (0-1); voronoi_feature =
    f1 (the nearest point) | f2 (the second nearest) | smooth_f1 (all blended
    by smoothness) | distance_to_edge (the distance to the nearest cell
    border, its Distance output) | n_sphere_radius (half the distance from
    the nearest point to its own nearest, its Radius output), by voronoi_metric = euclidean | manhattan | chebychev |
    minkowski (with exponent); summed over 1 + detail octaves (roughness,
    lacunarity; normalize divides by the largest distance); voronoi_output =
    distance | color | position | w | radius picks what the colour is (distance, w
    and radius as grey; an output the feature does not give is 0); voronoi_pcg: cells hashed as Blender 5.0 hashes them (PCG of
    their integer coordinates; 1D keeps lookup3), else as Blender 4.5 and
    before (lookup3 of their corners' float bits). (detail, roughness,
    lacunarity and normalize default to the Noise node's values; Blender's
    Voronoi node has detail 0 and normalize off.)
    | wave (Blender's Wave Texture; no image): wave_type = bands (along
    wave_direction = x | y | z | diagonal) | rings (about wave_direction = x |
    y | z, or spherical), 20 per unit of the point x scale, moved by phase and
    by distortion x fBM noise of the point x detail_scale (detail, roughness;
    noise_wrap as for noise), through wave_profile = sine | saw | triangle;
    grey, alpha the same (its Fac). | magic (Blender's Magic Texture):
    sines and cosines of the point (modulo 2 pi) x scale nested depth (0-10)
    times, each times distortion; alpha the colour's average (its Fac). | white_noise
    (Blender's White Noise Texture): hashes of the bits of the point's
    coordinates in `dimensions` (w as the fourth; no scale); use_alpha gives
    its Value. | brick (Blender's Brick Texture), in the (x, y) plane of the
    point x scale: rows row_height high of bricks brick_width wide, every
    offset_frequency-th row shifted by offset_amount of a brick and every
    squash_frequency-th row's bricks squash_amount as wide (neither if either
    frequency is 0); each brick color1 tinted towards color2 by a hashed
    amount + brick_bias, in mortar (a colour) mortar_size wide, its edge
    blended over mortar_smooth; use_alpha gives the mortar's share (its Fac).
    ramp: a colour ramp the value goes through last (Blender's Color Ramp
    node in RGB mode): stops of 5 numbers, (position, R, G, B, A), in
    increasing position, at most 256 (a flat sequence of 5n numbers is taken
    too; None: no ramp); its input is the value after channel, gain, bias and clamp, grey as
    it is, else its luminance; ramp_interpolation: linear | ease | constant.
    image: a gridwalk.Image, or an index into Scene(images=...); an Image used
    by several textures is stored once. coordinates: uv (the hit's (u, v, 0)
    from Scene(uvs=...)) | generated (Blender's Generated coordinates from
    Scene(generated=...)) | object (Blender's Object coordinates from
    Scene(object_coords=...)) | position (the point in world space: Blender's
    Geometry Position, and through vector_transform another object's Object
    coordinates) | normal (Blender's Normal coordinates: the shading normal in
    its object's space, from Scene(object_normals=...), turned over on a back
    face) | camera (the point in the rendering camera's space: x right, y up, z
    forward) | window (the point's place in the image, (0, 0) at its
    bottom-left corner and (1, 1) at its top-right, z 0; under a panoramic
    camera where its direction lies in the projection's square) | reflection (the view direction mirrored about the shading
    normal, world space) | geometry_normal, true_normal (Blender's Geometry
    node's Normal and True Normal: the shading and the geometric normal in
    world space, turned over on a back face) | incoming (its Incoming: the unit
    direction back along the ray); generated, object, normal and position on
    triangles only. A bump map at any of the normals, reflection or incoming
    bends nothing (as in Cycles, whose bump takes them as fixed), nor does one
    at window coordinates (not computed). vector_transform: 12 numbers, a
    row-major 3 x 4 affine map applied to that point (Blender's Mapping node;
    the identity by default); an image then takes the point's (x, y) as its
    (u, v), mapped on by uv_transform. Normal maps and the world's
    environment take images at the UV map only. projection (an image's, Blender's Image Texture
    Projection, as Cycles projects): flat (the point's x and y) | box (three flat lookups along the
    object's axes blended by its object-space normal, Scene(object_normals=...), projection_blend
    wide; not bumped) | sphere | tube (the angles of 2 (point - 0.5) about the origin, or about z
    and the height along it). interpolation: linear | closest. extension: repeat | extend
    | clip (transparent black outside) | mirror (every other tile flipped). use_alpha: the image's alpha channel
    (Blender's Alpha output): a scalar input takes it instead of the colour's
    luminance, a colour input as grey. premultiply: the colour is multiplied by
    alpha before filtering (an 8-bit image's in its bytes; Cycles' associated
    colour); unassociate: divided by it after filtering, before an 8-bit sRGB
    image is decoded (where alpha is not 0 or 1; Cycles' Color output when the
    node's Alpha output is used). uv_transform: 6 numbers (a, b, c, d, e, f):
    the texture coordinates are mapped before the lookup, u' = a u + b v + c,
    v' = d u + e v + f (Blender's Mapping node on the UV map; the identity by
    default; a world's environment takes environment_rotation instead).
    tiles: UDIM tiles (Blender's tiled images), a sequence of (tile number,
    image) pairs, each image a gridwalk.Image or an index into
    Scene(images=...); empty: the texture reads `image` alone (which a tiled
    texture may leave None: its first tile's image is taken). A tiled texture
    reads, at its (mapped) (u, v), the tile numbered 1001 + 10 int(v) + int(u)
    (int truncating toward zero, as Cycles picks the tile) at (u - int(u),
    v - int(v)), extended within the tile as `extension` says; where no tile
    lies (a tile not given, u <= -1 or u >= 10, v <= -1) it reads magenta,
    Cycles' colour for a missing texture. Not for a world's environment.
    channel, gain, bias, clamp: what the value goes through before a material
    reads it (Blender's Separate Color, Math, Mix and Invert nodes): channel -1
    the colour, 0, 1, 2 its red, green or blue as grey, 3 its luminance as
    grey, 4 the average of the three as grey (a vector read as a number, as
    Cycles converts it) (use_alpha: the alpha as grey); then value x gain + bias (3 numbers
    each, channel by channel); then clamped to [0, 1] if clamp. The defaults
    change nothing; an environment takes none of them. ramp_channel,
    ramp_gain, ramp_bias, ramp_clamp: the same steps taken after the ramp, on
    its colour (the nodes between a Color Ramp and the shader's input); only
    with a ramp."""
    image: object = None
    kind: str = TEXTURE_KINDS[0]
    coordinates: str = TEXTURE_COORDS[0]
    vector_transform: tuple = tuple(_TEX.vector_transform)
    color1: tuple = tuple(_f32(x) for x in _TEX.color1)
    color2: tuple = tuple(_f32(x) for x in _TEX.color2)
    scale: float = _f32(_TEX.scale)
    gradient: str = GRADIENTS[0]
    noise_type: str = NOISE_TYPES[0]
    dimensions: int = _TEX.dimensions
    w: float = _f32(_TEX.w)
    detail: float = _f32(_TEX.detail)
    roughness: float = _f32(_TEX.roughness)
    lacunarity: float = _f32(_TEX.lacunarity)
    distortion: float = _f32(_TEX.distortion)
    noise_offset: float = _f32(_TEX.noise_offset)
    noise_gain: float = _f32(_TEX.noise_gain)
    normalize: bool = _TEX.normalize
    noise_wrap: bool = _TEX.noise_wrap
    voronoi_feature: str = VORONOI_FEATURES[0]
    voronoi_metric: str = VORONOI_METRICS[0]
    voronoi_output: str = VORONOI_OUTPUTS[0]
    exponent: float = _f32(_TEX.exponent)
    randomness: float = _f32(_TEX.randomness)
    smoothness: float = _f32(_TEX.smoothness)
    voronoi_pcg: bool = _TEX.voronoi_pcg
    wave_type: str = WAVE_TYPES[0]
    wave_direction: str = WAVE_DIRECTIONS[0]
    wave_profile: str = WAVE_PROFILES[0]
    detail_scale: float = _f32(_TEX.detail_scale)
    phase: float = _f32(_TEX.phase)
    depth: int = _TEX.depth
    mortar: tuple = tuple(_f32(x) for x in _TEX.mortar)
    mortar_size: float = _f32(_TEX.mortar_size)
    mortar_smooth: float = _f32(_TEX.mortar_smooth)
    brick_bias: float = _f32(_TEX.brick_bias)
    brick_width: float = _f32(_TEX.brick_width)
    row_height: float = _f32(_TEX.row_height)
    offset_amount: float = _f32(_TEX.offset_amount)
    offset_frequency: int = _TEX.offset_frequency
    squash_amount: float = _f32(_TEX.squash_amount)
    squash_frequency: int = _TEX.squash_frequency
    ramp: tuple = ()
    ramp_interpolation: str = RAMP_INTERPOLATIONS[0]
    interpolation: str = INTERPOLATIONS[0]
    extension: str = EXTENSIONS[0]
    projection: str = IMAGE_PROJECTIONS[0]
    projection_blend: float = _f32(_TEX.projection_blend)
    use_alpha: bool = _TEX.use_alpha
    premultiply: bool = _TEX.premultiply
    unassociate: bool = _TEX.unassociate
    uv_transform: tuple = tuple(_TEX.uv_transform)
    tiles: tuple = ()
    channel: int = _TEX.channel
    gain: tuple = tuple(_TEX.gain)
    bias: tuple = tuple(_TEX.bias)
    clamp: bool = _TEX.clamp
    ramp_channel: int = _TEX.ramp_channel
    ramp_gain: tuple = tuple(_TEX.ramp_gain)
    ramp_bias: tuple = tuple(_TEX.ramp_bias)
    ramp_clamp: bool = _TEX.ramp_clamp
    CORE = _core.Texture

    def converters(self) -> dict:
        def image(value, where):
            if value is None and self.kind != "image":
                return -1
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, numbers.Integral):
                raise ValueError(f"{where} must be a gridwalk.Image or an index into Scene(images=...), "
                                 f"got {type(value).__name__}")
            return _scalar(value, int, where)
        def ramp(value, where):
            if value is None:
                return []
            try:
                flat = np.asarray(value, dtype=np.float64).reshape(-1)
            except (TypeError, ValueError):
                raise ValueError(f"{where} must be stops of 5 numbers (position, R, G, B, A)") from None
            if flat.size % 5:
                raise ValueError(f"{where} must be stops of 5 numbers (position, R, G, B, A), got {flat.size} numbers")
            return [float(x) for x in flat]
        def tiles(value, where):
            try:
                pairs = [tuple(pair) for pair in (value or ())]
            except TypeError:
                raise ValueError(f"{where} must be (tile number, image) pairs") from None
            flat = []
            for k, pair in enumerate(pairs):
                if len(pair) != 2:
                    raise ValueError(f"{where}[{k}] must be a (tile number, image) pair, got {len(pair)} values")
                flat += [_scalar(pair[0], int, f"{where}[{k}] tile number"), image(pair[1], f"{where}[{k}] image")]
            return flat
        return {"image": image, "ramp": ramp, "tiles": tiles, "interpolation": _choice(INTERPOLATIONS, _core.Interpolation),
                "extension": _choice(EXTENSIONS, _core.Extension), "kind": _choice(TEXTURE_KINDS, _core.TextureKind),
                "coordinates": _choice(TEXTURE_COORDS, _core.TextureCoords),
                "projection": _choice(IMAGE_PROJECTIONS, _core.ImageProjection),
                "gradient": _choice(GRADIENTS, _core.Gradient),
                "noise_type": _choice(NOISE_TYPES, _core.NoiseType),
                "voronoi_feature": _choice(VORONOI_FEATURES, _core.VoronoiFeature),
                "voronoi_metric": _choice(VORONOI_METRICS, _core.VoronoiMetric),
                "voronoi_output": _choice(VORONOI_OUTPUTS, _core.VoronoiOutput),
                "wave_type": _choice(WAVE_TYPES, _core.WaveType),
                "wave_direction": _choice(WAVE_DIRECTIONS, _core.WaveDirection),
                "wave_profile": _choice(WAVE_PROFILES, _core.WaveProfile),
                "ramp_interpolation": _choice(RAMP_INTERPOLATIONS, _core.RampInterpolation)}


@dataclass
class World(Record):
    """What surrounds the scene besides the background colour.

    ambient: Whitted's ambient light I_a: every surface adds
    color * kd * ambient, the light a diffuse surface gets from a uniform
    world of that radiance when nothing blocks its view of it (there is no
    occlusion: a crease gets as much as a roof). environment: an index into
    Scene(textures=...) of an equirectangular image (Z up; its centre looks
    along +X) that rays which miss everything see, times
    environment_strength; -1: they see the background colour.
    environment_rotation: 9 numbers, a row-major rotation R: the image is
    looked up along R d for a direction d (Blender's Mapping node rotating
    the environment); the identity by default.
    environment_light: surfaces also get the environment's diffuse light,
    color * kd * E(n) / pi for the irradiance E its image (times
    environment_strength) sends on the shading normal n (a table over
    64 x 32 normals of its exact cosine integral, interpolated), added to
    ambient and likewise unoccluded unless RenderSettings.world_shadows. transparent:
    camera rays that miss see nothing (RGB 0, alpha 0: a premultiplied
    transparent film); reflections still see the environment. inset: a texture
    index showing a small part of the environment in detail (a sky's sun:
    gridwalk.sky.sky_inset), -1 none: rays that miss see it within the square
    |x / z|, |y / z| < inset_extent of inset_frame (9 numbers, row-major
    orthonormal rows: the square's x, y and centre z axes in the environment
    image's frame), its u along x and v along y; lighting reads the environment
    alone."""
    ambient: tuple = _WORLD.ambient
    environment: int = _WORLD.environment
    environment_strength: float = _WORLD.environment_strength
    environment_light: bool = _WORLD.environment_light
    environment_rotation: tuple = tuple(_WORLD.environment_rotation)
    transparent: bool = _WORLD.transparent
    inset: int = _WORLD.inset
    inset_frame: tuple = tuple(_WORLD.inset_frame)
    inset_extent: float = _WORLD.inset_extent
    CORE = _core.World


def _light_kind(value, where):
    if value not in LIGHT_KINDS:
        raise ValueError(f"{where} must be one of {list(LIGHT_KINDS)}, got {value!r}")
    return getattr(_core.LightKind, value)


@dataclass
class Light(Record):
    """A light. kind: point | sphere | rect | disk | ellipse | sun | spot.

    position: centre (point, sphere, rect, disk, ellipse, spot).
    color: RGB radiant intensity scale (already multiplied by strength).
    radius: sphere / disk radius (a point light with radius > 0 is a sphere; a spot
    with radius > 0 is a sphere whose cone weighs each sampled point, as in Cycles).
    size: (w, h) of a rect light, or an ellipse's diameters, along axis_u and axis_v.
    axis_u, axis_v: orientation of rect / disk / ellipse lights (emitting along u x v).
    direction: direction light travels (sun), or spot axis.
    angle: sun angular diameter (radians); whatever the angle, a surface facing the sun gets its
    colour as irradiance, as in Cycles 4.0 and later (its disc's radiance is colour / (pi sin^2 of half
    the angle), in the units of the other lights).
    spot_size: full cone angle (radians); spot_blend: 0..1 soft edge.
    inverse_square: divide by distance^2 (physical falloff); off for NFF.
    casts_shadows: False lights every point facing it, through any object (Blender's Cast Shadow off).
    visible_diffuse, visible_glossy, visible_transmission: the light object's Ray Visibility, as
    Cycles reads it: False leaves out its diffuse light; its highlights and what glossy and sharp
    mirror rays see of its shape; what refraction rays see of its shape, and its light that
    transparent shadows would carry through glass.
    soft_falloff: a sphere light (or a spot with a radius) is, as in Cycles, a Lambertian disk facing the
    point it lights (True, Blender's Soft Falloff, its default), or a sphere of uniform radiance (False),
    which near the light lights like a point light at its centre (see core/src/sphere_light.h); for
    lights with inverse_square only (one without falloff averages its disk's points: soft shadows).
    Area lights (rect, disk, ellipse) emit along `direction` with a cosine falloff.
    """
    position: tuple = _LIGHT.position
    color: tuple = _LIGHT.color
    kind: str = LIGHT_KINDS[0]
    radius: float = _LIGHT.radius
    size: tuple = tuple(_LIGHT.size)
    axis_u: tuple = _LIGHT.axis_u
    axis_v: tuple = _LIGHT.axis_v
    direction: tuple = _LIGHT.direction
    angle: float = _LIGHT.angle
    spot_size: float = _LIGHT.spot_size
    spot_blend: float = _f32(_LIGHT.spot_blend)
    inverse_square: bool = _LIGHT.inverse_square   # NFF lights have no falloff; Blender's do
    casts_shadows: bool = _LIGHT.casts_shadows
    soft_falloff: bool = _LIGHT.soft_falloff
    visible_diffuse: bool = _LIGHT.visible_diffuse
    visible_glossy: bool = _LIGHT.visible_glossy
    visible_transmission: bool = _LIGHT.visible_transmission
    CORE = _core.Light

    def converters(self) -> dict:
        return {"kind": _light_kind}


def _projection(value, where):
    if value not in PROJECTIONS:
        raise ValueError(f"{where} must be one of {list(PROJECTIONS)}, got {value!r}")
    return getattr(_core.Projection, value)


@dataclass
class Camera(Record):
    """The camera. projection: perspective | orthographic | a panorama, as
    Cycles projects each: equirectangular | fisheye_equidistant |
    fisheye_equisolid | fisheye_polynomial | mirror_ball | cubemap_face |
    central_cylindrical.

    eye, target, up: position, a point on the view axis, and the up hint; eye
    and target are kept in double, so a camera far from the origin keeps its
    viewing direction.
    fov: perspective: the vertical field of view in degrees.
    ortho_height: orthographic: the height of the view in scene units.
    width, height: image size in pixels; pixel_aspect: a pixel's width /
    height (2 = wide pixels: the view shows twice the width per pixel).
    shift = (sx, sy) moves the image window, in units of the image plane's
    larger side (Blender's convention); a panorama's, in units of its unit
    square (Cycles').
    longitude, latitude: equirectangular: the (min, max) angles in radians
    spanned by the image from left to right and from bottom to top; the
    image centre at longitude 0, latitude 0 looks at the target.
    Central cylindrical: longitude as above, cylinder_height the (bottom, top)
    heights spanned on a cylinder of radius 1 around the view axis' upright.
    window = (u0, u1, v0, v1): the part of a panorama's unit square the image
    spans, left to right and bottom to top (before the shift; the viewport
    stretches it to show the camera's frame).
    fisheye_fov (radians): the fisheyes' widest angle across the view axis;
    fisheye_equidistant fills the image's ellipse with it, fisheye_equisolid
    maps the angle theta to 2 fisheye_lens sin(theta / 2) mm on a sensor of
    size sensor = (width, height) mm, and fisheye_polynomial maps a radius r mm
    to theta = -(k0 + k1 r + ... + k4 r^4), polynomial = (k0, ..., k4). Image
    positions beyond the fisheye's circle (or a mirror ball's) get no ray
    (Camera.rays: a zero direction): black and opaque, as in Cycles, also on a
    transparent film. mirror_ball: the world reflected by a
    ball filling the image. cubemap_face: 90 x 90 degrees, equiangular.
    aperture is the thin-lens radius (0 = pinhole); focus_distance defaults to
    |target - eye|. blades: 0 (or under 3) a round aperture, else a regular
    polygon of that many corners on the aperture's radius, turned by
    blade_rotation (radians; at 0 an edge faces the image's right);
    aperture_ratio > 1 narrows the aperture across by 1 / ratio (anamorphic
    bokeh), all as Cycles samples its aperture. hither, yon: rays start and end this far along the view
    axis (near and far clipping; a panorama clips by distance from the eye).
    origin_ahead: Camera texture coordinates are measured from the point this
    far along the view axis from the eye (0: the eye; an orthographic viewport
    view, whose eye moves back to its near plane, sets the view point).
    mirror: flip the image left to right (a camera with a negative scale).
    """
    eye: tuple = _CAM.eye
    target: tuple = _CAM.target
    up: tuple = _CAM.up
    fov: float = _CAM.fov
    width: int = _CAM.width
    height: int = _CAM.height
    aperture: float = _CAM.aperture
    focus_distance: float | None = None
    blades: int = _CAM.blades
    blade_rotation: float = _CAM.blade_rotation
    aperture_ratio: float = _CAM.aperture_ratio
    shift: tuple = tuple(_CAM.shift)
    hither: float = _CAM.hither
    origin_ahead: float = _CAM.origin_ahead
    projection: str = PROJECTIONS[0]
    ortho_height: float = _CAM.ortho_height
    pixel_aspect: float = _CAM.pixel_aspect
    longitude: tuple = tuple(_f32(x) for x in _CAM.longitude)
    latitude: tuple = tuple(_f32(x) for x in _CAM.latitude)
    window: tuple = tuple(_CAM.window)
    fisheye_fov: float = _CAM.fisheye_fov
    fisheye_lens: float = _CAM.fisheye_lens
    sensor: tuple = tuple(_CAM.sensor)
    polynomial: tuple = tuple(_CAM.polynomial)
    cylinder_height: tuple = tuple(_CAM.cylinder_height)
    yon: float = _CAM.yon
    mirror: bool = _CAM.mirror
    CORE = _core.Camera

    @property
    def panoramic(self) -> bool:
        """Whether the projection is one of the panoramas (not perspective or orthographic)."""
        return self.projection not in ("perspective", "orthographic")

    def resized(self, width: int, height: int) -> "Camera":
        """This camera for a width x height image. The view keeps its vertical
        extent (fov, ortho_height, a panorama's ranges); a fisheye that maps
        millimetres on a sensor (equisolid, polynomial) keeps the sensor's
        height, and its width changes with the image's aspect, so its circle
        stays round (the same size is the same camera). (A panorama that spans
        its unit square, such as equirectangular or the equidistant fisheye's
        ellipse, stretches with the image. Blender, rendering at another size,
        fits its sensor anew: with AUTO fit on a wide image it keeps the width.)"""
        width, height = _scalar(width, int, "width"), _scalar(height, int, "height")
        if width < 1 or height < 1:
            raise ValueError(f"Camera.resized: the image size must be at least 1 x 1, not {width} x {height}")
        sensor = self.sensor
        if self.projection in ("fisheye_equisolid", "fisheye_polynomial"):
            # (the width in mm over the image's aspect, kept: the pixel aspect cancels)
            stretch = (width / height) / (self.width / self.height)
            sensor = (float(sensor[0]) * stretch, float(sensor[1]))
        return replace(self, width=width, height=height, sensor=sensor)

    def converters(self) -> dict:
        def focus(value, where):
            if value is None:   # |target - eye|, in double
                eye, target = as_floats(self.eye, 3, "Camera.eye"), as_floats(self.target, 3, "Camera.target")
                return float(np.linalg.norm(np.subtract(target, eye)))
            return _scalar(value, float, where)
        return {"focus_distance": focus, "projection": _projection}

    def rays(self, px, py, lens=(0.5, 0.5)):
        """The core's camera rays through image positions (px, py), in pixels
        from the image's top-left corner, for the lens sample `lens` in
        [0, 1)^2: (origins, directions, tmin, tmax), float32."""
        px = np.ascontiguousarray(px, np.float32).reshape(-1)
        py = np.ascontiguousarray(py, np.float32).reshape(-1)
        try:
            lens_u, lens_v = (float(x) for x in lens)
        except (TypeError, ValueError):
            raise ValueError(f"lens must be two numbers in [0, 1), got {lens!r}") from None
        return _core.camera_rays(self.to_core(), px, py, lens_u, lens_v)
