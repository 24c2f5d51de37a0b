"""Texture(kind="wave" | "magic" | "white_noise" | "brick") are Blender's Wave, Magic, White Noise
and Brick Textures as Cycles computes them. Each is rendered at exact points (a vector_transform
with no linear part moves every hit to its translation) and checked against numpy's float32
evaluation of the same rules, written out from Cycles' kernel (intern/cycles/kernel/svm/wave.h,
magic.h, white_noise.h, brick.h; util/hash.h). Blender's side: tests/blender/test_b41."""
import numpy as np
import pytest

import gridwalk as gw
from test76_noise_texture_is_perlin_noise_as_cycles_computes_it import U32, VERTS, _hash, fractal

f32 = np.float32
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
POINTS = np.concatenate([np.random.default_rng(5).uniform(-3, 3, (60, 3)),
                         [[0, 0, 0], [0.25, 0.5, 0.0], [-0.7, -0.13, 0.2], [7.3, -9.1, 12.6], [-40.2, 3.3, 55.1]]]
                        ).astype(np.float32)


def value_at(texture, point):
    """(RGB, alpha-as-grey) the texture gives at exactly `point` (an emissive square, 2 x 2 pixels)."""
    at = dict(vector_transform=(0, 0, 0, float(point[0]), 0, 0, 0, float(point[1]), 0, 0, 0, float(point[2])))
    images = []
    for alpha in (False, True):
        s = gw.Scene(VERTS, TRIS, generated=np.zeros((2, 3, 3), np.float32),
                     textures=[gw.Texture(coordinates="generated", use_alpha=alpha, **texture, **at)],
                     camera=gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                                      ortho_height=1.0, width=2, height=2),
                     materials=[gw.Material(kd=0, emission=1.0, color_texture=0)])
        image = gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., :3]
        assert np.ptp(image.reshape(-1, 3), axis=0).max() == 0      # one point: one colour
        images.append(image[0, 0])
    return images[0], images[1][0]


def rendered(texture, points=POINTS):
    colours, alphas = zip(*(value_at(texture, p) for p in points))
    return np.array(colours), np.array(alphas)


# ---- Wave ---------------------------------------------------------------------------------------

def wave(p, scale=5.0, kind="bands", direction="x", profile="sine", phase=0.0, distortion=0.0, detail=2.0,
         detail_scale=1.0, roughness=0.5):
    p = (p * f32(scale) + f32(0.000001)) * f32(0.999999)
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    if kind == "bands":
        n = {"x": x * f32(20), "y": y * f32(20), "z": z * f32(20)}.get(direction, (x + y + z) * f32(10))
    else:
        keep = {"x": (0, 1, 1), "y": (1, 0, 1), "z": (1, 1, 0)}.get(direction, (1, 1, 1))
        r = p * np.array(keep, np.float32)
        n = np.sqrt(np.sum(r * r, axis=1, dtype=np.float32)) * f32(20)
    n = n + f32(phase)
    if distortion:
        q = p * f32(detail_scale)
        noise = fractal([q[:, 0], q[:, 1], q[:, 2]], "fbm", detail, roughness, 2.0)
        n = n + f32(distortion) * (noise * f32(2) - f32(1))
    if profile == "sine":
        return f32(0.5) + f32(0.5) * np.sin(n - f32(np.pi / 2))
    n = n / f32(2 * np.pi)
    return n - np.floor(n) if profile == "saw" else np.abs(n - np.floor(n + f32(0.5))) * f32(2)


WAVES = [dict(), dict(wave_profile="saw", phase=1.3), dict(wave_profile="triangle", wave_direction="diagonal"),
         dict(wave_type="rings", wave_direction="spherical", scale=2.0),
         dict(wave_type="rings", wave_direction="z", distortion=4.0, detail=3.5, detail_scale=1.7, roughness=0.6),
         dict(wave_direction="y", distortion=-2.0, detail=0.0)]


