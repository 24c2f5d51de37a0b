"""Texture(kind="noise") is Blender's Noise Texture as Cycles computes it: Perlin noise whose
lattice gradients come from Bob Jenkins' lookup3 hash of the cell's corner, in 1 to 4
dimensions, summed over octaves by each of Blender's five types, moved by its Distortion, with
its Color output (the noise at two places further on, by hashed offsets) and its Fac output.
Checked here against numpy's evaluation of the same rules, written out from Cycles' kernel
(intern/cycles/kernel/svm/noise.h, fractal_noise.h, noisetex.h; util/hash.h), pixel by pixel
of a render. Blender's side: tests/blender/test_b39."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk import _core

U32 = np.uint32
N = 24
VERTS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
# Generated coordinates of the square: x and y across [-2.1, 1.9], z 0.35
GENERATED = np.column_stack([-0.1 + 2 * VERTS[:, 0], -0.1 + 2 * VERTS[:, 1], np.full(4, 0.35)]).astype(np.float32)


def _rot(x, k):
    return (x << U32(k)) | (x >> U32(32 - k))


def _hash(keys):
    """lookup3's hash of 1-4 uint32 arrays, seeded as Cycles seeds it."""
    n = len(keys)
    with np.errstate(over="ignore"):
        a = np.full(keys[0].shape, 0xDEADBEEF + (n << 2) + 13, dtype=np.uint64).astype(U32)
        b, c = a.copy(), a.copy()
        a = a + keys[0]
        if n > 1:
            b = b + keys[1]
        if n > 2:
            c = c + keys[2]
        if n == 4:
            a = a - c; a ^= _rot(c, 4); c = c + b
            b = b - a; b ^= _rot(a, 6); a = a + c
            c = c - b; c ^= _rot(b, 8); b = b + a
            a = a - c; a ^= _rot(c, 16); c = c + b
            b = b - a; b ^= _rot(a, 19); a = a + c
            c = c - b; c ^= _rot(b, 4); b = b + a
            a = a + keys[3]
        c ^= b; c = c - _rot(b, 14)
        a ^= c; a = a - _rot(c, 11)
        b ^= a; b = b - _rot(a, 25)
        c ^= b; c = c - _rot(b, 16)
        a ^= c; a = a - _rot(c, 4)
        b ^= a; b = b - _rot(a, 14)
        c ^= b; c = c - _rot(b, 24)
    return c


def _grad(h, f):
    """The hashed gradient dotted with the offsets f (list of arrays), per dimension."""
    n = len(f)
    sign = lambda v, bit: np.where(bit != 0, -v, v)
    if n == 1:
        g = h & U32(15)
        return sign((1 + (g & U32(7))).astype(np.float32), g & U32(8)) * f[0]
    if n == 2:
        g = h & U32(7)
        u, v = np.where(g < 4, f[0], f[1]), np.float32(2) * np.where(g < 4, f[1], f[0])
        return sign(u, g & U32(1)) + sign(v, g & U32(2))
    if n == 3:
        g = h & U32(15)
        u = np.where(g < 8, f[0], f[1])
        v = np.where(g < 4, f[1], np.where((g == 12) | (g == 14), f[0], f[2]))
        return sign(u, g & U32(1)) + sign(v, g & U32(2))
    g = h & U32(31)
    u, v, s = np.where(g < 24, f[0], f[1]), np.where(g < 16, f[1], f[2]), np.where(g < 8, f[2], f[3])
    return sign(u, g & U32(1)) + sign(v, g & U32(2)) + sign(s, g & U32(4))


