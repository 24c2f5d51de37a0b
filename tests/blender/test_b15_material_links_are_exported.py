"""What the exporter makes of each linked material input (issue 13), in every
Blender (bpy 4.5, bpy 5.0, Debian's 3.4): which UV layer and colour attribute
it reads, the Emission shader, textures on Metallic and Alpha, the node's
interpolation and extension, each image stored once and 8-bit kept 8-bit, and
the images' share of the memory estimate. Scene: texture_links_scene."""
import numpy as np
import pytest


@pytest.fixture
def links(export):
    out = export("texture_links")
    mats = out.materials

    def only(test):
        found = [i for i, m in enumerate(mats) if test(m)]
        assert len(found) == 1, f"expected one material, found {found} in {mats}"
        return found[0]

    out.by_node = only(lambda m: m["color_texture"] >= 0 and m["metallic_texture"] < 0 and not m["vertex_color"])
    out.by_render = only(lambda m: m["metallic_texture"] >= 0)
    out.painted = only(lambda m: m["vertex_color"])
    out.lamp = only(lambda m: any(m["emission_color"]))
    return out


def _uvs_of(out, material):
    uv = out.uvs[out.triangle_materials == material]
    assert uv.size > 0
    return uv


def test_a_uv_map_node_picks_its_layer(links):
    uv = _uvs_of(links, links.by_node)
    assert uv.min() == pytest.approx(0.25) and uv.max() == pytest.approx(0.75)    # "Second", not "UVMap"


def test_without_a_uv_map_node_the_active_render_layer_is_read(links):
    uv = _uvs_of(links, links.by_render)
    assert uv.min() == pytest.approx(3.0) and uv.max() == pytest.approx(4.0)      # "Render", not the edited one


def test_a_material_reading_two_uv_maps_reads_its_first_and_says_so(export):
    # (the core has one UV map per material: before, the render map's texture silently read the
    # UV Map node's layer too, as Blender's glTF importer builds models with two UV sets)
    out = export("texture_links", mixed_maps=True)
    centres = out.vertices[out.triangles].mean(axis=1)[:, 0]
    uv = out.uvs[np.abs(centres - 9.0) < 0.6]
    assert uv.size > 0 and uv.min() == pytest.approx(0.0) and uv.max() == pytest.approx(1.0)   # the render map
    assert ("Object 'Mixed': the textures of material 'Mixed' read the UV maps 'UVMap', 'Second': every "
            "texture of a material reads one, 'UVMap'") in out.warnings, out.warnings


def test_from_instancer_is_named_not_silently_read_as_the_objects_own(export):
    out = export("texture_links", from_instancer=True)
    assert any("From Instancer" in w and "ByNode" in w for w in out.warnings), out.warnings


def test_an_image_in_a_colour_space_the_core_does_not_decode_is_named(export):
    # (Display P3, Rec.1886, AgX, Filmic Log...: read as sRGB or linear, 28-62% off Cycles where
    # nothing was said, found by a review probe)
    out = export("texture_links", odd_space=True)
    space = out.expected["space"]
    assert any(f"image 'MetalMap': its colour space {space!r} is read as" in w for w in out.warnings), out.warnings
    assert not any("image 'Shared'" in w for w in out.warnings)


