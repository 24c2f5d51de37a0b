"""A light's Ray Visibility (Light.visible_diffuse, visible_glossy, visible_transmission: Blender's
on a light object, as Cycles reads it): hidden from diffuse rays it lights no diffuse surface but
still makes highlights; hidden from glossy rays it makes no highlight and no sharp or rough mirror
shows it, while diffuse surfaces stay lit; hidden from transmission, glass does not show it. Before,
Blender's switches were ignored (a review probe: 0.426 against Cycles' 0.338 with Diffuse off).
With every switch on, images are unchanged to the bit (test07). Blender's side: test_b02."""
import dataclasses

import numpy as np

import gridwalk as gw
from test29_sharp_mirrors_show_lights_by_their_shapes import LIGHTS, QUAD_F, QUAD_V, camera

RECT = LIGHTS["rect"][0]


def _render(material, light, **settings):
    scene = gw.Scene(vertices=QUAD_V, triangles=QUAD_F, materials=[material], lights=[light], camera=camera(),
                     background=(0, 0, 0))
    return gw.render(scene, gw.RenderSettings(threads=2, aa="jittered", aa_samples=4, **settings))[..., :3]


def hidden(**switches):
    return dataclasses.replace(RECT, **switches)


def test_hidden_from_diffuse_rays_it_lights_no_diffuse_surface_but_keeps_its_highlight():
    diffuse = gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)
    assert _render(diffuse, RECT).mean() > 0.003
    assert _render(diffuse, hidden(visible_diffuse=False)).max() == 0.0
    glossy = gw.Material(color=(1, 1, 1), kd=0.0, ks=1.0, roughness=0.3)
    np.testing.assert_array_equal(_render(glossy, hidden(visible_diffuse=False)), _render(glossy, RECT))


def test_hidden_from_glossy_rays_it_makes_no_highlight_and_no_mirror_shows_it():
    for material in (gw.Material(color=(1, 1, 1), kd=0.0, ks=1.0, roughness=0.3),            # a highlight
                     gw.Material(color=(1, 1, 1), kd=0.0, ks=0.5, mirror=1.0, roughness=0.0),  # its shape
                     gw.Material(color=(1, 1, 1), kd=0.0, ks=1.0, mirror=1.0, roughness=0.05)):  # rays share it
        assert _render(material, RECT, glossy_samples=4).max() > 0.01
        assert _render(material, hidden(visible_glossy=False), glossy_samples=4).max() == 0.0
    diffuse = gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)
    np.testing.assert_array_equal(_render(diffuse, hidden(visible_glossy=False)), _render(diffuse, RECT))


def test_hidden_from_transmission_glass_does_not_show_it():
    # the camera looks down through a sharp glass quad at the light, which sits below it facing up
    light = dataclasses.replace(RECT, position=(0, 0, -20), direction=(0, 0, 1), axis_v=(0, 1, 0))
    glass = gw.Material(color=(1, 1, 1), kd=0.0, ks=0.0, transmittance=1.0, ior=1.0, roughness=0.0)
    seen = _render(glass, light)
    assert seen.max() > 1.0
    assert _render(glass, dataclasses.replace(light, visible_transmission=False)).max() < 1e-3 * seen.max()
    assert _render(glass, dataclasses.replace(light, visible_glossy=False)).max() == seen.max()


def test_hidden_from_transmission_it_lights_nothing_through_glass():
    # (Whitted's transparent shadows let a lamp's light through glass; a lamp hidden from
    # transmission rays reaches nothing that way, as in Cycles, where that light comes by a
    # transmission bounce; an alpha cut-out still lets it pass)
    from test66_coloured_glass_tints_what_it_lets_through import _pane
    v, f = _pane(0.95, 1.05, size=1.0)
    floor = np.array([[-5, -5, 0], [5, -5, 0], [5, 5, 0], [-5, 5, 0]], np.float32)
    verts, tris = np.concatenate([floor, v]), np.concatenate([[[0, 1, 2], [0, 2, 3]], f + 4])
    cam = gw.Camera(eye=(0, 0, 0.5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=0.2,
                    width=8, height=8)   # (the floor under the pane's middle)
    lamp = gw.Light(kind="point", position=(0, 0, 3), color=(9, 9, 9), inverse_square=True)

    def under(pane, light):
        mats = [gw.Material(color=(1, 1, 1), kd=1.0), pane]
        scene = gw.Scene(verts, tris, triangle_materials=np.array([0, 0] + [1] * len(f)), materials=mats,
                         lights=[light], camera=cam)
        return gw.render(scene, gw.RenderSettings(threads=1))[..., :3].mean()
    glass = gw.Material(color=(1, 1, 1), kd=0.0, ks=0.0, transmittance=1.0, ior=1.5)
    cutout = gw.Material(color=(1, 1, 1), kd=1.0, alpha=0.5)
    hidden = dataclasses.replace(lamp, visible_transmission=False)
    assert under(glass, lamp) > 0.1
    assert under(glass, hidden) == 0.0
    assert under(cutout, hidden) == under(cutout, lamp) > 0.1
