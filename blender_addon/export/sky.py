"""A world's Sky Texture node -> the environment image gridwalk.sky bakes, as Cycles renders it.

Read: Blender 3.x-4.x's Nishita type, 5.0's Single and Multiple Scattering
types, with every setting (Sun Disc, Sun Size, Sun Intensity, Sun Elevation,
Sun Rotation, Altitude, Air, Dust or Aerosol, Ozone), evaluated with the rules
of the Blender that runs the export (gridwalk.sky), and the Preetham type (Sun
Direction, Turbidity). The image is 2048 x 1024
(0.18 degrees a texel: the default sun spans three texels, its light exact);
each distinct setting is baked once (0.3-0.6 s on 2 cores) and kept in the viewport's image
cache, and the last four settings in this module (an animation's frames bake once).
A sun under 8 texels across also gets an inset (World.inset: gridwalk.sky.sky_inset),
its disc 48 texels across, which rays that see the sky directly read: the disc
is Cycles' crisp one, with its limb darkening, where the image alone blurs it
into a square of three texels.
Not read: the Hosek / Wilkie type (an analytic sky fitted to tables of
simulations), which falls back to the world's viewport colour with a warning.
"""
from __future__ import annotations

import zlib

from gridwalk.sky import sky_environment

MODELS = {"NISHITA": "single", "SINGLE_SCATTERING": "single", "MULTIPLE_SCATTERING": "multiple",
          "PREETHAM": "preetham"}
WIDTH = 2048


def _settings(node) -> dict:
    if node.sky_type == "PREETHAM":
        return dict(sun_direction=tuple(float(v) for v in node.sun_direction), turbidity=float(node.turbidity))
    dust = node.aerosol_density if hasattr(node, "aerosol_density") else node.dust_density
    return dict(sun_elevation=float(node.sun_elevation), sun_rotation=float(node.sun_rotation),
                sun_disc=bool(node.sun_disc), sun_size=float(node.sun_size), sun_intensity=float(node.sun_intensity),
                altitude=float(node.altitude), air_density=float(node.air_density), dust_density=float(dust),
                ozone_density=float(node.ozone_density))


_RECENT: dict = {}     # key -> (image, inset) of the last few bakes (a final render's export starts a new cache)
_RECENT_SIZE = 4


def _bake(key, model: str, version: tuple, settings: dict):
    if key not in _RECENT:
        while len(_RECENT) >= _RECENT_SIZE:
            del _RECENT[next(iter(_RECENT))]
        _RECENT[key] = sky_environment(model, blender_version=version, width=WIDTH, **settings)
    return _RECENT[key]


def sky_world(node, textures) -> tuple[dict | None, str | None]:
    """(gridwalk.World fields of the sky: its environment texture in `textures`, and the
    inset showing its sun in detail; None), or (None, why it is not read)."""
    import bpy
    model = MODELS.get(node.sky_type)
    if model is None:
        return None, f"the Sky Texture's {node.sky_type.replace('_', ' ').title()} type is not supported"
    version = tuple(bpy.app.version[:2])
    settings = _settings(node)
    key = ("sky", model, version, WIDTH, tuple(sorted(settings.items())))
    # (the names tell the settings apart: the viewport's scene signature reads image names)
    name = f"Sky Texture {node.name!r} {zlib.crc32(repr(key).encode()):08x}"
    try:
        image, inset = _bake(key, model, version, settings)
    except ValueError as exc:                  # (NaN or infinite settings, set from a script)
        return None, f"the Sky Texture {node.name!r} cannot be computed ({exc})"
    fields = dict(environment=textures.generated(key, lambda: image, name))
    if inset is not None:
        pixels, frame, extent = inset
        fields.update(inset=textures.generated(key + ("inset",), lambda: pixels, name + " (sun)"),
                      inset_frame=frame, inset_extent=extent)
    return fields, None
