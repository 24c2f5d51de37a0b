"""`shadow="area"` gives each pixel an n x n grid of light points, one stratum per pixel sample.
A pixel of more samples than strata (anti-aliasing raised, shadow samples left at 2) takes a
finer grid, one stratum per sample: it met the same n x n jittered points again and again
before, so a penumbra at 8 x 8 samples a pixel stayed as grainy as at 2 x 2."""
import numpy as np

import gridwalk as gw

RES = 32


def penumbra(aa, shadow_samples, seed):
    """A floor with a quad's soft shadow from a sphere light across the view (linear red)."""
    verts = np.array([[-20, -20, 0], [20, -20, 0], [20, 20, 0], [-20, 20, 0],
                      [-3, -3, 1], [0, -3, 1], [0, 3, 1], [-3, 3, 1]], np.float32)
    cam = gw.Camera(eye=(0, 0, 5), target=(0, 0, 0), up=(0, 1, 0), projection="orthographic", ortho_height=1.5,
                    width=RES, height=RES)
    lamp = gw.Light(kind="sphere", position=(0, 0, 3), radius=0.8, color=(9, 9, 9), inverse_square=True)
    white = gw.Material(color=(1, 1, 1), kd=1.0, ks=0.0)
    scene = gw.Scene(verts, np.array([[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]]), materials=[white],
                     lights=[lamp], camera=cam)
    settings = gw.RenderSettings(aa="jittered", aa_samples=aa, shadow="area", shadow_samples=shadow_samples,
                                 seed=seed)
    return gw.render(scene, settings)[..., 0]


def test_a_grid_coarser_than_the_pixels_samples_is_refined_to_one_stratum_per_sample():
    reference = np.mean([penumbra(16, 16, seed) for seed in (11, 12)], axis=0)
    assert reference.std() > 0.2 * reference.mean()                  # (a penumbra across the view)
    coarse = np.sqrt(np.mean((penumbra(8, 2, 1) - reference) ** 2))     # 64 samples, a 2 x 2 grid
    matched = np.sqrt(np.mean((penumbra(8, 8, 1) - reference) ** 2))    # 64 samples, an 8 x 8 grid
    few = np.sqrt(np.mean((penumbra(2, 2, 1) - reference) ** 2))        # 4 samples, a 2 x 2 grid
    # Repeating the 2 x 2 grid's 4 points, the 64 samples' error was that of 4 (about 4x the 8 x
    # 8 grid's); refined, it is the 8 x 8 grid's.
    assert coarse < 1.3 * matched, (coarse, matched)
    assert few > 2.5 * matched, (few, matched)
