"""Texture(kind="checker") is Blender's Checker Texture: color1 and color2 in
cubes of side 1 / scale, chosen per pixel as Cycles chooses (checked here
against numpy's evaluation of that rule); Texture(kind="gradient") its
Gradient Texture, each type's grey ramp as Cycles computes it; Texture.ramp
a Color Ramp after any texture, read from a 256-entry table as Cycles reads it; at the UV map's (u, v, 0), at the
Generated coordinates (Scene(generated=...)) or at the Object coordinates
(Scene(object_coords=...)), mapped by vector_transform (a Mapping node); an
image can take those coordinates too. What has no such coordinates
(spheres, cylinders, a scene without the array) or
cannot take a pattern (normal maps, the environment) is refused with
the field named. (Blender's side: tests/blender/test_b38.)"""
from dataclasses import replace

import numpy as np
import pytest

import gridwalk as gw
from gridwalk import memory

N = 32
VERTS = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
RED, BLUE = (1.0, 0.0, 0.0), (0.0, 0.0, 1.0)
# Generated coordinates of the square: x and y across [0.1, 0.9], z 0.3 (a flat object's mid-plane)
GENERATED = np.column_stack([0.5 + 0.4 * VERTS[:, 0], 0.5 + 0.4 * VERTS[:, 1], np.full(4, 0.3)]).astype(np.float32)


def _camera():
    return gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                     ortho_height=2.0, width=N, height=N)


def _render(texture, images=None, **scene):
    scene.setdefault("generated", GENERATED[TRIS])
    s = gw.Scene(VERTS, TRIS, camera=_camera(), images=images, textures=[texture],
                 materials=[gw.Material(kd=0, emission=1.0, color_texture=0)], **scene)
    return gw.RenderJob(s, gw.RenderSettings(threads=1)).start().wait()[..., :3]


def _pixel_points():
    """The square's (x, y) under each pixel centre (row 0 = top)."""
    c = -1 + 2 * (np.arange(N) + 0.5) / N
    return np.meshgrid(c, c[::-1])


def _cycles_checker(p, scale):
    """Whether color1 shows at the points p (..., 3): Cycles' rule, in float32."""
    f32 = np.float32
    index = np.floor((p.astype(f32) * f32(scale) + f32(0.000001)) * f32(0.999999))
    odd = np.abs(index).astype(np.int64) & 1
    return (odd[..., 0] == odd[..., 1]) == (odd[..., 2] != 0)


def _expected(first):
    return np.where(first[..., None], RED, BLUE)


def test_a_checker_at_generated_coordinates_alternates_as_in_cycles():
    x, y = _pixel_points()
    p = np.stack([0.5 + 0.4 * x, 0.5 + 0.4 * y, np.full_like(x, 0.3)], axis=-1)
    for scale in (3.0, 5.0, 7.5):
        image = _render(gw.Texture(kind="checker", coordinates="generated", color1=RED, color2=BLUE, scale=scale))
        first = _cycles_checker(p, scale)
        assert 0.2 < first.mean() < 0.8                                   # both colours show
        np.testing.assert_array_equal(image, _expected(first))


def test_the_z_coordinate_flips_the_pattern():
    # z = 0.3 at scale 5 lies in cube 1 (odd); z = 0.1 in cube 0: every square changes colour
    flat = GENERATED.copy()
    flat[:, 2] = 0.1
    texture = gw.Texture(kind="checker", coordinates="generated", color1=RED, color2=BLUE)
    a, b = _render(texture), _render(texture, generated=flat[TRIS])
    np.testing.assert_array_equal(a, b[..., ::-1])


