"""Materials (Principled BSDF across Blender versions, per-triangle slots) and the world."""
import numpy as np
import pytest


def test_principled_inputs_map_to_the_whitted_model(export):
    out = export("materials")
    mats = out.materials
    red, glass = mats[1], mats[2]
    np.testing.assert_allclose(red["color"], [0.8, 0.1, 0.1], rtol=1e-5)
    assert red["mirror"] == pytest.approx(0.25)
    assert red["kd"] == pytest.approx(0.75)
    assert red["roughness"] == pytest.approx(0.3)
    assert glass["transmittance"] == pytest.approx(1.0)
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
    assert len(mentions) == 1 and "Toon" in mentions[0] and "Holdout" in mentions[0]


def test_world_colour_times_strength_is_the_background(export):
    out = export("materials")
    np.testing.assert_allclose(out.background, [0.1, 0.15, 0.2], rtol=1e-5)
    np.testing.assert_allclose(out.world["ambient"], [0.1, 0.15, 0.2], rtol=1e-5)   # and the ambient light


def test_a_world_invisible_to_diffuse_rays_lights_nothing_but_is_still_seen(export):
    out = export("materials", world_lights_diffuse=False)
    np.testing.assert_allclose(out.background, [0.1, 0.15, 0.2], rtol=1e-5)
    assert list(out.world["ambient"]) == [0.0, 0.0, 0.0]
