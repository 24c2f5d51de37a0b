"""Scene file input: NFF and PLY files to keyword arguments for `gridwalk.Scene`.

    kwargs = gridwalk.io.load_scene("balls_s4.nff")
    scene = gridwalk.Scene(**kwargs)

Every loader returns a dict with exactly the `Scene` keywords: vertices,
triangles, normals, triangle_materials, sphere_centers, sphere_radii,
sphere_materials, cylinder_base, cylinder_apex, cylinder_base_radius,
cylinder_apex_radius, cylinder_materials (float32 / int32 arrays, empty when
a file has none of a kind; normals may be None), materials, lights, camera,
background. Malformed files raise SceneFileError (a ValueError).
"""
from pathlib import Path

from .common import SceneFileError
from .nff import load_nff, nff_resized, read_nff
from .ply import default_view, load_ply, load_ply_mesh

__all__ = ["SceneFileError", "load_nff", "read_nff", "load_ply", "load_ply_mesh", "load_scene",
           "default_view"]

_LOADERS = {".nff": load_nff, ".ply": load_ply}


def load_scene(path, width: int | None = None, height: int | None = None) -> dict:
    """Load an .nff or .ply file (chosen by extension, case-insensitive);
    width / height, where given, replace the image size of its camera (an
    NFF view's `angle` spans the centres of the outer pixel rows of the image
    rendered, so its field of view follows the new height: nff_resized)."""
    suffix = Path(path).suffix.lower()
    if suffix not in _LOADERS:
        raise SceneFileError(f"{path}: unknown scene file type {suffix!r}; expected .nff or .ply")
    kwargs = _LOADERS[suffix](path)
    if width is not None or height is not None:
        cam = kwargs["camera"]
        size = dict(width=cam.width if width is None else int(width), height=cam.height if height is None else int(height))
        kwargs["camera"] = nff_resized(cam, **size) if suffix == ".nff" else cam.resized(**size)
    return kwargs