def test_a_mapping_moves_the_checker():
    # turned 30 degrees about z, scaled and moved: the 3 x 4 map of a Point Mapping node
    c, s = np.cos(np.radians(30)), np.sin(np.radians(30))
    m = np.array([[1.5 * c, -0.7 * s, 0, 0.2], [1.5 * s, 0.7 * c, 0, -0.1], [0, 0, 1.2, 0.05]])
    texture = gw.Texture(kind="checker", coordinates="generated", color1=RED, color2=BLUE, scale=4.0,
                         vector_transform=tuple(m.reshape(-1)))
    x, y = _pixel_points()
    p = np.stack([0.5 + 0.4 * x, 0.5 + 0.4 * y, np.full_like(x, 0.3), np.ones_like(x)], axis=-1)
    mapped = (p.astype(np.float32) @ m.T.astype(np.float32))
    image = _render(texture)
    first = _cycles_checker(mapped, 4.0)
    # (the core maps in float32 in its own order: a pixel centre within rounding of a cube face may differ)
    assert np.mean(np.all(image == _expected(first), axis=-1)) > 0.995
    assert np.mean(np.all(image == _render(replace(texture, vector_transform=gw.Texture().vector_transform)),
                          axis=-1)) < 0.8


def test_a_checker_at_the_uv_map_takes_u_v_and_zero():
    uvs = np.array([[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]], np.float32)
    image = _render(gw.Texture(kind="checker", color1=RED, color2=BLUE, scale=3.0), uvs=uvs, generated=None)
    x, y = _pixel_points()
    first = _cycles_checker(np.stack([(x + 1) / 2, (y + 1) / 2, np.zeros_like(x)], axis=-1), 3.0)
    np.testing.assert_array_equal(image, _expected(first))


def test_object_coordinates_are_their_own_array():
    # the square's object space: scaled by 2 and moved, so that its Object coordinates differ from Generated
    local = (VERTS * 2 + [0.25, -0.5, 0.7]).astype(np.float32)
    texture = gw.Texture(kind="checker", coordinates="object", color1=RED, color2=BLUE, scale=1.3)
    image = _render(texture, object_coords=local[TRIS], generated=None)
    x, y = _pixel_points()
    first = _cycles_checker(np.stack([2 * x + 0.25, 2 * y - 0.5, np.full_like(x, 0.7)], axis=-1), 1.3)
    assert 0.2 < first.mean() < 0.8
    np.testing.assert_array_equal(image, _expected(first))
    # a scene with both arrays: each texture reads its own
    both = _render(texture, object_coords=local[TRIS])
    np.testing.assert_array_equal(both, image)


def test_position_coordinates_are_the_world_point_under_the_texture_map():
    # the square's world corners are VERTS; a map as the export makes for another object's
    # Object coordinates (that object's inverse world matrix) moves the pattern off the
    # square's own
    texture = gw.Texture(kind="checker", coordinates="position", color1=RED, color2=BLUE, scale=1.7,
                         vector_transform=(0.5, 0, 0, 0.3, 0, 0.5, 0, -0.2, 0, 0, 0.5, 0.4))
    image = _render(texture, generated=None)
    x, y = _pixel_points()
    first = _cycles_checker(np.stack([0.5 * x + 0.3, 0.5 * y - 0.2, np.full_like(x, 0.4)], axis=-1), 1.7)
    assert 0.2 < first.mean() < 0.8
    np.testing.assert_array_equal(image, _expected(first))
    # the same as Object coordinates that equal the world corners
    same = _render(replace(texture, coordinates="object"), object_coords=VERTS[TRIS], generated=None)
    np.testing.assert_array_equal(same, image)


def _cycles_gradient(kind, p):
    """Blender's Gradient Texture value at the points p (..., 3), clamped, as Cycles computes it."""
    x, y = p[..., 0], p[..., 1]
    sphere = np.maximum(0.999999 - np.linalg.norm(p, axis=-1), 0)
    r = np.clip(x, 0, 1)
    f = {"linear": x, "quadratic": np.maximum(x, 0) ** 2, "easing": 3 * r * r - 2 * r * r * r,
         "diagonal": (x + y) / 2, "spherical": sphere, "quadratic_sphere": sphere ** 2,
         "radial": np.arctan2(y, x) / (2 * np.pi) + 0.5}[kind]
    return np.clip(f, 0, 1)


