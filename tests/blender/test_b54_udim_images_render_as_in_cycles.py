"""A UDIM (tiled) image renders as Cycles renders it, in bpy 4.5, bpy 5.0 and Debian's 3.4:
each tile where its number says, tiles of different sizes, missing tiles magenta, UVs in
(-1, 0) in tile 1001 (Cycles truncates), the Extend and Closest settings within each tile,
tiles in 8-bit PNG and float OpenEXR files and packed into the .blend. Before, the whole
image rendered magenta. The export reads every tile (Texture.tiles), in the tiled image's
colour space, names missing tiles in its warning, leaves no image behind, and the memory
estimate counts every tile. Scene: udim_scenes.udim_scene; the core's side: test95."""
import json

import numpy as np
import pytest

from runner import luminance_by_engine, run_script

VARIANTS = {"files": {}, "exr": {"storage": "exr"}, "packed": {"storage": "packed"},
            "extend_closest": {"extension": "EXTEND", "interpolation": "Closest"}}
MAGENTA_LUMINANCE = 0.2126 + 0.0722


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"udim_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
    variants = {k: dict(v, folder=str(out / f"tiles_{k}")) for k, v in VARIANTS.items()}
    return luminance_by_engine(module_blender, out, "udim", engines, variants)


@pytest.mark.parametrize("variant", list(VARIANTS))
def test_the_tiles_render_where_cycles_puts_them(renders, variant):
    ours, cycles = renders[("GRIDWALK", variant)], renders[("CYCLES", variant)]
    assert cycles.std() > 0.05                                           # the tiles' colours, not one colour
    # the two missing tiles (u in [2, 3), v in [0, 1), and u in [1, 2), v in [1, 1.5)) are magenta in both
    h, w = cycles.shape
    missing = cycles[h // 4 + 2:3 * h // 4 - 2, 5 * w // 8 + 2:7 * w // 8 - 2]
    assert np.allclose(missing, MAGENTA_LUMINANCE, atol=0.01)
    # each half unit of UV (a 12-pixel block) holds the same colours; pixel by pixel the
    # two agree up to the pixel filters (Cycles' Blackman-Harris blurs Closest texels' edges)
    blocks = lambda image: image.reshape(4, h // 4, 8, w // 8).mean(axis=(1, 3))
    assert np.abs(blocks(ours) - blocks(cycles)).max() < 0.02
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.98
    assert np.abs(ours - cycles).mean() < 0.02


def test_the_export_reads_every_tile(export, tmp_path):
    out = export("udim", folder=str(tmp_path / "tiles"))
    assert out.expected["tiles"] == [1001, 1002, 1011, 1013]
    (texture,) = out.textures
    tiles = dict(texture["tiles"])
    assert sorted(tiles) == out.expected["tiles"]
    sizes = {n: out.images[i]["shape"][:2] for n, i in tiles.items()}
    assert sizes == {1001: [8, 8], 1002: [4, 8], 1011: [16, 4], 1013: [6, 6]}   # (rows, columns)
    assert texture["image"] == tiles[1001]
    assert all(out.images[i]["colorspace"] == "srgb" for i in tiles.values())
    assert not any("magenta" in w for w in out.warnings), out.warnings
    # every tile counted: 8-bit RGBA, plus the largest tile's float32 read copy
    assert out.texture_bytes == 4 * (64 + 32 + 64 + 36) + 4 * 4 * 64
    assert out.leftover_images == [], "a tile's loaded image was left in bpy.data"


def test_a_non_color_tiled_image_stays_data(export, tmp_path):
    out = export("udim", folder=str(tmp_path / "tiles"), non_color=True)
    (texture,) = out.textures
    assert all(out.images[i]["colorspace"] == "data" for _, i in texture["tiles"])


def test_a_missing_tile_file_is_named(export, tmp_path):
    out = export("udim", folder=str(tmp_path / "tiles"), remove_tile=1002)
    (texture,) = out.textures
    tiles = dict(texture["tiles"])
    assert out.images[tiles[1002]]["shape"][:2] == [1, 1]                 # the magenta stand-in
    assert any("renders magenta" in w and "tile 1002" in w and "missing" in w for w in out.warnings), out.warnings


def test_work_is_handed_to_the_main_thread_and_a_cancel_abandons_it(any_blender, tmp_path):
    # (a GUI render's job thread reads the tiles this way: export/main_thread.py)
    run_script(any_blender, "main_thread_handover.py", tmp_path)
    info = json.loads((tmp_path / "handover.json").read_text())
    assert info["timer_registered"] is True and info["timer_after_unregister"] is False
    assert info["waiting"] is True                          # nothing ran before the main thread drained
    assert info["value"] == 42 and info["ran_on_main"] == [True]
    assert info["cancelled"] == "cancelled" and info["cancel_seconds"] < 1.0
    assert info["abandoned_ran"] is False
    assert info["on_main_directly"] is True
