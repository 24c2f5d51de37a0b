"""Scene.gridwalk (properties.py) -> gridwalk.RenderSettings.

Every render property is a row of the core's settings table of the same
name; enum identifiers are the choices' ids in upper case ("JITTERED" ->
"jittered").
"""
from __future__ import annotations

from .properties import blender_settings


def settings_dict(props, schema) -> dict:
    """The property group as RenderSettings keyword arguments."""
    values = {}
    for setting in blender_settings(schema):
        value = getattr(props, setting.name)
        if setting.kind == "enum":
            value = value.lower()
        elif setting.kind == "float":
            # A FloatProperty holds a float32: its own limits, set from the table's
            # doubles, can round outside them (0.01 reads back as 0.009999999776,
            # which the core refused: every render failed at the slider's end).
            value = min(max(value, setting.min), setting.max)
        values[setting.name] = value
    return values


def render_settings(gridwalk, props):
    """A gridwalk.RenderSettings from the scene's properties."""
    return gridwalk.RenderSettings(**settings_dict(props, gridwalk.settings.SCHEMA))