def snoise(p, wrap=True):
    """Cycles' signed noise at p (list of float32 arrays, 1-4 of them); wrap: Blender 4.0 and
    later wrap the coordinates every 100000 and move them by 1/2 from a million on."""
    n = len(p)
    if wrap:
        p = [np.fmod(np.float32(x), np.float32(100000)) + np.float32(0.5) * (np.abs(x) >= 1e6) for x in p]
    cell = [np.floor(x) for x in p]
    frac = [(x - c).astype(np.float32) for x, c in zip(p, cell)]
    fade = [t * t * t * (t * (t * np.float32(6) - np.float32(15)) + np.float32(10)) for t in frac]
    corners = []
    for c in range(1 << n):
        bits = [(c >> i) & 1 for i in range(n)]
        # (a cell beyond int range is INT_MIN, as x86 converts it: Blender 3.4 does not wrap)
        index = [np.where(np.abs(c) < 2.0 ** 31, c, -2.0 ** 31).astype(np.int64) for c in cell]
        keys = [(index[i] + bits[i]).astype(U32) for i in range(n)]
        corners.append(_grad(_hash(keys), [frac[i] - np.float32(bits[i]) for i in range(n)]))
    for i in range(n):
        corners = [a + fade[i] * (b - a) for a, b in zip(corners[0::2], corners[1::2])]
    return np.float32([0, 0.25, 0.6616, 0.9820, 0.8344][n]) * corners[0]


def fractal(p, kind, detail, roughness, lacunarity, offset=0.0, gain=1.0, normalize=True):
    f32 = np.float32
    detail = min(max(detail, 0.0), 15.0)
    roughness, lacunarity, offset, gain = f32(roughness), f32(lacunarity), f32(offset), f32(gain)
    octaves, rest = int(detail), f32(detail - np.floor(detail))
    finer = lambda q: [x * lacunarity for x in q]
    if kind == "fbm":
        scale, amp, max_amp, total = f32(1), f32(1), f32(0), f32(0)
        for _ in range(octaves + 1):
            total = total + snoise([scale * x for x in p]) * amp
            max_amp, amp, scale = max_amp + amp, amp * roughness, scale * lacunarity
        whole = f32(0.5) * total / max_amp + f32(0.5) if normalize else total
        if rest == 0:
            return whole
        more = total + snoise([scale * x for x in p]) * amp
        blended = f32(0.5) * more / (max_amp + amp) + f32(0.5) if normalize else more
        return whole + rest * (blended - whole)
    if kind == "multifractal":
        value, power = f32(1), f32(1)
        for _ in range(octaves + 1):
            value, power, p = value * (power * snoise(p) + f32(1)), power * roughness, finer(p)
        return value * (rest * power * snoise(p) + f32(1)) if rest else value
    if kind == "hetero_terrain":
        power, value, p = roughness, offset + snoise(p), finer(p)
        for _ in range(octaves):
            value = value + (snoise(p) + offset) * power * value
            power, p = power * roughness, finer(p)
        return value + rest * ((snoise(p) + offset) * power * value) if rest else value
    if kind == "hybrid_multifractal":
        power, value, weight = f32(1), np.zeros_like(p[0]), np.ones_like(p[0])
        for _ in range(octaves + 1):      # (a point whose weight falls to 0.001 or below stops there)
            on = weight > f32(0.001)
            weight = np.where(on, np.minimum(weight, f32(1)), weight)
            signal = (snoise(p) + offset) * power
            value = np.where(on, value + weight * signal, value)
            weight = np.where(on, weight * gain * signal, weight)
            power, p = power * roughness, finer(p)
        if not rest:
            return value
        last = value + rest * np.minimum(weight, f32(1)) * ((snoise(p) + offset) * power)
        return np.where(weight > f32(0.001), last, value)
    signal = offset - np.abs(snoise(p))
    signal = signal * signal
    value, power = signal, roughness
    for _ in range(octaves):
        p = finer(p)
        weight = np.clip(signal * gain, 0, 1)
        signal = offset - np.abs(snoise(p))
        signal = signal * signal * weight
        value, power = value + signal * power, power * roughness
    return value


def offsets(n, seed):
    """Cycles' random_float*_offset(seed) for n dimensions."""
    bits = lambda x: np.array([x], np.float32).view(U32)
    keys = [[bits(seed)]] if n == 1 else [[bits(seed), bits(float(i))] for i in range(n)]
    return [np.float32(100) + (_hash(k).astype(np.float32) * np.float32(2.0 ** -32)) * np.float32(100)
            for k in keys]


def _render(texture, generated=GENERATED):
    """The texture as emission on a square seen straight on, one pixel per sample (the Generated
    coordinates at its corners: `generated`)."""
    s = gw.Scene(VERTS, TRIS, generated=generated[TRIS], textures=[texture],
                 camera=gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                                  ortho_height=2.0, width=N, height=N),
                 materials=[gw.Material(kd=0, emission=1.0, color_texture=0)])
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., :3]


