"""A PNG's colour, shown through an Emission shader with the Alpha output unused, is associated
(premultiplied by alpha) as Cycles associates it: an RGBA file in its sRGB bytes; a grey + alpha
file not at all (Cycles reads such a file itself and associates only images with colour channels;
Blender reads it as RGBA, so the export reads the file's header); the same image packed, as RGBA
(Cycles takes packed images from Blender). The grey + alpha file rendered 0.298 where Cycles
shows 0.502 (display values), in bpy 4.5, bpy 5.0 and Debian's 3.4. Scene:
material_scenes.png_alpha_scene."""
import pytest

from runner import rgb_by_engine


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"png_alpha_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 2}', "CYCLES": "samples=4"}
    return rgb_by_engine(module_blender, out, "png_alpha", engines)


@pytest.mark.parametrize("plane, column", [("RGBA", 1 / 6), ("GreyAlpha", 0.5), ("GreyAlphaPacked", 5 / 6)])
def test_each_png_shows_the_colour_cycles_shows(renders, plane, column):
    def centre(rgb):
        h, w = rgb.shape[:2]
        return rgb[h // 2 - 3:h // 2 + 3, int(column * w) - 3:int(column * w) + 3].mean()
    ours, cycles = centre(renders["GRIDWALK"]), centre(renders["CYCLES"])
    assert cycles > 0.05
    assert ours == pytest.approx(cycles, rel=0.02)
