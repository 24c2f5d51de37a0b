"""Materials (Principled BSDF across Blender versions, per-triangle slots) and the world."""
import re

import numpy as np
import pytest


def test_principled_inputs_map_to_the_whitted_model(export):
    out = export("materials")
    mats = out.materials
    red, glass = mats[1], mats[2]
    np.testing.assert_allclose(red["color"], [0.8, 0.1, 0.1], rtol=1e-5)
    assert red["mirror"] == pytest.approx(0.25)
    # the dielectric's specular layer reflects the scene; from Blender 4 the diffuse lies under
    # it (the core takes the layer's albedo seen from the viewer out of kd, as Cycles does)
    assert red["kd"] == pytest.approx(0.75, rel=1e-5)
    assert red["dielectric_reflection"] and red["layered_diffuse"] == (out.blender[0] >= 4)
    assert glass["layered_diffuse"] == (out.blender[0] >= 4)
    assert red["roughness"] == pytest.approx(0.3)
    assert glass["transmittance"] == pytest.approx(1.0)
    # Blender 4's default distribution, Multiscatter GGX, for the glass too (GGX in 3.4)
    assert red["multiscatter"] == glass["multiscatter"] == (out.blender[0] >= 4)
    assert glass["ior"] == pytest.approx(1.33, rel=1e-5)
    assert glass["kd"] == pytest.approx(0.0)


def test_material_per_triangle_follows_the_slots(export):
    out = export("materials")
    # each quad face gives two triangles; slot i -> material i + 1 (0 is the default)
    per_face = out.triangle_materials.reshape(6, 2)
    assert np.all(per_face[:, 0] == per_face[:, 1])
    assert sorted(per_face[:, 0]) == sorted(s + 1 for s in out.expected["face_slots"])


def test_unsupported_shaders_fall_back_with_one_warning(export):
    out = export("materials")
    np.testing.assert_allclose(out.materials[3]["color"], [0.1, 0.7, 0.2], rtol=1e-5)
    mentions = [w for w in out.warnings if "Toon" in w or "Holdout" in w]
    assert len(mentions) == 1 and "Toon" in mentions[0] and "Holdout" not in mentions[0]
    assert sum(bool(m.get("holdout")) for m in out.materials) == 1   # a Holdout shader is a holdout (test_b45)


def test_world_colour_times_strength_is_the_background(export):
    out = export("materials")
    np.testing.assert_allclose(out.background, [0.1, 0.15, 0.2], rtol=1e-5)
    np.testing.assert_allclose(out.world["ambient"], [0.1, 0.15, 0.2], rtol=1e-5)   # and the ambient light


def test_a_world_invisible_to_diffuse_rays_lights_nothing_but_is_still_seen(export):
    out = export("materials", world_lights_diffuse=False)
    np.testing.assert_allclose(out.background, [0.1, 0.15, 0.2], rtol=1e-5)
    assert list(out.world["ambient"]) == [0.0, 0.0, 0.0]