def _pixel_points(scale):
    """The Generated point under each pixel centre (row 0 = top), times scale, as float32."""
    c = -1 + 2 * (np.arange(N) + 0.5) / N
    x, y = np.meshgrid(c, c[::-1])
    p = [np.float32(-0.1 + 2 * x), np.float32(-0.1 + 2 * y), np.full(x.shape, 0.35, np.float32)]
    return [q * np.float32(scale) for q in p]


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_signed_noise_is_cycles_perlin_noise_in_each_dimension(n):
    rng = np.random.default_rng(n)
    points = rng.uniform(-50, 50, (300, n)).astype(np.float32)
    points[:10] = np.round(points[:10])                       # on lattice points: exactly 0
    ours = np.array([_core.signed_noise(list(map(float, q))) for q in points], np.float32)
    want = snoise([points[:, i] for i in range(n)])
    np.testing.assert_allclose(ours, want, rtol=0, atol=2e-6)
    assert np.all(ours[:10] == 0) and ours.std() > 0.1 and np.abs(ours).max() <= 1.1


def test_far_coordinates_wrap_as_in_blender_4_and_stay_as_they_are_in_3_4():
    assert _core.signed_noise([123456.5, 3.2, 1.1]) == _core.signed_noise([23456.5, 3.2, 1.1]) != 0
    # from a million on, moved by half a cell after the wrap (which would leave them on lattice points)
    assert _core.signed_noise([3000000.0, 3.2]) == _core.signed_noise([0.5, 3.2]) != 0
    rng = np.random.default_rng(9)
    far = rng.uniform(-3e6, 3e6, (200, 3)).astype(np.float32)
    for wrap in (True, False):
        ours = np.array([_core.signed_noise(list(map(float, q)), wrap) for q in far], np.float32)
        np.testing.assert_allclose(ours, snoise([far[:, i] for i in range(3)], wrap), rtol=0, atol=2e-6)
    assert _core.signed_noise([123456.5, 3.2, 1.1], False) != _core.signed_noise([123456.5, 3.2, 1.1], True)
    assert _core.signed_noise([3e9, 0.25, 0.5], False) == pytest.approx(float(snoise([np.float32([3e9]), np.float32([0.25]), np.float32([0.5])], False)[0]), abs=2e-6)


def test_non_finite_coordinates_and_overflowing_octaves_give_zero():
    assert _core.signed_noise([float("nan"), 0.5, 0.5]) == _core.signed_noise([0.0, 0.5, 0.5])
    assert _core.signed_noise([float("inf")] * 4) == 0.0
    for kind in ("fbm", "multifractal", "hetero_terrain"):   # Roughness 1000 over 15 octaves overflows
        image = _render(gw.Texture(kind="noise", coordinates="generated", noise_type=kind, detail=15.0,
                                   roughness=1000.0))
        assert np.isfinite(image).all() and (image == 0).mean() > 0.3, kind


@pytest.mark.parametrize("detail", [0.0, 2.0, 3.7])
def test_the_default_noise_colour_is_three_fbm_noises_at_cycles_offsets(detail):
    image = _render(gw.Texture(kind="noise", coordinates="generated", scale=2.5, detail=detail, roughness=0.6))
    p = _pixel_points(2.5)
    red = fractal(p, "fbm", detail, 0.6, 2.0)
    green = fractal([a + b for a, b in zip(p, offsets(3, 3.0))], "fbm", detail, 0.6, 2.0)
    blue = fractal([a + b for a, b in zip(p, offsets(3, 4.0))], "fbm", detail, 0.6, 2.0)
    np.testing.assert_allclose(image, np.stack([red, green, blue], axis=-1), rtol=0, atol=2e-5)
    assert all(image[..., k].std() > 0.02 for k in range(3))
    assert np.abs(image[..., 0] - image[..., 1]).mean() > 0.02          # the channels differ


