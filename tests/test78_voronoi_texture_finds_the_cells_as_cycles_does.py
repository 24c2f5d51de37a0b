"""Texture(kind="voronoi") is Blender's Voronoi Texture as Cycles computes it: one point per unit
cell, placed by lookup3 of the cell corner's float bits (Blender 4.5 and before) or by the PCG
hash of its integer coordinates (5.0: voronoi_pcg); the nearest point (F1), the second nearest
(F2) or a smooth blend (Smooth F1) by each distance metric, in 1 to 4 dimensions, over octaves;
its Distance, Color, Position and W outputs. Checked pixel by pixel against numpy's evaluation
of the same rules (intern/cycles/kernel/svm/voronoi.h, util/hash.h). Blender's side:
tests/blender/test_b40."""
import itertools

import numpy as np
import pytest

import gridwalk as gw
from test76_noise_texture_is_perlin_noise_as_cycles_computes_it import U32, VERTS, N, _hash
from test76_noise_texture_is_perlin_noise_as_cycles_computes_it import _render as render_square

GENERATED = np.column_stack([0.2 + VERTS[:, 0], 0.3 + VERTS[:, 1], np.full(4, 0.35)]).astype(np.float32)
f32 = np.float32


def _bits(x):
    return np.asarray(x, np.float32).view(U32)


def _lookup3(keys):
    return _hash([_bits(k) for k in keys]).astype(np.float32) * f32(2.0 ** -32)


def _pcg(keys):
    v = [(np.asarray(k, np.int64).astype(np.uint32) * U32(1664525) + U32(1013904223)) for k in keys]
    n = len(v)

    def mix():
        with np.errstate(over="ignore"):
            if n == 2:
                v[0] += v[1] * U32(1664525); v[1] += v[0] * U32(1664525)
            elif n == 3:
                v[0] += v[1] * v[2]; v[1] += v[2] * v[0]; v[2] += v[0] * v[1]
            else:
                v[0] += v[1] * v[3]; v[1] += v[2] * v[0]; v[2] += v[0] * v[1]; v[3] += v[1] * v[2]
    mix()
    v = [x ^ (x.view(np.int32) >> 16).view(np.uint32) for x in v]
    mix()
    return [(x & U32(0x7FFFFFFF)).astype(np.float32) * f32(2.0 ** -31) for x in v]


def _jitter(cell, pcg):
    n = len(cell)
    if pcg and n > 1:
        return _pcg([c.astype(np.int64) for c in cell])
    one = lambda extra: _lookup3(list(cell) + [np.full(cell[0].shape, extra, np.float32)])
    if n == 1:
        return [_lookup3(cell)]
    if n == 2:
        return [_lookup3(cell), one(1.0)]
    if n == 3:
        return [_lookup3(cell), one(1.0), one(2.0)]
    return [_lookup3([cell[(i + 4 - r) % 4] for i in range(4)]) for r in range(4)]


def _color(cell, pcg):
    n = len(cell)
    if pcg and n > 1:
        keys = [c.astype(np.int64) for c in cell] + ([np.zeros(cell[0].shape, np.int64)] if n == 2 else [])
        return _pcg(keys)[:3]
    if n < 3:
        extra = lambda e: _lookup3(list(cell) + [np.full(cell[0].shape, e, np.float32)])
        return [_lookup3(cell), extra(1.0), extra(2.0)]
    if n == 3:
        return _jitter(cell, False)
    return [_lookup3(cell), _lookup3([cell[2], cell[0], cell[3], cell[1]]), _lookup3([cell[3], cell[2], cell[1], cell[0]])]


def _distance(a, b, metric, exponent):
    d = [np.abs(x - y) for x, y in zip(a, b)]
    if len(d) == 1:
        return d[0]
    if metric == "euclidean":
        return np.sqrt(sum(x * x for x in d))
    if metric == "manhattan":
        return sum(d)
    if metric == "chebychev":
        return np.maximum.reduce(d)
    with np.errstate(divide="ignore", over="ignore"):   # (exponent 0: every distance is infinite)
        return sum(np.power(x, f32(exponent)) for x in d) ** (f32(1) / f32(exponent))