def test_a_color_attribute_node_reads_its_named_layer(links):
    centres = links.vertices[links.triangles].mean(axis=1)[:, 0]
    colours = links.colors[(links.triangle_materials == links.painted) & (np.abs(centres - 1.0) < 0.6)]   # "Painted"
    assert colours.size > 0
    np.testing.assert_allclose(colours.reshape(-1, 3), np.tile([0.2, 0.6, 0.9], (colours.size // 3, 1)), rtol=1e-5)


def test_a_color_attribute_the_mesh_lacks_reads_black_with_a_warning(links):
    # It read the render layer (red) or white, where Cycles reads black; nothing was said.
    centres = links.vertices[links.triangles].mean(axis=1)[:, 0]
    for x in (5.0, 7.0):                      # Unpainted (no attribute), OtherPaint (only "Col")
        mine = (np.abs(centres - x) < 0.6) & (links.triangle_materials == links.painted)
        assert mine.sum() == 2 and np.all(links.colors[mine] == 0.0)
    for name in ("Unpainted", "OtherPaint"):
        assert (f"Object '{name}' has no colour attribute 'Paint', which its material's Color Attribute node "
                "reads: black there, as in Cycles") in links.warnings


def test_the_emission_shader_is_colour_times_strength(links):
    lamp = links.materials[links.lamp]
    np.testing.assert_allclose(lamp["emission_color"], [4.0, 2.0, 1.0], rtol=1e-6)
    assert lamp["kd"] == 0.0 and lamp["ks"] == 0.0


def test_metallic_and_alpha_textures_and_node_settings_are_read(links):
    textures, images = links.textures, links.images
    name = lambda t: images[textures[t]["image"]]["name"]
    node, render = links.materials[links.by_node], links.materials[links.by_render]
    for field in ("color_texture", "roughness_texture"):
        assert node[field] >= 0, field
    for field in ("color_texture", "metallic_texture", "alpha_texture"):
        assert render[field] >= 0, field
    assert name(node["color_texture"]) == "Shared"
    # (the image straight into the input: no map of its coordinates, no adjustment of its value)
    assert textures[node["color_texture"]] == {"image": textures[node["color_texture"]]["image"],
                                               "interpolation": "closest", "extension": "clip", "projection": "flat",
                                               "projection_blend": 0.0, "use_alpha": False,
                                               "premultiply": True,   # its Alpha output is not linked: associated
                                               "unassociate": False, "uv_transform": [1.0, 0.0, 0.0, 0.0, 1.0, 0.0], "tiles": [],
                                               "channel": -1, "gain": [1.0, 1.0, 1.0], "bias": [0.0, 0.0, 0.0],
                                               "clamp": False, "ramp_channel": -1, "ramp_gain": [1.0, 1.0, 1.0],
                                               "ramp_bias": [0.0, 0.0, 0.0], "ramp_clamp": False,
                                               "kind": "image", "coordinates": "uv",
                                               "vector_transform": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0,
                                                                    0.0, 0.0, 1.0, 0.0],
                                               "color1": [0.8, 0.8, 0.8], "color2": [0.2, 0.2, 0.2], "scale": 5.0,
                                               "gradient": "linear", "ramp": [], "ramp_interpolation": "linear",
                                               "noise_type": "fbm", "dimensions": 3, "w": 0.0, "detail": 2.0,
                                               "roughness": 0.5, "lacunarity": 2.0, "distortion": 0.0,
                                               "noise_offset": 0.0, "noise_gain": 1.0, "normalize": True,
                                               "noise_wrap": True, "voronoi_feature": "f1",
                                               "voronoi_metric": "euclidean", "voronoi_output": "distance",
                                               "exponent": 0.5, "randomness": 1.0, "smoothness": 1.0,
                                               "voronoi_pcg": True, "wave_type": "bands", "wave_direction": "x",
                                               "wave_profile": "sine", "detail_scale": 1.0, "phase": 0.0,
                                               "depth": 2, "mortar": [0.0, 0.0, 0.0],
                                               "mortar_size": 0.02, "mortar_smooth": 0.1, "brick_bias": 0.0,
                                               "brick_width": 0.5, "row_height": 0.25, "offset_amount": 0.5,
                                               "offset_frequency": 2, "squash_amount": 1.0, "squash_frequency": 2}
    assert name(node["roughness_texture"]) == "RoughHDR"
    assert not textures[node["roughness_texture"]]["premultiply"]   # float images are held associated already
    assert name(render["metallic_texture"]) == "MetalMap"
    # metallic 0: the core blends towards metal per hit; Blender 4+'s diffuse lies under the
    # specular layer (the core takes the layer's albedo seen from the viewer out of it)
    assert render["mirror"] == 0.0
    assert render["kd"] == 1.0 and render["layered_diffuse"] == (links.blender[0] >= 4)
    alpha = textures[render["alpha_texture"]]
    assert name(render["alpha_texture"]) == "Shared" and alpha["use_alpha"] and alpha["extension"] == "extend"
    colour = textures[render["color_texture"]]
    assert (colour["interpolation"], colour["extension"], colour["use_alpha"]) == ("linear", "extend", False)
    # (its Alpha comes from a second node: the node on Base Color gives associated colour, as in Cycles)
    assert colour["premultiply"]


def test_each_image_is_stored_once_and_8_bit_stays_8_bit(links):
    images = {im["name"]: im for im in links.images}
    assert sorted(images) == ["MetalMap", "RoughHDR", "Shared"]      # "Shared" serves three textures
    assert len(links.images) == 3
    assert (images["Shared"]["dtype"], images["Shared"]["colorspace"]) == ("uint8", "srgb")
    assert (images["MetalMap"]["dtype"], images["MetalMap"]["colorspace"]) == ("uint8", "data")
    assert (images["RoughHDR"]["dtype"], images["RoughHDR"]["colorspace"]) == ("float32", "linear")
    assert images["Shared"]["shape"] == [4, 4, 4] and images["Shared"]["memory_bytes"] >= 4 * 4 * 4


def test_the_memory_estimate_counts_each_image_once_plus_one_read_buffer(links):
    stored = sum(int(np.prod(im["shape"])) * (1 if im["dtype"] == "uint8" else 4) for im in links.images)
    read_buffer = max(int(np.prod(im["shape"])) * 4 for im in links.images)    # foreach_get's float32 copy
    assert links.texture_bytes == stored + read_buffer
