"""A sharp mirror (roughness 0) shows the lights that have a shape as Cycles does: a rect, a
disk, an ellipse, a sphere light, a spot with a radius and a sun with an angle appear in it at their
radiance (pi x the light's colour over its area or solid angle: the lights carry the diffuse
BRDF's 1 / pi), where the mirror ray meets them before any surface, and the mirror's share of
their highlight goes (the reflection is it), and sharp glass keeps only its Fresnel reflection
of them. A point light with distance falloff (Blender's)
leaves no highlight in a perfect mirror, as in Cycles. A rough mirror keeps its highlight and
shows no shape; lights without falloff (NFF's) keep Whitted's highlight, so the SPD scenes
render as before. test_b19 compares the same with Cycles through Blender."""
import math

import numpy as np
import pytest

import gridwalk as gw

N = 65
# a mirror quad at z = 0 under a camera looking straight down from z = 10
QUAD_V = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0]], np.float32)
QUAD_F = np.array([[0, 1, 2], [0, 2, 3]], np.int32)
DOWN = (0.0, 0.0, -1.0)


def camera():
    return gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=40.0, width=N, height=N)


def render(light, roughness=0.0, mirror=1.0, ks=0.5, shininess=1e4, blocker=False):
    """The mirror under `light`; blocker: a small opaque quad just below the light."""
    v, f = QUAD_V, QUAD_F
    if blocker:
        v = np.concatenate([QUAD_V, np.array([[-0.3, -0.3, 14], [0.3, -0.3, 14], [0.3, 0.3, 14], [-0.3, 0.3, 14]],
                                             np.float32)])
        f = np.concatenate([QUAD_F, QUAD_F + 4])
    mat = gw.Material(color=(1, 1, 1), kd=0.0, ks=ks, shininess=shininess, mirror=mirror, roughness=roughness)
    scene = gw.Scene(vertices=v, triangles=f, materials=[mat], lights=[light], camera=camera(),
                     background=(0, 0, 0))
    return gw.render(scene, gw.RenderSettings(threads=2, aa="jittered", aa_samples=4))[..., :3].mean(axis=2)


def pixel_area():
    """The mirror image's plane at z = -20 (the lights sit 20 above the mirror, seen from 30 away):
    world units per pixel there."""
    return 2 * 30 * math.tan(math.radians(20)) / N


LIGHTS = {   # light, its radiance as a mirror shows it, the area it covers on the z = -20 plane
    "rect": (gw.Light(kind="rect", position=(0, 0, 20), size=(4.0, 2.0), direction=(0, 0, -1),
                      axis_u=(1, 0, 0), axis_v=(0, -1, 0), color=(3, 3, 3), inverse_square=True),
             math.pi * 3 / 8.0, 8.0),
    "disk": (gw.Light(kind="disk", position=(0, 0, 20), radius=1.5, direction=(0, 0, -1),
                      axis_u=(1, 0, 0), axis_v=(0, -1, 0), color=(3, 3, 3), inverse_square=True),
             3 / 1.5 ** 2, math.pi * 1.5 ** 2),
    "ellipse": (gw.Light(kind="ellipse", position=(0, 0, 20), size=(4.0, 1.5), direction=(0, 0, -1),
                         axis_u=(1, 0, 0), axis_v=(0, -1, 0), color=(3, 3, 3), inverse_square=True),
                3 * math.pi / (math.pi * 4.0 * 1.5 / 4), math.pi * 4.0 * 1.5 / 4),
    "sphere": (gw.Light(kind="sphere", position=(0, 0, 20), radius=1.5, color=(3, 3, 3), inverse_square=True),
               3 / 1.5 ** 2, math.pi * 1.5 ** 2),
    "spot": (gw.Light(kind="spot", position=(0, 0, 20), radius=1.5, direction=(0, 0, -1), color=(3, 3, 3),
                      spot_size=math.radians(90), spot_blend=0.1, inverse_square=True),
             3 / 1.5 ** 2, math.pi * 1.5 ** 2),
}


