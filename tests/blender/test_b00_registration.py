"""The add-on registers its engine, properties and panels, and unregisters cleanly."""
import json

from runner import run_script


def test_register_and_unregister(any_blender, tmp_path):
    run_script(any_blender, "registration.py", tmp_path)
    info = json.loads((tmp_path / "registration.json").read_text())
    assert info["engine"] == "GRIDWALK"
    panels = set(info["panels"])
    ours = {"GRIDWALK_RENDER_PT_sampling", "GRIDWALK_RENDER_PT_acceleration",
            "GRIDWALK_OBJECT_PT_settings", "GRIDWALK_LIGHT_PT_light"}
    assert ours <= panels
    # Blender's own camera, material, world and output panels show for GRIDWALK
    assert {"DATA_PT_lens", "DATA_PT_camera_dof", "EEVEE_MATERIAL_PT_surface",
            "EEVEE_WORLD_PT_surface", "RENDER_PT_format"} <= panels
    assert info["object_option"]
    assert info["settings"]["accel"] == "grid" and info["settings"]["aa"] == "jittered"
    # unregister leaves nothing behind
    assert info["panels_after"] == [] and not info["engine_after"]
    assert not info["scene_property_after"]
