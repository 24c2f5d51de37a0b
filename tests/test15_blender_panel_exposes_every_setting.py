"""Every gridwalk.RenderSettings field is a Blender property, mapped and drawn
(region is the exception: it comes from Blender's render border)."""
import dataclasses
import importlib.util
import re
from pathlib import Path

import gridwalk as gw

ADDON = Path(__file__).resolve().parents[1] / "blender_addon"
FROM_BLENDER = {"region"}


def addon_settings_module():
    spec = importlib.util.spec_from_file_location("gw_addon_settings", ADDON / "settings.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_every_render_setting_is_mapped_declared_and_drawn():
    fields = {f.name for f in dataclasses.fields(gw.RenderSettings)} - FROM_BLENDER
    mod = addon_settings_module()
    mapped = set(mod.ENUM_FIELDS) | set(mod.PLAIN_FIELDS)
    assert mapped == fields, (fields - mapped, mapped - fields)
    declared = set(re.findall(r"^\s+(\w+): \w+Property\(", (ADDON / "properties.py").read_text(), re.M))
    assert fields <= declared, fields - declared
    drawn = set(re.findall(r'\.prop\(props, "(\w+)"', (ADDON / "ui.py").read_text()))
    assert fields <= drawn, fields - drawn



def test_every_property_bound_is_accepted_by_the_core():
    """A slider pushed to either end must never produce settings the core refuses."""
    mod = addon_settings_module()
    text = (ADDON / "properties.py").read_text()
    checked = 0
    for name in mod.PLAIN_FIELDS:
        decl = re.search(rf"^\s+{name}: (\w+)Property\((.*?)\)\n(?=\s+\w+:|\n|\Z)", text, re.M | re.S)
        assert decl, name
        for bound in ("min", "max"):
            m = re.search(rf"\b{bound}=([-0-9.e*]+)", decl.group(2))
            if not m:
                continue
            value = eval(m.group(1), {})   # literals such as 2**31 - 1 written as 2**31
            value = int(value) if decl.group(1) == "Int" else float(value)
            gw.RenderSettings(**{name: value}).to_core()
            checked += 1
    assert checked >= 15
