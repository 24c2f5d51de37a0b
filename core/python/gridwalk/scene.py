"""gridwalk.Scene: validated numpy arrays in, a native scene out.

Shapes and dtypes are checked here (with the array's name); values (NaN/Inf,
index ranges, negative radii, empty scenes) are checked by the core, which
raises ValueError naming the array and the first bad index.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, replace

import math

import numpy as np

from . import _core
from .image import Image
from .model import Camera, Light, Material, Texture, World, as_floats
from .settings import SCHEMA, RenderSettings


def _array(value, name, dtype, width):
    """Convert to a C-contiguous array of `dtype` with shape (N, width) or (N,)."""
    if value is None:
        return np.zeros((0, width) if width else (0,), dtype=dtype)
    if (dtype is np.float32 and type(value) is np.ndarray and value.dtype == np.float32 and value.size
            and value.flags.c_contiguous and value.flags.aligned
            and (value.shape[1:] == (width,) if width else value.ndim == 1)):
        return value   # already what the core reads (read-only), e.g. rays from a previous query
    a = np.asarray(value)
    if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool):
        raise ValueError(f"{name} must be a numeric array, got dtype {a.dtype}")
    if np.issubdtype(dtype, np.integer) and not np.issubdtype(a.dtype, np.integer):
        if a.size:   # refuse to silently truncate float indices
            raise ValueError(f"{name} must be an integer array, got dtype {a.dtype}")
        a = a.astype(dtype)
    if np.issubdtype(a.dtype, np.complexfloating):
        raise ValueError(f"{name} must be real, got dtype {a.dtype}")
    if a.size == 0:
        a = a.reshape((0, width) if width else (0,))
    expected = f"(N, {width})" if width else "(N,)"
    if width and (a.ndim != 2 or a.shape[1] != width):
        raise ValueError(f"{name} must have shape {expected}, got {a.shape}")
    if not width and a.ndim != 1:
        raise ValueError(f"{name} must have shape {expected}, got {a.shape}")
    if np.issubdtype(dtype, np.integer) and a.size:
        info = np.iinfo(np.int32)
        lo, hi = int(a.min()), int(a.max())
        if lo < info.min or hi > info.max:
            bad = int(np.argmax((a < info.min) | (a > info.max)) // max(1, (width or 1)))
            raise ValueError(f"{name}[{bad}] does not fit in int32")
    with np.errstate(over="ignore", invalid="ignore"):
        return np.ascontiguousarray(a, dtype=dtype)


def _corners(value, name, width, n_tris):
    """Per-corner values: (M, 3, width) (or (3M, width)) float32, flattened; empty if None."""
    if value is None:
        return np.zeros(0, np.float32)
    a = np.asarray(value)
    if a.ndim == 3 and a.shape[1:] == (3, width):
        a = a.reshape(-1, width)
    if a.ndim != 2 or a.shape[1] != width or a.shape[0] != 3 * n_tris:
        raise ValueError(f"{name} must have shape ({n_tris}, 3, {width}): one value per triangle corner, "
                         f"got {np.shape(value)}")
    return _array(a, name, np.float32, width).reshape(-1)


def _textures(images, textures):
    """(images, core textures): the images list extended by the distinct
    gridwalk.Image objects the textures hold, each texture pointing at its index."""
    images = list(images or [])
    for i, image in enumerate(images):
        if not isinstance(image, Image):
            raise ValueError(f"images[{i}] must be a gridwalk.Image, got {type(image).__name__}")
    index = {id(image): i for i, image in enumerate(images)}
    out = []
    for i, tex in enumerate(textures or []):
        if not isinstance(tex, Texture):
            raise ValueError(f"textures[{i}] must be a gridwalk.Texture, got {type(tex).__name__}")
        def image_index(image):
            if not isinstance(image, Image):
                return image
            if id(image) not in index:
                index[id(image)] = len(images)
                images.append(image)
            return index[id(image)]
        if tex.tiles:
            try:
                pairs = tuple((number, image_index(image)) for number, image in tex.tiles)
            except (TypeError, ValueError):
                raise ValueError(f"textures[{i}].tiles must be (tile number, image) pairs") from None
            first = pairs[0][1] if pairs else None
            tex = replace(tex, tiles=pairs, image=first if tex.image is None else tex.image)
        out.append(replace(tex, image=image_index(tex.image)).to_core())
    return images, out


@dataclass
class Hits:
    """Result of Scene.intersect: one entry per ray."""
    t: np.ndarray        # float32, inf on a miss
    prim: np.ndarray     # int32 index within its kind, -1 on a miss
    kind: np.ndarray     # int32: 0 miss, 1 triangle, 2 sphere, 3 cylinder/cone
    u: np.ndarray        # barycentric of vertex 1 (triangles), else 0
    v: np.ndarray        # barycentric of vertex 2 (triangles), else 0
    normal: np.ndarray   # (N, 3) unit geometric normal (triangle winding / outward)
    stats: dict


@dataclass
class InstanceMove:
    """One instance of a scene moved (Scene.moved): its vertices
    [vertex_start, vertex_start + len(positions)) become matrix x positions,
    and its triangles [triangle_start, triangle_start + triangle_count), which
    use only those vertices, follow them."""
    vertex_start: int
    triangle_start: int
    triangle_count: int
    positions: np.ndarray             # (k, 3) object space
    matrix: np.ndarray                # (4, 4) object to world, rows as in Blender
    normals: np.ndarray | None = None  # (k, 3) object space, mapped by the inverse transpose (cofactors if singular), renormalised
    flat: bool = False                # unshared corners, 3 per triangle, whose normals are their face's
    previous_matrix: np.ndarray | None = None   # the matrix it had: then a grid of an earlier version serves


BuildCancelled = _core.BuildCancelled
POLL_SECONDS = 0.01


def build(native, core_settings, should_stop=None):
    """Build the structure on a native thread (_core.BuildJob) while this
    thread waits in slices of POLL_SECONDS, so that should_stop() and Ctrl-C
    can cancel it: the builder checks its cancel token milliseconds apart. No
    Python thread is started (inside Blender one is a hazard; docs/blender.md)."""
    job = _core.BuildJob(native, core_settings)
    try:
        while not job.wait(POLL_SECONDS):
            if should_stop is not None and should_stop():
                job.cancel()
    except BaseException:   # KeyboardInterrupt: stop the builder, then let it propagate
        job.cancel()
        job.wait(-1)
        raise
    if job.cancelled:
        raise BuildCancelled("the build was cancelled")
    return job.result()


def structure_key(settings: RenderSettings) -> tuple:
    """The settings that shape an acceleration structure: the acceleration
    group's values, less its on/off traversal switches (mailboxes, skip_empty).
    Two settings with the same key share one structure."""
    return tuple(getattr(settings, name) for name in _STRUCTURE_SETTINGS)


# The acceleration group's on/off switches of the walk, not of the structure.
_TRAVERSAL_SWITCHES = ("mailboxes", "skip_empty")
_STRUCTURE_SETTINGS = tuple(x.name for x in SCHEMA if x.group == "acceleration" and x.name not in _TRAVERSAL_SWITCHES)


# The keywords Scene.intersect / occluded took before they took a RenderSettings.
DEPRECATED_QUERY_KEYWORDS = ("accel", "grid_density", "mailboxes", "threads", "skip_empty")

KIND_MISS, KIND_TRIANGLE, KIND_SPHERE, KIND_CYLINDER = 0, 1, 2, 3


def _declare_instances(native, triangles, meshes, matrices):
    """Scene(instance_triangles=..., instance_meshes=..., instance_matrices=...)."""
    given = [x is not None for x in (triangles, meshes, matrices)]
    if not any(given):
        return
    if not all(given):
        raise ValueError("instance_triangles, instance_meshes and instance_matrices come together (all three or none)")
    ranges = np.asarray(triangles)
    if ranges.ndim != 2 or ranges.shape[1] != 2 or not np.issubdtype(ranges.dtype, np.integer):
        raise ValueError(f"instance_triangles must be an (I, 2) integer array, got shape {ranges.shape} of {ranges.dtype}")
    ids = np.asarray(meshes)
    if ids.shape != (len(ranges),) or not np.issubdtype(ids.dtype, np.integer):
        raise ValueError(f"instance_meshes must be an ({len(ranges)},) integer array, got shape {ids.shape} of {ids.dtype}")
    if len(ids) and (ids.min() < 0 or ids.max() > np.iinfo(np.int32).max):
        raise ValueError("instance_meshes must lie in [0, 2^31)")
    m = np.asarray(matrices)
    if m.shape != (len(ranges), 4, 4) or m.dtype == object or not np.issubdtype(m.dtype, np.number) \
            or np.issubdtype(m.dtype, np.complexfloating):
        raise ValueError(f"instance_matrices must have shape ({len(ranges)}, 4, 4) of real numbers, got {m.shape} "
                         f"of {m.dtype}")
    native.set_instances(np.ascontiguousarray(ranges, dtype=np.int64), np.ascontiguousarray(ids, dtype=np.int32),
                         np.ascontiguousarray(m, dtype=np.float64))


class Scene:
    """Geometry, materials, lights and camera, copied into the native core."""

    def __init__(self, vertices=None, triangles=None, normals=None, triangle_materials=None,
                 sphere_centers=None, sphere_radii=None, sphere_materials=None,
                 cylinder_base=None, cylinder_apex=None, cylinder_base_radius=None,
                 cylinder_apex_radius=None, cylinder_materials=None,
                 materials=None, lights=None, camera=None, background=(0.0, 0.0, 0.0),
                 uvs=None, colors=None, images=None, textures=None, world=None, generated=None,
                 object_coords=None, object_normals=None, matte_keys=None, instance_triangles=None, instance_meshes=None,
                 instance_matrices=None):
        """uvs: (M, 3, 2) texture coordinates per triangle corner; colors:
        (M, 3, 3) RGB per triangle corner (Material.vertex_color); generated:
        (M, 3, 3) Blender's Generated coordinates per triangle corner, what
        textures with coordinates="generated" take (needed where a triangle's
        material has one; spheres and cylinders have none); object_coords:
        likewise Blender's Object coordinates (each corner in its object's
        own space), for coordinates="object"; object_normals: likewise each
        corner's shading normal in its object's own space (a flat face's
        normal at all three), for coordinates="normal"; images:
        gridwalk.Image list that textures may refer to by index; textures:
        gridwalk.Texture list that materials and the world refer to by index
        (a Texture's image may also be a gridwalk.Image: each distinct Image
        is stored once); world: gridwalk.World (ambient light, environment);
        matte_keys: (triangles + spheres + cylinders,) or (that, L) int, each
        primitive's key (-1: none), in that order, in each of L <= 4 layers
        (say its object's and its material's): a render with
        RenderSettings.matte_ranks > 0 reports, per layer, which keys cover
        each pixel and how much (RenderJob.matte_keys / matte_coverage):
        Cryptomatte's object and material mattes. instance_triangles (I, 2)
        int (first triangle, count), instance_meshes (I,) int and
        instance_matrices (I, 4, 4) float (object to world, rows as in
        Blender), all three or none: triangles that are copies of one mesh
        (equal instance_meshes), each the mesh under its matrix, corner for
        corner in the same order as the mesh's first copy; the adaptive grid
        then traces the copies through one grid of the mesh
        (RenderSettings.instancing: "auto", the default, where they make at
        least half of the primitives and over 2^20 triangles; "on" wherever
        one checks out). Each copy is checked against the first
        on its corners; one that does not match is traced as plain triangles."""
        f32, i32 = np.float32, np.int32
        self.materials = list(materials) if materials else [Material()]
        self.lights = list(lights) if lights else []
        self.camera = camera if camera is not None else Camera()
        for i, m in enumerate(self.materials):
            if not isinstance(m, Material):
                raise ValueError(f"materials[{i}] must be a gridwalk.Material, got {type(m).__name__}")
        for i, l in enumerate(self.lights):
            if not isinstance(l, Light):
                raise ValueError(f"lights[{i}] must be a gridwalk.Light, got {type(l).__name__}")
        if not isinstance(self.camera, Camera):
            raise ValueError(f"camera must be a gridwalk.Camera, got {type(self.camera).__name__}")
        self.background = as_floats(background, 3, "background")
        self.world = world if world is not None else World()
        if not isinstance(self.world, World):
            raise ValueError(f"world must be a gridwalk.World, got {type(self.world).__name__}")
        self.images, core_textures = _textures(images, textures)
        self.textures = list(textures or [])
        n_tris = len(triangles) if triangles is not None else 0
        self._native = _core.Scene(
            _array(vertices, "vertices", f32, 3), _array(triangles, "triangles", i32, 3),
            _array(normals, "normals", f32, 3), _array(triangle_materials, "triangle_materials", i32, 0),
            _array(sphere_centers, "sphere_centers", f32, 3), _array(sphere_radii, "sphere_radii", f32, 0),
            _array(sphere_materials, "sphere_materials", i32, 0),
            _array(cylinder_base, "cylinder_base", f32, 3), _array(cylinder_apex, "cylinder_apex", f32, 3),
            _array(cylinder_base_radius, "cylinder_base_radius", f32, 0),
            _array(cylinder_apex_radius, "cylinder_apex_radius", f32, 0),
            _array(cylinder_materials, "cylinder_materials", i32, 0),
            [m.to_core() for m in self.materials], [l.to_core() for l in self.lights], self.camera.to_core(),
            self.background, _corners(uvs, "uvs", 2, n_tris), _corners(colors, "colors", 3, n_tris),
            [image._native for image in self.images], core_textures, self.world.to_core(),
            _corners(generated, "generated", 3, n_tris), _corners(object_coords, "object_coords", 3, n_tris),
            _corners(object_normals, "object_normals", 3, n_tris))
        if matte_keys is not None:
            keys = np.asarray(matte_keys)
            layers = keys.shape[1] if keys.ndim == 2 else 1
            self._native.set_matte_keys(_array(keys.reshape(-1) if keys.ndim == 2 else keys, "matte_keys", i32, 0),
                                        layers)
        _declare_instances(self._native, instance_triangles, instance_meshes, instance_matrices)
        self._accels = {}

    def moved(self, moves) -> "Scene":
        """A new scene, this one with the instances `moves` (InstanceMove) in
        new places, made in the core: the arrays of what did not move are
        copied there, not passed in again. Materials, lights, camera and world
        are this scene's. The result is a Scene built from the same arrays, each
        instance transformed as the Blender exporter transforms it (to within
        an ulp: numpy's matrix product may round differently). With
        previous_matrix given (and checked on a sample of vertices), a grid of
        this or an earlier version can serve the result (the viewport's).
        Declared instances (instance_triangles, ...) carry over: one a move
        moves whole takes its matrix, one a move cuts into is dropped."""
        moves = list(moves)
        for i, m in enumerate(moves):
            if not isinstance(m, InstanceMove):
                raise ValueError(f"moves[{i}] must be a gridwalk.InstanceMove, got {type(m).__name__}")
            for name in ("vertex_start", "triangle_start", "triangle_count"):
                value = getattr(m, name)
                if not (isinstance(value, (int, np.integer)) and 0 <= value < 2 ** 63):
                    raise ValueError(f"moves[{i}].{name} must be a non-negative integer, got {value!r}")
        matrices, previous = [], []
        for i, m in enumerate(moves):
            for name, value, out in (("matrix", m.matrix, matrices), ("previous_matrix", m.previous_matrix, previous)):
                matrix = np.asarray(value if value is not None else np.zeros((0, 0)), dtype=np.float64)
                if matrix.shape != (4, 4) and (value is not None or name == "matrix"):
                    raise ValueError(f"moves[{i}].{name} must have shape (4, 4), got {matrix.shape}")
                if matrix.shape == (4, 4) and np.isfinite(matrix[3]).all() and \
                        not np.array_equal(matrix[3], [0.0, 0.0, 0.0, 1.0]):   # (NaN: the core names it)
                    raise ValueError(f"moves[{i}].{name} must be affine, its last row (0, 0, 0, 1), got "
                                     f"{matrix[3].tolist()} (a column-major matrix? give its transpose)")
                out.append(np.ascontiguousarray(matrix))
        native = self._native.moved(
            [int(m.vertex_start) for m in moves], [int(m.triangle_start) for m in moves],
            [int(m.triangle_count) for m in moves],
            [_array(m.positions, f"moves[{i}].positions", np.float32, 3) for i, m in enumerate(moves)],
            [_array(m.normals, f"moves[{i}].normals", np.float32, 3) for i, m in enumerate(moves)],
            [bool(m.flat) for m in moves], matrices, previous)
        out = object.__new__(Scene)
        out.__dict__.update(self.__dict__)
        out._native, out._accels = native, {}
        return out

    def geometry(self) -> dict:
        """Copies of the triangle arrays the core holds: vertices, triangles,
        normals (None when the scene has none) and triangle_materials."""
        v, t, n, m = self._native.geometry()
        return {"vertices": v, "triangles": t, "normals": n if len(n) else None,
                "triangle_materials": m.reshape(-1)}

    @property
    def texture_bytes(self) -> int:
        """Memory of the images (each stored once)."""
        return self._native.texture_bytes

    # -- counts ---------------------------------------------------------------
    @property
    def num_triangles(self) -> int:
        return self._native.num_triangles

    @property
    def num_spheres(self) -> int:
        return self._native.num_spheres

    @property
    def num_cylinders(self) -> int:
        return self._native.num_cylinders

    @property
    def num_primitives(self) -> int:
        return self.num_triangles + self.num_spheres + self.num_cylinders

    @property
    def bounds(self):
        lo, hi = self._native.bounds
        return np.array(lo), np.array(hi)

    # -- acceleration ---------------------------------------------------------
    def accel(self, settings: RenderSettings | None = None, should_stop=None):
        """The acceleration structure these settings build (built once, cached).
        Structures are keyed by the settings that shape them: the acceleration
        group's values, less its on/off traversal switches (mailboxes, skip_empty).

        should_stop: a function polled every POLL_SECONDS while the structure
        builds (in a native thread, the GIL released); once it returns True
        the build stops and BuildCancelled is raised. A KeyboardInterrupt
        (Ctrl-C) during the build stops it too, then propagates."""
        s = settings or RenderSettings()
        return self._accel(s, s.to_core(), should_stop)

    def _accel(self, s: RenderSettings, core, should_stop=None):
        """accel(s), given s.to_core() (checked once per query)."""
        key = structure_key(s)
        if key not in self._accels:
            self._accels[key] = build(self._native, core, should_stop)
        return self._accels[key]

    def grid_info(self, settings: RenderSettings | None = None) -> dict:
        """Kind, (root) resolution, grids, cells, references, memory and build
        time of the grid these settings build (the default one for accel="none")."""
        s = settings or RenderSettings()
        if s.accel == "none":
            s = s.replace(accel=RenderSettings().accel)
        return dict(self.accel(s).grid)

    # -- ray queries ----------------------------------------------------------
    def _rays(self, origins, directions, tmin, tmax):
        o = _array(origins, "origins", np.float32, 3)
        d = _array(directions, "directions", np.float32, 3)
        if d.shape != o.shape:
            raise ValueError(f"directions must have the shape of origins {o.shape}, got {d.shape}")
        n = o.shape[0]

        def per_ray(value, name):
            if type(value) in (float, int) and not 3.4028234663852886e38 < abs(value) < math.inf:
                # a number float32 holds (or NaN, or an infinity): the same for every ray
                return np.full(n, value, np.float32)
            a = np.asarray(value)
            if a.dtype == object or not (np.issubdtype(a.dtype, np.number) or a.dtype == bool) \
                    or np.issubdtype(a.dtype, np.complexfloating):
                raise ValueError(f"{name} must be a number or an array of {n} numbers, got dtype {a.dtype}")
            if a.ndim > 1 or (a.ndim == 1 and a.shape[0] != n):
                raise ValueError(f"{name} must be a number or have shape ({n},), got shape {a.shape}")
            with np.errstate(over="ignore"):
                return np.ascontiguousarray(np.broadcast_to(a.astype(np.float32), (n,)))

        return o, d, per_ray(tmin, "tmin"), per_ray(tmax, "tmax")

    def _query_settings(self, settings, deprecated: dict, method: str) -> RenderSettings:
        """The settings a ray query traces with; the keywords of the old API
        (accel=, grid_density=, mailboxes=, threads=, skip_empty=) still work
        for this release, with a warning."""
        s = settings if settings is not None else RenderSettings()
        if not isinstance(s, RenderSettings):
            raise ValueError(f"settings must be a gridwalk.RenderSettings, got {type(s).__name__}")
        if deprecated:
            unknown = set(deprecated) - set(DEPRECATED_QUERY_KEYWORDS)
            if unknown:
                raise TypeError(f"Scene.{method}() got unexpected keyword arguments {sorted(unknown)}")
            args = ", ".join(f"{k}={v!r}" for k, v in deprecated.items())
            warnings.warn(f"Scene.{method}({args}) is deprecated and will be removed in the next release: "
                          f"pass settings=RenderSettings({args}) instead", FutureWarning, stacklevel=3)
            s = s.replace(**deprecated)
        return s

    def intersect(self, origins, directions, tmin=0.0, tmax=np.inf, settings: RenderSettings | None = None,
                  spawned=False, **deprecated) -> Hits:
        """Closest hits of a batch of rays (multithreaded, GIL released),
        traced through the structure `settings` builds, as the renderer traces
        (threads, mailboxes, skip_empty are taken from it too).

        spawned=True treats the rays as leaving a surface (as the renderer's
        secondary rays do, e.g. from spawn_origins): hits closer than the
        triangle test's own error bound are then rejected as self-hits.
        """
        s = self._query_settings(settings, deprecated, "intersect")
        o, d, lo, hi = self._rays(origins, directions, tmin, tmax)
        core = s.to_core()
        t, prim, kind, u, v, n, stats = _core.intersect(self._accel(s, core), o, d, lo, hi, core, bool(spawned))
        return Hits(t, prim, kind, u, v, n, stats)

    def occluded(self, origins, directions, tmin=0.0, tmax=np.inf, settings: RenderSettings | None = None,
                 spawned=False, **deprecated) -> np.ndarray:
        """True where anything is hit in (tmin, tmax): shadow-ray queries (see intersect)."""
        s = self._query_settings(settings, deprecated, "occluded")
        o, d, lo, hi = self._rays(origins, directions, tmin, tmax)
        core = s.to_core()
        hit, _ = _core.occluded(self._accel(s, core), o, d, lo, hi, core, bool(spawned))
        return hit.astype(bool)

    def spawn_origins(self, origins, directions, hits: Hits, new_directions) -> np.ndarray:
        """Origins for rays leaving `hits` along `new_directions`, offset off the
        surface exactly as the renderer offsets its secondary rays (misses keep
        their origin). Used to test self-intersection."""
        o, d, _, _ = self._rays(origins, directions, 0.0, 0.0)
        w = _array(new_directions, "new_directions", np.float32, 3)
        if w.shape != o.shape:
            raise ValueError(f"new_directions must have shape {o.shape}, got {w.shape}")
        base = np.array([0, 0, self.num_triangles, self.num_triangles + self.num_spheres], np.int64)
        glob = np.where(hits.kind > 0, hits.prim + base[hits.kind], -1).astype(np.int32)
        return _core.spawn_origins(self.accel(), o, d, np.ascontiguousarray(hits.t, np.float32), glob,
                                   np.ascontiguousarray(hits.u, np.float32),
                                   np.ascontiguousarray(hits.v, np.float32), w)