def test_the_cycles_output_and_muted_nodes_and_links_are_honoured(export):
    out = export("node_states")
    centres = out.vertices[out.triangles].mean(axis=1)[:, 0]
    by_plane = [out.materials[int(out.triangle_materials[np.argmin(np.abs(centres - x))])]
                for x in (-4.0, -2.0, 0.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0)]
    targets, muted_node, muted_link, muted_mix, constants, reroute_muted, reroute_loop, unlinked, no_output = by_plane
    np.testing.assert_allclose(targets["color"], [0.8, 0.0, 0.0], rtol=1e-5)   # not the active EEVEE output's green
    for mat in (muted_node, muted_link):          # Base Color's own value, no texture
        np.testing.assert_allclose(mat["color"], [0.1, 0.1, 0.8], rtol=1e-5)
        assert mat["color_texture"] < 0
    # a muted Mix node passing its unlinked A: Cycles reads 0, not A's red nor Base Color's blue
    np.testing.assert_allclose(muted_mix["color"], [0.0, 0.0, 0.0], atol=1e-7)
    # the same through a reroute from a muted Image Texture, and from a reroute loop (which hung the export)
    for mat in (reroute_muted, reroute_loop):
        np.testing.assert_allclose(mat["color"], [0.0, 0.0, 0.0], atol=1e-7)
        assert mat["color_texture"] < 0
    # no surface shader (the output's Surface unlinked, or no output): black, as Cycles renders it, and said so
    for mat, name in ((unlinked, "NoSurfaceLink"), (no_output, "NoOutput")):
        assert list(mat["color"]) == [0.0, 0.0, 0.0] and mat["kd"] == 0 and mat["ks"] == 0, mat
        assert any(name in w and "black" in w for w in out.warnings), out.warnings
    # RGB nodes are constants: Base Color takes the colour, Roughness a colour's Rec. 709 luminance
    np.testing.assert_allclose(constants["color"], [0.2, 0.7, 0.3], rtol=1e-5)
    assert constants["roughness"] == pytest.approx(0.2126 * 0.5 + 0.7152 * 0.25 + 0.0722 * 1.0, rel=1e-5)
    # the world: through a reroute, its Color's muted link (own value) and Strength through a muted Math node
    np.testing.assert_allclose(out.background, [0.4, 0.6, 0.8], rtol=1e-5)
    np.testing.assert_allclose(out.world["ambient"], [0.4, 0.6, 0.8], rtol=1e-5)
    assert not any("World" in w for w in out.warnings)
    assert not any("default value" in w for w in out.warnings)
    # a UV Map node naming a layer the mesh lacks: the render layer is read, and said so
    assert ("Object 'MissingMap' has no UV map 'Missing', which its material's UV Map node names: its render "
            "UV map is used instead (Cycles reads UV (0, 0) there)") in out.warnings


def test_settings_the_export_cannot_read_are_named_and_a_nan_uv_does_not_stop_it(export):
    out = export("unread_settings")
    assert "error" not in out.info, out.info.get("error")
    said = "\n".join(out.warnings)
    # (a Box-projected image is read: test_b50)
    assert "image projection" not in said and any(t["projection"] == "box" for t in out.textures)
    assert "TwoMaps" not in said                  # each material its own UV map, below
    assert "Object 'NanUV': 2 triangle corners have a non-finite UV or colour (NaN or Inf), read as 0" in said
    assert "World 'Hidden': Ray Visibility > Camera off is not supported" in said
    assert re.search(r"Layers: (Coat Weight|Clearcoat) 0\.5, (Sheen Weight|Sheen) 1 not modelled \(rendered as if unset\)",
                     said), said
    # Specular Tint (4.x a colour, 3.x a float), Anisotropic, a negative Emission Strength (the core takes
    # no negative light: it gave a grey surface where Cycles' is black) and a Diffuse BSDF's Roughness
    assert re.search(r"Tinted: Specular Tint (\(1, 0\.2, 0\.2\)|0\.5), Anisotropic 0\.9, Emission Strength -2 not "
                     r"modelled \(rendered as if unset\)", said), said
    assert "RoughDiffuse: Roughness 0.6 not modelled (rendered as if unset)" in said
    # bump, normal maps and displacement were ignored without a word (a Bump of a Noise is read: test_b39;
    # of a Sky Texture, which the core does not read in a material, it is not)
    assert ("Bumpy: Normal (ShaderNodeBump) not read: the surface is shaded with the mesh's own normals" in said), said
    assert "Displaced: Displacement (ShaderNodeDisplacement) not read" in said
    # a tangent-space normal map is read (test_b18); other spaces are named
    assert "ObjectSpace: Normal (ShaderNodeNormalMap) not read" in said
    # an unlinked Color: the flat one changes nothing, so nothing is said; another is named
    assert "FlatNormalMap" not in said
    assert "TiltedNormalMap: Normal (ShaderNodeNormalMap) not read" in said
    assert np.isfinite(out.uvs).all()
    # TwoMaps (the grid at the origin, faces alternating between two materials):
    # the material naming 'UVMap' gets [0, 1], the one naming 'Second' [0.25, 0.75]
    centre = out.vertices[out.triangles].mean(axis=1)
    mine = np.abs(centre).max(axis=1) < 0.6
    ranges = sorted((float(out.uvs[mine & (out.triangle_materials == m)].min()),
                     float(out.uvs[mine & (out.triangle_materials == m)].max()))
                    for m in np.unique(out.triangle_materials[mine]))
    np.testing.assert_allclose(ranges, [(0.0, 1.0), (0.25, 0.75)], atol=1e-6)


