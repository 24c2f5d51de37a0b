"""Scene description records: materials, lights and the camera.

These are plain Python records. `gridwalk.Scene` packs them into the float32
tables the native core reads (see `pack_*` below), so the packing layout lives
in exactly one place.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

# Packed material table: float32 rows of (r, g, b, kd, ks, shininess,
# transmittance, ior, mirror, roughness, emission, pad); see Material.packed.
# Light kinds, as stored in column 0 of the packed light table.
LIGHT_KINDS = {"point": 0, "sphere": 1, "rect": 2, "disk": 3, "sun": 4, "spot": 5}
LIGHT_WIDTH = 24


def _vec3(value, name):
    v = np.asarray(value, dtype=np.float64).reshape(-1)
    if v.shape != (3,):
        raise ValueError(f"{name} must have 3 components, got shape {np.shape(value)}")
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} has a non-finite component: {tuple(v)}")
    return v


@dataclass
class Material:
    """Whitted / NFF material. NFF's `f r g b Kd Ks Shine T ior` maps to
    color, kd, ks, shininess, transmittance, ior, with mirror = Ks."""
    color: tuple = (1.0, 1.0, 1.0)
    kd: float = 0.8
    ks: float = 0.0
    shininess: float = 32.0
    transmittance: float = 0.0
    ior: float = 1.0
    mirror: float = 0.0
    roughness: float = 0.0      # 0 = exact mirror; > 0 glossy (sampling issue)
    emission: float = 0.0       # self-lit strength (added to the shaded colour)

    def packed(self) -> np.ndarray:
        c = _vec3(self.color, "Material.color")
        row = [c[0], c[1], c[2], self.kd, self.ks, self.shininess, self.transmittance,
               self.ior, self.mirror, self.roughness, self.emission, 0.0]
        row = np.asarray(row, dtype=np.float64)
        if not np.all(np.isfinite(row)):
            raise ValueError(f"Material has a non-finite field: {self}")
        if self.ior <= 0:
            raise ValueError(f"Material.ior must be > 0, got {self.ior}")
        if self.roughness < 0 or self.shininess < 0:
            raise ValueError("Material.roughness and shininess must be >= 0")
        return row.astype(np.float32)


@dataclass
class Light:
    """A light. kind: point | sphere | rect | disk | sun | spot.

    position: centre (point, sphere, rect, disk, spot).
    color: RGB radiant intensity scale (already multiplied by strength).
    radius: sphere / disk radius (a point light with radius > 0 is a sphere).
    size: (w, h) of a rect light, along axis_u and axis_v.
    axis_u, axis_v: orientation of rect / disk lights (emitting along u x v).
    direction: direction light travels (sun), or spot axis.
    angle: sun angular diameter (radians).
    spot_size: full cone angle (radians); spot_blend: 0..1 soft edge.
    inverse_square: divide by distance^2 (physical falloff); off for NFF.
    Area lights (rect, disk) emit along `direction` with a cosine falloff.
    """
    position: tuple = (0.0, 0.0, 0.0)
    color: tuple = (1.0, 1.0, 1.0)
    kind: str = "point"
    radius: float = 0.0
    size: tuple = (1.0, 1.0)
    axis_u: tuple = (1.0, 0.0, 0.0)
    axis_v: tuple = (0.0, 1.0, 0.0)
    direction: tuple = (0.0, 0.0, -1.0)
    angle: float = 0.0
    spot_size: float = math.pi / 4
    spot_blend: float = 0.15
    inverse_square: bool = False   # NFF lights have no falloff; Blender's do

    def packed(self) -> np.ndarray:
        if self.kind not in LIGHT_KINDS:
            raise ValueError(f"Light.kind must be one of {sorted(LIGHT_KINDS)}, got {self.kind!r}")
        p = _vec3(self.position, "Light.position")
        c = _vec3(self.color, "Light.color")
        u = _vec3(self.axis_u, "Light.axis_u")
        v = _vec3(self.axis_v, "Light.axis_v")
        d = _vec3(self.direction, "Light.direction")
        if self.kind in ("sun", "spot", "rect", "disk") and np.linalg.norm(d) == 0:
            raise ValueError("Light.direction must be non-zero for sun, spot, rect and disk lights")
        if self.radius < 0 or self.angle < 0:
            raise ValueError("Light.radius and Light.angle must be >= 0")
        w, h = float(self.size[0]), float(self.size[1])
        row = np.zeros(LIGHT_WIDTH, dtype=np.float64)
        row[0] = LIGHT_KINDS[self.kind]
        row[1:4] = p
        row[4:7] = c
        row[7:10] = u
        row[10:13] = v
        row[13:16] = d
        row[16] = self.radius
        row[17] = w
        row[18] = h
        row[19] = self.angle
        row[20] = math.cos(0.5 * self.spot_size)
        row[21] = min(max(self.spot_blend, 0.0), 1.0)
        row[22] = 1.0 if self.inverse_square else 0.0
        if not np.all(np.isfinite(row)):
            raise ValueError(f"Light has a non-finite field: {self}")
        return row.astype(np.float32)


@dataclass
class Camera:
    """Perspective camera. fov is the vertical field of view in degrees.

    shift = (sx, sy) moves the image window, in units of the image plane's
    larger side (Blender's convention). aperture is the thin-lens radius
    (0 = pinhole); focus_distance defaults to |target - eye|.
    """
    eye: tuple = (0.0, -10.0, 0.0)
    target: tuple = (0.0, 0.0, 0.0)
    up: tuple = (0.0, 0.0, 1.0)
    fov: float = 45.0
    width: int = 512
    height: int = 512
    aperture: float = 0.0
    focus_distance: float | None = None
    shift: tuple = (0.0, 0.0)
    hither: float = 0.0

    def packed(self) -> np.ndarray:
        e = _vec3(self.eye, "Camera.eye")
        t = _vec3(self.target, "Camera.target")
        up = _vec3(self.up, "Camera.up")
        fwd = t - e
        if np.linalg.norm(fwd) == 0:
            raise ValueError("Camera.eye and Camera.target coincide")
        if np.linalg.norm(np.cross(fwd, up)) <= 1e-12 * np.linalg.norm(fwd) * max(np.linalg.norm(up), 1e-300):
            raise ValueError("Camera.up is parallel to the viewing direction (or zero)")
        if not (0.0 < float(self.fov) < 180.0):
            raise ValueError(f"Camera.fov must be in (0, 180) degrees, got {self.fov}")
        if int(self.width) < 1 or int(self.height) < 1:
            raise ValueError(f"Camera resolution must be at least 1x1, got {self.width}x{self.height}")
        if int(self.width) * int(self.height) > 1 << 28:
            raise ValueError(f"Camera resolution {self.width}x{self.height} is too large")
        if self.aperture < 0:
            raise ValueError("Camera.aperture must be >= 0")
        fd = float(np.linalg.norm(fwd)) if self.focus_distance is None else float(self.focus_distance)
        if not (fd > 0 and math.isfinite(fd)):
            raise ValueError(f"Camera.focus_distance must be > 0, got {self.focus_distance}")
        row = np.array([*e, *t, *up, self.fov, self.width, self.height, self.aperture, fd,
                        self.shift[0], self.shift[1], self.hither, 0.0, 0.0, 0.0], dtype=np.float64)
        if not np.all(np.isfinite(row)):
            raise ValueError(f"Camera has a non-finite field: {self}")
        return row.astype(np.float32)
