"""Particle hair (a Hair particle system rendered as Path: Blender's hair
before the Curves object, still in many files) -> cone frusta, as hair curves
become (hair.py).

What Cycles reads, read the same way:
* the strands: the children alone where the system has children, else the
  parents; in the viewport only the first display_percentage of the children;
* each strand's keys from the particle system's path cache
  (`ParticleSystem.co_hair`, world space): 2^steps + 1 of them, steps being the
  settings' render_step in a final render and display_step in the viewport,
  plus kink_extra_steps under a Spiral kink (children only); a key past a
  path's end, which co_hair gives as (0, 0, 0), holds the strand's last key;
* each key's radius: radius_scale / 2 times root_radius at the root and
  tip_radius at the tip, shaped by `shape` along the strand's length, and 0 at
  the last key with use_close_tip ("Close Tip");
* the material: the object's slot that the settings' `material` names.

An instance of the emitter (a collection instance) moves its hair with it.
Only systems whose modifier is enabled for the render (or the viewport) count.
"""
from __future__ import annotations

import itertools

import numpy as np

from ._matrix import to_numpy, transform_points
from .hair import ConeSet, polyline_cones


def hair_systems(obj, render: bool):
    """The object's particle systems that render as hair strands."""
    enabled = {mod.particle_system.name for mod in getattr(obj, "modifiers", ())
               if mod.type == "PARTICLE_SYSTEM" and (mod.show_render if render else mod.show_viewport)}
    return [psys for psys in getattr(obj, "particle_systems", ())
            if psys.name in enabled and psys.settings.type == "HAIR" and psys.settings.render_type == "PATH"]


def strand_range(psys, render: bool) -> range:
    """The particle numbers whose paths render (co_hair's particle_no)."""
    settings = psys.settings
    parents, children = len(psys.particles), len(psys.child_particles)
    if not render:
        children = int(children * settings.display_percentage / 100)
    start = parents if settings.child_type != "NONE" and children > 0 else 0
    return range(start, parents + children)


def keys_per_strand(psys, render: bool) -> int:
    """Keys a strand's path has at most: 2^steps + 1, and a Spiral kink's
    extra steps, which Blender gives children only."""
    settings = psys.settings
    steps = settings.render_step if render else settings.display_step
    children = strand_range(psys, render).start > 0
    return (1 << steps) + 1 + (max(settings.kink_extra_steps, 1) if children and settings.kink == "SPIRAL" else 0)


def shape_radius(shape: float, root: float, tip: float, time: np.ndarray) -> np.ndarray:
    """The radius at fractions `time` of a strand's length, root to tip:
    (1 - time) raised to 1 + shape for a negative shape, to 1 / (1 - shape)
    for a positive one, then from tip to root."""
    x = 1.0 - np.clip(time, 0.0, 1.0)
    if shape < 0:
        x = x ** (1.0 + shape)
    elif shape >= 1:
        x = (x >= 1.0).astype(np.float64)      # (the power's limit: the root alone keeps its radius)
    elif shape > 0:
        x = x ** (1.0 / (1.0 - shape))
    return x * (root - tip) + tip


def strand_points(obj, psys, strands: range, keys: int) -> np.ndarray:
    """(strands * keys, 3) float64 world-space points of the strands' paths.
    co_hair gives (0, 0, 0) for a key beyond a path's end (a strand with
    fewer keys: Blender's virtual parents have none): from the first such key
    on, each strand repeats its last key, so it adds no segment and no length."""
    co = psys.co_hair
    values = itertools.chain.from_iterable(co(obj, particle_no=i, step=k) for i in strands for k in range(keys))
    points = np.fromiter(values, np.float64, count=3 * keys * len(strands)).reshape(-1, keys, 3)
    beyond = np.cumsum(~points.any(axis=2)[:, 1:], axis=1) > 0          # keys 1.. at or after the first zero one
    if beyond.any():
        last = np.where(beyond.any(axis=1), np.argmax(beyond, axis=1), keys - 1)   # the last key before it
        held = np.take_along_axis(points, last[:, None, None].repeat(3, axis=2), axis=1)
        points[:, 1:] = np.where(beyond[:, :, None], held, points[:, 1:])
    return points.reshape(-1, 3)


def strand_radii(settings, points: np.ndarray, keys: int) -> np.ndarray:
    """Each key's radius (object units) from the settings' hair shape."""
    per_strand = points.reshape(-1, keys, 3)
    steps = np.linalg.norm(np.diff(per_strand, axis=1), axis=2)
    along = np.concatenate([np.zeros((len(per_strand), 1)), np.cumsum(steps, axis=1)], axis=1)
    total = along[:, -1:]
    time = np.divide(along, total, out=np.zeros_like(along), where=total > 0)
    half = 0.5 * settings.radius_scale
    radii = shape_radius(settings.shape, half * settings.root_radius, half * settings.tip_radius, time)
    if settings.use_close_tip:
        radii[:, -1] = 0.0
    return radii.reshape(-1)


def particle_cone_sets(inst, lookup, max_coordinate, render: bool) -> list[tuple[ConeSet | None, str | None, bool]]:
    """[(cones, why skipped, non-uniform scale)] for each hair particle system of
    a depsgraph instance's (evaluated) object; lookup maps its material slots
    to material indices."""
    obj = inst.object
    systems = hair_systems(obj, render)
    if not systems:
        return []
    own = to_numpy(obj.matrix_world)
    placed = to_numpy(inst.matrix_world)
    # co_hair places a strand by the object's own matrix; an instance moves it on by placed @ own^-1.
    move = None
    if not np.array_equal(own, placed):
        try:
            move = placed @ np.linalg.inv(own)
        except np.linalg.LinAlgError:
            return [(None, "its hair's object transform is singular", False)]
    scales = np.linalg.norm(placed[:3, :3], axis=0)
    out = []
    for psys in systems:
        settings = psys.settings
        strands, keys = strand_range(psys, render), keys_per_strand(psys, render)
        if not len(strands):
            continue
        points = strand_points(obj, psys, strands, keys)
        if not np.isfinite(points).all():
            out.append((None, f"its hair '{psys.name}' has non-finite points (NaN or Inf)", False))
            continue
        # (Radii in object units, as Cycles takes them, scaled like the object: by its largest axis.)
        radii = strand_radii(settings, points, keys) * scales.max()
        if move is not None:
            points = transform_points(move, points)
        offsets = np.arange(0, len(points) + 1, keys, dtype=np.int64)
        slots = np.full(len(strands), max(settings.material - 1, 0), np.int32)
        out.append(polyline_cones(obj.name, points, radii, offsets, slots, lookup, max_coordinate, scales))
    return out


def particle_segment_count(obj, render: bool) -> int:
    """The cones an object's hair particle systems give at most (for the memory estimate)."""
    return sum(len(strand_range(p, render)) * (keys_per_strand(p, render) - 1)
               for p in hair_systems(obj, render))