def test_the_view_layers_material_override_replaces_every_material(export):
    out = export("unread_settings", override=True)
    used = np.unique(out.triangle_materials)
    assert len(used) == 1                                        # every triangle, every object
    np.testing.assert_allclose(out.materials[int(used[0])]["color"], [0.3, 0.3, 0.3], rtol=1e-5)


def test_a_mix_with_a_transparent_bsdf_is_an_alpha_cut_out(export):
    out = export("mix_shaders")
    centres = out.vertices[out.triangles].mean(axis=1)[:, 0]
    mats = [out.materials[int(out.triangle_materials[np.argmin(np.abs(centres - (2.0 * i - 5.0)))])]
            for i in range(7)]
    clear_first, clear_second, linked_second, tinted, own_alpha, two_shaders, from_math = mats
    assert clear_first["alpha"] == pytest.approx(0.3) and clear_second["alpha"] == pytest.approx(0.7)
    for mat in (clear_first, clear_second, linked_second, tinted, own_alpha):
        np.testing.assert_allclose(mat["color"], [0.2, 0.4, 0.6], rtol=1e-5)     # the Principled BSDF's
        assert mat["alpha_texture"] < 0
    assert linked_second["alpha"] == pytest.approx(0.7)        # 1 - Fac's own value (a texture would need 1 - it)
    assert tinted["alpha"] == pytest.approx(0.3)
    assert own_alpha["alpha"] == pytest.approx(0.5)            # the Principled BSDF's own Alpha
    assert from_math["alpha"] == pytest.approx(0.3)            # Fac's own value, as the warning says (was 0)
    said = "\n".join(out.warnings)
    assert "LinkedFacSecond: inputs Fac (ShaderNodeMixShader: a linked Fac with the Transparent BSDF second)" in said
    assert "Tinted: inputs Color (ShaderNodeBsdfTransparent: a tinted Transparent BSDF is read as clear)" in said
    assert "OwnAlpha: inputs Fac (ShaderNodeMixShader: the shader's own Alpha is kept, the mix is not read)" in said
    assert ("TwoShaders: unsupported shader ShaderNodeMixShader (the mixes read: a Transparent BSDF with one "
            "shader, a Diffuse BSDF with a Glossy BSDF or an Emission, by a constant Fac or a Diffuse and a Glossy "
            "BSDF by Fresnel): its viewport colour is used") in said
    assert re.search(r"FacFromMath: inputs Fac(tor)? \(ShaderNodeMath\) use their default values", said)  # (5.0: Factor)
    assert "ClearFirst" not in said and "ClearSecond" not in said