@pytest.mark.parametrize("fields", WAVES, ids=[str(i) for i in range(len(WAVES))])
def test_wave_bands_and_rings_are_cycles_wave(fields):
    colours, alphas = rendered(dict(kind="wave", **fields))
    names = {"wave_type": "kind", "wave_direction": "direction", "wave_profile": "profile"}
    want = wave(POINTS, **{names.get(k, k): v for k, v in fields.items()})
    assert np.ptp(want) > 0.5
    np.testing.assert_allclose(alphas, want, rtol=0, atol=2e-5)
    np.testing.assert_allclose(colours, np.repeat(want[:, None], 3, axis=1), rtol=0, atol=2e-5)


def test_a_wave_direction_that_does_not_go_with_its_type_is_refused():
    for fields in (dict(wave_type="rings", wave_direction="diagonal"), dict(wave_direction="spherical")):
        with pytest.raises(ValueError, match="wave_direction"):
            value_at(dict(kind="wave", **fields), POINTS[0])


# ---- Magic --------------------------------------------------------------------------------------

def magic(p, scale=5.0, depth=2, distortion=1.0):
    d, s = f32(distortion), f32(scale)
    p = np.fmod(p, f32(2 * np.pi))
    px, py, pz = p[:, 0], p[:, 1], p[:, 2]
    x = np.sin((px + py + pz) * f32(5) * s)
    y = np.cos((-px + py - pz) * f32(5) * s)
    z = -np.cos((-px - py + pz) * f32(5) * s)
    steps = [("x", lambda x, y, z: np.cos(x - y - z)), ("z", lambda x, y, z: np.sin(-x - y - z)),
             ("x", lambda x, y, z: -np.cos(-x + y - z)), ("y", lambda x, y, z: -np.sin(-x + y + z)),
             ("y", lambda x, y, z: -np.cos(-x + y + z)), ("x", lambda x, y, z: np.cos(x + y + z)),
             ("z", lambda x, y, z: np.sin(x + y - z)), ("x", lambda x, y, z: -np.cos(-x - y + z)),
             ("y", lambda x, y, z: -np.sin(x - y + z))]
    if depth > 0:
        x, y, z = x * d, y * d, z * d
        y = -np.cos(x - y + z) * d
        v = {"x": x, "y": y, "z": z}
        for axis, step in steps[:depth - 1]:
            v[axis] = step(v["x"], v["y"], v["z"]) * d
        x, y, z = v["x"], v["y"], v["z"]
    if d != 0:
        x, y, z = x / (f32(2) * d), y / (f32(2) * d), z / (f32(2) * d)
    return np.stack([f32(0.5) - x, f32(0.5) - y, f32(0.5) - z], axis=1)


# (atol: numpy's sin and cos differ from the C library's in the last bits, and each level of a
# strong distortion magnifies that)
@pytest.mark.parametrize("depth, distortion, scale, atol",
                         [(2, 1.0, 5.0, 3e-5), (0, 1.0, 5.0, 3e-5), (10, 2.5, 1.3, 1e-3), (10, 1.1, 1.3, 1e-4),
                          (0, 0.0, 2.0, 3e-5), (7, 1.8, 0.7, 3e-4), (3, 1.2, 1.13, 3e-5)])
def test_magic_nests_sines_and_cosines_as_cycles_does(depth, distortion, scale, atol):
    colours, alphas = rendered(dict(kind="magic", depth=depth, distortion=distortion, scale=scale))
    want = magic(POINTS, scale, depth, distortion)
    assert np.ptp(want) > 0.2
    # (below 0 at depth 0: Gridwalk's emission keeps no negative light, where Cycles' film does)
    want = np.maximum(want, 0)
    close = np.abs(colours - want) <= atol
    assert close.mean() > 0.98 and np.median(np.abs(colours - want)) < 3e-6
    average = np.maximum(magic(POINTS, scale, depth, distortion).mean(axis=1), 0)
    np.testing.assert_allclose(alphas[close.all(axis=1)], average[close.all(axis=1)], rtol=0, atol=atol)


