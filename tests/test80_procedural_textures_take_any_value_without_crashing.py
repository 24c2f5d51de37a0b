"""Every procedural Texture kind takes any value in any numeric field without crashing the
process or putting NaN or infinity in the image: each field of each kind, set to each of a set
of extreme values (infinities, NaN, 1e30, subnormals, huge integers), is either refused with a
ValueError naming the problem or renders finite, non-negative pixels. Blender's sockets accept
most of these from scripts and links (a Brick Width of 0 used to fail the render; an integer
remainder by -1 of INT_MIN traps on x86)."""
import dataclasses
import math

import numpy as np
import pytest

import gridwalk as gw
from gridwalk.model import TEXTURE_KINDS

VERTS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
GENERATED = np.array([[-3.0, -2.0, 0.4], [5.0, -2.0, 0.4], [5.0, 6.0, 0.4], [-3.0, 6.0, 0.4]], np.float32)[TRIS]
# corner colours, which an attribute texture reads (the other kinds none)
COLORS = np.array([[0.9, 0.1, 0.3], [0.2, 0.7, 0.4], [0.5, 0.5, 1.0], [0.0, 0.3, 0.8]], np.float32)[TRIS]
REALS = (float("inf"), float("-inf"), float("nan"), 1e30, -1e30, 0.0, -0.0, 1e-40, -7.5)
INTS = (0, -1, 2**31 - 1, -2**31, 11)
KINDS = [k for k in TEXTURE_KINDS if k != "image"]


def render(texture):
    scene = gw.Scene(VERTS, TRIS, generated=GENERATED, colors=COLORS, textures=[texture],
                     camera=gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                                      ortho_height=2.0, width=6, height=6),
                     materials=[gw.Material(kd=0, emission=1.0, color_texture=0)])
    return gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()


def numeric_fields():
    """(name, values) of every number, and every tuple of numbers, a Texture holds."""
    out = []
    for f in dataclasses.fields(gw.Texture):
        value = getattr(gw.Texture(), f.name)
        if f.name in ("image", "ramp", "channel"):
            continue
        if isinstance(value, bool) or isinstance(value, str):
            continue
        if isinstance(value, int):
            out.append((f.name, INTS))
        elif isinstance(value, float):
            out.append((f.name, REALS))
        elif isinstance(value, tuple) and value and all(isinstance(x, float) for x in value):
            out.append((f.name, tuple(tuple(x if i == 0 else value[i] for i in range(len(value))) for x in REALS)))
    return out


FIELDS = numeric_fields()


@pytest.mark.parametrize("kind", KINDS)
def test_every_field_takes_extreme_values_or_refuses_them(kind):
    assert {"brick_width", "row_height", "depth", "phase", "detail", "mortar", "offset_frequency"} <= \
        {name for name, _ in FIELDS}
    rendered = refused = 0
    for name, values in FIELDS:
        for value in values:
            texture = gw.Texture(kind=kind, coordinates="generated", **{name: value})
            try:
                image = render(texture)
            except ValueError as e:
                assert str(e), (name, value)
                refused += 1
                continue
            assert np.isfinite(image).all() and (image[..., :3] >= 0).all(), (kind, name, value)
            rendered += 1
    # (most values render: refusals are for what cannot mean anything, such as a NaN scale)
    assert rendered > refused > 0


@pytest.mark.parametrize("fields", [dict(kind="brick", row_height=0.0, squash_frequency=-1, offset_frequency=-1),
                                    dict(kind="brick", brick_width=1e-45, row_height=-1e-45),
                                    dict(kind="wave", distortion=1e30, detail=64.0, roughness=-3.0),
                                    dict(kind="wave", detail=1e30, distortion=1.0),
                                    dict(kind="magic", depth=10, distortion=1e30),
                                    dict(kind="voronoi", voronoi_feature="distance_to_edge", detail=15.0,
                                         lacunarity=1e30),
                                    dict(kind="voronoi", voronoi_feature="n_sphere_radius", voronoi_output="radius",
                                         randomness=1e-40)])
def test_hard_combinations_render_finite_pixels_quickly(fields):
    image = render(gw.Texture(coordinates="generated", **fields))
    assert np.isfinite(image).all() and not math.isnan(float(image.sum()))