@pytest.mark.parametrize("n", [1, 2, 4])
def test_the_colour_in_other_dimensions_takes_their_own_offsets(n):
    texture = gw.Texture(kind="noise", coordinates="generated", dimensions=n, w=0.8, scale=2.0)
    x, y, z = _pixel_points(2.0)
    w = np.full(x.shape, np.float32(0.8) * np.float32(2.0), np.float32)
    p = {1: [w], 2: [x, y], 4: [x, y, z, w]}[n]
    channels = [fractal([a + b for a, b in zip(p, offsets(n, float(seed)))] if seed else p, "fbm", 2.0, 0.5, 2.0)
                for seed in (0, n, n + 1)]
    # (points 100-200 out, where float32 keeps fewer digits of the fraction)
    np.testing.assert_allclose(_render(texture), np.stack(channels, axis=-1), rtol=0, atol=6e-5)


def test_normalize_off_detail_past_15_and_roughness_past_1_are_taken_as_cycles_takes_them():
    p = _pixel_points(2.0)
    for fields, want in [
            (dict(normalize=False), fractal(p, "fbm", 2.0, 0.5, 2.0, normalize=False)),   # in [-1, 1]
            (dict(detail=20.0, roughness=0.7), fractal(p, "fbm", 15.0, 0.7, 2.0)),      # 15 octaves at most
            (dict(detail=3.0, roughness=1.6), fractal(p, "fbm", 3.0, 1.6, 2.0))]:       # not clamped to 1
        texture = gw.Texture(kind="noise", coordinates="generated", scale=2.0, use_alpha=True, **fields)
        # (an image holds no negative light: below 0 the emission is 0)
        np.testing.assert_allclose(_render(texture)[..., 0], np.maximum(want, 0), rtol=0, atol=6e-5)
    assert (fractal(p, "fbm", 2.0, 0.5, 2.0, normalize=False) < 0).mean() > 0.2


@pytest.mark.parametrize("kind,offset,gain", [("multifractal", 0.0, 1.0), ("ridged_multifractal", 1.0, 2.0),
                                              ("hybrid_multifractal", 0.7, 1.2), ("hetero_terrain", 0.5, 1.0)])
def test_each_noise_type_sums_its_octaves_as_cycles_does(kind, offset, gain):
    texture = gw.Texture(kind="noise", coordinates="generated", noise_type=kind, detail=2.5, roughness=0.5,
                         lacunarity=2.2, noise_offset=offset, noise_gain=gain, use_alpha=True)
    image = _render(texture)
    want = fractal(_pixel_points(texture.scale), kind, 2.5, 0.5, 2.2, offset, gain)
    # (an image holds no negative light: below 0 the emission is 0)
    np.testing.assert_allclose(image, np.repeat(np.maximum(want, 0)[..., None], 3, axis=-1), rtol=2e-5, atol=2e-5)
    assert want.std() > 0.05


@pytest.mark.parametrize("n", [1, 2, 4])
def test_distortion_moves_the_point_by_noise_in_2d_1d_and_4d(n):
    texture = gw.Texture(kind="noise", coordinates="generated", dimensions=n, w=0.8, scale=1.5,
                         distortion=1.3, use_alpha=True)
    x, y, _ = _pixel_points(1.5)
    w = np.full(x.shape, np.float32(0.8) * np.float32(1.5), np.float32)
    p = {1: [w], 2: [x, y], 4: [x, y, _pixel_points(1.5)[2], w]}[n]
    moved = [snoise([a + b for a, b in zip(p, offsets(n, float(k)))]) * np.float32(1.3) for k in range(n)]
    p = [a + b for a, b in zip(p, moved)]
    want = fractal(p, "fbm", 2.0, 0.5, 2.0)
    image = _render(texture)
    np.testing.assert_allclose(image, np.repeat(want[..., None], 3, axis=-1), rtol=0, atol=2e-5)
    undistorted = _render(gw.Texture(kind="noise", coordinates="generated", dimensions=n, w=0.8, scale=1.5,
                                     use_alpha=True))
    assert np.abs(image - undistorted).max() > 0.05


def test_bad_noise_settings_are_refused_naming_the_field():
    for fields, match in [(dict(dimensions=5), "dimensions = 5"), (dict(detail=float("nan")), "detail"),
                          (dict(noise_type="perlin"), "noise_type"), (dict(lacunarity=float("inf")), "lacunarity")]:
        with pytest.raises(ValueError, match=match):
            _render(gw.Texture(kind="noise", coordinates="generated", **fields))
