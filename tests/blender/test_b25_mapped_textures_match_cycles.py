"""An Image Texture read through Mapping nodes (the way tiled and rotated
textures are set up: Texture Coordinate UV or UV Map -> Mapping -> Image
Texture) lands where Cycles puts it, in bpy 4.5, bpy 5.0 and Debian's 3.4:
Point, Texture and Vector types, two maps chained and turned about every
axis, a Mapping whose own Vector is unlinked (one colour everywhere), and
the Mirror extension (not in 3.4), which was read as Repeat.
Before, the Mapping node was warned about and the image lay unmapped. The
export's uv_transform is checked against Blender's documented formulas, and
what is not read (the Normal type, a linked Scale) is named in a warning.
Scene: texture_scenes.mapped_texture_scene."""
import math

import numpy as np
import pytest

from runner import luminance_by_engine

VARIANTS = {"point": {"chain": "point"}, "texture": {"chain": "texture"}, "vector": {"chain": "vector"},
            "chain": {"chain": "chain", "source": "uvmap"}, "constant": {"chain": "point", "source": "constant"},
            "mirror": {"chain": "point", "extension": "MIRROR"}, "valued": {"chain": "point", "valued": True}}
NO_MIRROR = ("blender34",)      # Blender 3.4's Image Texture has no Mirror extension


@pytest.fixture(scope="module")
def renders(module_blender, tmp_path_factory):
    out = tmp_path_factory.mktemp(f"mapped_{module_blender}")
    engines = {"GRIDWALK": 'settings={"aa": "JITTERED", "aa_samples": 4}', "CYCLES": "samples=16"}
    variants = {k: v for k, v in VARIANTS.items() if k != "mirror" or module_blender not in NO_MIRROR}
    return luminance_by_engine(module_blender, out, "mapped_texture", engines, variants)


@pytest.mark.parametrize("variant", [v for v in VARIANTS if v != "constant"])
def test_the_mapped_image_lands_where_cycles_puts_it(renders, variant, module_blender):
    if variant == "mirror" and module_blender in NO_MIRROR:
        pytest.skip("Blender 3.4 has no Mirror extension")
    ours, cycles = renders[("GRIDWALK", variant)], renders[("CYCLES", variant)]
    assert cycles.std() > 0.05                                           # a pattern, not a flat colour
    assert np.corrcoef(ours.reshape(-1), cycles.reshape(-1))[0, 1] > 0.99
    assert np.abs(ours - cycles).mean() < 0.01


def test_a_mapping_of_nothing_shows_one_colour_as_in_cycles(renders):
    # (the plane leaves a column or two of black world at each side)
    ours, cycles = renders[("GRIDWALK", "constant")][:, 4:-4], renders[("CYCLES", "constant")][:, 4:-4]
    assert ours.std() < 1e-3 and cycles.std() < 1e-3
    assert ours.mean() == pytest.approx(cycles.mean(), rel=0.01)
    assert abs(ours.mean() - renders[("GRIDWALK", "point")][:, 4:-4].mean()) > 0.005   # one texel, not the image's mean


def _euler(rx, ry, rz):
    c, s = np.cos, np.sin
    x = np.array([[1, 0, 0], [0, c(rx), -s(rx)], [0, s(rx), c(rx)]])
    y = np.array([[c(ry), 0, s(ry)], [0, 1, 0], [-s(ry), 0, c(ry)]])
    z = np.array([[c(rz), -s(rz), 0], [s(rz), c(rz), 0], [0, 0, 1]])
    return z @ y @ x


def _apply(kind, location, rotation, scale, p):
    """Blender's Mapping node on the point p (its manual's formulas)."""
    r, s, loc = _euler(*rotation), np.asarray(scale, float), np.asarray(location, float)
    if kind == "POINT":
        return r @ (s * p) + loc
    if kind == "VECTOR":
        return r @ (s * p)
    return (r.T @ (p - loc)) / s                                          # TEXTURE


@pytest.mark.parametrize("variant", ["point", "texture", "vector", "chain", "valued", "constant"])
def test_the_exported_transform_is_the_nodes_affine_map(export, variant):
    out = export("mapped_texture", **VARIANTS[variant])
    (texture,) = out.textures
    m = np.asarray(texture["uv_transform"]).reshape(2, 3)
    for u, v in ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (0.37, -2.5)):
        start = out.expected["start"]
        p = np.array([u, v, 0.0]) if start is None else np.array(start, float)
        for step in out.expected["maps"]:
            p = _apply(step[0], *step[1:], p)
        np.testing.assert_allclose(m @ [u, v, 1.0], p[:2], atol=1e-6)
    assert not any("Mapping" in w or "Vector" in w for w in out.warnings), out.warnings


def test_what_is_not_read_is_named_in_a_warning(export):
    out = export("mapped_texture", chain="unread")
    text = " ".join(out.warnings)
    assert "of type Normal (passed over)" in text, out.warnings
    assert "Scale of 'Mapping.001' (ShaderNodeTexCoord: its own value is used)" in text, out.warnings
    # the Point map's own values are still applied
    (texture,) = out.textures
    r = math.radians(30.0)
    np.testing.assert_allclose(texture["uv_transform"], [2.5 * math.cos(r), -1.5 * math.sin(r), 0.3,
                                                         2.5 * math.sin(r), 1.5 * math.cos(r), -0.2], atol=1e-6)
