"""An image reaching a shader through Separate Color, Math, Mix (and 3.x's
MixRGB and Separate RGB) and Invert nodes, as Blender's glTF importer and
many hand-made materials set it up, renders as in Cycles, in bpy 4.5, bpy
5.0 and Debian's 3.4. Before, such an input took its default value, with a
warning. A real glTF model (written by gltf_scenes.py, imported by
Blender's own importer) exports its factors, its packed roughness and
metallic channels and its texture transform as the glTF file states them.
Scenes: texture_scenes.node_chain_scene, gltf_scenes.gltf_model_scene."""
import math

import numpy as np
import pytest

from runner import luminance_by_engine

CHAINS = ["tint", "green", "invert", "luminance", "alpha", "legacy",    # texture_scenes.CHAINS
          "divide", "overdrive", "float_clamp"]
LEGACY = ("bpy50",)            # Blender 5.0 has no Separate RGB node any more (files convert it)
ENGINES = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}


@pytest.fixture(scope="module")
def chains(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"chains_{module_blender}")
    return luminance_by_engine(module_blender, out, "node_chain", ENGINES,
                               {c: {"chain": c} for c in CHAINS if c != "legacy" or module_blender not in LEGACY})


@pytest.mark.parametrize("chain", CHAINS)
def test_the_chain_gives_what_cycles_gives(chains, chain, module_blender):
    if chain == "legacy" and module_blender in LEGACY:
        pytest.skip("Blender 5.0 has no Separate RGB node")
    ours, cycles = chains[("GRIDWALK", chain)][:, 3:-3], chains[("CYCLES", chain)][:, 3:-3]
    assert cycles.std() > 0.02                                       # the image's pattern
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.99
    assert np.abs(ours - cycles).mean() < 0.015 * max(1.0, cycles.mean())


def test_a_chain_is_folded_into_the_texture(export):
    out = export("node_chain", chain="green")     # Separate Color green, x 0.7, + 0.1 clamped
    (texture,) = out.textures
    assert texture["channel"] == 1 and texture["clamp"]
    np.testing.assert_allclose(texture["gain"], [0.7] * 3, rtol=1e-6)
    np.testing.assert_allclose(texture["bias"], [0.1] * 3, rtol=1e-6)
    assert not out.warnings, out.warnings


def test_a_node_that_is_not_read_is_named(export):
    out = export("node_chain", chain="unread")
    assert not out.textures
    assert any("'Gamma'" in w or "ShaderNodeGamma" in w for w in out.warnings), out.warnings
    # an Invert whose factor the image's alpha gives is not an affine map: named, not folded
    out = export("node_chain", chain="linked_fac")
    assert not out.textures
    assert any("ShaderNodeInvert" in w and "with a linked factor" in w for w in out.warnings), out.warnings


def _gltf_uv_map(transform, u, v):
    """Blender's UV (v up) of the texel glTF's KHR_texture_transform reads at Blender's (u, v)."""
    c, s = math.cos(transform["rotation"]), math.sin(transform["rotation"])
    (sx, sy), (ox, oy) = transform["scale"], transform["offset"]
    gu, gv = u, 1.0 - v                                                 # glTF's v runs down
    tu, tv = c * sx * gu + s * sy * gv + ox, -s * sx * gu + c * sy * gv + oy
    return tu, 1.0 - tv


def test_a_gltf_model_exports_its_factors_channels_and_transform(export):
    out = export("gltf_model")
    factors, transform = out.expected["factors"], out.expected["transform"]
    (model,) = [m for m in out.materials if m["color_texture"] >= 0]
    tex = {field: out.textures[model[field]] for field in
           ("color_texture", "roughness_texture", "metallic_texture", "alpha_texture")}
    np.testing.assert_allclose(tex["color_texture"]["gain"], factors["baseColorFactor"][:3], rtol=1e-6)
    assert tex["roughness_texture"]["channel"] == 1 and tex["metallic_texture"]["channel"] == 2   # G and B
    np.testing.assert_allclose(tex["roughness_texture"]["gain"], [factors["roughnessFactor"]] * 3, rtol=1e-6)
    np.testing.assert_allclose(tex["metallic_texture"]["gain"], [factors["metallicFactor"]] * 3, rtol=1e-6)
    assert tex["alpha_texture"]["use_alpha"]
    np.testing.assert_allclose(tex["alpha_texture"]["gain"], [factors["baseColorFactor"][3]] * 3, rtol=1e-6)
    for field in ("color_texture", "alpha_texture"):
        m = np.asarray(tex[field]["uv_transform"]).reshape(2, 3)
        for u, v in ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.3, 0.8)):
            np.testing.assert_allclose(m @ [u, v, 1.0], _gltf_uv_map(transform, u, v), atol=1e-5)
    assert not out.warnings, out.warnings


def test_a_gltf_model_renders_as_in_cycles(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"gltf_{module_blender}")
    renders = luminance_by_engine(module_blender, out, "gltf_model",
                                  {**ENGINES, "CYCLES": "samples=64"}, {"model": {}})
    ours, cycles = renders[("GRIDWALK", "model")], renders[("CYCLES", "model")]
    assert cycles.std() > 0.05
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.95
    assert 0.8 < ours.mean() / cycles.mean() < 1.25


@pytest.fixture(scope="module")
def tinted(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"tinted_{module_blender}")
    return luminance_by_engine(module_blender, out, "tinted_by_attribute", ENGINES,
                               {"mix": {}, "legacy": {"legacy": True}})


@pytest.mark.parametrize("variant", ["mix", "legacy"])
def test_an_image_times_a_colour_attribute_gives_what_cycles_gives(tinted, variant):
    # (Blender's glTF importer wires a textured model's vertex colours so: a Mix, Multiply, factor 1)
    ours, cycles = tinted[("GRIDWALK", variant)][:, 3:-3], tinted[("CYCLES", variant)][:, 3:-3]
    assert cycles.std() > 0.02
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.99
    assert np.abs(ours - cycles).mean() < 0.015


def test_an_image_times_a_colour_attribute_exports_both(export):
    out = export("tinted_by_attribute")
    (material,) = [m for m in out.materials if m["color_texture"] >= 0]
    assert material["vertex_color"]
    assert out.colors.shape[1:] == (3, 3) and np.ptp(out.colors[..., 0]) > 0.5      # the "Tint" corners
    assert not out.warnings, out.warnings
    assert out.corner_arrays_read == {"uvs": True, "colors": True}    # what the memory estimate counts
