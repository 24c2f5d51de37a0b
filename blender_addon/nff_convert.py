"""NFF scene values -> Blender datablock values, for File > Import > NFF.

Plain functions (numpy, no bpy) on the keyword arguments of
`gridwalk.io.read_nff`; nff_import.py puts the results into Blender. Each one
inverts the exporter (export/), so that exporting the imported scene gives the
core's scene back (exactly, or as noted):

* Camera: a VERTICAL sensor fit whose lens gives the NFF camera's vertical fov.
* Lights: NFF lights do not fall off with distance; Blender point lights do,
  and the exporter has no switch to turn that off. Each light gets the power
  at which its 1/d^2 intensity equals the NFF intensity at a reference
  distance d0: the d0 that minimises the mean relative intensity error
  |1 - d0^2 / d^2| over the surface points the camera sees, i.e. the median
  of d^2 weighted by 1/d^2 (reference_distances). The exporter gives
  light.color = rgb * W * POINT_FACTOR, so W = max(c) * d0^2 / POINT_FACTOR
  and rgb = c / max(c). Surfaces nearer the light than d0 come out brighter
  than in the core's render of the file, farther ones darker.
* Materials: metallic = mirror, transmission = T / (1 - mirror) (the exporter
  multiplies by 1 - metallic), roughness 0 (an exact mirror), specular level 0,
  base colour = color * kd / ((1 - metallic)(1 - T)) so the diffuse albedo
  kd * color is exact. Not representable: NFF's Phong highlight. A sharp
  mirror forces the exporter's shininess to its cap (1000) and
  ks = mirror * 126, so the highlight is a small bright spot instead of NFF's
  `Shine` lobe.
* Polygons: the reader also returns them untriangulated, so NFF polygons
  come back as n-gons (Blender triangulates concave ones itself).
* Spheres: a unit UV sphere whose bounding box is exactly [-1, 1]^3, scaled by
  r and moved to the centre; the exporter's "render as sphere" gives it back.
* Cones and cylinders: the exporter has no analytic cone, so they become
  open, tessellated meshes with the analytic normals as custom normals.
"""
from __future__ import annotations

import math

import numpy as np

from .export.lights import POINT_FACTOR

SENSOR_HEIGHT = 24.0           # mm; Blender's lens must stay >= 1 mm


def _unit(v):
    v = np.asarray(v, dtype=np.float64)
    length = np.linalg.norm(v, axis=-1, keepdims=True)
    return v / np.where(length > 0, length, 1.0)


# -- camera -----------------------------------------------------------------
def camera_matrix(eye, target, up) -> np.ndarray:
    """4x4 world matrix of a Blender camera at `eye` looking at `target`
    (Blender cameras look along local -Z with local +Y up)."""
    eye = np.asarray(eye, dtype=np.float64)
    forward = _unit(np.asarray(target, dtype=np.float64) - eye)
    right = np.cross(forward, np.asarray(up, dtype=np.float64))
    if np.linalg.norm(right) < 1e-12:
        raise ValueError("the camera's up vector is parallel to its view direction")
    right = _unit(right)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = right, np.cross(right, forward), -forward, eye
    return m


def camera_lens(fov_degrees: float) -> tuple[float, float]:
    """(sensor height, lens) in mm giving a vertical fov with sensor fit VERTICAL."""
    half_tan = math.tan(math.radians(fov_degrees) / 2.0)
    sensor = SENSOR_HEIGHT if SENSOR_HEIGHT / (2.0 * half_tan) >= 1.0 else 100.0
    return sensor, sensor / (2.0 * half_tan)


# -- lights -----------------------------------------------------------------
def point_light(color, reference_distance: float) -> tuple[tuple, float]:
    """(rgb, watts) of a Blender point light whose intensity at
    `reference_distance` equals the falloff-free NFF intensity `color`."""
    c = np.asarray(color, dtype=np.float64)
    peak = float(c.max())
    if peak <= 0.0:
        return (1.0, 1.0, 1.0), 0.0
    return tuple(float(x) for x in c / peak), peak * reference_distance ** 2 / POINT_FACTOR


def camera_rays(camera, samples: int = 64):
    """(origins, directions) of a samples x samples grid of pinhole rays."""
    eye = np.asarray(camera.eye, dtype=np.float64)
    m = camera_matrix(eye, camera.target, camera.up)
    half = math.tan(math.radians(camera.fov) / 2.0)
    s = (np.arange(samples) + 0.5) / samples * 2.0 - 1.0
    x, y = np.meshgrid(s * half * camera.width / camera.height, -s * half)
    d = _unit(x.reshape(-1, 1) * m[:3, 0] + y.reshape(-1, 1) * m[:3, 1] - m[:3, 2])
    return np.broadcast_to(eye, d.shape).copy(), d


def scene_bounds(kwargs):
    """(lo, hi) of every primitive, or None for a scene without geometry."""
    boxes = [kwargs["vertices"]]
    c, r = kwargs["sphere_centers"], kwargs["sphere_radii"][:, None]
    boxes += [c - r, c + r]
    for end, radius in (("cylinder_base", "cylinder_base_radius"), ("cylinder_apex", "cylinder_apex_radius")):
        boxes += [kwargs[end] - kwargs[radius][:, None], kwargs[end] + kwargs[radius][:, None]]
    points = np.concatenate([np.asarray(b, dtype=np.float64).reshape(-1, 3) for b in boxes])
    return (points.min(axis=0), points.max(axis=0)) if len(points) else None


