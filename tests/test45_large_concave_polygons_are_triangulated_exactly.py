"""Large non-convex polygons (a CAD outline, a map's coastline, a gear of many
teeth) are ear-clipped in the core with a grid of their reflex corners
(core/src/ear_clip.h). The triangles cover each polygon exactly once: every
sample point lies in as many triangles as the polygon holds it (0 or 1)."""
from __future__ import annotations

import numpy as np
import pytest

from gridwalk.io import load_nff
from gridwalk.io.triangulate import MAX_CLIPPED_CORNERS, TooManyCorners, ear_clip, polygons


def gear(n, inner=0.6):
    k = np.arange(n)
    r = np.where(k % 2 == 0, 1.0, inner)
    a = 2 * np.pi * k / n
    return np.column_stack([r * np.cos(a), r * np.sin(a)])


def spiral_band(n, turns=20):
    t = np.linspace(0, 2 * np.pi * turns, n // 2)
    inner = np.column_stack([(1 + t) * np.cos(t), (1 + t) * np.sin(t)])
    outer = np.column_stack([(1.5 + t) * np.cos(t), (1.5 + t) * np.sin(t)])
    xy = np.vstack([inner, outer[::-1]])
    return xy if signed_area(xy) > 0 else xy[::-1]


def signed_area(xy):
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y)


def inside_polygon(points, xy):
    """Even-odd test of each point against the closed outline xy."""
    a, b = xy, np.roll(xy, -1, axis=0)
    px, py = points[:, None, 0], points[:, None, 1]
    crosses = (a[None, :, 1] > py) != (b[None, :, 1] > py)
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[None, :, 0] + (py - a[None, :, 1]) * (b[None, :, 0] - a[None, :, 0]) / (b[None, :, 1] - a[None, :, 1])
    return (np.sum(crosses & (px < x), axis=1) % 2) == 1


def star_polygon(rng, n):
    """n corners at random angles and radii about 0, star-shaped (no gap of pi or more)."""
    angles = np.sort(rng.uniform(0, 2 * np.pi, n))
    while np.diff(np.append(angles, angles[0] + 2 * np.pi)).max() >= np.pi:
        angles = np.sort(rng.uniform(0, 2 * np.pi, n))
    return np.column_stack([np.cos(angles), np.sin(angles)]) * rng.uniform(0.1, 1.0, (n, 1))


def covering(points, xy, tris):
    """How many triangles hold each point (strictly inside, by edge signs)."""
    a, b, c = (xy[tris[:, k]] for k in range(3))
    count = np.zeros(len(points), int)
    for lo in range(0, len(tris), 20_000):
        s = slice(lo, lo + 20_000)
        px, py = points[:, None, 0], points[:, None, 1]

        def edge(p, q):
            return (q[None, s, 0] - p[None, s, 0]) * (py - p[None, s, 1]) - (q[None, s, 1] - p[None, s, 1]) * (px - p[None, s, 0])
        count += np.sum((edge(a, b) > 0) & (edge(b, c) > 0) & (edge(c, a) > 0), axis=1)
    return count


def check_exact_cover(xy, tris, points):
    assert tris.shape == (len(xy) - 2, 3)
    assert tris.min() >= 0 and tris.max() < len(xy)
    a, b, c = (xy[tris[:, k]] for k in range(3))
    doubled = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
    assert doubled.min() >= 0, "a triangle winds the other way (a fold)"
    assert doubled.sum() / 2 == pytest.approx(signed_area(xy), rel=1e-9)
    np.testing.assert_array_equal(covering(points, xy, tris), inside_polygon(points, xy).astype(int))


@pytest.mark.parametrize("shape", ["gear", "spiral band"])
def test_a_polygon_of_200000_corners_is_covered_exactly_once(shape):
    rng = np.random.default_rng(5)
    if shape == "gear":
        xy = gear(200_000)
        r, a = rng.uniform(0.55, 1.02, 300), rng.uniform(0, 2 * np.pi, 300)     # the teeth's ring
        points = np.column_stack([r * np.cos(a), r * np.sin(a)])
    else:
        xy = spiral_band(200_000)
        points = rng.uniform(xy.min(0), xy.max(0), (300, 2))
    check_exact_cover(xy, ear_clip(xy), points)