def test_a_distortion_of_0_leaves_grey_beyond_depth_0_as_in_cycles():
    colours, alphas = rendered(dict(kind="magic", depth=3, distortion=0.0), POINTS[:5])
    assert np.all(colours == 0.5) and np.all(alphas == 0.5)


def test_far_points_are_taken_modulo_2_pi_before_the_scale():
    """(Blender 3.4 and later: a point and the same point 3 turns further on give one colour,
    whatever the scale; scaled first, as older Blenders did, they would not at scale 1.13)"""
    near = np.abs(POINTS[:10])                                      # (in [0, 2 pi): fmod keeps them)
    far = near + np.float32(6 * np.pi)
    a, _ = rendered(dict(kind="magic", distortion=1.0, scale=1.13), near)
    b, _ = rendered(dict(kind="magic", distortion=1.0, scale=1.13), far)
    np.testing.assert_allclose(a, b, atol=2e-3)
    x = lambda p: np.sin(p.sum(axis=1) * f32(1.13) * f32(5))       # (the first sine, scaled first)
    assert np.abs(x(near) - x(far)).max() > 0.5


# ---- White Noise --------------------------------------------------------------------------------

def hash01(*keys):
    """Cycles' hash_float*_to_float of float32 arrays: lookup3 of their bits, over 2^32."""
    return _hash([np.asarray(k, np.float32).view(U32) for k in keys]).astype(np.float32) * f32(1 / 4294967296)


def white_noise(p, n, w):
    w = np.full(len(p), w, np.float32)
    one, two = np.ones_like(w), np.full_like(w, 2)
    x, y, z = p[:, 0], p[:, 1], p[:, 2]
    if n == 1:
        return np.stack([hash01(w), hash01(w, one), hash01(w, two)], axis=1)
    if n == 2:
        return np.stack([hash01(x, y), hash01(x, y, one), hash01(x, y, two)], axis=1)
    if n == 3:
        return np.stack([hash01(x, y, z), hash01(x, y, z, one), hash01(x, y, z, two)], axis=1)
    return np.stack([hash01(x, y, z, w), hash01(z, x, w, y), hash01(w, z, y, x)], axis=1)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_white_noise_hashes_the_coordinates_bits_as_cycles_does(n):
    colours, alphas = rendered(dict(kind="white_noise", dimensions=n, w=0.37))
    want = white_noise(POINTS, n, 0.37)
    np.testing.assert_array_equal(colours, want)
    np.testing.assert_array_equal(alphas, want[:, 0])
    if n > 1:
        assert len(np.unique(want[:, 0])) > len(POINTS) - 2        # a value per point


# ---- Brick --------------------------------------------------------------------------------------

def brick_noise(n):
    with np.errstate(over="ignore"):
        n = (n + U32(1013)) & U32(0x7FFFFFFF)
        n = (n >> U32(13)) ^ n
        nn = (n * (n * n * U32(60493) + U32(19990303)) + U32(1376312589)) & U32(0x7FFFFFFF)
    return f32(0.5) * (nn.astype(np.float32) / f32(1073741824))


