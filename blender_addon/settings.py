"""Scene.gridwalk (properties.py) -> gridwalk.RenderSettings.

Every property has a RenderSettings field of the same name; enum identifiers
are the field's string values in upper case ("JITTERED" -> "jittered").
"""
from __future__ import annotations

ENUM_FIELDS = ("accel", "aa", "shadow", "filter")
PLAIN_FIELDS = ("grid_density", "mailboxes", "skip_empty", "max_cells", "min_weight", "threads", "tile_size",
                "max_depth", "seed",
                "aa_samples", "adaptive_threshold", "adaptive_depth", "filter_width",
                "shadow_samples", "dof_samples", "glossy_samples")


def settings_dict(props) -> dict:
    """The property group as RenderSettings keyword arguments."""
    values = {name: getattr(props, name) for name in PLAIN_FIELDS}
    values.update({name: getattr(props, name).lower() for name in ENUM_FIELDS})
    return values


def render_settings(gridwalk, props):
    """A gridwalk.RenderSettings from the scene's properties."""
    return gridwalk.RenderSettings(**settings_dict(props))