def test_every_convex_run_is_clipped_in_rounds_not_as_a_fan():
    # A regular 4096-gon passed to the clipper: a fan around one corner would
    # give triangles as long as the polygon; clipping every other corner per
    # round gives a triangle with two short sides at each corner.
    n = 4096
    a = 2 * np.pi * np.arange(n) / n
    xy = np.column_stack([np.cos(a), np.sin(a)])
    tris = ear_clip(xy)
    check_exact_cover(xy, tris, np.random.default_rng(1).uniform(-1, 1, (200, 2)))
    degree = np.bincount(tris.ravel(), minlength=n)
    assert degree.max() <= 2 * np.log2(n) + 2        # a fan's centre is in n - 2 triangles


def test_small_concave_polygons_match_every_sample_point():
    rng = np.random.default_rng(11)
    for _ in range(300):
        n = int(rng.integers(4, 80))
        xy = star_polygon(rng, n)
        check_exact_cover(xy, ear_clip(xy), rng.uniform(-1, 1, (100, 2)))


def test_repeated_corners_and_a_closing_corner_do_not_fold_a_concave_polygon():
    # Exporters repeat corners and close outlines with the first corner again. A corner at the
    # same point as the next turns by 0, counted reflex, never an ear: with two such corners a
    # concave outline ran out of ears and had a triangle clipped across its notch (a review
    # probe found 1,042 of 7,669 such polygons folded; the first one is below).
    a, b, c, d = (-0.352, 0.355), (-0.057, -0.497), (-0.043, -0.749), (0.679, -0.319)
    xy = np.array([a, b, c, c, d, a], float)
    rng = np.random.default_rng(12)
    check_exact_cover(xy, ear_clip(xy), rng.uniform(-1, 1, (400, 2)))
    for _ in range(300):
        n = int(rng.integers(4, 40))
        xy = star_polygon(rng, n)
        repeat = rng.choice(n, size=int(rng.integers(1, 4)), replace=False)
        xy = np.insert(xy, repeat, xy[repeat], axis=0)                        # doubled corners
        if rng.random() < 0.5:
            xy = np.vstack([xy, xy[:1]])                                      # closed with the first corner
        check_exact_cover(xy, ear_clip(xy), rng.uniform(-1, 1, (100, 2)))


def test_an_outline_of_random_points_still_gives_one_triangle_per_corner_less_two():
    # Self-intersecting: no triangulation is right, but the clipper must end
    # with n - 2 triangles of the outline's corners (it clips the most convex
    # corner when no ear is left).
    xy = np.random.default_rng(2).uniform(-1, 1, (100_000, 2))
    tris = ear_clip(xy)
    assert tris.shape == (len(xy) - 2, 3)
    assert len(np.unique(tris)) == len(xy)
    assert np.all((tris[:, 0] != tris[:, 1]) & (tris[:, 1] != tris[:, 2]) & (tris[:, 0] != tris[:, 2]))


@pytest.mark.parametrize("xy", [np.zeros((6, 2)), np.array([[0, 0], [1, 0], [2, 0], [3, 0], [1.5, 0]], float),
                                np.array([[0, 0], [1, np.nan], [1, 1], [0, 1], [0.5, 0.5]], float)])
def test_degenerate_outlines_give_n_minus_2_triangles(xy):
    tris = ear_clip(xy)
    assert tris.shape == (len(xy) - 2, 3)
    assert tris.min() >= 0 and tris.max() < len(xy)


def test_ear_clip_refuses_points_of_the_wrong_shape():
    with pytest.raises(ValueError, match=r"shape \(N, 2\)"):
        ear_clip(np.zeros((5, 3)))


def test_a_concave_nff_polygon_of_100000_corners_loads_and_more_than_the_limit_is_refused(tmp_path):
    xy = gear(100_000)
    body = "\n".join(f"{x:.9g} {y:.9g} 0" for x, y in xy)
    path = tmp_path / "gear.nff"
    path.write_text("v\nfrom 0 0 5\nat 0 0 0\nup 0 1 0\nangle 40\nhither 1\nresolution 64 64\n"
                    f"l 0 0 10\nf 1 1 1 1 0 0 0 1\np {len(xy)}\n{body}\n")
    scene = load_nff(path)
    assert len(scene["triangles"]) == len(xy) - 2
    with pytest.raises(TooManyCorners):
        polygons(np.column_stack([gear(MAX_CLIPPED_CORNERS + 2), np.zeros(MAX_CLIPPED_CORNERS + 2)]),
                 [MAX_CLIPPED_CORNERS + 2])