def reference_distances(kwargs, samples: int = 64) -> list[float]:
    """d0 for each light: the median of d^2 weighted by 1/d^2 over the first
    hits of a samples x samples grid of camera rays (the core's intersector),
    which minimises the mean of |1 - d0^2 / d^2| over those points. If the
    camera sees nothing: the distance to the scene's bounding box centre."""
    import gridwalk
    lights = kwargs["lights"]
    if not lights:
        return []
    origins, dirs = camera_rays(kwargs["camera"], samples)
    hits = gridwalk.Scene(**kwargs).intersect(origins, dirs, tmin=kwargs["camera"].hither)
    seen = hits.kind != 0
    points = origins[seen] + dirs[seen] * hits.t[seen, None]
    bounds = scene_bounds(kwargs)
    centre = (bounds[0] + bounds[1]) / 2.0 if bounds is not None else np.zeros(3)
    out = []
    for light in lights:
        position = np.asarray(light.position, dtype=np.float64)
        if not len(points):
            out.append(max(float(np.linalg.norm(position - centre)), 1e-6))
            continue
        d2 = np.sort(np.maximum(np.sum((points - position) ** 2, axis=1), 1e-12))
        weight = np.cumsum(1.0 / d2)
        out.append(math.sqrt(float(d2[np.searchsorted(weight, weight[-1] / 2.0)])))
    return out


# -- materials --------------------------------------------------------------
def principled_inputs(material) -> dict:
    """Principled BSDF input values (Blender 4.x names) for a gridwalk.Material."""
    metallic = min(max(float(material.mirror), 0.0), 1.0)
    transmission = 0.0
    if metallic < 1.0:
        transmission = min(max(float(material.transmittance) / (1.0 - metallic), 0.0), 1.0)
    kd_exported = (1.0 - metallic) * (1.0 - transmission * (1.0 - metallic))
    albedo = np.asarray(material.color, dtype=np.float64) * float(material.kd)
    base = albedo / kd_exported if kd_exported > 1e-6 else np.asarray(material.color, dtype=np.float64)
    return {"Base Color": (*(float(c) for c in base), 1.0), "Metallic": metallic,
            "Roughness": min(max(float(material.roughness), 0.0), 1.0),
            "Transmission Weight": transmission, "IOR": float(material.ior),
            "Specular IOR Level": 0.0, "Emission Color": (1.0, 1.0, 1.0, 1.0),
            "Emission Strength": float(material.emission)}


# -- geometry ---------------------------------------------------------------
def uv_sphere(segments: int = 32, rings: int = 16):
    """(vertices, corners, starts) of a unit UV sphere. With segments a
    multiple of 4 and rings even, its bounding box is exactly [-1, 1]^3."""
    theta = math.pi * np.arange(1, rings) / rings
    phi = 2.0 * math.pi * np.arange(segments) / segments
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.repeat(np.cos(theta)[:, None], segments, axis=1)], axis=-1).reshape(-1, 3)
    vertices = np.concatenate([[(0.0, 0.0, 1.0)], ring, [(0.0, 0.0, -1.0)]])
    k = np.arange(segments)
    k1 = (k + 1) % segments
    bottom = len(vertices) - 1
    faces = [np.stack([np.zeros(segments, np.int64), 1 + k, 1 + k1], axis=1)]
    for r in range(rings - 2):
        a, b = 1 + r * segments, 1 + (r + 1) * segments
        faces.append(np.stack([a + k, b + k, b + k1, a + k1], axis=1))
    last = 1 + (rings - 2) * segments
    faces.append(np.stack([last + k1, last + k, np.full(segments, bottom)], axis=1))
    corners = np.concatenate([f.reshape(-1) for f in faces])
    counts = np.concatenate([np.full(len(f), f.shape[1]) for f in faces])
    return vertices, corners, np.cumsum(counts) - counts


def cone_mesh(base, apex, base_radius: float, apex_radius: float, segments: int = 32):
    """(vertices, normals, corners, starts) of an open cone or cylinder, or
    None when it has no area. Normals are the analytic ones; a zero-radius end
    gets one tip vertex per segment so each keeps its own normal."""
    base, apex = np.asarray(base, dtype=np.float64), np.asarray(apex, dtype=np.float64)
    axis = apex - base
    length = float(np.linalg.norm(axis))
    if length == 0.0 or (base_radius <= 0.0 and apex_radius <= 0.0):
        return None
    a = axis / length
    u = _unit(np.cross(a, (1.0, 0.0, 0.0) if abs(a[0]) < 0.9 else (0.0, 1.0, 0.0)))
    v = np.cross(a, u)

    def ring(centre, radius, phi):
        radial = np.outer(np.cos(phi), u) + np.outer(np.sin(phi), v)
        normal = _unit(radial * length + a * (base_radius - apex_radius))
        return centre + radius * radial, normal

    k = np.arange(segments)
    phi = 2.0 * math.pi * k / segments
    k1 = (k + 1) % segments
    if base_radius > 0.0 and apex_radius > 0.0:
        (p0, n0), (p1, n1) = ring(base, base_radius, phi), ring(apex, apex_radius, phi)
        faces = np.stack([k, k1, segments + k1, segments + k], axis=1)
    else:
        rim_end, rim_r, tip = (base, base_radius, apex) if base_radius > 0.0 else (apex, apex_radius, base)
        p0, n0 = ring(rim_end, rim_r, phi)
        p1, n1 = ring(tip, 0.0, phi + math.pi / segments)
        faces = np.stack([k, k1, segments + k], axis=1)
        if base_radius <= 0.0:
            faces = faces[:, ::-1]          # keep the winding outward
    corners = faces.reshape(-1)
    return (np.concatenate([p0, p1]), np.concatenate([n0, n1]), corners,
            np.arange(len(faces)) * faces.shape[1])
