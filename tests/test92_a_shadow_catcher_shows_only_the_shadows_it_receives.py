"""Material.shadow_catcher (Blender's object Shadow Catcher): camera rays that meet the
surface see what lies behind it, darkened by the share of light the scene keeps from it (its
light with shadows over its light without them); on a transparent film that shadow is black
coverage. Checked against the shadow a sphere casts, worked out pixel by pixel (a floor point
is in shadow where its ray towards the sun meets the sphere): full shadow is alpha 1 and
black, light is alpha 0 (or the background, on an opaque film); world light fills the shadow
by exactly its share of the floor's light (and, with world shadows, the sphere hides some of
it); a catcher covering half (alpha 0.5) darkens by half; rays other than the camera's see
the floor as its material; the image is the same on one thread and two. Blender's side:
tests/blender/test_b49."""
import numpy as np

import gridwalk as gw

N = 64
FLOOR = np.array([[-4, -4, 0], [4, -4, 0], [4, 4, 0], [-4, 4, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
CENTRE, RADIUS = np.array([0.0, 0.0, 1.5]), 0.8
TO_SUN = np.array([1.0, 0.3, 1.0]) / np.linalg.norm([1.0, 0.3, 1.0])
BACKGROUND = (0.2, 0.3, 0.4)


def _render(transparent=True, ambient=(0.0, 0.0, 0.0), catcher=True, ball_mirror=0.0, alpha=1.0, world_shadows=False,
            threads=1):
    cam = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=8.0,
                    width=N, height=N)
    s = gw.Scene(FLOOR, TRIS, sphere_centers=[tuple(CENTRE)], sphere_radii=[RADIUS], sphere_materials=[1],
                 camera=cam, background=BACKGROUND, world=gw.World(transparent=transparent, ambient=ambient),
                 materials=[gw.Material(color=(0.5, 0.5, 0.5), shadow_catcher=catcher, alpha=alpha),
                            gw.Material(color=(0.8, 0.2, 0.2), kd=0.2 if ball_mirror else 0.8, mirror=ball_mirror)],
                 lights=[gw.Light(kind="sun", direction=tuple(-TO_SUN), color=(1, 1, 1))])
    return gw.RenderJob(s, gw.RenderSettings(threads=threads, world_shadows=world_shadows, shadow_samples=16,
                                             tile_size=16)).start().wait()


def _regions():
    """(floor in shadow, floor in light) at the pixel centres, both off the sphere's image and
    a pixel away from the shadow's edge."""
    c = (np.arange(N) + 0.5) / N * 8.0 - 4.0
    x, y = np.meshgrid(c, c[::-1])
    on_floor = np.stack([x, y, np.zeros_like(x)], axis=-1)
    # the ray from each floor point towards the sun against the sphere: |p + t s - c|^2 = r^2
    oc = on_floor - CENTRE
    b = oc @ TO_SUN
    gap = b * b - ((oc * oc).sum(-1) - RADIUS ** 2)          # > 0: the line meets the sphere
    off_sphere = np.hypot(x - CENTRE[0], y - CENTRE[1]) > RADIUS + 0.15
    margin = 0.25 * RADIUS ** 2
    shadow = (gap > margin) & (-b > 0) & off_sphere
    light = ((gap < -margin) | (-b < 0)) & off_sphere
    return shadow, light


def test_on_a_transparent_film_full_shadow_is_black_coverage_and_light_is_clear():
    image = _render()
    shadow, light = _regions()
    assert shadow.sum() > 50 and light.sum() > 1000
    np.testing.assert_allclose(image[shadow], [[0, 0, 0, 1]] * int(shadow.sum()), atol=1e-6)
    np.testing.assert_allclose(image[light], [[0, 0, 0, 0]] * int(light.sum()), atol=1e-6)


def test_on_an_opaque_film_the_floor_shows_the_background_darkened_by_the_shadow():
    image = _render(transparent=False)
    shadow, light = _regions()
    np.testing.assert_allclose(image[light][:, :3], np.broadcast_to(BACKGROUND, (int(light.sum()), 3)), atol=1e-6)
    np.testing.assert_allclose(image[shadow][:, :3], 0.0, atol=1e-6)


def test_world_light_fills_the_shadow_part_way():
    # the floor's light: the world's 0.3 against the sun's cosine; in the shadow only the world's
    image = _render(ambient=(0.3, 0.3, 0.3))
    shadow, light = _regions()
    np.testing.assert_allclose(image[shadow][:, 3], 1 - 0.3 / (0.3 + TO_SUN[2]), atol=1e-5)
    np.testing.assert_allclose(image[light][:, 3], 0.0, atol=1e-6)
    # with world shadows the sphere hides part of the world too: deeper in its shadow, and a
    # faint shadow of the world's light around it
    hidden = _render(ambient=(0.3, 0.3, 0.3), world_shadows=True)
    assert hidden[shadow][:, 3].mean() > image[shadow][:, 3].mean() + 0.01
    assert 0.005 < hidden[light][:, 3].max() < 0.5 and hidden[light][:, 3].mean() < 0.05


def test_a_partly_covering_catcher_darkens_by_its_share():
    half, full = _render(alpha=0.5), _render()
    shadow, light = _regions()
    np.testing.assert_allclose(half[shadow][:, 3], 0.5, atol=1e-6)
    np.testing.assert_allclose(half[light][:, 3], 0.0, atol=1e-6)
    np.testing.assert_allclose(full[shadow][:, 3], 1.0, atol=1e-6)


def test_the_image_does_not_depend_on_the_thread_count():
    one = _render(ambient=(0.3, 0.3, 0.3), world_shadows=True)
    two = _render(ambient=(0.3, 0.3, 0.3), world_shadows=True, threads=2)
    np.testing.assert_array_equal(one, two)


def test_without_the_flag_the_floor_is_a_surface():
    image = _render(catcher=False)
    shadow, light = _regions()
    assert image[light][:, 3].min() == 1.0 and image[light][:, 0].min() > 0.1


def test_other_rays_see_the_catcher_as_its_material():
    # a mirror ball reflects the floor below it: its grey, lit by the sun, not the background
    with_catcher, without = _render(ball_mirror=0.8), _render(ball_mirror=0.8, catcher=False)
    c = (np.arange(N) + 0.5) / N * 8.0 - 4.0
    x, y = np.meshgrid(c, c[::-1])
    r = np.hypot(x - CENTRE[0], y - CENTRE[1])
    rim = (r > 0.85 * RADIUS) & (r < 0.95 * RADIUS)          # (its rim mirrors the view down onto the floor)
    assert rim.sum() > 10
    np.testing.assert_allclose(with_catcher[rim], without[rim], atol=1e-6)
    assert np.abs(with_catcher[rim][:, :3] - BACKGROUND).max() > 0.05


def test_a_catcher_made_of_a_closed_slab_catches_as_its_top_face_alone():
    # (a catcher floor modelled as a thin box, Blender's cube scaled flat: the ray gone on behind
    # its top met its underside, a catcher in the top's shadow, and the whole floor covered; it
    # passes every catcher now, as in Cycles)
    cam = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=8.0,
                    width=N, height=N)
    under = FLOOR - np.float32([0, 0, 0.02])
    slab_v = np.concatenate([FLOOR, under])
    sides = [[0, 1, 5], [0, 5, 4], [1, 2, 6], [1, 6, 5], [2, 3, 7], [2, 7, 6], [3, 0, 4], [3, 4, 7]]
    slab_t = np.concatenate([TRIS, TRIS[:, ::-1] + 4, sides])
    images = []
    for v, t in ((FLOOR, TRIS), (slab_v, slab_t)):
        s = gw.Scene(v, t, sphere_centers=[tuple(CENTRE)], sphere_radii=[RADIUS], sphere_materials=[1], camera=cam,
                     world=gw.World(transparent=True),
                     materials=[gw.Material(color=(0.5, 0.5, 0.5), shadow_catcher=True),
                                gw.Material(color=(0.8, 0.2, 0.2))],
                     lights=[gw.Light(kind="sun", direction=tuple(-TO_SUN), color=(1, 1, 1))])
        images.append(gw.render(s, gw.RenderSettings(aa="center")))
    plane, slab = images
    assert 0.05 < plane[..., 3].mean() < 0.5               # the ball and its shadow, the rest clear
    np.testing.assert_allclose(slab, plane, atol=1e-6)
