"""A dielectric's specular layer reflects what surrounds it, not only the lamps
(Material.dielectric_reflection, which the Blender export sets for the Principled BSDF): rays
along the lobe of its roughness, weighted by the exact Fresnel of the IOR whose reflectance at
normal incidence the material gives, checked against that Fresnel and the GGX lobe integrated
here; the diffuse under the layer (Material.layered_diffuse, Blender 4.0+) gets what the layer
does not reflect towards the viewer; an emitter seen in the layer is not counted twice; and a
material without the flag (NFF's Phong highlight) still reflects nothing."""
import numpy as np
import pytest

import gridwalk as gw
from microfacet_math import dielectric_fresnel, ggx_albedo

RES = 41                                       # odd: the middle pixel's ray goes through the target
EYE = np.array([0.0, -3.0, 2.0])               # looking at the origin of the floor z = 0
COS_O = EYE[2] / np.linalg.norm(EYE)
# (a layer reflecting more than 0.25 from the view is traced at every hit; less, by Russian
# roulette, which the last test checks)
F0 = 0.3


def dielectric(roughness=0.0, kd=0.0, color=(1, 1, 1), f0=F0, **flags):
    """A Principled-like dielectric of reflectance f0 at normal incidence (ks is f0 times the
    normalised Phong weight (shininess + 8) / 8, shininess as the export sets it)."""
    shininess = 1000.0 if roughness == 0 else min(2 / max(roughness ** 2, 1e-3) ** 2 - 2, 1000.0)
    return gw.Material(color=color, kd=kd, ks=f0 * (shininess + 8) / 8, shininess=shininess,
                       roughness=roughness, **flags)


def floor_scene(material, background=(1, 1, 1), lights=(), extra=None, eye=EYE, world=None):
    verts = [[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]]
    tris, mats, tri_mats = [[0, 1, 2], [0, 2, 3]], [material], [0, 0]
    if extra is not None:                      # (corners, material) of one more quad
        corners, extra_material = extra
        verts += corners
        tris += [[4, 6, 5], [4, 7, 6]]
        mats.append(extra_material)
        tri_mats += [1, 1]
    cam = gw.Camera(eye=tuple(eye), target=(0, 0, 0), fov=30, width=RES, height=RES)
    extra_world = {} if world is None else {"world": world}
    return gw.Scene(vertices=np.array(verts, np.float32), triangles=tris, triangle_materials=tri_mats,
                    materials=mats, camera=cam, lights=list(lights), background=background, **extra_world)


