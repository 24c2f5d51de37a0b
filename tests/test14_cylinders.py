"""Cones and cylinders (NFF "c"): ray intersection against an extended-precision
reference, the grid against brute force, and a rendered NFF cylinder."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk.io import load_nff
from gridwalk.scene import KIND_CYLINDER, KIND_MISS
from gridwalk.validate import camera_rays

REL_T = 1e-5


def random_rotations(rng, n):
    q, r = np.linalg.qr(rng.normal(size=(n, 3, 3)))
    return q * np.sign(np.diagonal(r, axis1=1, axis2=2))[:, None, :]


def random_cones(rng, n, cylinders_only=False):
    """Canonical cones (axis +z, height h, radii r0 -> r1) under random
    rotations, scales (0.01 .. 100) and translations (up to 50 sizes away)."""
    height = rng.uniform(0.5, 3.0, n)
    r0 = rng.uniform(0.1, 1.0, n)
    r1 = r0.copy() if cylinders_only else np.where(rng.random(n) < 0.3, r0, rng.uniform(0.0, 1.0, n))
    r1[~cylinders_only & (rng.random(n) < 0.1)] = 0.0                  # pointed cones
    scale = 10.0 ** rng.uniform(-2, 2, n)
    rot = random_rotations(rng, n)
    shift = rng.uniform(-50, 50, (n, 3)) * scale[:, None]
    base = shift.astype(np.float32)
    apex = (shift + scale[:, None] * rot[:, :, 2] * height[:, None]).astype(np.float32)
    return base, apex, (r0 * scale).astype(np.float32), (r1 * scale).astype(np.float32)


def rays_at(rng, base, apex, r_base, r_apex, n):
    """Rays from around one cone (some inside it) aimed near its axis."""
    b, a = base.astype(np.float64), apex.astype(np.float64)
    size = np.linalg.norm(a - b) + 2 * max(r_base, r_apex)
    centre = (a + b) / 2
    origins = centre + rng.uniform(-1.5, 1.5, (n, 3)) * size
    origins[: n // 10] = b + (a - b) * rng.random((n // 10, 1))        # on the axis: inside
    targets = b + (a - b) * rng.uniform(-0.2, 1.2, (n, 1)) + rng.normal(size=(n, 3)) * max(r_base, r_apex)
    d = targets - origins
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    return origins.astype(np.float32), d.astype(np.float32)


def reference_t(origins, dirs, base, apex, r_base, r_apex):
    """Nearest t > 0 on the open cone frustum, in long double from the float32
    inputs. Written as |p - B|^2 - s^2 = r(s)^2 with s = (p - B).axis, without
    the core's projection onto the axis' normal plane."""
    ld = np.longdouble
    o, d = origins.astype(ld), dirs.astype(ld)
    b, a = base.astype(ld), apex.astype(ld)
    height = np.sqrt(np.sum((a - b) ** 2))
    axis = (a - b) / height
    r0, r1 = ld(abs(float(r_base))), ld(abs(float(r_apex)))
    k = (r1 - r0) / height
    w = o - b
    wh, dh = w @ axis, d @ axis
    qa = np.sum(d * d, 1) - dh * dh - (k * dh) ** 2
    qb = np.sum(w * d, 1) - wh * dh - k * dh * (r0 + k * wh)                 # half b
    qc = np.sum(w * w, 1) - wh * wh - (r0 + k * wh) ** 2
    disc = qb * qb - qa * qc
    root = np.sqrt(np.maximum(disc, 0))
    q = -(qb + np.copysign(root, qb))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0, t1 = q / qa, qc / q
    best = np.full(len(o), np.inf)
    for t in (np.maximum(t0, t1), np.minimum(t0, t1)):                     # nearest wins
        s = wh + t * dh
        ok = (disc >= 0) & np.isfinite(t) & (t > 0) & (s >= 0) & (s <= height) & (r0 + k * s >= 0)
        best = np.where(ok, t.astype(np.float64), best)
    return best


def one_cone_scene(base, apex, r_base, r_apex):
    return gw.Scene(cylinder_base=base[None], cylinder_apex=apex[None], cylinder_base_radius=[r_base],
                    cylinder_apex_radius=[r_apex])


@pytest.mark.parametrize("cylinders_only", [True, False], ids=["cylinders", "cones"])
def test_cone_hits_match_an_extended_precision_reference(cylinders_only):
    rng = np.random.default_rng(14 + cylinders_only)
    base, apex, r_base, r_apex = random_cones(rng, 60, cylinders_only)
    rays = hit_rays = disagree = 0
    worst = 0.0
    for i in range(len(base)):
        o, d = rays_at(rng, base[i], apex[i], r_base[i], r_apex[i], 2000)
        hits = one_cone_scene(base[i], apex[i], r_base[i], r_apex[i]).intersect(o, d, settings=gw.RenderSettings(accel="none"))
        t_ref = reference_t(o, d, base[i], apex[i], r_base[i], r_apex[i])
        hit = np.isfinite(hits.t)
        assert np.all(hits.kind[hit] == KIND_CYLINDER) and np.all(hits.kind[~hit] == KIND_MISS)
        disagree += int(np.sum(hit != np.isfinite(t_ref)))
        both = hit & np.isfinite(t_ref)
        worst = max(worst, float(np.max(np.abs(hits.t[both] - t_ref[both]) / t_ref[both], initial=0)))
        rays, hit_rays = rays + len(o), hit_rays + int(both.sum())
    print(f"{rays} rays, {hit_rays} hits, {disagree} hit/miss disagreements, max rel t error {worst:.3g}")
    assert hit_rays > rays / 4                     # the rays do test the surface
    assert disagree <= rays * 1e-5, f"{disagree} of {rays} rays disagree on hit / miss"
    assert worst <= REL_T, f"largest relative t error {worst:.3g}"


def _hard_rays(case, rng, n, apex_radius):
    """Numerically hard rays for a cone from (0,0,0) (radius 1) to (0,0,10)."""
    y = np.tile([0.0, 1.0, 0.0], (n, 1))
    if case == "tangent":          # pass within ~1e-6 of the silhouette
        z = rng.uniform(0, 10, n)
        x = (1 + (apex_radius - 1) * z / 10) * (1 + rng.normal(size=n) * 1e-6)
        return np.stack([x, np.full(n, -5.0), z], 1), y
    if case == "rim":              # cross the open end's plane within ~1e-5
        return np.stack([rng.uniform(-2, 2, n), np.full(n, -5.0), rng.normal(size=n) * 1e-5], 1), y
    if case == "far":              # from 1e4 away, aimed at the cone
        d = rng.normal(size=(n, 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        target = rng.uniform([-1.2, -1.2, -1], [1.2, 1.2, 11], (n, 3))
        return target - 1e4 * d, d
    if case == "slant":            # parallel to a generator line of the cone (quadratic term ~ 0)
        d = np.tile(np.array([-1.0, 0.0, 10.0]) / np.sqrt(101.0), (n, 1))
        return np.stack([rng.uniform(-3, 3, n), rng.uniform(-0.5, 0.5, n), np.full(n, -5.0)], 1), d
    angle, phi = 10 ** rng.uniform(-5, -0.5, n), rng.uniform(0, 2 * np.pi, n)   # "axial": inside, nearly
    d = np.stack([np.sin(angle) * np.cos(phi), np.sin(angle) * np.sin(phi), np.cos(angle)], 1)  # along the axis
    return np.column_stack([rng.uniform(-0.5, 0.5, (n, 2)), rng.uniform(0, 2, n)]), d


@pytest.mark.parametrize("apex_radius", [1.0, 0.5, 0.0])
@pytest.mark.parametrize("case", ["tangent", "rim", "far", "slant", "axial"])
def test_numerically_hard_rays_match_the_reference(case, apex_radius):
    base, apex = np.float32([0, 0, 0]), np.float32([0, 0, 10])
    o, d = (a.astype(np.float32) for a in _hard_rays(case, np.random.default_rng(3), 5000, apex_radius))
    hits = one_cone_scene(base, apex, 1.0, apex_radius).intersect(o, d, settings=gw.RenderSettings(accel="none"))
    t_ref = reference_t(o, d, base, apex, 1.0, apex_radius)
    hit, ref_hit = np.isfinite(hits.t), np.isfinite(t_ref)
    assert hit.sum() > 500 and np.sum(hit != ref_hit) == 0
    both = hit & ref_hit
    np.testing.assert_array_less(np.abs(hits.t[both] - t_ref[both]), REL_T * t_ref[both] + 1e-30)


def test_rays_along_the_axis_of_a_cylinder_miss_its_open_tube():
    scene = one_cone_scene(np.float32([0, 0, 0]), np.float32([0, 0, 2]), 1.0, 1.0)
    o = np.float32([[0, 0, -1], [0.5, 0, -1], [0, 0, 1], [0, 0, 1]])
    d = np.float32([[0, 0, 1], [0, 0, 1], [1, 0, 0], [0, 0, -1]])
    hits = scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    np.testing.assert_array_equal(hits.kind, [KIND_MISS, KIND_MISS, KIND_CYLINDER, KIND_MISS])
    assert hits.t[2] == pytest.approx(1.0, rel=1e-6)
    np.testing.assert_allclose(hits.normal[2], [1, 0, 0], atol=1e-6)


def test_grid_finds_the_same_hits_as_brute_force_among_many_cylinders():
    rng = np.random.default_rng(7)
    n = 3000
    base = rng.uniform(-10, 10, (n, 3))
    axis = rng.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    apex = base + axis * rng.uniform(0.2, 2.0, (n, 1))
    r0, r1 = rng.uniform(0.02, 0.3, n), rng.uniform(0.0, 0.3, n)
    scene = gw.Scene(cylinder_base=base.astype(np.float32), cylinder_apex=apex.astype(np.float32),
                     cylinder_base_radius=r0.astype(np.float32), cylinder_apex_radius=r1.astype(np.float32))
    o = rng.uniform(-12, 12, (20000, 3)).astype(np.float32)
    d = rng.normal(size=(20000, 3)).astype(np.float32)
    d[:6000] = np.repeat(np.eye(3, dtype=np.float32), 2000, axis=0)   # axis-parallel: DDA edge cases
    o[:6000] = np.round(o[:6000])
    brute = scene.intersect(o, d, settings=gw.RenderSettings(accel="none"))
    assert 0.2 < np.mean(np.isfinite(brute.t)) < 0.95
    for mailboxes in (True, False):
        grid = scene.intersect(o, d, settings=gw.RenderSettings(accel="grid", mailboxes=mailboxes))
        np.testing.assert_array_equal(grid.t, brute.t)
        np.testing.assert_array_equal(grid.kind, brute.kind)
        np.testing.assert_array_equal(grid.prim, brute.prim)


def test_a_rendered_nff_cylinder_and_cone_appear_where_rays_hit_them(tmp_path):
    path = tmp_path / "c.nff"
    path.write_text("v\nfrom 0 -6 1\nat 0 0 0\nup 0 0 1\nangle 40\nhither 0.01\nresolution 48 40\n"
                    "b 0.1 0.2 0.5\nl 3 -5 4\n"
                    "f 0.9 0.1 0.1 0.9 0 10 0 1\nc\n-1 0 -1 0.5\n-1 0 1 0.5\n"     # red cylinder
                    "f 0.1 0.9 0.1 0.9 0 10 0 1\nc\n1 0 -1 0.7\n1 0 1 0\n")        # green cone
    kwargs = load_nff(path)
    assert len(kwargs["cylinder_base"]) == 2
    scene = gw.Scene(**kwargs)
    rgba = gw.render(scene, gw.RenderSettings())
    o, d = camera_rays(scene.camera, 48 * 40)      # one ray through each pixel centre
    hits = scene.intersect(o, d)
    covered = rgba[..., 3].reshape(-1) > 0.5
    assert np.mean(covered == (hits.kind == KIND_CYLINDER)) > 0.99
    red = (hits.kind == KIND_CYLINDER) & (hits.prim == 0)
    green = (hits.kind == KIND_CYLINDER) & (hits.prim == 1)
    assert red.sum() > 50 and green.sum() > 50
    rgb = rgba[..., :3].reshape(-1, 3)
    assert rgb[red, 0].mean() > 3 * rgb[red, 1].mean() and rgb[green, 1].mean() > 3 * rgb[green, 0].mean()
