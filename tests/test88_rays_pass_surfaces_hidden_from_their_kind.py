"""Material.visible_camera / visible_glossy / visible_transmission /
visible_shadow (Blender's object Ray Visibility): a ray passes a surface
hidden from its kind as it passes an alpha cut-out; shadow rays pass a
surface that casts no shadow."""
import numpy as np

import gridwalk as gw

QUAD = np.array([[-2, -1.5, 1], [0, -1.5, 1], [0, 1.5, 1], [-2, 1.5, 1]], np.float32)


def render(quad, floor=None, **settings):
    """A floor filling the view (light grey, or `floor`) and a red quad above it, lit from overhead."""
    v = np.concatenate([np.array([[-40, -40, 0], [40, -40, 0], [40, 40, 0], [-40, 40, 0]], np.float32), QUAD])
    t = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]], np.int32)
    materials = [floor or gw.Material(color=(0.5, 0.5, 0.5)), gw.Material(color=(0.9, 0.1, 0.1), **quad)]
    camera = gw.Camera(eye=(0, -3, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=48, height=48)
    scene = gw.Scene(vertices=v, triangles=t, triangle_materials=[0, 0, 1, 1], materials=materials, camera=camera,
                     lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])
    job = gw.RenderJob(scene, gw.RenderSettings(aa="center", **settings)).start()
    job.wait()
    return job.image


def red(image):
    return (image[..., 0] - image[..., 1]) > 0.3


def shadow(image):
    return image[..., 0] < 0.05


def test_camera_rays_pass_but_the_shadow_stays():
    seen, hidden = render({}), render(dict(visible_camera=False))
    assert red(seen).sum() > 100 and not red(hidden).any()
    assert shadow(hidden).sum() > 100                      # the floor under it, in its shadow
    assert np.all(hidden[..., 3] == 1.0)                   # the floor behind it covers the pixels


def test_shadow_rays_pass_a_surface_that_casts_none():
    casting, not_casting = render({}), render(dict(visible_shadow=False))
    hidden_too = render(dict(visible_shadow=False, visible_camera=False))
    assert shadow(render(dict(visible_camera=False))).sum() > 100
    assert not shadow(hidden_too).any()
    assert red(not_casting).sum() == red(casting).sum()    # still seen


def test_reflection_rays_pass_a_surface_hidden_from_glossy_rays():
    mirror = gw.Material(color=(0.9, 0.9, 0.9), kd=0.0, mirror=1.0)
    # looking down on a mirror floor the quad is seen directly and in the mirror: count the reflection
    # where the direct view shows the floor (the quad hidden from the camera, both times)
    # (the quad glows: its underside, which the mirror shows, is not lit)
    reflected = render(dict(visible_camera=False, emission=1.0), floor=mirror)
    unreflected = render(dict(visible_camera=False, visible_glossy=False, emission=1.0), floor=mirror)
    assert red(reflected).sum() > 50 and not red(unreflected).any()


def test_refraction_rays_pass_a_surface_hidden_from_transmission():
    glass = gw.Material(color=(1, 1, 1), kd=0.0, transmittance=1.0, ior=1.0)
    # a clear pane between the camera and the quad: the quad is seen by refraction rays only
    behind_glass_seen = _through_pane(glass, dict())
    behind_glass_hidden = _through_pane(glass, dict(visible_transmission=False))
    assert red(behind_glass_seen).sum() > 100 and not red(behind_glass_hidden).any()


