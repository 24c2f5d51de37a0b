"""Blender's GUI (Debian's blender under Xvfb) with GRIDWALK selected, its panels
and a finished render: the screenshot in docs/images/ comes from the same code
(python tests/blender/gui.py docs/images/blender_gridwalk.png)."""
import shutil

import numpy as np
import pytest
from PIL import Image

from gui import SIZE, screenshot
from runner import missing_reason


def test_gui_shows_the_gridwalk_render(tmp_path):
    reason = missing_reason("blender34") or (None if shutil.which("Xvfb") else "Xvfb is missing")
    if reason:
        pytest.skip(reason)
    shot = np.asarray(Image.open(screenshot(tmp_path / "gui.png")).convert("RGB"), dtype=np.float32)
    assert shot.shape == (SIZE[1], SIZE[0], 3)
    # the render, shown in the main area, is colourful: the red monkey and blue cubes
    main = shot[100:780, 20:1300]
    assert (main[..., 0] - main[..., 2] > 60).mean() > 0.005
    assert (main[..., 2] - main[..., 0] > 60).mean() > 0.005