def brick(p, color1=(0.8, 0.8, 0.8), color2=(0.2, 0.2, 0.2), mortar=(0, 0, 0), scale=5.0, mortar_size=0.02,
          mortar_smooth=0.1, bias=0.0, width=0.5, height=0.25, offset=0.5, offset_freq=2, squash=1.0, squash_freq=2):
    p = p * f32(scale)
    height = f32(height)
    row = np.floor(p[:, 1] / height).astype(np.int64)
    width = np.full(len(p), width, np.float32)
    shift = np.zeros(len(p), np.float32)
    if offset_freq and squash_freq:
        remainder = lambda a, b: np.fmod(a, b)                    # (C's remainder: the sign of a)
        width = np.where(remainder(row, squash_freq) != 0, width, width * f32(squash)).astype(np.float32)
        shift = np.where(remainder(row, offset_freq) != 0, f32(0), width * f32(offset)).astype(np.float32)
    n = np.floor((p[:, 0] + shift) / width).astype(np.int64)
    x = (p[:, 0] + shift) - width * n.astype(np.float32)
    y = p[:, 1] - height * row.astype(np.float32)
    key = ((row.astype(np.int64) << 16) + (n & 0xFFFF)).astype(np.int64) & 0xFFFFFFFF
    tint = np.clip(brick_noise(key.astype(U32)) + f32(bias), 0, 1)
    edge = np.minimum(np.minimum(x, y), np.minimum(width - x, height - y))
    s = (f32(1) - edge / f32(mortar_size)) / f32(mortar_smooth) if mortar_smooth else np.zeros_like(edge)
    smooth = np.where(s <= 0, 0, np.where(s >= 1, 1, f32(3) * s * s - f32(2) * s * s * s))
    f = np.where(edge >= f32(mortar_size), f32(0), smooth if mortar_smooth else f32(1)).astype(np.float32)
    c1, c2, m = (np.array(c, np.float32) for c in (color1, color2, mortar))
    tinted = np.where((f != 1)[:, None], c1 * (f32(1) - tint)[:, None] + c2 * tint[:, None], c1)
    return tinted * (f32(1) - f)[:, None] + m * f[:, None], f


BRICK_POINTS = np.concatenate([POINTS, np.random.default_rng(9).uniform(-0.5, 0.5, (40, 3)).astype(np.float32)])
BRICKS = [dict(), dict(color1=(0.9, 0.3, 0.1), color2=(0.1, 0.5, 0.9), mortar=(1.0, 1.0, 0.6), mortar_size=0.08,
                       mortar_smooth=0.6, bias=-0.3, width=0.7, height=0.3, offset=0.25, offset_freq=3,
                       squash=0.5, squash_freq=4, scale=3.0),
          dict(mortar_smooth=0.0, mortar_size=0.1, offset_freq=0, squash=2.0)]
FIELDS = {"bias": "brick_bias", "width": "brick_width", "height": "row_height", "offset": "offset_amount",
          "offset_freq": "offset_frequency", "squash": "squash_amount", "squash_freq": "squash_frequency"}


@pytest.mark.parametrize("fields", BRICKS, ids=["default", "everything", "hard_mortar_no_offset"])
def test_bricks_rows_tints_and_mortar_are_cycles_bricks(fields):
    colours, alphas = rendered(dict(kind="brick", **{FIELDS.get(k, k): v for k, v in fields.items()}), BRICK_POINTS)
    want, mortar = brick(BRICK_POINTS, **fields)
    assert 0 < np.mean(mortar > 0) < 0.9 and len(np.unique(want[:, 0].round(4))) > 5   # mortar and tints
    np.testing.assert_allclose(alphas, mortar, rtol=0, atol=2e-6)
    np.testing.assert_allclose(colours, want, rtol=0, atol=2e-6)


@pytest.mark.parametrize("fields, message", [(dict(brick_width=float("nan")), "brick_width"),
                                             (dict(row_height=float("inf")), "row_height"),
                                             (dict(kind="magic", depth=11), "depth"),
                                             (dict(mortar=(0, float("nan"), 0)), "mortar")])
def test_bad_settings_are_refused_naming_the_field(fields, message):
    with pytest.raises(ValueError, match=message):
        value_at(dict(dict(kind="brick"), **fields), POINTS[0])


def test_bricks_of_no_width_or_height_are_mortar_as_in_cycles():
    """(Blender's sockets take a Brick Width or Row Height of 0 and below from a script or a
    link; Cycles divides by it into an out-of-range brick number, and its mortar fills the
    plane. Gridwalk renders the same, and does not trap on that number's remainder.)"""
    for fields in (dict(brick_width=0.0), dict(row_height=0.0, squash_frequency=-1, offset_frequency=-1),
                   dict(brick_width=-0.4, mortar=(0.2, 0.4, 0.6))):
        colours, alphas = rendered(dict(kind="brick", **fields), POINTS[:8])
        assert np.all(alphas == 1) and np.all(colours == np.array(fields.get("mortar", (0, 0, 0)), np.float32))
