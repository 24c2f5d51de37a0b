"""A world's Sky Texture renders and lights the scene as in Cycles, in bpy 4.5, bpy 5.0 and
Debian's 3.4: the node as Blender adds it (Nishita in 3.x-4.x, Multiple Scattering in 5.0),
5.0's Single Scattering, a low sun turned round with every atmosphere setting changed, no sun
disc, a Mapping node turning the sky (read where Blender gives the node a Vector input: without
the disc), the Preetham type (sun direction and turbidity), the sun's disc seen through a long lens,
and an unread type (Hosek / Wilkie: the
viewport colour). Before, every Sky Texture was a
warning and the viewport colour. Cycles renders direct light only (max bounces 0), as Gridwalk
does. Scenes: sky_scenes.sky_scene; the numbers behind the sky: test81."""
import numpy as np
import pytest

from runner import rgb_by_engine

SCENE_VARIANTS = ("default", "single", "evening", "mapped", "mapped_disc", "no_disc", "preetham", "hosek")
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=32"}


def _renders(kind, tmp_path_factory, variants, **scene):
    import json
    out = tmp_path_factory.mktemp(f"sky_{kind}")
    from runner import render_batch
    import exr
    jobs, keys = [], []
    for variant in variants:
        for engine, option in ENGINES.items():
            folder = out / f"{engine}_{variant}"
            folder.mkdir()
            jobs.append(["sky", folder, engine, "transparent=false",
                         f"scene={json.dumps(dict(scene, variant=variant))}", option])
            keys.append((engine, variant))
    outputs = render_batch(kind, jobs)
    images = {key: exr.rgba(exr.read_exr(out / f"{key[0]}_{key[1]}" / f"{key[0].lower()}.exr"),
                            "ViewLayer.Combined.")[..., :3] for key in keys}
    images["output"] = dict(zip(keys, outputs))
    return images


@pytest.fixture(scope="module")
def scenes(module_blender, tmp_path_factory):
    # (before 5.0 "single" is the default type: not rendered twice)
    variants = [v for v in SCENE_VARIANTS if v != "single" or module_blender == "bpy50"]
    return _renders(module_blender, tmp_path_factory, variants)


@pytest.fixture(scope="module")
def panoramas(module_blender, tmp_path_factory):
    return _renders(module_blender, tmp_path_factory, ("default", "evening", "preetham"), panorama=True,
                    resolution=[192, 96])


@pytest.fixture(scope="module")
def sun_views(module_blender, tmp_path_factory):
    return _renders(module_blender, tmp_path_factory, ("default",), sun_view=True, resolution=[96, 64])


def test_the_sun_seen_through_a_long_lens_is_cycles_disc(sun_views):
    """The disc (13 pixels across) with its limb darkening and redder lower edge, as Cycles
    draws it: the sky's image alone blurred it into a square of three texels (about 20 pixels)."""
    ours, cycles = sun_views[("GRIDWALK", "default")], sun_views[("CYCLES", "default")]
    disc = cycles.sum(-1) > 1000 * np.median(cycles.sum(-1))
    assert 80 < disc.sum() < 200                                         # (about pi 6.5^2 pixels)
    assert ((ours.sum(-1) > 1000 * np.median(cycles.sum(-1))) != disc).sum() <= 0.15 * disc.sum()
    assert np.allclose(ours.sum((0, 1)), cycles.sum((0, 1)), rtol=0.03)
    a, b = (x.sum(-1).ravel() for x in (ours, cycles))
    assert np.corrcoef(a, b)[0, 1] > 0.98
    centre, edge = disc & np.roll(disc, 3, 0) & np.roll(disc, -3, 0), disc & ~np.roll(disc, 2, 0)
    assert ours[centre].sum(-1).mean() > 1.3 * ours[edge].sum(-1).mean()   # (the limb: darker)


@pytest.mark.parametrize("variant", ["default", "evening", "preetham"])
def test_the_sky_seen_in_every_direction_is_cycles(panoramas, variant):
    ours, cycles = panoramas[("GRIDWALK", variant)], panoramas[("CYCLES", variant)]
    rows = np.arange(96)
    # (the rows across the horizon, where the sky changes by 10x within a pixel, are compared by their mean)
    smooth = (np.abs(rows + 0.5 - 48) > 2)[:, None]
    keep = np.broadcast_to(smooth, cycles.shape[:2])
    if variant != "preetham":                        # (Preetham's sky has no disc)
        # (the sun's pixel, a few samples of a disc a third of a pixel wide, is noise in both: left out)
        r, c = np.unravel_index(np.argmax(cycles.sum(-1)), cycles.shape[:2])
        assert cycles[r, c].sum() > 100 * np.median(cycles.sum(-1))            # (it is there)
        keep = smooth & ((rows[:, None] - r) ** 2 + (np.arange(192)[None, :] - c) ** 2 > 9)
    assert cycles[keep].mean() > 0.02
    assert np.abs(ours - cycles)[keep].mean() < 0.01 * cycles[keep].mean()
    horizon = ~smooth[:, 0]
    assert np.allclose(ours[horizon].mean((0, 1)), cycles[horizon].mean((0, 1)), rtol=0.05)


@pytest.mark.parametrize("variant", ["default", "single", "evening", "mapped", "mapped_disc", "no_disc",
                                     "preetham"])
def test_the_sky_lights_the_scene_as_in_cycles(scenes, variant, module_blender):
    if ("GRIDWALK", variant) not in scenes:
        pytest.skip(f"{module_blender}: the Nishita type is the default one, rendered as 'default'")
    ours, cycles = scenes[("GRIDWALK", variant)], scenes[("CYCLES", variant)]
    sky, ground = slice(0, 12), slice(28, 64)
    assert np.allclose(ours[sky].mean((0, 1)), cycles[sky].mean((0, 1)), rtol=0.01)
    # (lit floor, shadows and objects: the world's light and its sun, blocked by the scene)
    assert np.allclose(ours[ground].mean((0, 1)), cycles[ground].mean((0, 1)), rtol=0.03)
    # (4 x 4 pixel blocks: a sky without its sun lights by soft occlusion, below the noise of 4 samples a pixel)
    a, b = (x[ground].sum(-1).reshape(9, 4, 24, 4).mean((1, 3)) for x in (ours, cycles))
    assert np.corrcoef(a.ravel(), b.ravel())[0, 1] > 0.98


def test_settings_change_the_render(scenes):
    base = scenes[("GRIDWALK", "default")]
    for variant in ("evening", "mapped", "no_disc", "preetham"):
        assert np.abs(scenes[("GRIDWALK", variant)] - base).mean() > 0.05 * base.mean(), variant
    # with its disc, Blender gives the node no Vector input: the Mapping node is not read (nor by Cycles)
    assert np.allclose(scenes[("GRIDWALK", "mapped_disc")], base, rtol=0.05, atol=0.02 * base.mean())


def test_an_unread_sky_type_renders_the_viewport_colour_with_a_warning(scenes):
    sky = scenes[("GRIDWALK", "hosek")][0:12]
    assert np.allclose(sky, (0.2, 0.3, 0.4), atol=1e-3)
    said = scenes["output"][("GRIDWALK", "hosek")]
    assert "Gridwalk warning: World 'Sky': the Sky Texture's Hosek Wilkie type is not supported" in said
    assert "Gridwalk warning: World" not in scenes["output"][("GRIDWALK", "default")]
