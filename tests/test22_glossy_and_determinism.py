"""Glossy reflection (roughness 0 is the exact mirror; no brightening) and
bit-identical images for every sampling mode at any thread count."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk.scenes import balls, distant

FLOOR_V = np.array([[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]], np.float32)
FLOOR_F = np.array([[0, 1, 2], [0, 2, 3]], np.int32)


def mirror_floor(roughness, res=40):
    mat = gw.Material(color=(1, 1, 1), kd=0.0, mirror=1.0, roughness=roughness)
    cam = gw.Camera(eye=(0, -8, 3), target=(0, 0, 0), fov=40, width=res, height=res)
    return gw.Scene(vertices=FLOOR_V, triangles=FLOOR_F, materials=[mat], camera=cam, background=(1, 1, 1))


def test_roughness_zero_is_the_exact_mirror():
    sc = mirror_floor(0.0)
    one = gw.render(sc, gw.RenderSettings(glossy_samples=1))
    many = gw.render(sc, gw.RenderSettings(glossy_samples=32, seed=3))
    assert np.array_equal(one, many)
    assert np.allclose(one[..., :3], 1.0)


@pytest.mark.parametrize("roughness", [0.1, 0.3, 0.7])
def test_glossy_never_brightens_a_mirror(roughness):
    img = gw.render(mirror_floor(roughness), gw.RenderSettings(glossy_samples=16))[..., :3]
    assert img.max() <= 1.0 + 1e-6
    assert img.mean() > (0.9 if roughness < 0.5 else 0.5)


def test_glossy_blurs_reflections():
    # (no lamp highlights: a glossy surface's are GGX's, a sharp one's Phong's)
    kw = balls(1)
    for m in kw["materials"]:
        m.roughness, m.ks = 0.4, 0.0
    kw["camera"].width = kw["camera"].height = 48
    sharp_kw = balls(1)
    for m in sharp_kw["materials"]:
        m.ks = 0.0
    sharp_kw["camera"].width = sharp_kw["camera"].height = 48
    glossy = gw.render(gw.Scene(**kw), gw.RenderSettings(glossy_samples=32))[..., :3]
    sharp = gw.render(gw.Scene(**sharp_kw))[..., :3]
    grad = lambda im: np.abs(np.diff(im, axis=1)).mean()
    assert grad(glossy) < grad(sharp)


def glass_before_stripes(roughness, res=48, ior=1.5, sphere=True, multiscatter=False):
    """An analytic glass sphere (clear: kd 0; sphere False: none) in front of a wall of 16 vertical
    stripes, alternately emissive (1) and black; the camera looks through the sphere at the wall."""
    verts, tris, mats = [], [], []
    for k in range(16):
        x0, x1 = -4 + 0.5 * k, -3.5 + 0.5 * k
        base = len(verts)
        verts += [[x0, 3, -4], [x1, 3, -4], [x1, 3, 4], [x0, 3, 4]]
        tris += [[base, base + 1, base + 2], [base, base + 2, base + 3]]
        mats += [k % 2, k % 2]
    materials = [gw.Material(color=(0, 0, 0), kd=0.0, ks=0.0),
                 gw.Material(color=(1, 1, 1), kd=0.0, ks=0.0, emission=1.0),
                 gw.Material(color=(1, 1, 1), kd=0.0, ks=0.0, transmittance=1.0, ior=ior, roughness=roughness,
                             multiscatter=multiscatter)]
    cam = gw.Camera(eye=(0, -6, 0), target=(0, 0, 0), fov=20, width=res, height=res)
    ball = dict(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], sphere_materials=[2]) if sphere else {}
    return gw.Scene(vertices=np.array(verts, np.float32), triangles=np.array(tris, np.int32),
                    triangle_materials=np.array(mats, np.int32), materials=materials, camera=cam, **ball)


@pytest.mark.parametrize("roughness", [0.0, 0.3])
def test_glass_of_ior_1_is_invisible_and_casts_no_shadow(roughness):
    # Schlick's grazing term drew a rim round it (Cycles shows nothing) and a dark ring in its
    # shadow; rough, it blurred what lies behind though it bends nothing. F is 0 at IOR 1.
    settings = gw.RenderSettings(aa="jittered", aa_samples=3, glossy_samples=2)
    through = gw.render(glass_before_stripes(roughness, ior=1.0), settings)
    without = gw.render(glass_before_stripes(roughness, sphere=False), settings)
    np.testing.assert_allclose(through, without, atol=1e-5)
    # its shadow on a lit floor: a point light above it, the camera below looking at the floor
    floor = np.array([[-9, -9, 0], [9, -9, 0], [9, 9, 0], [-9, 9, 0]], np.float32)
    cam = gw.Camera(eye=(0, 0, 1.5), target=(0, 0, 0), up=(0, 1, 0), fov=90, width=32, height=32)
    glass = gw.Material(color=(1, 1, 1), kd=0.0, ks=0.0, transmittance=1.0, ior=1.0, roughness=roughness)
    lit = lambda ball: gw.render(gw.Scene(floor, FLOOR_F, materials=[gw.Material(), glass], camera=cam,
                                          lights=[gw.Light(position=(0, 0, 8), color=(1, 1, 1))], **ball), settings)
    np.testing.assert_allclose(lit(dict(sphere_centers=[[0, 0, 4]], sphere_radii=[1.0], sphere_materials=[1])),
                               lit({}), atol=1e-5)


def test_rough_glass_blurs_what_lies_behind_it():
    # Roughness was read for reflections only: rough glass rendered as clear glass. (Multiscatter:
    # single-scattering GGX glass loses light between its microfacets, 11% of the stripes' light
    # here at roughness 0.6, as Cycles' GGX glass does; its multiscatter returns it.)
    settings = gw.RenderSettings(aa="jittered", aa_samples=4, glossy_samples=4)
    images = {r: gw.render(glass_before_stripes(r, multiscatter=True), settings)[..., 0] for r in (0.0, 0.3, 0.6)}
    inside = np.hypot(*np.meshgrid(np.arange(48) - 23.5, np.arange(48) - 23.5)) < 12   # well inside the sphere

    def contrast(img):   # the spread of the image smoothed over 5 x 5 pixels (the samples' noise averaged out)
        padded = np.pad(img, 2, mode="edge")
        smooth = sum(padded[i:i + 48, j:j + 48] for i in range(5) for j in range(5)) / 25
        return smooth[inside].std()
    c = {r: contrast(img) for r, img in images.items()}
    assert c[0.0] > 0.3                                    # the stripes, sharp through clear glass
    assert c[0.3] < 0.6 * c[0.0] and c[0.6] < 0.5 * c[0.3]
    # blurred, not darkened: about the stripes' mean light comes through (Fresnel takes a little)
    means = {r: img[inside].mean() for r, img in images.items()}
    assert 0.3 < means[0.0] < 0.6 and abs(means[0.6] - means[0.0]) < 0.1
    # roughness 0 is the exact refraction: more lobe samples change nothing
    clear = glass_before_stripes(0.0)
    assert np.array_equal(gw.render(clear, settings), gw.render(clear, settings.replace(glossy_samples=16)))


MODES = [
    dict(aa="jittered", aa_samples=3),
    dict(aa="random", aa_samples=2, filter="gaussian"),
    dict(aa="sobol", aa_samples=3),
    dict(aa="adaptive", adaptive_depth=2),
    dict(shadow="random", shadow_samples=3),
    dict(shadow="area", shadow_samples=3, aa="jittered", aa_samples=2),
    dict(glossy_samples=4),
]


@pytest.mark.parametrize("mode", MODES, ids=lambda m: "-".join(f"{k}={v}" for k, v in m.items()))
def test_every_mode_is_bit_identical_across_thread_counts(mode):
    kw = balls(1)
    kw["camera"].width = kw["camera"].height = 40
    kw["lights"] = [gw.Light(position=l.position, color=l.color, kind="sphere", radius=0.3) for l in kw["lights"]]
    for m in kw["materials"]:
        m.roughness = 0.2
    sc = gw.Scene(**kw)
    a = gw.render(sc, gw.RenderSettings(threads=1, tile_size=16, **mode))
    b = gw.render(sc, gw.RenderSettings(threads=4, tile_size=7, **mode))
    c = gw.render(sc, gw.RenderSettings(threads=4, tile_size=7, **mode))
    assert np.array_equal(a, b) and np.array_equal(b, c)
    d = gw.render(sc, gw.RenderSettings(threads=1, tile_size=16, seed=1, **mode))
    assert not np.array_equal(a, d)   # the seed does change the samples


def test_depth_of_field_is_deterministic_on_the_distant_scene():
    kw = distant()
    kw["camera"].width = kw["camera"].height = 40
    sc = gw.Scene(**kw)
    a = gw.render(sc, gw.RenderSettings(dof_samples=8, threads=1))
    b = gw.render(sc, gw.RenderSettings(dof_samples=8, threads=3, tile_size=9))
    assert np.array_equal(a, b)