def _srgb_decode(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def _sphere_mean(rgb):
    """Mean of an equirectangular image's (h, w, 3) pixels over the sphere (cos latitude weights)."""
    rows = rgb.shape[0]
    weight = np.cos((np.arange(rows) + 0.5) / rows * np.pi - np.pi / 2)[:, None, None]
    return (rgb * weight).sum(axis=(0, 1)) / (weight.sum() * rgb.shape[1])


@pytest.mark.parametrize("parametrization", ["COLOR", "MELANIN", "ABSORPTION"])
def test_a_principled_hair_bsdf_gives_its_fibre_colour(export, parametrization):
    """Hair curves with a Principled Hair BSDF: the fibre colour its inputs give
    (Chiang et al. 2016: colour = exp(-sqrt(sigma_a) f(radial roughness))). It
    was the material's viewport colour, with a warning."""
    out = export("hair", material=parametrization)
    if out.expected["segments"] is None:
        pytest.skip(f"Blender {out.blender} has no Python API to add hair curves")
    colour = np.asarray(out.materials[int(out.cylinder_materials[0])]["color"])
    assert not [w for w in out.warnings if "Hair" in w]
    if parametrization == "COLOR":                                   # Direct Coloring: the Color itself
        np.testing.assert_allclose(colour, [0.6, 0.25, 0.05], rtol=1e-5)
        return
    if parametrization == "ABSORPTION":                              # sigma_a (0.2, 0.6, 1.5), beta 0.3
        b = 0.3
        f = 5.969 - 0.215 * b + 2.532 * b ** 2 - 10.73 * b ** 3 + 5.574 * b ** 4 + 0.245 * b ** 5
        np.testing.assert_allclose(colour, np.exp(-np.sqrt([0.2, 0.6, 1.5]) * f), rtol=1e-4)
        return
    assert 0.5 > colour[0] > colour[1] > colour[2] > 0                # Melanin 0.5, Redness 0.4: a brown


def test_an_8_bit_environment_with_alpha_lights_with_the_colour_it_shows(export):
    """Cycles' Environment Texture gives associated colour (it has no Alpha
    output): the background is premultiplied per texel (in bytes, then
    decoded), so the world's colour is that colour's mean over the sphere; it was
    the straight colour's mean, as bright as an opaque image's. The light it
    gives surfaces comes from the same premultiplied texels (the core's
    environment_light: test46)."""
    opaque = export("environment", eight_bit_alpha=1.0).background
    out = export("environment", eight_bit_alpha=0.25)
    assert [t["premultiply"] for t in out.textures] == [True]
    assert out.world["environment_light"] and out.world["environment"] == 0 and out.world["ambient"] == [0, 0, 0]
    px = out.image_0.astype(np.int64)                        # (h, w, 4) bytes
    assert out.images[0]["dtype"] == "uint8" and (px[:, :, 3] == 64).mean() == 0.5
    straight = _sphere_mean(_srgb_decode(px[..., :3] / 255.0))
    associated = _sphere_mean(_srgb_decode((px[..., :3] * px[..., 3:] // 255) / 255.0))
    np.testing.assert_allclose(opaque, straight, rtol=2e-3)
    np.testing.assert_allclose(out.background, associated, rtol=2e-3)
    assert np.all(associated < 0.9 * straight)


def test_a_material_without_nodes_is_a_diffuse_of_its_viewport_colour(export):
    # (Cycles renders it as a Diffuse BSDF of the viewport colour; its viewport Metallic and
    # Roughness made it a dark metal here before: 0.53x Cycles' brightness, found by a review probe)
    out = export("nodeless_material")
    if out.expected["use_nodes"]:
        pytest.skip("this Blender gives every material nodes")
    (mat,) = [m for m in out.materials if np.allclose(m["color"], [0.2, 0.4, 0.6], rtol=1e-6)]
    assert mat["kd"] == 1.0 and mat["ks"] == 0.0 and mat["metallic"] == 0.0 and mat["mirror"] == 0.0
    assert not any("NoNodes" in w for w in out.warnings), out.warnings


def test_a_volume_that_geometry_nodes_make_is_named_as_such(export):
    # (it read "Volume objects are not rendered: 'Smoky'", as if the cube were not rendered)
    out = export("volume_output")
    assert "error" not in out.info, out.info.get("error")
    assert any("Volumes that Geometry Nodes make (the rest of each object renders) are not rendered: 'Smoky'" in w
               for w in out.warnings), out.warnings
    assert not any(w.startswith("Volume objects are") for w in out.warnings)
    assert len(out.triangles) == 12                     # (the cube itself renders)
