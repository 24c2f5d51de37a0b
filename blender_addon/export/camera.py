"""The scene camera -> gridwalk.model.Camera.

Field of view. Blender's sensor fit picks which image side the sensor size
spans: HORIZONTAL (sensor_width spans the width), VERTICAL (sensor_height spans
the height), AUTO (sensor_width spans the larger side). Our Camera wants the
VERTICAL field of view in degrees:
    side = h if the sensor spans the height, else w
    fov_vertical = 2 * atan(sensor / (2 * lens) * h / side)

Shift. Blender measures shift_x/shift_y in units of the fitted side (width for
horizontal fit, height for vertical fit); our Camera measures it in units of
the larger side, so shift = blender_shift * side / max(w, h).

Depth of field (when enabled). The thin-lens aperture radius in scene units is
    aperture = (lens [mm] / 1000) / (2 * f-stop) / unit_scale
(unit_scale = scene length unit scale, metres per Blender unit). The focus
distance is the focus object's distance along the view axis, or the camera's
focus_distance.
"""
from __future__ import annotations

import math

import numpy as np

from gridwalk.model import Camera

from ._matrix import axis, to_numpy, unit


class CameraError(ValueError):
    """The scene cannot be viewed (no camera, unsupported projection)."""


def resolution(render) -> tuple[int, int]:
    """Image size in pixels, computed as Blender does (BKE_render_resolution, integers)."""
    pct = render.resolution_percentage
    return max(1, render.resolution_x * pct // 100), max(1, render.resolution_y * pct // 100)


def render_region(render) -> tuple[int, int, int, int] | None:
    """Blender's render border as (x, y, w, h) pixels, row 0 at the top, or None.

    Blender truncates border * size in float32 (render_init_from_main), so do
    we: the region is exactly the rectangle of the render result Blender
    allocates for a border render. None when the border is off or covers the
    whole frame.
    """
    if not render.use_border:
        return None
    width, height = resolution(render)
    f32 = np.float32
    x0, x1 = (int(f32(v) * f32(width)) for v in (render.border_min_x, render.border_max_x))
    y0, y1 = (int(f32(v) * f32(height)) for v in (render.border_min_y, render.border_max_y))
    x0, x1 = max(0, min(x0, width)), max(0, min(x1, width))
    y0, y1 = max(0, min(y0, height)), max(0, min(y1, height))
    if (x0, y0, x1, y1) == (0, 0, width, height):
        return None
    if x1 <= x0 or y1 <= y0:
        raise CameraError(f"The render region is empty ({x1 - x0} x {y1 - y0} pixels): "
                          "draw a larger border or turn Render Region off")
    return x0, height - y1, x1 - x0, y1 - y0


def vertical_fov_and_side(cam, width: int, height: int) -> tuple[float, float]:
    """(vertical fov in degrees, length in pixels of the side the sensor spans)."""
    fit = cam.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if width >= height else "VERTICAL"
        sensor = cam.sensor_width
    elif fit == "HORIZONTAL":
        sensor = cam.sensor_width
    else:
        sensor = cam.sensor_height
    side = float(width if fit == "HORIZONTAL" else height)
    half_tan = sensor / (2.0 * cam.lens) * height / side
    return math.degrees(2.0 * math.atan(half_tan)), side


def _focus_distance(cam, eye, forward) -> float | None:
    dof = cam.dof
    target = dof.focus_object
    if target is not None:
        position = np.array(tuple(target.matrix_world.translation), dtype=np.float64)
        distance = float(np.dot(position - eye, forward))
        return max(distance, 1e-6)
    return max(float(dof.focus_distance), 1e-6)


def convert_camera(cam_obj, render, unit_scale: float = 1.0) -> Camera:
    """The camera object `cam_obj` (evaluated) for the render settings `render`."""
    if cam_obj is None:
        raise CameraError("The scene has no active camera: add a camera and make it active "
                          "(Scene properties > Camera)")
    if cam_obj.type != "CAMERA":
        raise CameraError(f"The active camera {cam_obj.name!r} is not a camera object")
    cam = cam_obj.data
    if cam.type != "PERSP":
        raise CameraError(f"Camera {cam_obj.name!r} uses a {cam.type} projection; "
                          "Gridwalk supports perspective cameras only")
    width, height = resolution(render)
    m = to_numpy(cam_obj.matrix_world)
    if not np.isfinite(m).all():
        raise CameraError(f"Camera {cam_obj.name!r} has a non-finite transform (NaN or Inf)")
    eye = m[:3, 3].copy()
    forward = unit(-axis(m, 2))
    up = unit(axis(m, 1))
    fov, side = vertical_fov_and_side(cam, width, height)
    larger = float(max(width, height))
    shift = (cam.shift_x * side / larger, cam.shift_y * side / larger)
    aperture, focus = 0.0, None
    if cam.dof.use_dof:
        aperture = (cam.lens / 1000.0) / (2.0 * max(cam.dof.aperture_fstop, 1e-6)) / max(unit_scale, 1e-12)
        focus = _focus_distance(cam, eye, forward)
    return Camera(eye=tuple(eye), target=tuple(eye + forward), up=tuple(up), fov=fov,
                  width=width, height=height, aperture=aperture, focus_distance=focus,
                  shift=shift, hither=float(cam.clip_start))
