"""Bump maps (Material.bump_texture, Blender's Bump node): the shading normal
becomes normalize(n - bump_distance x the height's gradient along the
surface), blended with n by bump_strength, as Cycles' Bump node computes it
(Mikkelsen's surface gradient). A height that rises linearly along x on a
square seen from above gives a normal computed here by hand; a texture map,
a larger square, Invert and Strength change it as the formula says; light
follows the bent normal."""
import numpy as np
import pytest

import gridwalk as gw
from test24_normal_maps_tilt_the_shading_normal import N, _square

RAMP = gw.Image(((np.arange(64, dtype=np.float32) + 0.5) / 64)[None, :].repeat(2, axis=0), "data")   # h = u


def _render(distance=1.0, strength=1.0, size=1.0, uv_transform=(1, 0, 0, 0, 1, 0), light=(0.0, 0.0, -1.0),
            bumped=True, extension="extend", normals=None, image=RAMP, interpolation="linear"):
    verts, tris, uvs = _square()
    material = gw.Material(color=(1, 1, 1), kd=1.0, bump_texture=0 if bumped else -1, bump_distance=distance,
                           bump_strength=strength)
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=size, width=N, height=N)
    scene = gw.Scene(verts * size, tris, uvs=uvs, camera=cam, materials=[material], normals=normals,
                     textures=[gw.Texture(image, extension=extension, uv_transform=uv_transform,
                                          interpolation=interpolation)],
                     lights=[gw.Light(kind="sun", direction=light, color=(1, 1, 1))])
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start()
    return job.wait(), job.normal


def _expected(slope, strength=1.0, n=(0.0, 0.0, 1.0), along=(1.0, 0.0, 0.0)):
    """The normal n (unit) bent by a height gradient of `slope` along `along` (per unit of
    length) in the square's plane, its part along n removed along the plane's normal z."""
    n, grad = np.array(n), slope * np.array(along)
    grad = grad - np.array([0.0, 0.0, 1.0]) * (grad @ n) / n[2]
    bent = n - grad
    bent /= np.linalg.norm(bent)
    out = strength * bent + (1 - strength) * n
    return out / np.linalg.norm(out)


@pytest.mark.parametrize("case, kwargs, slope, strength", [
    ("u spans 2 units: h rises 0.5 a unit", {}, 0.5, 1.0),
    ("Invert: a negative distance", {"distance": -1.0}, -0.5, 1.0),
    ("1.6 times the distance", {"distance": 1.6}, 0.8, 1.0),
    ("half strength", {"strength": 0.5}, 0.5, 0.5),
    # (repeated: the pixels' u x 1.5 stay 0.03 or more from the ramp's wrap)
    ("a texture map stretching u 1.5 times", {"uv_transform": (1.5, 0, 0, 0, 1, 0), "extension": "repeat"},
     0.75, 1.0),
    ("a square 3 times as large: a third of the gradient", {"size": 3.0}, 0.5 / 3.0, 1.0),
])
def test_the_normal_pass_shows_the_bent_normal(case, kwargs, slope, strength):
    _, normal = _render(**kwargs)
    np.testing.assert_allclose(normal.reshape(-1, 3), np.tile(_expected(slope, strength), (N * N, 1)),
                               atol=2e-4, err_msg=case)


WIDE = gw.Image(((np.arange(4096, dtype=np.float32) + 0.5) / 4096)[None, :].repeat(2, axis=0), "data")


@pytest.mark.parametrize("case, kwargs, bent", [
    # vertex normals against the winding: the relief follows the normals' side, as Cycles bends N
    ("normals opposite the winding", {"normals": np.tile([0.0, 0.0, -1.0], (4, 1)).astype(np.float32)},
     -_expected(-0.5)),
    # a tilted shading normal (smooth shading of a coarse mesh): Cycles removes the gradient's part
    # along it along the geometric normal, not straight down onto its plane
    ("a tilted shading normal", {"normals": np.tile([0.3, 0.0, 1.0] / np.hypot(0.3, 1.0), (4, 1)).astype(np.float32)},
     _expected(0.5, n=np.array([0.3, 0.0, 1.0]) / np.hypot(0.3, 1.0))),
    ("the height along v (a map swapping u and v)", {"uv_transform": (0, 1, 0, 1, 0, 0)},
     _expected(0.5, along=(0.0, 1.0, 0.0))),
    ("u beyond 1024 on a 4096-texel ramp, repeated", {"image": WIDE, "extension": "repeat",
                                                      "uv_transform": (1, 0, 1024, 0, 1, 0)}, _expected(0.5)),
    ("Closest takes the slope of the bilinear height", {"interpolation": "closest"}, _expected(0.5)),
])
def test_the_bend_follows_cycles_rules(case, kwargs, bent):
    _, normal = _render(**kwargs)
    np.testing.assert_allclose(normal.reshape(-1, 3), np.tile(bent, (N * N, 1)), atol=2e-4, err_msg=case)


def test_light_follows_the_bent_normal():
    # light straight down: the bent normal gets its cosine of the flat square's light
    # (no bump shadowing: the light is at the flat normal's zenith)
    flat, _ = _render(bumped=False)
    bent, _ = _render()
    np.testing.assert_allclose(bent[..., :3] / flat[..., :3], _expected(0.5)[2], rtol=1e-4)
    # light from -x (travelling towards +x) lights the normal leaning to -x more than light from +x
    from_left, _ = _render(light=(1.0, 0.0, -1.0))
    from_right, _ = _render(light=(-1.0, 0.0, -1.0))
    assert from_left[..., 0].mean() > 2 * from_right[..., 0].mean()


@pytest.mark.parametrize("field, value, message", [("bump_strength", -1.0, "bump_strength"),
                                                   ("bump_distance", float("inf"), "bump_distance"),
                                                   ("bump_texture", 3, "bump_texture = 3 is out of range"),
                                                   ("bump_texture", -2, "bump_texture must be")])
def test_bad_bump_settings_are_refused(field, value, message):
    verts, tris, uvs = _square()
    with pytest.raises(ValueError, match=message):
        gw.Scene(verts, tris, uvs=uvs, materials=[gw.Material(**{"bump_texture": 0, field: value})],
                 textures=[gw.Texture(RAMP)])