def middle(scene, **settings):
    return gw.render(scene, gw.RenderSettings(**settings))[RES // 2, RES // 2, :3]


def test_a_sharp_dielectric_reflects_the_world_by_its_fresnel():
    value = middle(floor_scene(dielectric(dielectric_reflection=True)))
    assert value == pytest.approx([dielectric_fresnel(COS_O, F0)] * 3, rel=1e-4)


def test_without_the_flag_a_phong_highlight_reflects_nothing_of_the_world():
    assert middle(floor_scene(dielectric())).max() == 0


GRAZING_EYE = np.array([0.0, -3.0, 0.75])      # the floor's middle seen at cos 0.24
COS_GRAZING = GRAZING_EYE[2] / np.linalg.norm(GRAZING_EYE)


def middle_patch(scene, **settings):
    image = gw.render(scene, gw.RenderSettings(aa="jittered", aa_samples=8, max_depth=2, **settings))
    return image[RES // 2 - 1:RES // 2 + 2, RES // 2 - 1:RES // 2 + 2, :3].mean()


@pytest.mark.parametrize("roughness", [0.3, 0.6])
def test_a_rough_dielectric_returns_the_lobes_albedo_with_fresnel(roughness):
    # Seen at a grazing angle, where the Fresnel at each microfacet and the Fresnel at the view's
    # angle (or Schlick's) part most.
    scene = floor_scene(dielectric(roughness, dielectric_reflection=True), eye=GRAZING_EYE)
    expected = ggx_albedo(COS_GRAZING, roughness ** 2, n=600, f0=F0)
    assert middle_patch(scene, glossy_samples=16) == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("roughness, multiscatter", [(0.0, False), (0.5, False), (0.8, True)])
def test_a_white_layered_diffuse_in_a_white_world_returns_all_its_light(roughness, multiscatter):
    # The layer reflects what its albedo says, the diffuse under it gets the rest: a white furnace
    # (ambient light 1, a white background its rays see) returns 1 at a grazing view as head on.
    # (With the Fresnel at the view's angle times the lobe's albedo as the layer's albedo, the
    # diffuse lost 19% here at roughness 0.8.)
    material = dielectric(roughness, kd=1.0, f0=0.04, dielectric_reflection=True, layered_diffuse=True,
                          multiscatter=multiscatter)
    for eye in (GRAZING_EYE, EYE):
        scene = floor_scene(material, eye=eye, world=gw.World(ambient=(1, 1, 1)))
        assert middle_patch(scene, glossy_samples=16) == pytest.approx(1.0, abs=0.02), eye


def test_a_layered_diffuse_gets_what_the_layer_does_not_reflect_towards_the_viewer():
    lamp = gw.Light(position=(-1.5, 1.0, 2.5), color=(5, 5, 5))   # (far from the mirror direction)
    plain = middle(floor_scene(gw.Material(color=(1, 1, 1), kd=1.0), (0, 0, 0), [lamp]))
    layered = middle(floor_scene(dielectric(kd=1.0, layered_diffuse=True), (0, 0, 0), [lamp]))
    assert layered / plain == pytest.approx([1 - dielectric_fresnel(COS_O, F0)] * 3, rel=1e-3)


def test_highlights_the_rays_would_see_are_sampled_where_no_ray_is_traced():
    # At the last generation (max_depth 1) no reflection ray leaves the floor: the emitter's
    # highlight on a rough layer is sampled as on a surface without one (it was lost: black).
    panel = gw.Material(color=(1, 1, 1), kd=0.0, emission=4.0, emits_light=True)
    corners = [[-0.5, 2.5, 2.0], [0.5, 2.5, 2.0], [0.5, 3.5, 2.0], [-0.5, 3.5, 2.0]]
    settings = dict(shadow="random", shadow_samples=16, max_depth=1)
    layered = middle(floor_scene(dielectric(0.3, dielectric_reflection=True), (0, 0, 0), extra=(corners, panel)),
                     **settings)
    plain = middle(floor_scene(dielectric(0.3), (0, 0, 0), extra=(corners, panel)), **settings)
    assert plain.min() > 0.05
    assert layered == pytest.approx(plain, rel=1e-6)


def test_an_emitter_seen_in_sharp_glass_is_counted_once():
    # Glass's Fresnel reflection ray sees the panel; sampling it adds no highlight (it added a
    # Phong highlight of the whole ks: 1.21x here, a review found).
    h = 2.0
    centre = np.array([0.0, 3.0 * h / 2.0, h])
    corners = [list(centre + [dx, dy, 0]) for dx, dy in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))]
    panel = gw.Material(color=(1, 1, 1), kd=0.0, emission=4.0, emits_light=True)
    glass = gw.Material(color=(1, 1, 1), kd=0.0, ks=0.04 * 126, shininess=1000.0, transmittance=1.0, ior=1.5)
    value = middle(floor_scene(glass, (0, 0, 0), extra=(corners, panel)), shadow="random", shadow_samples=16)
    fresnel = dielectric_fresnel(COS_O, 0.04)        # (glass's Fresnel reflection ray: the exact Fresnel of IOR 1.5)
    assert value == pytest.approx([4 * fresnel] * 3, rel=1e-3)


def test_an_emitter_seen_in_the_layer_is_counted_once():
    # A 1 x 1 panel of radiance 4 where the middle pixel's mirror direction meets it, in a black
    # world: the sharp layer's ray sees it (F x 4); sampling the panel adds no highlight of its own.
    h = 2.0                                              # the panel's height
    centre = np.array([0.0, 3.0 * h / 2.0, h])          # on the reflection of the middle ray
    corners = [list(centre + [dx, dy, 0]) for dx, dy in ((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))]
    panel = gw.Material(color=(1, 1, 1), kd=0.0, emission=4.0, emits_light=True)
    scene = floor_scene(dielectric(dielectric_reflection=True), (0, 0, 0), extra=(corners, panel))
    value = middle(scene, shadow="random", shadow_samples=16)
    assert value == pytest.approx([4 * dielectric_fresnel(COS_O, F0)] * 3, rel=1e-3)


def test_a_faint_layer_traced_by_roulette_keeps_its_mean_with_fewer_rays():
    # Principled's usual f0 of 0.04 reflects 0.05 of the world here: its rays are traced at a
    # fifth of the hits, weighted by 5; over 9 x 9 pixels of 64 samples the mean stays.
    settings = gw.RenderSettings(aa="jittered", aa_samples=8, max_depth=2)
    job = gw.RenderJob(floor_scene(dielectric(f0=0.04, dielectric_reflection=True)), settings).start()
    job.wait()
    patch = job.image[RES // 2 - 4:RES // 2 + 5, RES // 2 - 4:RES // 2 + 5, :3].mean()
    # (seeds 0-7 gave 0.981-1.022 of the Fresnel at the middle)
    assert patch == pytest.approx(dielectric_fresnel(COS_O, 0.04), rel=0.04)
    # (every hit of the floor would trace one without the roulette; its far edge, seen at
    # grazing angles, reflects more than 0.25 and traces them all)
    assert 0.1 < job.stats["secondary_rays"] / job.stats["primary_rays"] < 0.5, job.stats
