"""Textures, colour attributes, emission, alpha, the world (ambient and
environment) and transparent shadows in the standalone API, checked against
values computed here with numpy: an emissive-only textured square seen by an
orthographic camera shows exactly the texture's filtered value at each
pixel's UV."""
import numpy as np
import pytest

import gridwalk as gw
from gridwalk import memory

N = 16   # pixels across the square


def _square(uv_lo=0.0, uv_hi=1.0):
    """Two triangles covering [-1, 1]^2 at z = 0, UVs spanning [uv_lo, uv_hi]^2."""
    verts = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], np.float32)
    tris = np.array([[0, 1, 2], [0, 2, 3]])
    a, b = uv_lo, uv_hi
    uvs = np.array([[[a, a], [b, a], [b, b]], [[a, a], [b, b], [a, b]]], np.float32)
    return verts, tris, uvs


def _ortho():
    return gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                     ortho_height=2.0, width=N, height=N)


def _render_texture(image, uv_lo=0.0, uv_hi=1.0, **texture):
    verts, tris, uvs = _square(uv_lo, uv_hi)
    scene = gw.Scene(verts, tris, uvs=uvs, camera=_ortho(),
                     materials=[gw.Material(kd=0, emission=1.0, color_texture=0)],
                     textures=[gw.Texture(image, **texture)])
    job = gw.RenderJob(scene, gw.RenderSettings(threads=1)).start()
    return job.wait(), job


def _pixel_uvs(uv_lo, uv_hi):
    """The UV under each pixel centre (row 0 = top = v high)."""
    c = (np.arange(N) + 0.5) / N
    u = uv_lo + (uv_hi - uv_lo) * c
    v = uv_lo + (uv_hi - uv_lo) * c[::-1]
    return np.meshgrid(u, v)