@pytest.mark.parametrize("kind", ["linear", "quadratic", "easing", "diagonal", "spherical", "quadratic_sphere",
                                  "radial"])
def test_a_gradient_is_the_grey_ramp_cycles_computes(kind):
    # object space: the square spans [-1.2, 1.2] x [-1.2, 1.2] at z = 0.3: every ramp's clamped ends show
    local = np.column_stack([1.2 * VERTS[:, 0], 1.2 * VERTS[:, 1], np.full(4, 0.3)]).astype(np.float32)
    image = _render(gw.Texture(kind="gradient", gradient=kind, coordinates="object"), object_coords=local[TRIS])
    x, y = _pixel_points()
    expected = _cycles_gradient(kind, np.stack([1.2 * x, 1.2 * y, np.full_like(x, 0.3)], axis=-1))
    assert expected.std() > 0.1
    np.testing.assert_allclose(image, np.repeat(expected[..., None], 3, axis=-1), atol=2e-5)


STOPS = ((0.15, 0.9, 0.2, 0.1, 1.0), (0.5, 0.1, 0.8, 0.2, 1.0), (0.8, 0.2, 0.3, 1.0, 1.0))


def _ramp_at(f, interpolation):
    """The ramp of STOPS at f (numpy, float64), as Blender's colour band gives it."""
    pos = np.array([s[0] for s in STOPS])
    rgb = np.array([s[1:4] for s in STOPS])
    k = np.clip(np.searchsorted(pos, f, side="right"), 1, len(pos) - 1)
    a, b = pos[k - 1], pos[k]
    s = np.clip((f - a) / (b - a), 0, 1)
    if interpolation == "ease":
        s = s * s * (3 - 2 * s)
    if interpolation == "constant":
        s = np.where(f >= b, 1.0, 0.0)
    out = rgb[k - 1] * (1 - s)[..., None] + rgb[k] * s[..., None]
    return np.where((f <= pos[0])[..., None], rgb[0], np.where((f >= pos[-1])[..., None], rgb[-1], out))


def _cycles_ramp(f, interpolation):
    """Cycles' lookup: 256 entries over [0, 1], f clamped, read between them (Constant: the one below)."""
    x = np.clip(f, 0, 1) * 255
    i = np.floor(x)
    below = _ramp_at(i / 255, interpolation)
    if interpolation == "constant":
        return below
    return below + (_ramp_at(np.minimum(i + 1, 255) / 255, interpolation) - below) * (x - i)[..., None]


@pytest.mark.parametrize("interpolation", ["linear", "ease", "constant"])
def test_a_ramp_colours_a_gradient_as_cycles_reads_its_table(interpolation):
    local = np.column_stack([0.6 * VERTS[:, 0] + 0.45, VERTS[:, 1], np.zeros(4)]).astype(np.float32)
    texture = gw.Texture(kind="gradient", coordinates="object", ramp=STOPS, ramp_interpolation=interpolation)
    image = _render(texture, object_coords=local[TRIS])
    x, _ = _pixel_points()
    expected = _cycles_ramp(np.clip(0.6 * x + 0.45, 0, 1), interpolation)
    assert expected.std() > 0.1
    np.testing.assert_allclose(image, expected, atol=2e-5)


