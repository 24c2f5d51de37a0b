"""Material.own_metal_color / metal_color: the metal share of a surface reflects metal_color
instead of the base colour (a Blender Mix Shader of a Diffuse BSDF and a Glossy BSDF of another
colour: blender_addon/export/shader_mix.py), in its mirror reflection and its highlights; the
diffuse keeps the base colour."""
import numpy as np
import pytest

import gridwalk as gw

N = 32


def render(**material):
    cam = gw.Camera(eye=(0, -5, 0), target=(0, 0, 0), up=(0, 0, 1), fov=20, width=N, height=N)
    scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], camera=cam,
                     materials=[gw.Material(**material)], background=(1.0, 1.0, 1.0),
                     lights=[gw.Light(position=(0, -5, 0), color=(1, 1, 1))])
    return gw.render(scene, gw.RenderSettings(aa="center"))[N // 2, N // 2, :3]


def test_a_mirror_takes_the_metal_colour_and_the_diffuse_the_base_colour():
    red_metal = render(color=(1, 0, 0), kd=0.0, mirror=1.0, metallic=1.0, ks=1.0)
    blue_metal = render(color=(1, 0, 0), kd=0.0, mirror=1.0, metallic=1.0, ks=1.0, own_metal_color=True,
                        metal_color=(0, 0, 1))
    assert red_metal[0] > 0.5 and red_metal[2] < 0.1          # (head on: the metal's colour)
    assert blue_metal[2] > 0.5 and blue_metal[0] < 0.1
    np.testing.assert_allclose(blue_metal[[2, 1, 0]], red_metal, rtol=1e-5, atol=1e-6)   # the same, channels swapped
    half = render(color=(1, 0, 0), kd=0.5, mirror=0.5, metallic=0.5, ks=0.5, own_metal_color=True,
                  metal_color=(0, 0, 1))
    assert half[0] > 0.1 and half[2] > 0.1 and half[1] < 0.05   # red diffuse beside a blue reflection
    # (the flag off: the metal_color is not read)
    assert np.array_equal(render(color=(1, 0, 0), kd=0.0, mirror=1.0, metallic=1.0, ks=1.0, metal_color=(0, 0, 1)),
                          red_metal)


def test_a_negative_metal_colour_is_refused():
    with pytest.raises(ValueError, match="metal_color"):
        gw.Material(metal_color=(0.5, -1.0, 0.5)).validate()


def test_the_albedo_pass_adds_the_diffuse_and_the_metal_colours():
    # (the denoiser's albedo was the base colour alone: a surface rendering blue said red)
    cam = gw.Camera(eye=(0, -5, 0), target=(0, 0, 0), up=(0, 0, 1), fov=20, width=N, height=N)
    mat = gw.Material(color=(1, 0, 0), kd=0.25, mirror=0.75, metallic=0.75, ks=0.75, own_metal_color=True,
                      metal_color=(0, 0, 1))
    job = gw.RenderJob(gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], camera=cam, materials=[mat]),
                       gw.RenderSettings(aa="center")).start()
    job.wait()
    np.testing.assert_allclose(job.albedo[N // 2, N // 2], [0.25, 0.0, 0.75], atol=1e-6)
