"""Gridwalk: a grid-accelerated (Amanatides & Woo) Whitted and distribution
ray tracer. The native core is private (gridwalk._core); this package is the API.
"""
from .image import Image
from .model import Camera, Light, Material, Texture, World
from .progressive import ProgressiveRenderer
from .render import RenderJob, TileResult, render
from .renderfarm import FarmError, farm
from .scene import BuildCancelled, Hits, InstanceMove, Scene
from .settings import RenderSettings

__all__ = ["Camera", "Light", "Material", "Image", "Texture", "World", "Scene", "InstanceMove", "Hits", "RenderSettings", "RenderJob", "TileResult", "render",
           "BuildCancelled", "farm", "FarmError", "ProgressiveRenderer"]
__version__ = "0.1.0"
