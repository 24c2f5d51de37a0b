"""The render passes GRIDWALK writes: one list, read by the engine's
update_render_passes (which passes exist) and by the result writer (what
goes into each). Names, channels and kinds are Cycles'.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


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
