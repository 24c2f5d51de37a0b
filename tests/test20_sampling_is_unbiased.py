"""Distribution estimates against analytic values: the penumbra under a disk
light (random and shuffled-grid soft shadows) and the blur circle of a point
out of focus (thin lens)."""
import numpy as np
import pytest

import gridwalk as gw

H_LIGHT, H_OCC, R_LIGHT = 4.0, 2.0, 1.0


def penumbra_scene(width):
    """Floor z=0, an opaque half-plane x<0 at z=2, a downward disk light of radius 1 at z=4."""
    floor_v = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
    occ_v = np.array([[-50, -50, H_OCC], [0, -50, H_OCC], [0, 50, H_OCC], [-50, 50, H_OCC]], np.float32)
    V = np.concatenate([floor_v, occ_v])
    F = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]], np.int32)
    light = gw.Light(kind="disk", position=(0, 0, H_LIGHT), radius=R_LIGHT, axis_u=(1, 0, 0), axis_v=(0, 1, 0),
                     direction=(0, 0, -1), color=(1, 1, 1))
    # Camera between floor and occluder looking straight down; its row of
    # pixels spans x in [-1.5, 2.5]: umbra (x < -1), penumbra, full light (x > 1).
    half = 2.0 / 1.5 / (width / 3)
    cam = gw.Camera(eye=(0.5, 0.0, 1.5), target=(0.5, 0.0, 0.0), up=(0, 1, 0),
                    fov=float(np.degrees(2 * np.arctan(half))), width=width, height=3)
    mat = gw.Material(color=(1, 1, 1), kd=1.0)
    return gw.Scene(vertices=V, triangles=F, materials=[mat], lights=[light], camera=cam), cam


def floor_points(cam):
    t = np.tan(np.radians(cam.fov) / 2)
    aspect = cam.width / cam.height
    x = (2 * (np.arange(cam.width) + 0.5) / cam.width - 1) * t * aspect
    # camera looks down -z with up = +y: right = fwd x up = (0,0,-1) x (0,1,0) = (1,0,0)
    return np.stack([cam.eye[0] + x * cam.eye[2], np.zeros_like(x), np.zeros_like(x)], -1)


def exact_shading(P, n=400):
    """Average over the light disk (uniform in area) of cos_i * cos_l * visibility."""
    r = R_LIGHT * np.sqrt((np.arange(n) + 0.5) / n)
    phi = 2 * np.pi * (np.arange(n) + 0.5) / n
    R, PHI = np.meshgrid(r, phi)
    Q = np.stack([R * np.cos(PHI), R * np.sin(PHI), np.full_like(R, H_LIGHT)], -1).reshape(-1, 3)
    out = []
    for p in P:
        w = Q - p
        dist = np.linalg.norm(w, axis=1)
        cos_i, cos_l = w[:, 2] / dist, w[:, 2] / dist
        x_at_occ = p[0] + (Q[:, 0] - p[0]) * (H_OCC / H_LIGHT)
        vis = x_at_occ >= 0
        out.append(np.mean(cos_i * cos_l * vis))
    return np.array(out)


@pytest.mark.parametrize("mode, n", [("random", 16), ("area", 4)])
def test_penumbra_matches_the_visible_fraction_of_the_disk(mode, n):
    sc, cam = penumbra_scene(width=96)
    P = floor_points(cam)
    exact = exact_shading(P)
    assert exact.min() < 0.05 and exact.max() > 0.8   # the image spans umbra to full light
    runs = np.stack([gw.render(sc, gw.RenderSettings(shadow=mode, shadow_samples=n, seed=s))[1, :, 0]
                     for s in range(24)])
    est = runs.mean(0)
    sem = runs.std(0, ddof=1) / np.sqrt(len(runs)) + 1e-4
    z = (est - exact) / sem
    assert np.all(np.abs(z) < 5), np.abs(z).max()
    assert abs(np.mean(est - exact)) < 4 * np.sqrt(np.mean(sem ** 2) / len(exact)) + 1e-4


def test_shuffled_light_grid_has_less_noise_than_random_points():
    sc, _ = penumbra_scene(width=96)
    var = {}
    for mode, n in (("random", 16), ("area", 4)):   # 16 shadow rays per pixel either way
        runs = np.stack([gw.render(sc, gw.RenderSettings(shadow=mode, shadow_samples=n, seed=s))[1, :, 0]
                         for s in range(16)])
        var[mode] = runs.var(0, ddof=1).mean()
    assert var["area"] < 0.5 * var["random"], var


def test_blur_circle_of_an_out_of_focus_point():
    Z, F, A, res, fov = 20.0, 8.0, 0.25, 160, 30.0
    cam = gw.Camera(eye=(0, 0, 0), target=(0, Z, 0), up=(0, 0, 1), fov=fov, width=res, height=res,
                    aperture=A, focus_distance=F)
    glow = gw.Material(color=(1, 1, 1), kd=0.0, emission=1.0)
    radius = 0.02
    sc = gw.Scene(sphere_centers=[[0, Z, 0]], sphere_radii=[radius], materials=[glow], camera=cam,
                  background=(0, 0, 0))
    img = gw.render(sc, gw.RenderSettings(aa="jittered", aa_samples=4, dof_samples=64))[..., 0].astype(np.float64)
    px_per_unit = res / (2 * np.tan(np.radians(fov) / 2))     # on the plane at distance 1
    r_blur = A * abs(1 / F - 1 / Z) * px_per_unit              # circle of confusion, pixels
    r_self = radius / Z * px_per_unit
    y, x = np.mgrid[0:res, 0:res] + 0.5 - res / 2
    m2 = np.sum(img * (x * x + y * y)) / np.sum(img)
    # Second moments add: uniform disk r^2/2, the sphere's own disk, and the 1-pixel box.
    r_measured = np.sqrt(2 * (m2 - r_self ** 2 / 2 - 1 / 6))
    assert r_blur > 5
    assert abs(r_measured - r_blur) < 0.03 * r_blur, (r_measured, r_blur)
    # The same point in focus stays sharp.
    focused = gw.Scene(sphere_centers=[[0, Z, 0]], sphere_radii=[radius], materials=[glow], background=(0, 0, 0),
                       camera=gw.Camera(eye=(0, 0, 0), target=(0, Z, 0), fov=fov, width=res, height=res,
                                        aperture=A, focus_distance=Z))
    img_f = gw.render(focused, gw.RenderSettings(aa="jittered", aa_samples=4, dof_samples=64))[..., 0]
    assert np.count_nonzero(img_f > 1e-3) < 16
    assert np.count_nonzero(img > 1e-3) > 0.5 * np.pi * r_blur ** 2
