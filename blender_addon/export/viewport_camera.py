"""A 3D viewport's view -> gridwalk.model.Camera.

The viewport gives its view as two matrices (RegionView3D.view_matrix,
world -> view, and window_matrix, the OpenGL-style projection) and a region
size in pixels. Every view is one of:

- perspective (free views, and a perspective camera seen through): the
  frustum's half extents at distance 1 are 1 / P[0][0] and 1 / P[1][1], its
  centre P[0][2] / P[0][0], P[1][2] / P[1][1] (an off-centre camera view,
  lens shift); near and far from P[2][2], P[2][3];
- orthographic (the numpad views, and orthographic cameras): half extents
  1 / P[0][0], 1 / P[1][1], centre -P[0][3] / P[0][0], -P[1][3] / P[1][1];
  Blender puts the near plane behind the view point, so the eye moves back
  to it, and origin_ahead keeps Camera texture coordinates measured from
  the view point, as Cycles measures them;
- a panoramic camera seen through: Blender draws its frame with the lens'
  perspective; the panorama's unit square is stretched linearly from the
  camera's frame to the whole region (Camera.window), as Cycles stretches
  its panorama viewplane: every panorama type shows in the frame what the
  final render shows.

These come from the matrices alone (no bpy), so a camera's own matrices
(matrix_world inverted, calc_matrix_camera) must give the camera's rays: the
tests check exactly that.
"""
from __future__ import annotations

import math

import numpy as np

from gridwalk.model import Camera

from ._matrix import to_numpy, unit


def view_camera(view_matrix, window_matrix, width: int, height: int, clip=None, **extra) -> Camera:
    """The Camera for a view of width x height pixels. clip = (near, far)
    where they are known: a perspective matrix in float32 holds the far
    distance only to about 1e-7 * far / near of itself (a 1000 / 0.001 range
    loses 3%). `extra` adds Camera fields (a camera's lens: aperture and
    focus_distance)."""
    view = to_numpy(view_matrix) if not isinstance(view_matrix, np.ndarray) else view_matrix
    p = to_numpy(window_matrix) if not isinstance(window_matrix, np.ndarray) else window_matrix
    to_world = np.linalg.inv(view)
    eye = to_world[:3, 3].copy()
    forward = unit(-to_world[:3, 2])
    up = unit(to_world[:3, 1])
    mirror = bool(np.linalg.det(to_world[:3, :3]) < 0)
    perspective = p[3, 3] == 0
    half_w, half_h = 1.0 / p[0, 0], 1.0 / p[1, 1]
    if perspective:
        centre = (p[0, 2] / p[0, 0], p[1, 2] / p[1, 1])
        near, far = p[2, 3] / (p[2, 2] - 1.0), p[2, 3] / (p[2, 2] + 1.0)
        if clip is not None:
            near, far = clip
    else:
        centre = (-p[0, 3] / p[0, 0], -p[1, 3] / p[1, 1])
        near, far = (p[2, 3] + 1.0) / p[2, 2], (p[2, 3] - 1.0) / p[2, 2]
    larger = 2.0 * max(half_w, half_h)
    fields = dict(width=int(width), height=int(height), up=tuple(up), mirror=mirror,
                  pixel_aspect=float(half_w * height / (half_h * width)),
                  shift=(float(centre[0] / larger), float(centre[1] / larger)))
    if perspective:
        fields.update(fov=math.degrees(2.0 * math.atan(half_h)), hither=max(float(near), 0.0), yon=float(far))
    else:
        eye = eye + forward * near          # the near plane may lie behind the view point
        fields.update(projection="orthographic", ortho_height=float(2.0 * half_h), hither=0.0,
                      yon=float(far - near), origin_ahead=float(-near))   # (Camera coordinates: from the view point)
        if extra.get("aperture", 0) > 0 and extra.get("focus_distance"):   # measured from the moved eye
            extra = dict(extra, focus_distance=max(float(extra["focus_distance"] - near), 1e-6))
    fields.update(extra)
    return Camera(eye=tuple(eye), target=tuple(eye + forward), **fields)


def frame_in_region(camera_projection, window_matrix, width: int, height: int) -> tuple:
    """(x0, y0, x1, y1): the camera's frame in region pixels (origin at the
    bottom left), for a view through the camera. Both matrices project the
    same view, so a point on the frame's edge (camera NDC +-1) lands at
    region NDC P_region(P_camera^-1(+-1))."""
    c = to_numpy(camera_projection) if not isinstance(camera_projection, np.ndarray) else camera_projection
    r = to_numpy(window_matrix) if not isinstance(window_matrix, np.ndarray) else window_matrix
    out = []
    for axis, size in ((0, width), (1, height)):
        for ndc in (-1.0, 1.0):
            if c[3, 3] == 0:                 # perspective: the frame edge on the plane z = -1
                x = (ndc + c[axis, 2]) / c[axis, axis]
                region = r[axis, axis] * x - r[axis, 2]
            else:
                x = (ndc - c[axis, 3]) / c[axis, axis]
                region = r[axis, axis] * x + r[axis, 3]
            out.append((region + 1.0) / 2.0 * size)
    x0, x1, y0, y1 = out
    return x0, y0, x1, y1


# The Camera fields that make a panorama what it is (the viewport keeps them, and the view's own frame).
PANORAMA_FIELDS = ("projection", "shift", "longitude", "latitude", "fisheye_fov", "fisheye_lens", "sensor",
                   "polynomial", "cylinder_height")


def stretch_panorama(camera: Camera, frame, width: int, height: int) -> dict:
    """Camera fields of the panoramic `camera` whose frame (x0, y0, x1, y1,
    region pixels from the bottom left) is stretched over a whole
    width x height region: its own projection and settings, and the window
    of its unit square that the region spans."""
    x0, y0, x1, y1 = frame
    per_x, per_y = 1.0 / max(x1 - x0, 1e-9), 1.0 / max(y1 - y0, 1e-9)
    fields = {name: getattr(camera, name) for name in PANORAMA_FIELDS}
    fields["window"] = (-x0 * per_x, (width - x0) * per_x, -y0 * per_y, (height - y0) * per_y)
    return fields
