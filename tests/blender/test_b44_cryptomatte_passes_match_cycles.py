"""Cryptomatte Object, Material and Asset passes: GRIDWALK writes Cycles'
passes (CryptoObject00, ...; channels r, g, b, a), the same ids for the same
names, mattes that match Cycles' over the same scene, and the metadata
(name, hash, conversion, manifest) a compositor reads the names from. The
Object and Material Index passes come from the same data."""
import json
import sys
from pathlib import Path

import numpy as np
import pytest

import exr
from runner import ALL_BLENDERS, script_output

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "blender_addon"))
import cryptomatte  # noqa: E402  (the add-on's module: numpy only)

# (Bare has no material: Cycles' default shader; Orb is an analytic sphere in GRIDWALK, a mesh in Cycles)
LAYERS = {"Object": ("Floor", "Box", "Ball", "Bare", "Orb"), "Material": ("Floor", "Red", "Blue", "default_surface"),
          "Asset": ("Floor", "Box", "Rig", "Bare", "Orb")}


@pytest.fixture(scope="module", params=ALL_BLENDERS)
def renders(request, tmp_path_factory):
    out = script_output(request.param, tmp_path_factory, "cryptomatte.py")
    return {engine: (exr.read_exr(out / f"{engine}.exr"), exr.read_metadata(out / f"{engine}.exr"))
            for engine in ("gridwalk", "cycles")} | {"blender": json.loads((out / "info.json").read_text())}


def matte(channels, layer, name):
    """The matte of `name`: its coverage summed over every rank of the layer's passes."""
    target, total = cryptomatte.id_float(name), 0.0
    for p in range(3):
        for i, c in (("r", "g"), ("b", "a")):
            total = total + np.where(channels[f"ViewLayer.Crypto{layer}{p:02d}.{i}"] == target,
                                     channels[f"ViewLayer.Crypto{layer}{p:02d}.{c}"], 0.0)
    return total


def test_the_same_passes_and_channels_as_cycles(renders):
    ours, theirs = ({k for k in renders[e][0] if ".Crypto" in k} for e in ("gridwalk", "cycles"))
    assert len(theirs) == 3 * 3 * 4          # three layers, 6 levels = 3 passes of 4 channels
    assert ours == theirs


@pytest.mark.parametrize("layer", LAYERS)
def test_each_names_matte_matches_cycles(renders, layer):
    ours, theirs = renders["gridwalk"][0], renders["cycles"][0]
    for name in LAYERS[layer]:
        a, b = matte(ours, layer, name), matte(theirs, layer, name)
        assert b.sum() > 50, f"Cycles' {layer} matte of {name} is empty"
        inside_a, inside_b = a > 0.5, b > 0.5
        iou = (inside_a & inside_b).sum() / (inside_a | inside_b).sum()
        assert iou > 0.97, (layer, name, iou)
        assert abs(a.sum() / b.sum() - 1) < 0.02, (layer, name, a.sum(), b.sum())
        assert np.abs(a - b).mean() < 0.02, (layer, name)


@pytest.mark.parametrize("layer", LAYERS)
def test_fully_covered_pixels_have_cycles_ids_at_rank_0(renders, layer):
    ours, theirs = renders["gridwalk"][0], renders["cycles"][0]
    rank0 = f"ViewLayer.Crypto{layer}00."
    solid = (theirs[rank0 + "g"] > 0.999) & (ours[rank0 + "g"] > 0.999)
    assert solid.mean() > 0.5
    same = ours[rank0 + "r"][solid] == theirs[rank0 + "r"][solid]      # bit for bit: the same hash
    assert same.mean() > 0.995
    # ranks hold no more than the pixel, most first
    cov = np.stack([ours[f"ViewLayer.Crypto{layer}{p:02d}.{c}"] for p in range(3) for c in "ga"], -1)
    assert np.all(cov.sum(-1) <= 1 + 1e-5) and np.all(np.diff(cov, axis=-1) <= 1e-7)


def test_metadata_names_each_layer_and_its_ids_as_cycles_does(renders):
    ours, theirs = renders["gridwalk"][1], renders["cycles"][1]
    layers = {v: k.rsplit("/", 1)[0] for k, v in theirs.items() if k.endswith("/name")}
    assert set(layers) == {f"ViewLayer.Crypto{layer}" for layer in LAYERS}
    for layer, key in layers.items():
        assert ours[f"{key}/name"] == layer
        assert ours[f"{key}/hash"] == theirs[f"{key}/hash"] == "MurmurHash3_32"
        assert ours[f"{key}/conversion"] == theirs[f"{key}/conversion"] == "uint32_to_float32"
        mine, cycles = json.loads(ours[f"{key}/manifest"]), json.loads(theirs[f"{key}/manifest"])
        assert set(LAYERS[layer.split("Crypto")[1]]) <= set(mine)
        assert all(cycles[name] == value for name, value in mine.items())


@pytest.mark.parametrize("name, values", [("IndexOB", {0, 1, 2, 3}), ("IndexMA", {0, 4, 5})])
def test_index_passes_hold_the_pass_index_cycles_writes(renders, name, values):
    ours, theirs = renders["gridwalk"][0], renders["cycles"][0]
    if renders["blender"]["blender"] >= [5, 0, 0]:       # (renamed in 5.0)
        name = {"IndexOB": "Object Index", "IndexMA": "Material Index"}[name]
    a, b = ours[f"ViewLayer.{name}.X"], theirs[f"ViewLayer.{name}.X"]
    assert set(np.unique(b).tolist()) == values
    assert set(np.unique(a).tolist()) == values
    solid = (theirs["ViewLayer.CryptoObject00.g"] > 0.999) & (ours["ViewLayer.CryptoObject00.g"] > 0.999) & \
        (theirs["ViewLayer.CryptoMaterial00.g"] > 0.999)
    assert (a[solid] == b[solid]).mean() > 0.995
    assert (a != b).mean() < 0.03          # (edges: Cycles takes its first sample's object, we the most covering)