def voronoi(coord, feature="f1", metric="euclidean", exponent=0.5, randomness=1.0, pcg=True):
    """(distance, [r, g, b], position) of one octave at coord (list of float32 arrays)."""
    n = len(coord)
    cell = [np.floor(c) for c in coord]
    local = [c - k for c, k in zip(coord, cell)]
    reach = 2 if feature == "smooth_f1" else 1
    offsets = [o[::-1] for o in itertools.product(range(-reach, reach + 1), repeat=n)]   # x fastest
    best = [np.full(coord[0].shape, np.inf, np.float32) for _ in range(2)]
    point = [[np.zeros_like(coord[0]) for _ in range(n)] for _ in range(2)]
    at = [[k.copy() for k in cell] for _ in range(2)]          # (this cell until a point is nearer)
    for offset in offsets:
        where = [k + f32(o) for k, o in zip(cell, offset)]
        p = [f32(o) + j * f32(randomness) for o, j in zip(offset, _jitter(where, pcg))]
        d = _distance(p, local, metric, exponent)
        first, second = d < best[0], (d >= best[0]) & (d < best[1])
        for slot, take in ((1, first), (0, first), (1, second)):
            src = (best[0], point[0], at[0]) if slot == 1 and take is first else (d, p, where)
            best[slot] = np.where(take, src[0], best[slot])
            point[slot] = [np.where(take, s, x) for s, x in zip(src[1], point[slot])]
            at[slot] = [np.where(take, s, x) for s, x in zip(src[2], at[slot])]
    k = 1 if feature == "f2" else 0
    return best[k], _color(at[k], pcg), [pp + kk for pp, kk in zip(point[k], cell)]


def _offsets(n):
    return [o[::-1] for o in itertools.product(range(-1, 2), repeat=n)]   # x fastest


def _points_around(coord, randomness, pcg, shift=None):
    """[(offset, point relative to the cell)] of the cells around coord's (offsets moved by shift)."""
    cell = [np.floor(c) for c in coord]
    out = []
    for offset in _offsets(len(coord)):
        o = [f32(k) + (s if shift is not None else f32(0)) for k, s in zip(offset, shift or [0] * len(coord))]
        where = [k + x for k, x in zip(cell, o)]
        out.append((offset, [x + j * f32(randomness) for x, j in zip(o, _jitter(where, pcg))]))
    return cell, [c - k for c, k in zip(coord, cell)], out


def edge_distance(coord, randomness=1.0, pcg=True):
    """Cycles' Distance to Edge at coord: the nearest point by squared distance, then the least
    distance to the bisectors between it and the other points (1D: the two midpoints)."""
    n = len(coord)
    _, local, around = _points_around(coord, randomness, pcg)
    if n == 1:
        p = [pt[0] for _, pt in around]
        return np.minimum(np.abs((p[1] + p[0]) / f32(2) - local[0]), np.abs((p[1] + p[2]) / f32(2) - local[0]))
    vectors = [[x - l for x, l in zip(pt, local)] for _, pt in around]
    least, closest = np.full(coord[0].shape, np.inf, np.float32), [np.zeros_like(coord[0]) for _ in range(n)]
    for v in vectors:
        d = sum(x * x for x in v)
        take = d < least
        least = np.where(take, d, least)
        closest = [np.where(take, x, c) for x, c in zip(v, closest)]
    least = np.full(coord[0].shape, np.inf, np.float32)
    for v in vectors:
        across = [x - c for x, c in zip(v, closest)]
        len2 = sum(x * x for x in across)
        length = np.sqrt(np.maximum(len2, f32(1e-30)))
        d = sum((c + x) / f32(2) * (a / length) for c, x, a in zip(closest, v, across))
        least = np.where(len2 > f32(0.0001), np.minimum(least, d), least)
    return least


def sphere_radius(coord, randomness=1.0, pcg=True):
    """Cycles' N-Sphere Radius: half the distance from the nearest point to its own nearest."""
    n = len(coord)
    dist = lambda a, b: np.abs(a[0] - b[0]) if n == 1 else np.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))
    _, local, around = _points_around(coord, randomness, pcg)
    least = np.full(coord[0].shape, np.inf, np.float32)
    closest = [np.zeros_like(coord[0]) for _ in range(n)]
    closest_offset = [np.zeros_like(coord[0]) for _ in range(n)]
    for offset, pt in around:
        d = dist(pt, local)
        take = d < least
        least = np.where(take, d, least)
        closest = [np.where(take, x, c) for x, c in zip(pt, closest)]
        closest_offset = [np.where(take, f32(o), c) for o, c in zip(offset, closest_offset)]
    _, _, around = _points_around(coord, randomness, pcg, shift=closest_offset)
    least, best = np.full(coord[0].shape, np.inf, np.float32), [np.zeros_like(coord[0]) for _ in range(n)]
    for offset, pt in around:
        if not any(offset):
            continue
        d = dist(closest, pt)
        take = d < least
        least = np.where(take, d, least)
        best = [np.where(take, x, b) for x, b in zip(pt, best)]
    return dist(best, closest) / f32(2)