def _srgb(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _expected(texels, u, v, interpolation, extension):
    """numpy reference lookup: texels (h, w, 3) linear, row 0 = top."""
    h, w = texels.shape[:2]
    bottom_up = texels[::-1]

    def fetch(x, y):
        if extension == "repeat":
            x, y = x % w, y % h
        elif extension == "extend":
            x, y = np.clip(x, 0, w - 1), np.clip(y, 0, h - 1)
        elif extension == "mirror":            # every other tile flipped: texel -1 - k is texel k
            x, y = (np.where(i < 0, -1 - i, i) % (2 * n) for i, n in ((x, w), (y, h)))
            x, y = np.where(x < w, x, 2 * w - 1 - x), np.where(y < h, y, 2 * h - 1 - y)
        inside = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        out = bottom_up[np.clip(y, 0, h - 1), np.clip(x, 0, w - 1)]
        return np.where(inside[..., None], out, 0.0)

    if interpolation == "closest":
        out = fetch(np.floor(u * w).astype(int), np.floor(v * h).astype(int))
    else:
        x, y = u * w - 0.5, v * h - 0.5
        x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
        fx, fy = (x - x0)[..., None], (y - y0)[..., None]
        out = (fetch(x0, y0) * (1 - fx) * (1 - fy) + fetch(x0 + 1, y0) * fx * (1 - fy)
               + fetch(x0, y0 + 1) * (1 - fx) * fy + fetch(x0 + 1, y0 + 1) * fx * fy)
    if extension == "clip":
        outside = (u < 0) | (u > 1) | (v < 0) | (v > 1)
        out = np.where(outside[..., None], 0.0, out)
    return out


RNG = np.random.default_rng(7)
BYTES = RNG.integers(0, 256, (5, 7, 3), dtype=np.uint8)


@pytest.mark.parametrize("interpolation", ["closest", "linear"])
@pytest.mark.parametrize("extension", ["repeat", "extend", "clip", "mirror"])
def test_lookup_matches_a_numpy_reference(interpolation, extension):
    lo, hi = -0.6, 1.7                     # the UVs leave the image on every side
    rgba, _ = _render_texture(gw.Image(BYTES), lo, hi, interpolation=interpolation, extension=extension)
    u, v = _pixel_uvs(lo, hi)
    # filtered as stored, then decoded (as Cycles does with 8-bit sRGB images)
    expected = _srgb(_expected(BYTES / 255.0, u, v, interpolation, extension))
    np.testing.assert_allclose(rgba[..., :3], expected, atol=2e-4)
    if interpolation == "linear":             # decoding first is brighter (sRGB's curve is convex)
        assert (_expected(_srgb(BYTES / 255.0), u, v, interpolation, extension) - expected).mean() > 0.01


def test_a_colour_input_takes_alpha_as_grey_or_the_colour_premultiplied():
    # Blender's Image Texture: its Alpha output into a colour input is grey;
    # its Color output is premultiplied by alpha when the Alpha output is not linked.
    rgba = np.zeros((2, 2, 4), np.float32)
    rgba[...] = (0.8, 0.4, 0.2, 0.25)
    image = gw.Image(rgba)
    straight, _ = _render_texture(image, interpolation="closest")
    grey, _ = _render_texture(image, interpolation="closest", use_alpha=True)
    associated, _ = _render_texture(image, interpolation="closest", premultiply=True)
    np.testing.assert_allclose(straight[..., :3], np.broadcast_to([0.8, 0.4, 0.2], (N, N, 3)), rtol=1e-6)
    np.testing.assert_allclose(grey[..., :3], 0.25, rtol=1e-6)
    np.testing.assert_allclose(associated[..., :3], np.broadcast_to([0.2, 0.1, 0.05], (N, N, 3)), rtol=1e-6)


@pytest.mark.parametrize("interpolation", ["closest", "linear"])
def test_an_8_bit_srgb_image_is_premultiplied_and_unassociated_before_it_is_decoded(interpolation):
    # As Cycles: the stored bytes times alpha (integer, truncating), filtered,
    # divided by alpha again where the Alpha output is used, then decoded.
    # Decoding first gave a transparent PNG 14% more light than Cycles.
    rgba = np.zeros((2, 2, 4), np.uint8)
    rgba[...] = (204, 102, 51, 64)
    image = gw.Image(rgba)
    associated, _ = _render_texture(image, interpolation=interpolation, premultiply=True)
    straight, _ = _render_texture(image, interpolation=interpolation, premultiply=True, unassociate=True)
    stored = np.array([204 * 64 // 255, 102 * 64 // 255, 51 * 64 // 255]) / 255.0       # 51, 25, 12
    np.testing.assert_allclose(associated[..., :3], np.broadcast_to(_srgb(stored), (N, N, 3)), rtol=1e-5)
    assert np.all(_srgb(np.array([204, 102, 51]) / 255.0) * (64 / 255.0) > 1.2 * _srgb(stored))
    np.testing.assert_allclose(straight[..., :3], np.broadcast_to(_srgb(stored * 255 / 64), (N, N, 3)),
                               rtol=1e-5)


def test_colorspaces_decode_only_srgb():
    data, _ = _render_texture(gw.Image(BYTES, colorspace="data"), interpolation="closest")
    srgb, _ = _render_texture(gw.Image(BYTES), interpolation="closest")
    u, v = _pixel_uvs(0.0, 1.0)
    np.testing.assert_allclose(data[..., :3], _expected(BYTES / 255.0, u, v, "closest", "repeat"), atol=1e-6)
    np.testing.assert_allclose(srgb[..., :3], _expected(_srgb(BYTES / 255.0), u, v, "closest", "repeat"),
                               atol=1e-6)
    floats = (BYTES / 255.0).astype(np.float32) * 4.0          # HDR values are kept as they are
    hdr, _ = _render_texture(gw.Image(floats), interpolation="closest")
    np.testing.assert_allclose(hdr[..., :3], _expected(floats, u, v, "closest", "repeat"), atol=1e-5)


def test_an_image_is_stored_once_and_8_bit_stays_8_bit():
    image = gw.Image(np.zeros((64, 32, 4), np.uint8))
    hdr = gw.Image(np.zeros((8, 8, 3), np.float32))
    verts, tris, uvs = _square()
    scene = gw.Scene(verts, tris, uvs=uvs,
                     materials=[gw.Material(color_texture=0, alpha_texture=1), gw.Material(color_texture=2)],
                     textures=[gw.Texture(image), gw.Texture(image, use_alpha=True), gw.Texture(hdr)],
                     world=gw.World(environment=2))
    assert len(scene.images) == 2
    assert scene.texture_bytes == 64 * 32 * 4 + 8 * 8 * 3 * 4
    est = memory.estimate(2, 4, texture_bytes=scene.texture_bytes, uvs=True)
    assert est.textures == scene.texture_bytes + 2 * 2 * 24
    assert "textures" in est.breakdown()


def test_colour_attribute_is_interpolated_over_the_triangle():
    verts, tris, _ = _square()
    vertex_colors = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, 1]], np.float32)
    scene = gw.Scene(verts, tris, colors=vertex_colors[tris], camera=_ortho(),
                     materials=[gw.Material(kd=0, emission=1.0, vertex_color=True)])
    job = gw.RenderJob(scene).start()
    rgba = job.wait()
    c = (np.arange(N) + 0.5) / N * 2 - 1
    x, y = np.meshgrid(c, c[::-1])
    expected = np.empty((N, N, 3))
    for tri in tris:                      # barycentric interpolation, in numpy
        p = verts[tri, :2].astype(np.float64)
        m = np.array([p[1] - p[0], p[2] - p[0]]).T
        b = np.linalg.solve(m, np.stack([x - p[0, 0], y - p[0, 1]]).reshape(2, -1)).T.reshape(N, N, 2)
        inside = (b >= -1e-9).all(axis=-1) & (b.sum(axis=-1) <= 1 + 1e-9)
        colour = (vertex_colors[tri[0]] * (1 - b.sum(-1, keepdims=True)) + vertex_colors[tri[1]] * b[..., :1]
                  + vertex_colors[tri[2]] * b[..., 1:])
        expected[inside] = colour[inside]
    np.testing.assert_allclose(rgba[..., :3], expected, atol=1e-5)
    np.testing.assert_allclose(job.albedo, rgba[..., :3], atol=1e-6)   # the albedo pass is the base colour


