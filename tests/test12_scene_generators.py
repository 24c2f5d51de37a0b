"""Built-in scenes: balls reproduces SPD's sphereflake files, distant is a depth-of-field test."""
import math
from pathlib import Path

import numpy as np
import pytest

from gridwalk.io import load_nff
from gridwalk.scenes import SCENES, balls, distant

SPD_DIR = Path(__file__).resolve().parents[1].parent / "shared" / "scenes" / "spd"
needs_spd = pytest.mark.skipif(not SPD_DIR.is_dir(), reason=f"SPD scenes not found in {SPD_DIR}")


@pytest.mark.parametrize("size", [0, 1, 2, 3, 4, 5])
def test_balls_has_sum_of_powers_of_nine_spheres(size):
    scene = balls(size)
    radii = scene["sphere_radii"]
    assert len(radii) == sum(9 ** k for k in range(size + 1))
    assert len(scene["sphere_materials"]) == len(scene["sphere_centers"]) == len(radii)


@needs_spd
@pytest.mark.parametrize("size", [1, 2, 3, 4])
def test_balls_matches_the_spd_file_sphere_for_sphere(size):
    generated = balls(size)
    spd = load_nff(SPD_DIR / f"balls_s{size}.nff")
    assert len(generated["sphere_radii"]) == len(spd["sphere_radii"])
    # The files print 6 significant digits, in the same depth-first order.
    np.testing.assert_allclose(generated["sphere_centers"], spd["sphere_centers"], atol=2e-6)
    np.testing.assert_allclose(generated["sphere_radii"], spd["sphere_radii"], atol=2e-6)


@needs_spd
def test_balls_floor_materials_lights_view_and_background_match_the_spd_file():
    generated, spd = balls(4), load_nff(SPD_DIR / "balls_s4.nff")
    for key in ("vertices", "triangles", "triangle_materials", "sphere_materials"):
        np.testing.assert_array_equal(generated[key], spd[key], err_msg=key)
    for key in ("materials", "lights", "camera", "background"):
        assert generated[key] == spd[key], key


def test_each_ball_touches_its_parent_and_is_a_third_of_its_size():
    scene = balls(2)
    centres, radii = scene["sphere_centers"].astype(np.float64), scene["sphere_radii"]
    # Depth-first order: sphere 0, child 1 with grandchildren 2..10, child 11, ...
    for parent, child in [(0, 1), (0, 11), (0, 81), (1, 2), (1, 10), (81, 90)]:
        gap = np.linalg.norm(centres[child] - centres[parent]) - radii[parent] - radii[child]
        assert gap == pytest.approx(0.0, abs=1e-6)
        assert radii[child] == pytest.approx(radii[parent] / 3)


def test_balls_rejects_a_negative_size():
    with pytest.raises(ValueError, match="size"):
        balls(-1)


def test_distant_has_three_spheres_at_increasing_distances_on_the_ground():
    scene = distant()
    eye = np.array(scene["camera"].eye)
    centres, radii = scene["sphere_centers"], scene["sphere_radii"]
    distances = np.linalg.norm(centres - eye, axis=1)
    assert len(radii) == 3 and np.all(np.diff(distances) > 3.0)
    np.testing.assert_allclose(centres[:, 2] - radii, 0.0, atol=1e-6)   # resting on z = 0
    assert np.all(scene["vertices"][:, 2] == 0) and len(scene["triangles"]) == 2


def test_distant_camera_has_a_lens_focused_on_the_middle_sphere():
    scene = distant()
    camera = scene["camera"]
    middle = scene["sphere_centers"][1].astype(np.float64)
    assert camera.aperture > 0
    assert camera.focus_distance == pytest.approx(np.linalg.norm(middle - np.array(camera.eye)))


@pytest.mark.parametrize("name", sorted(SCENES))
def test_generated_scenes_are_valid_scene_keywords(name):
    scene = SCENES[name]()
    for key in ("vertices", "sphere_centers", "sphere_radii", "cylinder_base"):
        assert scene[key].dtype == np.float32, key
    for key in ("triangles", "triangle_materials", "sphere_materials", "cylinder_materials"):
        assert scene[key].dtype == np.int32, key
    assert scene["sphere_materials"].max() < len(scene["materials"])
    for record in [*scene["materials"], *scene["lights"], scene["camera"]]:
        record.validate()          # raises ValueError naming the field of an invalid record
    assert len(scene["background"]) == 3 and math.isfinite(sum(scene["background"]))