def _render(texture):
    return render_square(texture, GENERATED)


def _points(scale, w=0.0, n=3):
    c = -1 + 2 * (np.arange(N) + 0.5) / N
    x, y = np.meshgrid(c, c[::-1])
    p = [f32(0.2 + x) * f32(scale), f32(0.3 + y) * f32(scale), np.full(x.shape, f32(0.35) * f32(scale))]
    ww = np.full(x.shape, f32(w) * f32(scale))
    return {1: [ww], 2: p[:2], 3: p, 4: p + [ww]}[n]


@pytest.mark.parametrize("pcg", [False, True])
@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_f1_distance_colour_and_position_in_each_dimension_and_hash(n, pcg):
    # (detail 0 and normalize off: Blender's Voronoi defaults; Texture's are the Noise's)
    fields = dict(kind="voronoi", coordinates="generated", dimensions=n, w=0.7, scale=3.0, detail=0.0,
                  normalize=False, voronoi_pcg=pcg)
    d, color, position = voronoi(_points(3.0, 0.7, n), pcg=pcg)
    np.testing.assert_allclose(_render(gw.Texture(voronoi_output="distance", **fields))[..., 0], d, atol=2e-5)
    np.testing.assert_allclose(_render(gw.Texture(voronoi_output="color", **fields)), np.stack(color, -1), atol=2e-5)
    assert np.std(color[0]) > 0.1 or n == 1
    # (position / scale; an image holds no negative light: below 0 the emission is 0)
    if n > 1:
        xyz = np.stack((position + [np.zeros_like(d)])[:3], -1) / f32(3.0)
        np.testing.assert_allclose(_render(gw.Texture(voronoi_output="position", **fields)), np.maximum(xyz, 0),
                                   atol=2e-5)
        assert (xyz > 0.1).mean() > 0.3
    else:
        np.testing.assert_allclose(_render(gw.Texture(voronoi_output="w", **fields))[..., 0],
                                   np.maximum(position[0] / f32(3.0), 0), atol=2e-5)


@pytest.mark.parametrize("feature,metric", [("f2", "manhattan"), ("f1", "chebychev"), ("f1", "minkowski"),
                                            ("f2", "euclidean")])
def test_the_second_nearest_and_each_metric(feature, metric):
    fields = dict(kind="voronoi", coordinates="generated", scale=3.0, detail=0.0, normalize=False, randomness=0.7,
                  voronoi_feature=feature, voronoi_metric=metric, exponent=1.5)
    d, _, _ = voronoi(_points(3.0), feature, metric, 1.5, 0.7)
    np.testing.assert_allclose(_render(gw.Texture(**fields))[..., 0], d, atol=3e-5)
    assert d.std() > 0.05


def test_pcg_and_lookup3_place_the_cells_differently():
    a, b = (_render(gw.Texture(kind="voronoi", coordinates="generated", scale=3.0, detail=0.0, normalize=False,
                               voronoi_pcg=pcg))
            for pcg in (False, True))
    assert np.abs(a - b).mean() > 0.05


def test_octaves_sum_as_cycles_sums_them():
    # detail 1.5: octaves 1 and 2 whole, a third half; normalized by the amplitudes and the largest distance
    fields = dict(kind="voronoi", coordinates="generated", scale=2.0, detail=1.5, roughness=0.6, lacunarity=2.2,
                  normalize=True)
    p = _points(2.0)
    amp, total, dist = f32(1), f32(0), 0
    for i in range(3):
        d, _, _ = voronoi([x * f32(2.2) ** i for x in p])
        if i <= 1.5:
            total, dist = total + amp, dist + d * amp
            amp = amp * f32(0.6)
        else:
            total, dist = total + f32(0.5) * amp, dist + f32(0.5) * d * amp
    dist = dist / (total * np.sqrt(f32(3)))
    np.testing.assert_allclose(_render(gw.Texture(**fields))[..., 0], dist, atol=5e-5)