def test_emission_colour_and_ambient_add_to_the_shading():
    verts, tris, _ = _square()
    scene = gw.Scene(verts, tris, camera=_ortho(), world=gw.World(ambient=(0.5, 1.0, 2.0)),
                     materials=[gw.Material(color=(0.4, 0.6, 0.8), kd=0.5, emission_color=(0.1, 0.2, 0.3))])
    rgba = gw.render(scene)
    expected = np.array([0.4, 0.6, 0.8]) * 0.5 * np.array([0.5, 1.0, 2.0]) + [0.1, 0.2, 0.3]
    np.testing.assert_allclose(rgba[..., :3], np.broadcast_to(expected, (N, N, 3)), atol=1e-6)


def test_environment_is_seen_where_rays_miss():
    sky = np.zeros((4, 8, 3), np.float32)
    sky[:, :, 0] = np.arange(8) + 1.0                                  # red encodes the column
    sky[:, :, 1] = (np.arange(4)[::-1] + 1.0)[:, None]                 # green the row (from the bottom)
    verts = np.array([[50, 50, 50], [51, 50, 50], [50, 51, 50]], np.float32)   # far out of view
    cams = {(1, 0, 0): (4, None), (0, 1, 0): (2, None), (-1, 0, 0): (0, 7), (0, -1, 0): (6, None)}
    for direction, columns in cams.items():
        cam = gw.Camera(eye=(0, 0, 0), target=direction, up=(0, 0, 1), fov=1.0, width=1, height=1)
        scene = gw.Scene(verts, [[0, 1, 2]], camera=cam, textures=[gw.Texture(gw.Image(sky), interpolation="closest")],
                         world=gw.World(environment=0, environment_strength=2.0))
        rgba = gw.render(scene)
        assert rgba[0, 0, 3] == 0                                      # a miss: transparent
        assert rgba[0, 0, 0] / 2 - 1 in columns                        # +X is the image's centre
        assert rgba[0, 0, 1] / 2 in (2.0, 3.0)                         # the horizon: the middle rows


def _shadow_scene(material):
    """A floor lit from straight above through a pane of `material`."""
    floor = np.array([[-3, -3, 0], [3, -3, 0], [3, 3, 0], [-3, 3, 0]], np.float32)
    pane = floor * np.float32(0.3) + np.array([0, 0, 1], np.float32)
    verts = np.vstack([floor, pane])
    tris = np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]])
    cam = gw.Camera(eye=(0, -0.01, 8), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic",
                    ortho_height=6.0, width=N, height=N)
    return gw.Scene(verts, tris, triangle_materials=[0, 0, 1, 1], camera=cam,
                    materials=[gw.Material(color=(1, 1, 1), kd=1.0), material],
                    lights=[gw.Light(kind="sun", direction=(0, 0, -1), color=(1, 1, 1))])


