"""Texture(tiles=...) (Blender's UDIM images): at texture coordinates (u, v) a tiled
texture reads tile 1001 + 10 int(v) + int(u) (int truncating toward zero, as Cycles
picks the tile) at the coordinates within that tile, extended within it; where no
tile lies it reads Cycles' magenta. Blender's side: tests/blender/test_b54."""
import numpy as np
import pytest

import gridwalk as gw

N = 40
# a quad whose UVs span u in [-0.5, 3.5] and v in [-0.5, 1.5] (x = u, y = v)
U0, U1, V0, V1 = -0.5, 3.5, -0.5, 1.5
VERTS = np.array([[U0, V0, 0], [U1, V0, 0], [U1, V1, 0], [U0, V1, 0]], np.float32)
TRIS = np.array([[0, 1, 2], [0, 2, 3]])
UVS = np.array([[U0, V0], [U1, V0], [U1, V1], [U0, V1]], np.float32)[TRIS]
CAMERA = gw.Camera(eye=((U0 + U1) / 2, (V0 + V1) / 2, 5), target=((U0 + U1) / 2, (V0 + V1) / 2, 0), up=(0, 1, 0),
                   projection="orthographic", ortho_height=V1 - V0, width=2 * N, height=N)
RED, GREEN, BLUE = (1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)
MAGENTA = (1.0, 0.0, 1.0)


def _flat(colour, width=4, height=4):
    return gw.Image(np.tile(np.array(colour, np.float32), (height, width, 1)), "linear")


def _render(texture, images=None):
    scene = gw.Scene(VERTS, TRIS, uvs=UVS, camera=CAMERA, textures=[texture], images=images,
                     materials=[gw.Material(kd=0, emission=1.0, color_texture=0)])
    return gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()[..., :3]


def _uv_of_pixel(width=2 * N, height=N):
    """Each pixel centre's (u, v) (row 0 at the top)."""
    x = U0 + (np.arange(width) + 0.5) / width * (U1 - U0)
    y = V1 - (np.arange(height) + 0.5) / height * (V1 - V0)
    return np.meshgrid(x, y)


def _expected(tiles):
    u, v = _uv_of_pixel()
    out = np.tile(np.array(MAGENTA, np.float32), u.shape + (1,))
    inside = (u > -1) & (u < 10) & (v > -1)
    tx, ty = np.trunc(u).astype(int), np.trunc(v).astype(int)
    for number, colour in tiles.items():
        out[inside & (1001 + 10 * ty + tx == number)] = colour
    return out


def test_each_tile_is_read_where_its_number_says():
    tiles = {1001: RED, 1002: GREEN, 1011: BLUE, 1013: (0.5, 0.25, 0.125)}
    image = _render(gw.Texture(tiles=[(n, _flat(c)) for n, c in tiles.items()]))
    want = _expected(tiles)
    # (pixels whose centre lies within half a pixel of a tile's edge may read either side)
    u, v = _uv_of_pixel()
    step = (U1 - U0) / (2 * N)
    clear = (np.abs(u - np.round(u)) > step) & (np.abs(v - np.round(v)) > step)
    assert clear.sum() > 0.5 * clear.size
    np.testing.assert_allclose(image[clear], want[clear], atol=1e-6)
    # the truncation: u in (-0.5, 0) reads tile 1001 (repeated), v in (-0.5, 0) too
    assert np.allclose(image[(u < 0) & (u > -0.5 + step) & (v > step) & (v < 1 - step)], RED)
    # tiles 1003 and 1012 are not given: magenta there
    assert np.allclose(image[clear & (u > 2) & (v > 0) & (v < 1)], MAGENTA)


def test_a_tile_is_filtered_and_extended_within_itself():
    # tile 1002: left half black, right half white, 8 texels wide; with Extend its left edge
    # stays black across the border with tile 1001 (white), where Repeat would blend in white
    half = np.zeros((2, 8, 3), np.float32)
    half[:, 4:] = 1.0
    tiles = [(1001, _flat((1.0, 1.0, 1.0))), (1002, gw.Image(half, "linear"))]
    extend = _render(gw.Texture(tiles=tiles, extension="extend"))
    repeat = _render(gw.Texture(tiles=tiles, extension="repeat"))
    u, v = _uv_of_pixel()
    band = (u > 1.0) & (u < 1.0 + 1 / 16) & (v > 0.1) & (v < 0.9)   # within half a texel of tile 1002's left edge
    assert band.any()
    assert np.allclose(extend[band], 0.0, atol=1e-6)
    assert (repeat[band] > 0.05).all()       # blended with the tile's own right edge (white), not with tile 1001


def test_a_mapping_moves_the_coordinates_before_the_tile_is_picked():
    tiles = {1001: RED, 1002: GREEN}
    # u' = u + 1: the left unit of the quad (u in [0, 1)) reads tile 1002
    image = _render(gw.Texture(tiles=[(n, _flat(c)) for n, c in tiles.items()], uv_transform=(1, 0, 1, 0, 1, 0)))
    u, v = _uv_of_pixel()
    assert np.allclose(image[(u > 0.1) & (u < 0.9) & (v > 0.1) & (v < 0.9)], GREEN)


def test_a_bump_map_of_tiles_bends_the_normal_by_the_tile_under_the_point():
    ramp_image = gw.Image(np.tile(np.linspace(0, 1, 16, dtype=np.float32)[None, :, None], (4, 1, 3)), "linear")
    light = gw.Light(kind="sun", direction=(-0.5, 0.0, -1.0), color=(1, 1, 1))

    def lit(tiles):
        scene = gw.Scene(VERTS, TRIS, uvs=UVS, camera=CAMERA, textures=[gw.Texture(tiles=tiles, extension="extend")],
                         materials=[gw.Material(color=(1, 1, 1), kd=1.0, bump_texture=0, bump_distance=0.5)],
                         lights=[light])
        return gw.RenderJob(scene, gw.RenderSettings(threads=1)).start().wait()[..., :3]
    u, v = _uv_of_pixel()
    inner = (v > 0.2) & (v < 0.8)
    # (the sloped image on tile 1002, the flat one on 1001, which is the texture's `image`: a bump
    # that ignored the tiles would read the flat image everywhere)
    sloped = lit([(1001, _flat((0.5, 0.5, 0.5))), (1002, ramp_image)])
    flat = lit([(1001, _flat((0.5, 0.5, 0.5))), (1002, _flat((0.5, 0.5, 0.5)))])
    tile_1002 = inner & (u > 1.2) & (u < 1.8)
    assert abs(sloped[tile_1002].mean() - flat[tile_1002].mean()) > 0.02
    np.testing.assert_array_equal(sloped[inner & (u > 0.2) & (u < 0.8)], flat[inner & (u > 0.2) & (u < 0.8)])


@pytest.mark.parametrize("tiles, message", [
    ([(1000, 0)], "not a UDIM tile"),
    ([(1001, 5)], "out of range"),
    ([(1001,)], "pair"),
    (7, "pairs"),
])
def test_bad_tiles_are_refused(tiles, message):
    with pytest.raises(ValueError, match=message):
        _render(gw.Texture(tiles=tiles), images=[_flat(RED)])


def test_an_environment_of_tiles_is_refused():
    with pytest.raises(ValueError, match="UDIM tiles"):
        gw.Scene(VERTS, TRIS, uvs=UVS, camera=CAMERA, textures=[gw.Texture(tiles=[(1001, _flat(RED))])],
                 world=gw.World(environment=0))
