"""An object set to Shadow Catcher renders as in Cycles, in bpy 4.5, bpy 5.0 and Debian's
3.4: a floor under a red cube and a sun. On a transparent film the floor is gone but for the
cube's shadow, black coverage of its strength (alpha correlates with Cycles' above 0.99, in a
black world where the shadow is full and in a grey one whose light fills it); on an opaque
film the floor shows the world, darkened in the shadow; a Geometry Nodes carrier set to
Shadow Catcher makes its copies catchers. Before, the floor rendered as a grey surface with a
warning. Scene: catcher_scenes.shadow_catcher_scene."""
import json

import numpy as np
import pytest

import exr
from runner import missing_reason, render_batch

VARIANTS = {"dark": ({"world": 0.0}, True), "grey": ({"world": 0.3}, True), "opaque": ({"world": 0.3}, False),
            "copies": ({"world": 0.3, "instanced": True}, True)}
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4, "shadow_samples": 8}', "CYCLES": "samples=64"}


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    reason = missing_reason(module_blender)
    if reason:
        pytest.skip(reason)
    out = tmp_path_factory.mktemp(f"catcher_{module_blender}")
    jobs = []
    for key, (scene, transparent) in VARIANTS.items():
        for engine, option in ENGINES.items():
            (out / f"{engine}_{key}").mkdir()
            jobs.append(["shadow_catcher", out / f"{engine}_{key}", engine, f"transparent={str(transparent).lower()}",
                         f"scene={json.dumps(scene)}", option])
    render_batch(module_blender, jobs, timeout_per_job=60)
    return {(engine, key): exr.rgba(exr.read_exr(out / f"{engine}_{key}" / f"{engine.lower()}.exr"),
                                    "ViewLayer.Combined.")
            for key in VARIANTS for engine in ENGINES}


@pytest.mark.parametrize("key", ["dark", "grey", "copies"])
def test_on_a_transparent_film_the_catcher_leaves_its_shadow_as_coverage(renders, key):
    ours, cycles = renders[("GRIDWALK", key)], renders[("CYCLES", key)]
    assert ours[..., 3].mean() < 0.3                     # the floor is not rendered as a surface
    assert cycles[..., 3].std() > 0.2                    # the cube and its shadow
    assert np.corrcoef(ours[..., 3].ravel(), cycles[..., 3].ravel())[0, 1] > 0.99
    assert np.abs(ours[..., 3] - cycles[..., 3]).mean() < 0.02
    shadow = (cycles[..., 3] > 0.2) & (cycles[..., 0] < 0.05)      # the shadow: covered, black
    assert shadow.sum() > 100
    assert np.abs(ours[shadow, :3]).max() < 0.02         # black where it covers


def test_a_world_that_fills_the_shadow_weakens_it(renders):
    dark, grey = renders[("GRIDWALK", "dark")], renders[("GRIDWALK", "grey")]
    # the full shadow in the black world, less the cube (its faces: red in the grey world's light)
    shadow = (dark[..., 3] > 0.9) & (dark[..., 0] < 0.02) & (grey[..., 0] < 0.02)
    assert shadow.sum() > 100
    assert 0.3 < grey[shadow, 3].mean() < 0.9


def test_the_catcher_of_copies_is_their_carrier(renders):
    np.testing.assert_allclose(renders[("GRIDWALK", "copies")][..., 3], renders[("GRIDWALK", "grey")][..., 3],
                               atol=1e-6)


def test_on_an_opaque_film_the_catcher_shows_the_world_darkened_by_its_shadow(renders):
    ours, cycles = renders[("GRIDWALK", "opaque")], renders[("CYCLES", "opaque")]
    assert np.abs(ours[..., :3] - cycles[..., :3]).mean() < 0.02
    floor = renders[("GRIDWALK", "grey")][..., 3] < 1e-4          # the floor lit in full
    assert floor.sum() > 1000
    np.testing.assert_allclose(ours[floor, :3], 0.3, atol=1e-3)   # the world's grey, as if no floor were there
    luminance = ours[..., :3].mean(axis=-1)
    assert luminance[renders[("GRIDWALK", "grey")][..., 3] > 0.3].min() < 0.2   # darker in the shadow


def test_the_export_makes_the_floors_materials_catchers_without_a_warning(export):
    out = export("shadow_catcher")
    catchers = [m for m in out.materials if m["shadow_catcher"]]
    assert len(catchers) == 1 and catchers[0]["color"][0] == pytest.approx(0.6, abs=0.01)
    assert not any("Shadow Catcher" in w for w in out.warnings), out.warnings
