"""A lamp with a shape (here a rect light, Blender's area light) lights a rough surface whose
reflection rays are traced (a metal, a Principled dielectric's layer) by both: the rays that meet
its shape and its light points, each weighted by the power heuristic (multiple importance
sampling, as for emissive triangles in test71). Before, the light points alone took the
highlight, and where the lobe was narrow against the lamp (alpha under a tenth of its angular
radius) only the lamp seen in the mirror direction was taken: GGX's long tails were cut off. A
1 x 1 m rect light over a metal floor of roughness 0.1 in Blender rendered at 0.46x Cycles'
brightness (its glow around the reflection missing), 2 x 2 m at roughness 0.15 at 0.47x."""
import numpy as np
import pytest

import gridwalk as gw
from panel_floor import BLOCKERS, CENTRE, EYE, blocker_quad, lobe_over_panel, white_metal

RADIANCE = 4.0


def lamp_scene(floor, size, centre=CENTRE, blocker=None, casts_shadows=True):
    """The floor (100 x 100) seen through one pixel at its origin, and a size x size rect light
    (radiance RADIANCE, facing down) centred at `centre`; blocker: a 2 x 2 quad of BLOCKERS
    halfway between them."""
    verts = [[-50, -50, 0], [50, -50, 0], [50, 50, 0], [-50, 50, 0]]
    tris, tri_mats = [[0, 1, 2], [0, 2, 3]], [0, 0]
    if blocker:
        verts += blocker_quad(centre)
        tris += [[4, 5, 6], [4, 6, 7]]
        tri_mats += [1, 1]
    lamp = gw.Light(kind="rect", position=tuple(centre), size=(size, size), axis_u=(1, 0, 0), axis_v=(0, -1, 0),
                    direction=(0, 0, -1), color=(RADIANCE * size * size / np.pi,) * 3, inverse_square=True,
                    casts_shadows=casts_shadows)
    camera = gw.Camera(eye=tuple(EYE), target=(0, 0, 0), up=(0, 0, 1), fov=1, width=1, height=1)
    return gw.Scene(vertices=np.array(verts, np.float32), triangles=tris, triangle_materials=tri_mats,
                    materials=[floor, BLOCKERS[blocker or "opaque"]], camera=camera, lights=[lamp],
                    background=(0, 0, 0))


def pixel(scene, seed, rays, points, mode="random"):
    settings = gw.RenderSettings(glossy_samples=rays, shadow=mode, shadow_samples=points, seed=seed)
    return float(gw.render(scene, settings)[0, 0, :3].mean())


@pytest.mark.parametrize("roughness, size", [(0.3, 0.5), (0.6, 0.2), (0.1, 1.0), (0.15, 2.0)])
def test_a_rough_metal_returns_the_lobe_integrated_over_the_lamp(roughness, size):
    scene = lamp_scene(white_metal(roughness), size)
    value = np.mean([pixel(scene, seed, 256, 64) for seed in range(2)])
    assert value == pytest.approx(lobe_over_panel(roughness, size, RADIANCE), rel=0.015)


def test_the_lobes_tail_beside_a_lamps_reflection_is_lit():
    # The mirror direction passes 0.6 m beside a 1 x 1 m lamp; roughness 0.1 (alpha 0.01) is
    # far narrower than the lamp, and only its tail reaches it (it was 0: the lamp seen in the
    # mirror direction alone).
    centre = CENTRE + np.array([0.0, 1.1, 0.0])
    scene = lamp_scene(white_metal(0.1), 1.0, centre)
    expected = lobe_over_panel(0.1, 1.0, RADIANCE, centre=centre)
    assert expected > 0.005
    # (64 x 64 stratified light points: the seeds agree within 0.2%)
    value = np.mean([pixel(scene, seed, 256, 64, mode="area") for seed in range(2)])
    assert value == pytest.approx(expected, rel=0.02)


@pytest.mark.parametrize("size", [1.0, 2.0])
def test_a_large_lamps_highlight_on_a_glossy_metal_is_smooth_at_few_samples(size):
    # Roughness 0.2 under a lamp of 1 or 2 m, 4 rays and 2 x 2 light points a pixel, 24 seeds:
    # the light points alone gave a standard deviation of 0.57 and 0.98 of the mean; now 0.15
    # and 0.13.
    scene = lamp_scene(white_metal(0.2), size)
    values = np.array([pixel(scene, seed, 4, 2, mode="area") for seed in range(24)])
    expected = lobe_over_panel(0.2, size, RADIANCE)
    assert values.std() < 0.3 * expected
    assert values.mean() == pytest.approx(expected, rel=0.1)


def test_a_lamp_that_casts_no_shadows_is_seen_through_what_blocks_it():
    # Its light points ignore what lies between; the lobe's rays that meet its shape must too
    # (with a blocker: 0 without the shadows' switch, all of it with it). One light point against
    # 256 rays: the rays take most of the highlight (testing the blocker, they took 0.0007 of it).
    floor = white_metal(0.3)

    def value(**blocking):
        return np.mean([pixel(lamp_scene(floor, 0.5, **blocking), seed, 256, 1) for seed in range(8)])
    free = value()
    assert value(blocker="opaque") < 0.01 * free
    assert value(blocker="opaque", casts_shadows=False) == pytest.approx(free, rel=0.02)


@pytest.mark.parametrize("blocker", ["cut-out", "clear pane"])
def test_a_cut_out_or_a_clear_pane_before_the_lamp_changes_nothing(blocker):
    # An alpha cut-out lets the lamp through to the rays and the light points alike (the rays
    # tested it as opaque: 0.73x); a pane of IOR 1 neither bends nor reflects, and the light
    # through it reaches the floor by its refraction ray alone (the light points added their
    # shared part on top: 1.2x).
    floor = white_metal(0.3)

    def value(**blocking):
        return np.mean([pixel(lamp_scene(floor, 0.5, **blocking), seed, 64, 4) for seed in range(8)])
    assert value(blocker=blocker) == pytest.approx(value(), rel=0.02)
