"""The add-on registers its engine, properties and panels, and unregisters
cleanly; its render properties are exactly the core's settings table."""
import json
import math

import pytest

from gridwalk.settings import SCHEMA
from runner import run_script

INT_MAX = 2**31 - 1


@pytest.fixture
def registration(any_blender, tmp_path):
    run_script(any_blender, "registration.py", tmp_path)
    return json.loads((tmp_path / "registration.json").read_text())


def test_register_and_unregister(registration):
    info = registration
    assert info["engine"] == "GRIDWALK"
    panels = set(info["panels"])
    ours = {"GRIDWALK_RENDER_PT_sampling", "GRIDWALK_RENDER_PT_acceleration",
            "GRIDWALK_OBJECT_PT_settings", "GRIDWALK_LIGHT_PT_light"}
    assert ours <= panels
    # Blender's own camera, material, world and output panels show for GRIDWALK
    assert {"DATA_PT_lens", "DATA_PT_camera_dof", "EEVEE_MATERIAL_PT_surface",
            "EEVEE_WORLD_PT_surface", "RENDER_PT_format"} <= panels
    assert info["object_option"]
    # unregister leaves nothing behind
    assert info["panels_after"] == [] and not info["engine_after"]
    assert not info["scene_property_after"]


def test_every_setting_is_a_blender_property_with_the_tables_default_and_limits(registration):
    props, settings = registration["properties"], registration["settings"]
    for s in SCHEMA:
        if s.group == "host":                     # region comes from the render border
            assert s.name not in props
            continue
        p = props[s.name]
        default = s.host_default if s.host_default is not None else s.default
        if s.host_default is not None:
            assert s.host_default_reason, s.name  # a different default says why
        assert p["label"] == s.label and s.help in p["description"], s.name
        if s.kind == "enum":
            assert p["items"] == [c.upper() for c in s.ids] and p["default"] == default.upper(), s.name
        elif s.kind == "bool":
            assert p["default"] is default, s.name
        else:
            assert p["default"] == pytest.approx(default, rel=1e-6), s.name
            assert p["min"] == pytest.approx(s.min, rel=1e-6), s.name
            high = min(s.max, INT_MAX) if s.kind == "int" else s.max
            if math.isfinite(high):
                assert p["max"] == pytest.approx(high, rel=1e-6), s.name
        # the settings the add-on hands the core are the property values
        assert settings[s.name] == pytest.approx(default) if s.kind in ("int", "float") \
            else settings[s.name] == default, s.name


def test_every_number_validates_at_both_ends_of_its_slider(registration):
    # Grid Density at its minimum read back as 0.009999999776 (a float32) and every render failed.
    assert registration["slider_ends_refused"] == []


def test_every_settings_group_has_a_panel(registration):
    shown = {g for groups in registration["panel_groups"].values() for g in groups}
    assert shown == {s.group for s in SCHEMA} - {"host"}


def test_the_panorama_cast_shadow_and_ray_visibility_settings_are_drawn(any_blender, tmp_path):
    # Blender's Lens panel draws a panoramic camera's type and settings for Cycles only;
    # Cast Shadow, which the export reads, was not drawn either. Every panorama type
    # this Blender has is drawn with the settings the export reads for it.
    run_script(any_blender, "panels_draw.py", tmp_path)
    info = json.loads((tmp_path / "panels.json").read_text())
    props = lambda drawn: [item["prop"] for item in drawn if "prop" in item]
    kinds = {key.split()[1] for key in info if key.startswith("panorama ")}
    assert {"EQUIRECTANGULAR", "FISHEYE_EQUIDISTANT", "FISHEYE_EQUISOLID", "FISHEYE_LENS_POLYNOMIAL",
            "MIRRORBALL", "EQUIANGULAR_CUBEMAP_FACE"} <= kinds
    for kind in kinds:
        panel = info[f"panorama {kind}"]
        assert panel["poll"] and props(panel["drawn"])[0] == "panorama_type"
        assert all(item["real"] for item in panel["drawn"] if "prop" in item), panel
        assert not any("label" in item for item in panel["drawn"]), panel      # (no "not rendered" notice)
    assert props(info["panorama EQUIRECTANGULAR"]["drawn"]) == [
        "panorama_type", "latitude_min", "latitude_max", "longitude_min", "longitude_max"]
    assert props(info["panorama FISHEYE_EQUISOLID"]["drawn"]) == ["panorama_type", "fisheye_lens", "fisheye_fov"]
    assert props(info["panorama FISHEYE_LENS_POLYNOMIAL"]["drawn"]) == [
        "panorama_type", "fisheye_fov"] + [f"fisheye_polynomial_k{i}" for i in range(5)]
    assert not info["perspective poll"]
    for kind in ("POINT", "SPOT", "SUN", "AREA"):
        drawn = info[f"light {kind}"]
        assert "use_shadow" in props(drawn) and all(item["real"] for item in drawn if "prop" in item), drawn
    # Blender's Visibility panel draws Ray Visibility and Shadow Catcher for Cycles and EEVEE only;
    # the export reads them (test_b46, test_b49)
    drawn = info["object"]
    assert props(drawn) == ["render_as_sphere", "visible_camera", "visible_glossy", "visible_transmission",
                            "visible_shadow", "is_shadow_catcher"]
    assert all(item["real"] for item in drawn), drawn