def test_shadows_through_glass_and_alpha_are_attenuated():
    """Seen from straight above, the pane's centre pixel shows the floor under
    it through the pane: the shadow's attenuation times the camera ray's."""
    def centre(material):
        return gw.render(_shadow_scene(material))[N // 2, N // 2, 0]

    lit = gw.render(_shadow_scene(gw.Material(kd=1.0)))[1, 1, 0]    # floor beside the pane
    assert centre(gw.Material(kd=1.0)) == pytest.approx(1.0 * lit)    # an opaque white pane, lit itself
    assert centre(gw.Material(kd=1.0, alpha=0.0)) == pytest.approx(lit, rel=1e-5)   # cut out: no shadow
    assert centre(gw.Material(kd=0.0, alpha=0.5)) == pytest.approx(0.25 * lit, rel=1e-4)   # half x half
    r0 = (0.5 / 2.5) ** 2                                              # Fresnel at normal incidence, ior 1.5
    assert centre(gw.Material(kd=0.0, transmittance=1.0, ior=1.5)) == pytest.approx((1 - r0) ** 2 * lit, rel=1e-3)
    opaque_below = gw.render(_shadow_scene(gw.Material(kd=0.0, alpha=1.0)))[N // 2, N // 2, 0]
    assert opaque_below == 0.0                                         # black opaque pane: nothing behind shows


@pytest.mark.parametrize("kwargs, message", [
    (dict(uvs=np.zeros((3, 3, 2))), "uvs must have shape (2, 3, 2)"),
    (dict(colors=np.zeros((2, 3, 2))), "colors must have shape (2, 3, 3)"),
    (dict(uvs=np.full((2, 3, 2), np.nan)), "uvs[0] has a non-finite value"),
    (dict(materials=[gw.Material(color_texture=3)], textures=[]), "materials[0].color_texture = 3 is out of range"),
    (dict(textures=[gw.Texture(5)]), "textures[0].image = 5 is out of range"),
    (dict(textures=[gw.Texture("x.png")]), "Texture.image must be a gridwalk.Image or an index"),
    (dict(textures=[gw.Texture(0, interpolation="cubic")], images=[gw.Image(np.zeros((2, 2)))]),
     "Texture.interpolation must be one of ['linear', 'closest']"),
    (dict(world=gw.World(environment=0)), "World.environment = 0 is out of range"),
    (dict(materials=[gw.Material(alpha=1.5)]), "materials[0].alpha must be in [0, 1]"),
    (dict(textures=["not a texture"]), "textures[0] must be a gridwalk.Texture"),
])
def test_bad_texture_input_is_refused_with_a_clear_message(kwargs, message):
    verts, tris, _ = _square()
    with pytest.raises(ValueError) as info:
        gw.Scene(verts, tris, **kwargs)
    assert message in str(info.value)


@pytest.mark.parametrize("pixels, message", [
    (np.zeros((0, 4, 3), np.uint8), "is 4 x 0 pixels"),
    (np.zeros((2, 2, 5), np.uint8), "C in 1..4"),
    (np.array([[np.inf]], np.float32), "non-finite pixel value"),
    (np.array([["a"]]), "real numeric array"),
])
def test_bad_images_are_refused(pixels, message):
    with pytest.raises(ValueError) as info:
        gw.Image(pixels, name="bad")
    assert message in str(info.value)
    with pytest.raises(ValueError, match="colorspace must be one of"):
        gw.Image(np.zeros((1, 1)), colorspace="rec709")


def test_a_textured_scene_pickles_and_renders_the_same():
    """Render farms pickle the scene's keyword arguments for their workers."""
    import pickle
    verts, tris, uvs = _square(-0.3, 1.2)
    kwargs = dict(vertices=verts, triangles=tris, uvs=uvs, camera=_ortho(),
                  materials=[gw.Material(kd=0, emission=1.0, color_texture=0)],
                  textures=[gw.Texture(gw.Image(BYTES, name="noise"), extension="extend")],
                  world=gw.World(ambient=(0.1, 0.2, 0.3)))
    copy = pickle.loads(pickle.dumps(kwargs))
    assert copy["textures"][0].image.name == "noise"
    np.testing.assert_array_equal(copy["textures"][0].image.pixels(), BYTES)
    np.testing.assert_array_equal(gw.render(gw.Scene(**copy)), gw.render(gw.Scene(**kwargs)))


def _lit_square(material, textures=()):
    verts, tris, uvs = _square()
    cam = gw.Camera(eye=(0.5, -3, 3), target=(0, 0, 0), up=(0, 0, 1), fov=50, width=N, height=N)
    return gw.render(gw.Scene(verts, tris, uvs=uvs, camera=cam, materials=[material], textures=list(textures),
                              lights=[gw.Light(position=(-1, -2, 3), color=(4, 4, 4))],
                              background=(0.2, 0.3, 0.4)))


@pytest.mark.parametrize("roughness, metallic", [(0.3, 0.0), (0.7, 1.0), (0.45, 0.4)])
def test_roughness_and_metallic_maps_redo_the_principled_mapping_per_hit(roughness, metallic):
    """A constant roughness / metallic map renders as the Principled mapping of
    those constants (blender_addon/export/materials.py) does."""
    from blender_addon.export.materials import principled_material

    def constant(value):
        return gw.Texture(gw.Image(np.full((2, 2), value, np.float32), colorspace="data"))

    args = dict(color=(0.8, 0.5, 0.2), transmission=0.0, ior=1.45, f0=0.04)
    expected = _lit_square(principled_material(metallic=metallic, roughness=roughness, **args))
    mapped = principled_material(metallic=0.0, roughness=0.9, **args)   # the record's own values are replaced
    mapped.roughness_texture, mapped.metallic_texture = 0, 1
    got = _lit_square(mapped, [constant(roughness), constant(metallic)])
    np.testing.assert_allclose(got, expected, rtol=1e-4, atol=1e-5)
    assert np.abs(got - _lit_square(principled_material(metallic=0.0, roughness=0.9, **args))).max() > 0.01


def test_alpha_map_cuts_out_where_its_alpha_channel_is_zero():
    rgba = np.zeros((2, 2, 4), np.uint8)
    rgba[0, :, 3] = 255                       # top row opaque, bottom row cut out
    rgba[..., :3] = 200
    verts, tris, uvs = _square()
    scene = gw.Scene(verts, tris, uvs=uvs, camera=_ortho(), background=(0.0, 0.0, 1.0),
                     materials=[gw.Material(kd=0, emission_color=(1, 0, 0), alpha_texture=0)],
                     textures=[gw.Texture(gw.Image(rgba), interpolation="closest", use_alpha=True)])
    out = gw.render(scene)
    np.testing.assert_array_equal(out[: N // 2, :, :3], np.broadcast_to([1.0, 0, 0], (N // 2, N, 3)))
    np.testing.assert_array_equal(out[N // 2:, :, :3], np.broadcast_to([0, 0, 1.0], (N // 2, N, 3)))
    assert np.all(out[N // 2:, :, 3] == 0) and np.all(out[: N // 2, :, 3] == 1)   # cut-outs are see-through


def test_transparent_film_hides_the_world_from_camera_rays_only():
    cam = gw.Camera(eye=(0, -6, 0), target=(0, 0, 0), up=(0, 0, 1), fov=40, width=N, height=N)
    sky = gw.Texture(gw.Image(np.full((2, 4, 3), 0.5, np.float32)))
    scene = gw.Scene(sphere_centers=[[0, 0, 0]], sphere_radii=[1.0], camera=cam, textures=[sky],
                     materials=[gw.Material(kd=0, mirror=1.0)],
                     world=gw.World(environment=0, environment_strength=2.0, transparent=True))
    rgba = gw.render(scene)
    miss = rgba[..., 3] == 0
    assert miss.mean() > 0.3 and np.all(rgba[miss] == 0)              # premultiplied: nothing behind
    np.testing.assert_allclose(rgba[N // 2, N // 2], [1.0, 1.0, 1.0, 1.0], atol=1e-6)   # the mirror sees the sky


@pytest.mark.parametrize("transparent", [False, True])
def test_a_partly_transparent_surface_covers_its_alpha_and_film_transparent_shows_nothing_behind(transparent):
    """A square of alpha 0.25 (emission red) over the sky: its pixels' alpha is
    0.25, its coverage; behind it the camera sees the sky, or with Film
    Transparent nothing (premultiplied: RGB = 0.25 x red), as Cycles writes it."""
    verts, tris, uvs = _square()
    sky = gw.Texture(gw.Image(np.full((2, 4, 3), 0.5, np.float32)))
    scene = gw.Scene(verts, tris, uvs=uvs, camera=_ortho(), textures=[sky],
                     materials=[gw.Material(kd=0, ks=0, emission_color=(1, 0, 0), alpha=0.25)],
                     world=gw.World(environment=0, transparent=transparent))
    out = gw.render(scene)
    behind = np.zeros(3) if transparent else np.full(3, 0.5)
    np.testing.assert_allclose(out[..., :3], np.broadcast_to(0.25 * np.array([1.0, 0, 0]) + 0.75 * behind,
                                                             (N, N, 3)), atol=1e-6)
    np.testing.assert_allclose(out[..., 3], 0.25, atol=1e-6)