def _through_pane(glass, quad_flags):
    """The red quad seen through a clear pane above it (a refraction ray reaches it)."""
    v = np.concatenate([np.array([[-40, -40, 0], [40, -40, 0], [40, 40, 0], [-40, 40, 0]], np.float32), QUAD,
                        np.array([[-5, -5, 3], [5, -5, 3], [5, 5, 3], [-5, 5, 3]], np.float32)])
    t = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7], [8, 9, 10], [8, 10, 11]], np.int32)
    materials = [gw.Material(color=(0.5, 0.5, 0.5)), gw.Material(color=(0.9, 0.1, 0.1), **quad_flags), glass]
    camera = gw.Camera(eye=(0, -3, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=48, height=48)
    scene = gw.Scene(vertices=v, triangles=t, triangle_materials=[0, 0, 1, 1, 2, 2], materials=materials,
                     camera=camera, lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])
    job = gw.RenderJob(scene, gw.RenderSettings(aa="center")).start()
    job.wait()
    return job.image


def test_an_emitter_hidden_from_glossy_rays_leaves_no_highlight():
    # a glowing panel over a rough metal floor: the floor shows it only by glossy reflection
    v = np.array([[-40, -40, 0], [40, -40, 0], [40, 40, 0], [-40, 40, 0],
                  [-1, -1, 3], [1, -1, 3], [1, 1, 3], [-1, 1, 3]], np.float32)
    t = np.array([[0, 1, 2], [0, 2, 3], [4, 6, 5], [4, 7, 6]], np.int32)
    camera = gw.Camera(eye=(0, -8, 4), target=(0, 0, 0), up=(0, 0, 1), fov=45, width=48, height=48)

    def mean(**flags):
        floor = gw.Material(color=(0.5, 0.5, 0.5), kd=0.0, ks=1.0, roughness=0.3, metallic=1.0, mirror=1.0)
        panel = gw.Material(color=(1, 1, 1), emission=5.0, emits_light=True, **flags)
        sc = gw.Scene(vertices=v, triangles=t, triangle_materials=[0, 0, 1, 1], materials=[floor, panel],
                      camera=camera)
        job = gw.RenderJob(sc, gw.RenderSettings(aa="jittered", aa_samples=2, glossy_samples=4)).start()
        job.wait()
        return float(job.image[..., :3].mean())

    seen, unseen = mean(visible_camera=False), mean(visible_camera=False, visible_glossy=False)
    assert seen > 0.02                 # its highlight on the floor (light points and glossy rays)
    assert unseen < 1e-6               # neither its light points' highlight nor the rays'


def test_many_hidden_layers_cost_no_bounces():
    # 40 quads hidden from the camera stacked over the floor (more than max_depth + 16 cut-outs):
    # the camera sees the floor at its own distance, and the light reaches it through 40 layers that
    # cast no shadow either
    layers = [QUAD + np.float32([0, 0, 0.05 * k]) for k in range(40)]
    v = np.concatenate([np.array([[-40, -40, 0], [40, -40, 0], [40, 40, 0], [-40, 40, 0]], np.float32)] + layers)
    t = np.array([[0, 1, 2], [0, 2, 3]] + [[4 * k + 4, 4 * k + 5, 4 * k + 6] for k in range(40)]
                 + [[4 * k + 4, 4 * k + 6, 4 * k + 7] for k in range(40)], np.int32)
    materials = [gw.Material(color=(0.5, 0.5, 0.5)), gw.Material(visible_camera=False, visible_shadow=False)]
    camera = gw.Camera(eye=(0, 0, 10), target=(0, 0, 0), up=(0, 1, 0), fov=45, width=32, height=32)
    plain = gw.Scene(vertices=v[:4], triangles=t[:2], materials=materials[:1], camera=camera,
                     lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])
    stacked = gw.Scene(vertices=v, triangles=t, triangle_materials=[0, 0] + [1] * 80, materials=materials,
                       camera=camera, lights=[gw.Light(position=(0, 0, 20), color=(1, 1, 1))])
    jobs = []
    for sc in (plain, stacked):
        job = gw.RenderJob(sc, gw.RenderSettings(aa="center", max_depth=1)).start()
        job.wait()
        jobs.append(job)
    np.testing.assert_allclose(jobs[1].image, jobs[0].image, atol=1e-6)
    np.testing.assert_allclose(jobs[1].depth, jobs[0].depth, rtol=1e-5)
