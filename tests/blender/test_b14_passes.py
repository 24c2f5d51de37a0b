"""Passes: Denoising Albedo and Denoising Normal, under Cycles' names, feed
the compositor's Denoise node (a 4-sample render denoised with them is closer
by RMSE to a 256-sample render than the noisy one); and every pass is written
with its tile, so a render cancelled part way has them where it has pixels."""
import json

import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, script_output


@pytest.fixture(scope="module", params=ALL_BLENDERS)
def images(request, tmp_path_factory):
    out = script_output(request.param, tmp_path_factory, "denoise.py")
    noisy = exr.read_exr(out / "noisy.exr")

    def single(name):
        channels = exr.read_exr(out / name)
        return np.stack([channels[c] for c in "RGB"], axis=-1)

    info = json.loads((out / "info.json").read_text())
    return {"kind": request.param, "noisy": noisy, "reference": single("reference.exr"),
            "denoised": single("denoised.exr"), "oidn": info["oidn"]}


def test_denoising_passes_are_written_under_cycles_names(images):
    noisy = images["noisy"]
    albedo = np.stack([noisy[f"ViewLayer.Denoising Albedo.{c}"] for c in "RGB"], axis=-1)
    normal = np.stack([noisy[f"ViewLayer.Denoising Normal.{c}"] for c in "XYZ"], axis=-1)
    np.testing.assert_allclose(albedo.max(axis=(0, 1)), 0.8, atol=1e-5)     # the white floor / pane colour
    np.testing.assert_allclose(np.linalg.norm(normal, axis=-1), 1.0, atol=1e-3)
    assert np.all(normal[..., 2] > 0.99)                                      # everything faces the camera (+Z)


def test_denoise_node_brings_4_samples_closer_to_256(images):
    noisy = exr.rgba(images["noisy"], "ViewLayer.Combined.")[..., :3]
    if not images["oidn"]:       # _cycles.with_openimagedenoise: Debian's Blender 3.4 has none
        assert np.array_equal(images["denoised"], noisy)     # the node passes the image through
        pytest.skip(f"{images['kind']} is built without OpenImageDenoise: its Denoise node passes the image through")
    rmse = lambda a: float(np.sqrt(((a - images["reference"]) ** 2).mean()))
    assert rmse(noisy) > 0.01, "the 4-sample render should be noisy"
    assert rmse(images["denoised"]) < 0.5 * rmse(noisy)


@pytest.fixture(scope="module", params=ALL_BLENDERS)
def partial(request, tmp_path_factory):
    out = script_output(request.param, tmp_path_factory, "tile_passes.py")
    return exr.read_exr(out / "partial.exr")


def test_a_cancelled_render_has_every_pass_in_its_finished_tiles(partial):
    covered = partial["ViewLayer.Combined.A"] > 0.999    # every sample hit (the passes are the first sample's)
    depth = partial["ViewLayer.Depth.Z"]
    written = depth <= 1e10                      # ours: a hit's distance, or 1e10 (Cycles' miss value)
    assert 0 < written.mean() < 1, "the render should have been cancelled part way"
    assert covered.any()
    assert np.all((depth[covered] > 5) & (depth[covered] < 20))
    for name in ("Normal", "Denoising Normal"):
        normal = np.stack([partial[f"ViewLayer.{name}.{c}"] for c in "XYZ"], axis=-1)
        np.testing.assert_allclose(np.linalg.norm(normal[covered], axis=-1), 1.0, atol=1e-3)
    assert np.all(partial["ViewLayer.Denoising Albedo.R"][covered] > 0)
