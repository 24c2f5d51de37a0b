"""The render passes GRIDWALK writes: one list, read by the engine's
update_render_passes (which passes exist) and by the result writer (what
goes into each). Names, channels and kinds are Cycles'.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

try:
    import bpy
    NEW_NAMES = bpy.app.version >= (5, 0, 0)   # Blender 5.0 renamed IndexOB / IndexMA
except ImportError:                            # (outside Blender: the tests read the table)
    NEW_NAMES = False


@dataclass(frozen=True)
class Pass:
    name: str           # Blender's pass name (Cycles' names)
    chanid: str         # one letter per channel
    kind: str           # COLOR, VALUE or VECTOR
    layer_flag: str     # the view layer's use_pass_* property, or "gridwalk.<name>" a
                        # property of scene.gridwalk; "" = always written
    source: str         # the gridwalk.RenderJob array it comes from

    @property
    def channels(self) -> int:
        return len(self.chanid)

    def values(self, arrays: dict) -> np.ndarray:
        """(h, w, channels) float32 from the job's arrays (misses: depth 1e10, as Cycles)."""
        v = arrays[self.source]
        if self.source == "depth":
            v = np.nan_to_num(v, posinf=1e10)
        return v.reshape(*v.shape[:2], self.channels)


PASSES = (
    Pass("Combined", "RGBA", "COLOR", "", "rgba"),
    Pass("Depth", "Z", "VALUE", "use_pass_z", "depth"),
    Pass("Normal", "XYZ", "VECTOR", "use_pass_normal", "normal"),
    # What the compositor's Denoise node takes, under Cycles' names.
    Pass("Denoising Albedo", "RGB", "COLOR", "gridwalk.denoising_data", "albedo"),
    Pass("Denoising Normal", "XYZ", "VECTOR", "gridwalk.denoising_data", "normal"),
    # From the matte ranks (cryptomatte.Mattes): the Pass Index of what covers most of the pixel.
    Pass("Object Index" if NEW_NAMES else "IndexOB", "X", "VALUE", "use_pass_object_index", "IndexOB"),
    Pass("Material Index" if NEW_NAMES else "IndexMA", "X", "VALUE", "use_pass_material_index", "IndexMA"),
)


def _asked(p: Pass, view_layer, scene) -> bool:
    if not p.layer_flag:
        return True
    if p.layer_flag.startswith("gridwalk."):
        props = getattr(scene, "gridwalk", None)
        return bool(getattr(props, p.layer_flag.split(".", 1)[1], False))
    return bool(getattr(view_layer, p.layer_flag, False))


def enabled(view_layer, scene=None) -> list[Pass]:
    """The passes this view layer (and the scene's Gridwalk settings) ask for (Combined always)."""
    return [p for p in PASSES if _asked(p, view_layer, scene)]


# The view layer's other passes (use_pass_* -> Cycles' name): GRIDWALK does not
# write them, and an enabled one is named in a warning (a compositor fed from
# it would get nothing without a word).
UNWRITTEN = {
    "use_pass_mist": "Mist", "use_pass_position": "Position", "use_pass_vector": "Vector", "use_pass_uv": "UV",
    "use_pass_diffuse_direct": "Diffuse Direct", "use_pass_diffuse_indirect": "Diffuse Indirect",
    "use_pass_diffuse_color": "Diffuse Color", "use_pass_glossy_direct": "Glossy Direct",
    "use_pass_glossy_indirect": "Glossy Indirect", "use_pass_glossy_color": "Glossy Color",
    "use_pass_transmission_direct": "Transmission Direct", "use_pass_transmission_indirect": "Transmission Indirect",
    "use_pass_transmission_color": "Transmission Color", "use_pass_emit": "Emission",
    "use_pass_environment": "Environment", "use_pass_ambient_occlusion": "Ambient Occlusion",
    "use_pass_shadow": "Shadow",
}


def unwritten_passes(view_layer) -> list[str]:
    """The passes enabled on `view_layer` that GRIDWALK leaves out: the
    built-in ones, Shader AOVs and light groups (each a pass of its own in
    Cycles)."""
    out = [name for flag, name in UNWRITTEN.items() if getattr(view_layer, flag, False) is True]
    out += [f"Shader AOV '{aov.name}'" for aov in getattr(view_layer, "aovs", ())]
    out += [f"Light Group '{group.name}'" for group in getattr(view_layer, "lightgroups", ())]
    return out