@pytest.mark.parametrize("name", list(LIGHTS))
def test_a_sharp_mirror_shows_the_light_at_its_radiance_and_size(name):
    light, radiance, area = LIGHTS[name]
    img = render(light)
    inside = img > 0.5 * radiance
    assert abs(img.max() / radiance - 1) < 1e-4                       # the light's own radiance
    assert abs(img[N // 2, N // 2] / radiance - 1) < 1e-4             # (at the centre, seen straight on)
    covered = img.sum() / radiance * pixel_area() ** 2               # anti-aliased edges count by their share
    assert abs(covered / area - 1) < 0.05
    near = inside.copy()                                              # the shape and the 8 pixels round each
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            near |= np.roll(inside, (dy, dx), axis=(0, 1))
    assert img[~near].max() == 0                                      # no highlight beside it


def test_an_ellipse_shows_its_own_shape():
    """4 x 1.5 diameters along x and y: as wide and as tall in the mirror (not a disk of its area)."""
    light, radiance, _ = LIGHTS["ellipse"]
    inside = render(light) > 0.5 * radiance
    rows, cols = np.nonzero(inside)
    width, height = (cols.max() - cols.min() + 1) * pixel_area(), (rows.max() - rows.min() + 1) * pixel_area()
    assert abs(width / 4.0 - 1) < 0.1 and abs(height / 1.5 - 1) < 0.15


def test_a_sun_with_an_angle_shows_as_a_disc_of_its_angle():
    angle, strength = math.radians(8.0), 0.5
    img = render(gw.Light(kind="sun", direction=DOWN, angle=angle, color=(strength,) * 3))
    radiance = strength / math.sin(angle / 2) ** 2     # (pi x colour over the disc's pi sin^2, as Cycles 4+)
    assert abs(img[N // 2, N // 2] / radiance - 1) < 1e-4
    fov = math.radians(40)
    pixels = img.sum() / radiance
    expected = (math.tan(angle / 2) / math.tan(fov / 2) * N / 2) ** 2 * math.pi
    assert abs(pixels / expected - 1) < 0.05


def test_a_surface_in_front_hides_the_light_and_a_half_mirror_shows_half():
    light, radiance, _ = LIGHTS["rect"]
    hidden = render(light, blocker=True)
    assert hidden[N // 2, N // 2] == 0 and hidden.max() > 0.9 * radiance   # the blocker covers the middle only
    half = render(light, mirror=0.5, ks=0.0)
    assert abs(half.max() / (0.5 * radiance) - 1) < 1e-4


def test_sharp_glass_shows_a_light_by_its_fresnel_reflection_alone():
    """Glass reflects the light it sees along its Fresnel ray (Schlick: 0.04 of it head-on at
    IOR 1.5), and its highlight, which stood for the same reflection, goes."""
    light, radiance, _ = LIGHTS["rect"]
    v, f = QUAD_V, QUAD_F
    glass = gw.Material(color=(1, 1, 1), kd=0.0, ks=5.0, shininess=1000.0, transmittance=1.0, ior=1.5)
    scene = gw.Scene(vertices=v, triangles=f, materials=[glass], lights=[light], camera=camera(),
                     background=(0, 0, 0))
    img = gw.render(scene, gw.RenderSettings(threads=2, aa="jittered", aa_samples=4))[..., :3].mean(axis=2)
    assert abs(img[N // 2, N // 2] / (0.04 * radiance) - 1) < 1e-3


def test_a_point_light_leaves_no_highlight_in_a_perfect_mirror_but_in_a_rough_one():
    point = gw.Light(kind="point", position=(0, 0, 20), color=(300, 300, 300), inverse_square=True)
    assert render(point).max() == 0
    rough = render(point, roughness=0.3, shininess=200.0)
    assert rough.max() > 0.01                                         # the highlight stays
    rect = render(LIGHTS["rect"][0], roughness=0.3, shininess=200.0)
    assert rect.max() < 0.5 * LIGHTS["rect"][1]                       # no sharp shape in a rough mirror


def test_lights_without_falloff_keep_whitteds_highlight():
    nff = gw.Light(kind="point", position=(0, 0, 20), color=(1, 1, 1))   # an NFF light
    img = render(nff, ks=0.5, shininess=50.0)
    h = img[N // 2, N // 2]
    assert abs(h / 0.5 - 1) < 1e-3                                    # ks x (n.h)^shine x I, n.h = 1