def test_bad_voronoi_settings_are_refused_naming_the_field():
    for fields, match in [(dict(voronoi_feature="distance_to_corner"), "voronoi_feature"),
                          (dict(voronoi_metric="hamming"), "voronoi_metric"),
                          (dict(randomness=float("nan")), "randomness"), (dict(dimensions=0), "dimensions = 0")]:
        with pytest.raises(ValueError, match=match):
            _render(gw.Texture(kind="voronoi", coordinates="generated", **fields))


@pytest.mark.parametrize("pcg", [False, True])
def test_where_no_distance_is_finite_each_cell_keeps_its_own_colour(pcg):
    # Minkowski with exponent 0: every distance is infinite, no point is nearer than none, and
    # the colour is the cell's own (Cycles' offsets start at 0), not one colour everywhere
    fields = dict(kind="voronoi", coordinates="generated", scale=3.0, detail=0.0, normalize=False, voronoi_pcg=pcg,
                  voronoi_metric="minkowski", exponent=0.0, voronoi_output="color")
    _, color, _ = voronoi(_points(3.0), metric="minkowski", exponent=0.0, pcg=pcg)
    image = _render(gw.Texture(**fields))
    np.testing.assert_allclose(image, np.stack(color, -1), atol=2e-5)
    assert len(np.unique(image[..., 0])) > 4


def test_a_position_read_as_a_number_is_its_average():
    fields = dict(kind="voronoi", coordinates="generated", scale=3.0, detail=0.0, normalize=False,
                  voronoi_output="position")
    _, _, position = voronoi(_points(3.0))
    xyz = np.stack(position, -1) / f32(3.0)
    # (the average of x, y, z; below 0 the emission is 0)
    np.testing.assert_allclose(_render(gw.Texture(channel=4, **fields))[..., 0],
                               np.maximum(xyz.mean(axis=-1), 0), atol=2e-5)


@pytest.mark.parametrize("pcg", [False, True])
@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_distance_to_edge_and_n_sphere_radius_in_each_dimension_and_hash(n, pcg):
    fields = dict(kind="voronoi", coordinates="generated", dimensions=n, w=0.7, scale=3.0, detail=0.0,
                  normalize=False, voronoi_pcg=pcg, randomness=0.8)
    p = _points(3.0, 0.7, n)
    edge = _render(gw.Texture(voronoi_feature="distance_to_edge", **fields))[..., 0]
    np.testing.assert_allclose(edge, edge_distance(p, 0.8, pcg), atol=3e-5)
    radius = _render(gw.Texture(voronoi_feature="n_sphere_radius", voronoi_output="radius", **fields))[..., 0]
    want = sphere_radius(p, 0.8, pcg)
    # (a cell's radius is one value: pixels on a cell border may fall on either side)
    assert np.mean(np.abs(radius - want) < 3e-5) > 0.97
    if n > 1:
        assert edge.std() > 0.03 and len(np.unique(want.round(5))) > 3
    # their other outputs are 0, as Cycles writes them
    assert not _render(gw.Texture(voronoi_feature="n_sphere_radius", voronoi_output="distance", **fields)).any()
    assert not _render(gw.Texture(voronoi_feature="distance_to_edge", voronoi_output="color", **fields)).any()


def test_distance_to_edge_over_octaves_takes_the_least_as_cycles_does():
    fields = dict(kind="voronoi", coordinates="generated", scale=2.0, detail=1.5, roughness=0.6, lacunarity=2.2,
                  normalize=True, voronoi_feature="distance_to_edge")
    p = _points(2.0)
    largest = f32(1.0)                                            # (0.5 + 0.5 x randomness 1)
    amp, top, dist, scale = f32(1), largest, np.full(p[0].shape, f32(8)), f32(1)
    mix = lambda a, b, t: a + t * (b - a)
    for i in range(3):
        d = edge_distance([x * scale for x in p])
        if i <= 1.5:
            top = mix(top, largest / scale, amp)
            dist = mix(dist, np.minimum(dist, d / scale), amp)
            scale, amp = scale * f32(2.2), amp * f32(0.6)
        else:
            top = mix(top, mix(top, largest / scale, amp), f32(0.5))
            dist = mix(dist, np.minimum(dist, mix(dist, np.minimum(dist, d / scale), amp)), f32(0.5))
    np.testing.assert_allclose(_render(gw.Texture(**fields))[..., 0], dist / top, atol=5e-5)
