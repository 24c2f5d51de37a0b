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
        values[setting.name] = value.lower() if setting.kind == "enum" else value
    return values


def render_settings(gridwalk, props):
    """A gridwalk.RenderSettings from the scene's properties."""
    return gridwalk.RenderSettings(**settings_dict(props, gridwalk.settings.SCHEMA))
