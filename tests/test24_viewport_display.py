"""The image the Rendered viewport uploads (blender_addon/viewport.py Display;
numpy only, no Blender): finite scene-linear values below the half-float
maximum (65504; above it the half-float texture holds inf and the view
turns black), rows bottom-up as the GPU texture wants them, coarse tiles
stretched over their blocks, full-resolution passes averaged."""
import numpy as np

from blender_addon.viewport import Display

HALF_MAX = float(np.finfo(np.float16).max)          # 65504


def tile(height, width, value):
    return np.full((height, width, 4), value, np.float32)


def test_values_stay_finite_and_below_the_half_float_maximum():
    display = Display()
    display.reset(4, 1)
    rgba = np.array([[[1e6, -1e6, 0.5, 1.0], [np.nan, np.inf, -np.inf, 1.0],
                      [65504.0, 70000.0, 2.0, 1.0], [0.25, 0.5, 0.75, 1.0]]], np.float32)
    display.add_tile(0, 0, rgba, 1)
    shown = display.rgba[0]
    assert np.isfinite(shown).all() and np.abs(shown).max() < HALF_MAX
    assert np.isfinite(shown.astype(np.float16)).all()              # what the RGBA16F texture holds
    assert shown[1, 0] == 0.0                                        # NaN shows black
    assert shown[0, 0] > 60000 and shown[1, 1] > 60000 and shown[1, 2] < -60000   # bright stays bright
    np.testing.assert_array_equal(shown[3], rgba[0, 3])              # ordinary values untouched


def test_rows_run_bottom_up_and_tiles_land_where_they_belong():
    display = Display()
    display.reset(6, 4)
    top = tile(1, 2, 1.0)                                            # row 0 (the top), columns 2-3
    display.add_tile(2, 0, top, 1)
    changed = np.argwhere(display.rgba[..., 0] > 0)
    assert changed.tolist() == [[3, 2], [3, 3]]                      # the texture's last row is the top


def test_coarse_tiles_cover_their_blocks_and_full_passes_average():
    display = Display()
    display.reset(8, 4)
    coarse = np.zeros((2, 4, 4), np.float32)
    coarse[0, 1] = 3.0                                               # block row 0 (top), block column 1
    display.add_tile(0, 0, coarse, 2)
    lit = display.rgba[..., 0] > 0
    assert lit.sum() == 4 and lit[2:, 2:4].all()                     # a 2 x 2 block, top rows
    display.reset(8, 4)
    display.add_tile(0, 0, tile(4, 8, 1.0), 1)
    display.add_tile(0, 0, tile(4, 8, 3.0), 1)
    np.testing.assert_allclose(display.rgba, 2.0)                     # the mean of the passes