def test_steps_after_a_ramp_adjust_its_colour():
    # a Separate Color's green, x 2 - 0.3 (a Math Multiply Add), clamped; and a tint (a Mix Multiply)
    local = np.column_stack([0.6 * VERTS[:, 0] + 0.45, VERTS[:, 1], np.zeros(4)]).astype(np.float32)
    base = gw.Texture(kind="gradient", coordinates="object", ramp=STOPS)
    x, _ = _pixel_points()
    ramped = _cycles_ramp(np.clip(0.6 * x + 0.45, 0, 1), "linear")
    green = _render(replace(base, ramp_channel=1, ramp_gain=(2.0,) * 3, ramp_bias=(-0.3,) * 3, ramp_clamp=True),
                    object_coords=local[TRIS])
    expected = np.clip(ramped[..., 1] * 2 - 0.3, 0, 1)
    assert 0.05 < expected.mean() < 0.95 and expected.std() > 0.1
    np.testing.assert_allclose(green, np.repeat(expected[..., None], 3, -1), atol=5e-5)
    tint = (0.5, 1.0, 0.25)
    tinted = _render(replace(base, ramp_gain=tint), object_coords=local[TRIS])
    np.testing.assert_allclose(tinted, ramped * tint, atol=2e-5)
    # the luminance after a ramp, as a number (the roughness of a lit, glossy square is not
    # the easiest to read back: a colour and its luminance go to an emitter here)
    lum = _render(replace(base, ramp_channel=3), object_coords=local[TRIS])
    np.testing.assert_allclose(lum[..., 0], ramped @ [0.2126, 0.7152, 0.0722], atol=5e-5)


def test_steps_after_a_ramp_need_the_ramp():
    with pytest.raises(ValueError, match="adjusts the value after a ramp .* but has no ramp"):
        _scene(textures=[gw.Texture(kind="checker", coordinates="generated", ramp_gain=(2, 2, 2))])
    with pytest.raises(ValueError, match="ramp_channel = 7 is not"):
        _scene(textures=[gw.Texture(kind="checker", coordinates="generated", ramp=STOPS, ramp_channel=7)])


