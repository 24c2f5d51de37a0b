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

Pixel aspect. With pixel_aspect_x / pixel_aspect_y = a, Blender's view is
w * a wide for h high (its sensor fit compares w * a with h): every length
above is in these view units, and Camera.pixel_aspect = a.

Orthographic: ortho_scale spans the fitted side, so the view's height is
ortho_height = ortho_scale * h / side. Panoramic: every type Cycles renders
(PANORAMAS; Blender 4.x keeps their settings on the camera, 3.x in Cycles'
camera settings), with the lens shift in units of the image, as Cycles shifts
a panorama. The equisolid and polynomial fisheyes measure the image on the
sensor as Cycles does: the sensor size spans the fitted side (AUTO: the
larger, with sensor_width). Clipping: clip_start and clip_end become hither
and yon. A camera with a negative scale (negative determinant) is mirrored,
as Cycles mirrors it.

Depth of field (when enabled). The thin-lens aperture radius in scene units is
    aperture = (lens [mm] / 1000) / (2 * f-stop)
and for an orthographic camera 1 / (2 * f-stop), as Cycles sets it: the
scene's Unit Scale plays no part (EEVEE divides by it, Cycles does not; an
exploration measured Cycles' blur unchanged at Unit Scale 0.1). The focus
distance is the focus object's (or its focus bone's head's) distance along the
view axis, or the camera's focus_distance. Blades (3 or more: a polygonal
aperture whose corners lie on that radius), Rotation and Ratio (an anamorphic
bokeh, narrowed across by 1 / ratio) shape the aperture as Cycles samples it.
"""
from __future__ import annotations

import math
import types

import numpy as np

from gridwalk.model import Camera

from ._matrix import axis, to_numpy, unit


class CameraError(ValueError):
    """The scene cannot be viewed (no camera, unsupported panorama, no viewing direction)."""


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


def pixel_aspect(render) -> float:
    """A pixel's width / height (Blender's pixel_aspect_x / pixel_aspect_y)."""
    return float(render.pixel_aspect_x) / float(render.pixel_aspect_y)


def fitted_side(cam, width: int, height: int, aspect: float = 1.0) -> tuple[float, float]:
    """(sensor size, length of the fitted side) as Blender fits the
    camera: HORIZONTAL (the width), VERTICAL (the height) or AUTO (the larger
    side; sensor_width). Lengths are in view units: the width is
    width * pixel aspect, the height is height."""
    view_w, view_h = width * aspect, float(height)
    fit = cam.sensor_fit
    if fit == "AUTO":
        fit = "HORIZONTAL" if view_w >= view_h else "VERTICAL"
        sensor = cam.sensor_width
    elif fit == "HORIZONTAL":
        sensor = cam.sensor_width
    else:
        sensor = cam.sensor_height
    return sensor, view_w if fit == "HORIZONTAL" else view_h


def _focus_distance(cam, eye, forward) -> float | None:
    dof = cam.dof
    target = dof.focus_object
    if target is not None:
        matrix = to_numpy(target.matrix_world)
        bone_name = getattr(dof, "focus_subtarget", "")
        bone = target.pose.bones.get(bone_name) if bone_name and target.pose is not None else None
        if bone is not None:                   # a bone of an armature: its head, as Cycles focuses
            matrix = matrix @ to_numpy(bone.matrix)
        position = matrix[:3, 3]
        distance = float(np.dot(position - eye, forward))
        return max(distance, 1e-6)
    return max(float(dof.focus_distance), 1e-6)


# Blender's panorama types: (Camera.projection, the settings read; ui.py's panel draws them).
PANORAMAS = {
    "EQUIRECTANGULAR": ("equirectangular", ("latitude_min", "latitude_max", "longitude_min", "longitude_max")),
    "FISHEYE_EQUIDISTANT": ("fisheye_equidistant", ("fisheye_fov",)),
    "FISHEYE_EQUISOLID": ("fisheye_equisolid", ("fisheye_lens", "fisheye_fov")),
    "FISHEYE_LENS_POLYNOMIAL": ("fisheye_polynomial",
                                ("fisheye_fov",) + tuple(f"fisheye_polynomial_k{i}" for i in range(5))),
    "MIRRORBALL": ("mirror_ball", ()),
    "EQUIANGULAR_CUBEMAP_FACE": ("cubemap_face", ()),
    "CENTRAL_CYLINDRICAL": ("central_cylindrical",
                            tuple(f"central_cylindrical_range_{k}" for k in ("u_min", "u_max", "v_min", "v_max"))
                            + ("central_cylindrical_radius",)),
}


def panorama_settings(cam, live: bool = False):
    """What holds a panoramic camera's settings: the camera (Blender 4.0+), its
    Cycles settings (3.x, with the Cycles add-on enabled), or None. live (the
    viewport): 3.x's Cycles settings of the original camera, as the panel and
    scripts set them: Blender 3.4 does not tag the depsgraph for them, and the
    evaluated camera kept its old panorama type (a fisheye drawn as the
    equirectangular panorama it was before)."""
    if hasattr(cam, "panorama_type"):
        return cam
    source = cam.original if live and getattr(cam, "is_evaluated", False) else cam
    holder = getattr(source, "cycles", None)
    return holder if hasattr(holder, "panorama_type") else None


def panorama(cam, name: str, width: int, height: int, aspect: float, live: bool = False) -> dict:
    """Camera fields of a panoramic camera, as Cycles projects its type (live: panorama_settings')."""
    settings = panorama_settings(cam, live)
    if settings is None:
        raise CameraError(f"Camera {name!r} is panoramic, and Blender 3.x keeps the panorama's settings in the "
                          "Cycles add-on: enable Cycles (Preferences > Add-ons) to render it")
    kind = settings.panorama_type
    if kind not in PANORAMAS:
        raise CameraError(f"Camera {name!r} uses the {kind.replace('_', ' ').title()} panorama, which Gridwalk "
                          "does not render (Camera properties > Lens > Panorama Type)")
    projection, names = PANORAMAS[kind]
    value = {key: float(getattr(settings, key)) for key in names}
    for low in (key for key in names if key.endswith("_min")):   # (reversed ranges flip the image, as in Cycles)
        if value[low] == value[low[:-4] + "_max"]:
            label = settings.bl_rna.properties[low].name
            raise CameraError(f"Camera {name!r}: the panorama's {label} and its maximum are equal "
                              f"({value[low]:g}), so the image spans nothing: set a range")
    fields = dict(projection=projection, shift=(float(cam.shift_x), float(cam.shift_y)))
    if kind == "EQUIRECTANGULAR":
        fields.update(longitude=(value["longitude_min"], value["longitude_max"]),
                      latitude=(value["latitude_min"], value["latitude_max"]))
    elif kind == "CENTRAL_CYLINDRICAL":
        radius = max(value["central_cylindrical_radius"], 1e-5)
        heights = tuple(value[f"central_cylindrical_range_{k}"] / radius for k in ("v_min", "v_max"))
        if not all(abs(h) < 1e30 for h in heights):
            raise CameraError(f"Camera {name!r}: the panorama's heights over its radius ({heights[0]:g}, "
                              f"{heights[1]:g}) are too large to render: lower them or raise the radius")
        fields.update(longitude=(value["central_cylindrical_range_u_min"], value["central_cylindrical_range_u_max"]),
                      cylinder_height=heights)
    elif kind.startswith("FISHEYE"):
        fields["fisheye_fov"] = value["fisheye_fov"]
        if kind != "FISHEYE_EQUIDISTANT":
            sensor, side = fitted_side(cam, width, height, aspect)
            fields["sensor"] = (sensor * width * aspect / side, sensor * height / side)
        if kind == "FISHEYE_EQUISOLID":
            fields["fisheye_lens"] = value["fisheye_lens"]
        elif kind == "FISHEYE_LENS_POLYNOMIAL":
            fields["polynomial"] = tuple(value[f"fisheye_polynomial_k{i}"] for i in range(5))
    return fields


def camera_frame(cam_obj) -> dict:
    """eye, target, up and mirror of a camera object; the basis is kept in
    double and relative to the eye (target = eye + unit forward), so a camera
    far from the origin keeps its direction. Refuses a transform without a
    viewing direction (zero scale, NaN), naming the camera."""
    m = to_numpy(cam_obj.matrix_world)
    if not np.isfinite(m).all():
        raise CameraError(f"Camera {cam_obj.name!r} has a non-finite transform (NaN or Inf)")
    scale = np.linalg.norm(m[:3, :3], axis=0)
    if not (scale.min() > 1e-12 * max(1.0, scale.max())):
        raise CameraError(f"Camera {cam_obj.name!r} has a zero scale ({', '.join(f'{s:g}' for s in scale)} along "
                          "its X, Y, Z axes): it has no viewing direction. Give it a non-zero scale")
    eye = m[:3, 3].copy()
    forward = unit(-axis(m, 2))
    return dict(eye=tuple(eye), target=tuple(eye + forward), up=tuple(unit(axis(m, 1))),
                mirror=bool(np.linalg.det(m[:3, :3]) < 0))


def shear_note(cam_obj) -> str | None:
    """A warning where the camera's transform is sheared (its axes not at right angles: a rotated
    parent scaled unevenly), which Cycles renders as a skewed view and Gridwalk as the view along
    the camera's -Z with its Y up; None otherwise."""
    if cam_obj is None:
        return None
    m = to_numpy(cam_obj.matrix_world)[:3, :3]
    scale = np.linalg.norm(m, axis=0)
    if not (np.isfinite(m).all() and scale.min() > 0):
        return None
    axes = m / scale
    skew = max(abs(float(axes[:, i] @ axes[:, j])) for i, j in ((0, 1), (0, 2), (1, 2)))
    if skew <= 1e-4:
        return None
    degrees = 90.0 - math.degrees(math.acos(min(skew, 1.0)))
    return (f"Camera {cam_obj.name!r} has a sheared transform (its axes are {degrees:.2g} degrees off right "
            "angles: a rotated parent with an uneven scale): Cycles renders it skewed, Gridwalk renders the "
            "unskewed view along its -Z axis with its Y axis up. Scale the parent evenly, or apply its scale")


# What Cycles renders from an active camera that is another kind of object (an Empty, a light
# looked through): its place and turn, with Cycles' default lens (a 50 mm perspective on a 36 mm
# sensor fitted to the larger side, no shift, clipping from 1e-5 to 1e5, no depth of field; a light's
# lens 16 / tan(half its spot cone), 45 degrees for a light that is no spot, as Cycles reads it).
DEFAULT_LENS = types.SimpleNamespace(type="PERSP", lens=50.0, sensor_width=36.0, sensor_height=24.0,
                                     sensor_fit="AUTO", shift_x=0.0, shift_y=0.0, clip_start=1e-5, clip_end=1e5,
                                     dof=types.SimpleNamespace(use_dof=False))


def convert_camera(cam_obj, render, live: bool = False) -> Camera:
    """The camera object `cam_obj` (evaluated) for the render settings `render`
    (live: the viewport's, see panorama_settings)."""
    if cam_obj is None:
        raise CameraError("The scene has no active camera: add a camera and make it active "
                          "(Scene properties > Camera)")
    cam = cam_obj.data if cam_obj.type == "CAMERA" else DEFAULT_LENS
    if cam_obj.type == "LIGHT":   # (Cycles: a light's spot cone as the lens; other lights keep a spot's 45 degrees)
        size = float(cam_obj.data.spot_size) if cam_obj.data.type == "SPOT" else math.radians(45.0)
        lens = 16.0 / math.tan(0.5 * size)
        cam = types.SimpleNamespace(**{**vars(DEFAULT_LENS), "lens": lens}) if lens > 0 else cam
    if cam.type not in ("PERSP", "ORTHO", "PANO"):       # (Blender 4.5's Custom: an OSL camera shader)
        raise CameraError(f"Camera {cam_obj.name!r}: the {cam.type.title()} camera type is not supported; "
                          "choose Perspective, Orthographic or Panoramic (Camera properties > Lens > Type)")
    width, height = resolution(render)
    aspect = pixel_aspect(render)
    frame = camera_frame(cam_obj)
    fields = dict(frame, width=width, height=height, pixel_aspect=aspect, hither=float(cam.clip_start),
                  yon=float(cam.clip_end))
    if cam.type == "PANO":
        fields.update(panorama(cam, cam_obj.name, width, height, aspect, live))
    else:
        sensor, side = fitted_side(cam, width, height, aspect)
        larger = max(width * aspect, float(height))
        fields["shift"] = (cam.shift_x * side / larger, cam.shift_y * side / larger)
        if cam.type == "ORTHO":
            fields.update(projection="orthographic", ortho_height=cam.ortho_scale * height / side)
        else:
            fields["fov"] = math.degrees(2.0 * math.atan(sensor / (2.0 * cam.lens) * height / side))
    if cam.dof.use_dof:
        eye, forward = np.array(frame["eye"]), np.subtract(frame["target"], frame["eye"])
        # Cycles' aperture radius: (lens / 1000) / (2 f-stop), and 1 / (2 f-stop) for an orthographic camera
        size = 1.0 if cam.type == "ORTHO" else cam.lens / 1000.0
        fields["aperture"] = size / (2.0 * max(cam.dof.aperture_fstop, 1e-6))
        fields["focus_distance"] = _focus_distance(cam, eye, forward)
        # the aperture's shape, as Cycles samples it: a polygon of 3+ blades, turned; narrowed by the ratio
        fields.update(blades=int(cam.dof.aperture_blades), blade_rotation=float(cam.dof.aperture_rotation),
                      aperture_ratio=float(cam.dof.aperture_ratio))
    return Camera(**fields)