def test_stops_at_one_position_make_a_hard_edge_in_their_order():
    # green then blue at 0.5: below it the ramp runs into green, above it out of blue
    stops = ((0.0, 1, 0, 0, 1), (0.5, 0, 1, 0, 1), (0.5, 0, 0, 1, 1), (1.0, 1, 1, 1, 1))
    local = np.column_stack([0.5 + 0.5 * VERTS[:, 0], VERTS[:, 1], np.zeros(4)]).astype(np.float32)
    image = _render(gw.Texture(kind="gradient", coordinates="object", ramp=stops), object_coords=local[TRIS])
    left, right = image[N // 2, N // 2 - 1], image[N // 2, N // 2]     # x just below and above 0.5
    assert left[1] > 0.9 and left[2] < 0.05 and right[2] > 0.9 and right[1] < 0.05   # (the table blurs by a bin)


def test_no_ramp_is_none_or_empty():
    plain = _render(gw.Texture(kind="gradient", coordinates="generated"))
    for empty in (None, ()):
        np.testing.assert_array_equal(_render(gw.Texture(kind="gradient", coordinates="generated", ramp=empty)), plain)


def test_a_ramp_takes_a_colour_texture_by_its_luminance():
    # an image of one colour: the ramp's input is its luminance
    colour = np.array([0.2, 0.7, 0.4], np.float32)
    picture = gw.Image(np.broadcast_to(colour, (2, 2, 3)).copy(), colorspace="linear")
    uvs = np.array([[[0, 0], [1, 0], [1, 1]], [[0, 0], [1, 1], [0, 1]]], np.float32)
    image = _render(gw.Texture(picture, ramp=STOPS), uvs=uvs, generated=None)
    lum = 0.2126 * 0.2 + 0.7152 * 0.7 + 0.0722 * 0.4
    np.testing.assert_allclose(image, np.broadcast_to(_cycles_ramp(np.array(lum), "linear"), image.shape), atol=1e-5)


@pytest.mark.parametrize("ramp, message", [
    (STOPS[::-1], "lies before the one before it"),
    ((0.1, 0.2, 0.3), "stops of 5 numbers"),
    ((0.0, 1, 1, 1, 1) * 257, "at most 256 stops"),
    (((0.0, float("nan"), 0, 0, 1),), "non-finite"),
])
def test_a_bad_ramp_is_refused_naming_it(ramp, message):
    with pytest.raises(ValueError, match=message):
        _scene(textures=[gw.Texture(kind="checker", coordinates="generated", ramp=ramp)])


def test_an_image_at_generated_coordinates_is_read_at_their_x_and_y():
    texels = np.random.default_rng(3).random((4, 4, 3)).astype(np.float32)
    picture = gw.Image(texels, colorspace="linear")
    image = _render(gw.Texture(picture, coordinates="generated", interpolation="closest"))
    x, y = _pixel_points()
    gx, gy = 0.5 + 0.4 * x, 0.5 + 0.4 * y
    expected = texels[::-1][(gy * 4).astype(int), (gx * 4).astype(int)]      # row 0 of the array is the top
    np.testing.assert_allclose(image, expected, atol=1e-6)


def _scene(**kw):
    base = dict(vertices=VERTS, triangles=TRIS, generated=GENERATED[TRIS],
                materials=[gw.Material(color_texture=0)],
                textures=[gw.Texture(kind="checker", coordinates="generated")])
    base.update(kw)
    return gw.Scene(**base)


@pytest.mark.parametrize("kw, message", [
    ({"generated": None}, r"triangle_materials\[0\] uses it, but the scene has none \(Scene\(generated=...\)\)"),
    ({"textures": [gw.Texture(kind="checker", coordinates="object")]},
     r"materials\[0\] has a texture at object coordinates, .* \(Scene\(object_coords=...\)\)"),
    ({"object_coords": np.zeros((2, 3, 2))}, "object_coords must have shape"),
    ({"generated": np.zeros((1, 3, 3))}, "generated must have shape"),
    ({"generated": np.full((2, 3, 3), np.nan)}, r"generated\[0\] has a non-finite value"),
    ({"sphere_centers": [[0, 0, 3]], "sphere_radii": [1.0], "sphere_materials": [0]},
     "which spheres do not have"),
    ({"sphere_centers": [[0, 0, 3]], "sphere_radii": [1.0], "sphere_materials": [0],
      "textures": [gw.Texture(kind="checker", coordinates="position")]},
     "texture at position coordinates, which spheres do not have"),
    ({"textures": [gw.Texture(kind="checker", image=0)], "images": [gw.Image(np.ones((2, 2, 3), np.float32))]},
     "a checker texture has no image"),
    ({"textures": [gw.Texture(kind="checker", vector_transform=(1, 0, 0, float("inf")) + (0,) * 8)]},
     "vector_transform has a non-finite value"),
    ({"textures": [gw.Texture(kind="checker", scale=float("nan"))]}, "scale is not finite"),
    ({"materials": [gw.Material(normal_texture=0)]}, r"normal_texture = 0 names a procedural texture"),
    ({"world": gw.World(environment=0)}, "environment is an image"),
])
def test_what_cannot_take_the_texture_is_refused_naming_it(kw, message):
    with pytest.raises(ValueError, match=message):
        _scene(**kw)


def test_unknown_kinds_and_coordinates_are_refused():
    with pytest.raises(ValueError, match="kind must be one of"):
        _scene(textures=[gw.Texture(kind="gabor")])
    with pytest.raises(ValueError, match="coordinates must be one of"):
        _scene(textures=[gw.Texture(kind="checker", coordinates="tangent")])
    with pytest.raises(ValueError, match="gradient must be one of"):
        _scene(textures=[gw.Texture(kind="gradient", gradient="wavy")])


def test_the_generated_coordinates_count_in_the_memory_estimate():
    plain = memory.estimate(1000)
    assert memory.estimate(1000, corner_points=2).total - plain.total == 1000 * 2 * 72
    without = gw.Scene(VERTS, TRIS, materials=[gw.Material()])
    assert _scene()._native.memory_bytes - without._native.memory_bytes == 2 * 9 * 4
    both = _scene(object_coords=GENERATED[TRIS])
    assert both._native.memory_bytes - without._native.memory_bytes == 2 * 2 * 9 * 4
