"""Export an evaluated Blender depsgraph to gridwalk.Scene keyword arguments.

One module per datablock kind: meshes (and instances), lights, camera,
materials, textures (images), world. Nothing here touches bpy.context: everything comes from the
depsgraph, so it works inside RenderEngine.render().
"""
from __future__ import annotations

import math
import time

import numpy as np

from .camera import CameraError, convert_camera, render_region, resolution, shear_note
from .carrier_instances import CarrierInstances
from .lights import light_from_instance
from .materials import MaterialTable
from .mesh_cache import MeshCache
from .meshes import MeshCollector, count_geometry
from .textures import TextureTable, reads_instance_attributes
from .world import convert_world

__all__ = ["CameraError", "Export", "ExportCancelled", "ExportError", "MeshCache", "count_geometry", "export_scene", "render_region",
           "resolution"]


class ExportError(ValueError):
    """The scene cannot be rendered; the message is meant for the user.

    `warnings` holds what the export found before it gave up (for example the
    objects it skipped), so that the report can show why nothing was left.
    """

    def __init__(self, message: str, warnings: list[str] | None = None):
        super().__init__(message)
        self.warnings = list(warnings or [])


STOP_SECONDS = 2e-4   # the export's time between should_stop() calls


class ExportCancelled(Exception):
    """should_stop() said stop while the export was reading the depsgraph."""


class Export:
    """One export of a depsgraph, before the triangle arrays are assembled:
    meshes (MeshCollector), materials, lights, background, camera, warnings.
    signature() tells two exports of the same content apart cheaply (the
    viewport restarts only when it changes); kwargs() assembles the arrays."""

    def __init__(self, depsgraph, cache: MeshCache | None = None, camera: bool = True, should_stop=None):
        """should_stop(), if given, is asked before the first object instance, then
        before each one that comes STOP_SECONDS or more after the last question
        (it costs a few microseconds, a third of an instance of a mesh read
        already: every instance after a mesh's first read, every 20th or so of
        the scattered ones), and before each block of mesh instances that
        MeshCollector.finish() makes into parts; when it says True the export
        stops with ExportCancelled (a cancel lands within one object's read)."""
        scene = depsgraph.scene_eval if hasattr(depsgraph, "scene_eval") else depsgraph.scene
        self.warnings: list[str] = []
        try:
            self.camera = convert_camera(scene.camera, scene.render) \
                if camera else None
        except CameraError as exc:
            raise ExportError(str(exc)) from None
        sheared = shear_note(scene.camera) if camera else None
        if sheared:
            self.warnings.append(sheared)
        cache = cache if cache is not None else MeshCache()
        self.textures = TextureTable(cache.images)
        if should_stop is not None:
            self.textures.cancelled = should_stop
        view_layer = getattr(depsgraph, "view_layer_eval", None) or getattr(depsgraph, "view_layer", None)
        self.materials = MaterialTable(self.textures, getattr(view_layer, "material_override", None))
        render = getattr(depsgraph, "mode", "RENDER") == "RENDER"   # (a final render's depsgraph; else the viewport's)
        self.meshes = MeshCollector(self.materials, cache, getattr(depsgraph, "view_layer", None), render)
        self.lights = []
        unrendered = {}   # label -> names of objects of a kind the core has no primitive for
        asked = -math.inf

        def visit(inst):
            obj = inst.object
            kind = obj.type
            if kind == "LIGHT":
                light = light_from_instance(inst, self.warnings)
                if light is not None:
                    self.lights.append(light)
            elif kind in UNRENDERED_TYPES:
                if inst.show_self and not obj.original.hide_render:
                    # (a volume that another object's Geometry Nodes make: that object's other geometry renders)
                    label = UNRENDERED_TYPES[kind] if obj.original.type == kind else \
                        f"{kind.title()}s that Geometry Nodes make (the rest of each object renders) are"
                    unrendered.setdefault(label, set()).add(obj.original.name)
            else:
                self.meshes.add_instance(inst, obj)

        # (a Geometry Nodes carrier's copies are read in bulk where they check out: carrier_instances)
        carriers = CarrierInstances(self.meshes, reads_instance_attributes(depsgraph))
        for inst in depsgraph.object_instances:
            if should_stop is not None and time.perf_counter() - asked >= STOP_SECONDS:
                if should_stop():
                    raise ExportCancelled()
                asked = time.perf_counter()
            if not carriers.take(inst):
                visit(inst)
        again = carriers.finish()
        self.bulk_copies = carriers.copies     # (Geometry Nodes copies read in bulk: tests and benchmarks)
        if again:       # (carriers whose copies did not check out: read one by one, under their numbers)
            last = self.meshes.next_seq()
            for inst in depsgraph.object_instances:
                if should_stop is not None and time.perf_counter() - asked >= STOP_SECONDS:
                    if should_stop():
                        raise ExportCancelled()
                    asked = time.perf_counter()
                seq = carriers.read_again(inst, again)
                if seq is not None:
                    self.meshes.count_from(seq)
                    visit(inst)
            self.meshes.count_from(last + 1)
        if not self.meshes.finish(should_stop):
            raise ExportCancelled()
        self.warnings.extend(f"{label} not rendered: " + ", ".join(f"'{n}'" for n in sorted(names))
                             for label, names in sorted(unrendered.items()))
        self.warnings.extend(_collection_warnings(depsgraph))
        self.world_warnings: list[str] = []
        self.background, self.world = convert_world(scene.world, self.textures, self.world_warnings)
        self.world.transparent = bool(scene.render.film_transparent)   # camera misses: RGB 0, alpha 0

    def signature(self) -> tuple:
        """What the scene arrays and records are made of: each instance's mesh
        entry, matrix and materials, the spheres (point clouds and hair by a hash), materials, lights, background,
        the instances' Object Info values."""
        parts = tuple((key, matrix.tobytes(), lookup.tobytes()) for key, _, matrix, lookup in self.meshes.parts)
        spheres = tuple((tuple(c), r, m) for c, r, m in self.meshes.spheres)
        points = tuple(p.digest() for p in self.meshes.point_sets + self.meshes.cone_sets)
        return (parts, spheres, points, repr(self.materials.materials), repr(self.lights), self.background,
                repr(self.world), repr(self.textures.textures), tuple(image.name for image in self.textures.images),
                None if self.meshes.part_values is None else self.meshes.part_values.tobytes())

    def kwargs(self, world_only: bool = False, mattes: tuple = ()) -> tuple[dict, list[str]]:
        """(scene_kwargs, warnings): `gridwalk.Scene(**scene_kwargs)` builds the scene.

        When there is nothing to render, raises ExportError with a user-facing
        message, or with world_only (a final render, where Cycles renders the
        world) gives a scene that shows the world alone and says why in a
        warning. Invalid objects (NaN transforms, ...) are skipped
        with a warning naming them. mattes: the layers of matte keys the scene
        gets (matte_keys: per primitive, a key of each layer named, in that
        order: "object", "material", "asset"); `matte_tables` then gives per
        layer each key's (name, pass index) (Cryptomatte, Object and Material
        Index)."""
        warnings = list(self.warnings)
        kwargs = self.meshes.arrays()
        if len(kwargs["triangles"]) == 0 and len(kwargs["sphere_radii"]) == 0 and "cylinder_materials" not in kwargs:
            if not world_only:
                raise ExportError(_nothing_to_render(self.meshes), warnings + self.meshes.warnings())
            warnings.append(_nothing_to_render(self.meshes) + ": the frame shows the world alone")
            # (The core takes no empty scene: one triangle of zero area, which no ray can hit.)
            kwargs.update(vertices=np.zeros((3, 3), np.float32), triangles=np.array([[0, 1, 2]], np.int32),
                          normals=None, triangle_materials=np.zeros(1, np.int32))
        if not self.lights and not any(self.world.ambient) and self.world.environment < 0 \
                and not any(m.emits_light for m in self.materials.materials):
            warnings.append("The scene has no lights and a black world: only emissive materials will be visible")
        warnings.extend(self.world_warnings)
        if self.camera is not None:
            kwargs["camera"] = self.camera
        kwargs.update(materials=self.materials.materials, lights=self.lights, background=self.background,
                      world=self.world)
        if self.textures.textures:
            kwargs.update(images=self.textures.images, textures=self.textures.textures)
        warnings.extend(self.materials.warnings())
        warnings.extend(self.textures.warnings())
        self.textures.prune()
        warnings.extend(self.meshes.warnings())
        if mattes:
            kwargs["matte_keys"], self.matte_tables = self._matte_keys(kwargs, mattes)
        return kwargs, warnings

    def _matte_keys(self, kwargs, layers) -> tuple[np.ndarray, dict]:
        """((primitives, len(layers)) int32 keys, -1 for none; per layer its keys' (name, pass index))."""
        entries, which = self.meshes.primitive_names(kwargs)     # entries: (object, asset, pass index)
        materials = np.concatenate([np.asarray(kwargs.get(k, np.zeros(0, np.int32)), np.int32).reshape(-1) for k in
                                    ("triangle_materials", "sphere_materials", "cylinder_materials")])
        if len(materials) != len(which):
            raise ValueError("matte keys: the primitives' names and materials do not line up")
        assets = sorted({e[1] for e in entries})
        asset_key = {name: k for k, name in enumerate(assets)}   # (a dict: a scene may have thousands)
        asset_of = np.array([asset_key[e[1]] for e in entries] + [-1], np.int32)   # (which -1: the last)
        # one key per (name, pass index): a material's copy for spheres (MaterialTable.shape_material)
        # is the same Blender material
        first = {}
        material_key = np.array([first.setdefault(n, len(first)) for n in self.materials.matte_names] + [-1], np.int32)
        columns = {"object": which, "material": material_key[np.where(which >= 0, materials, -1)],
                   "asset": asset_of[which]}
        tables = {"object": [(e[0], e[2]) for e in entries], "material": list(first),
                  "asset": [(a, 0) for a in assets]}
        return np.stack([columns[layer] for layer in layers], axis=1), {layer: tables[layer] for layer in layers}


def export_scene(depsgraph, cache: MeshCache | None = None, camera: bool = True) -> tuple[dict, list[str]]:
    """(scene_kwargs, warnings) of the depsgraph (see Export): a camera is
    required unless camera=False (the viewport renders its own view).
    Raises ExportError with a user-facing message when there is no camera or
    nothing to render."""
    return Export(depsgraph, cache, camera).kwargs()


# Object types whose geometry the core has no primitive for (warned, not rendered).
UNRENDERED_TYPES = {"VOLUME": "Volume objects are"}


def _collection_warnings(depsgraph) -> list[str]:
    """The view layer's collections set to Indirect Only, which the core does
    not model (their objects render as the others do). (Holdout is rendered:
    MeshCollector asks each object's holdout_get.)"""
    view_layer = getattr(depsgraph, "view_layer_eval", None) or getattr(depsgraph, "view_layer", None)
    if view_layer is None:
        return []
    found = {"Indirect Only": []}
    stack = list(view_layer.layer_collection.children)
    while stack:
        layer = stack.pop()
        if layer.exclude:
            continue
        if getattr(layer, "indirect_only", False):
            found["Indirect Only"].append(layer.name)
        stack.extend(layer.children)
    return [f"Collection setting {label} is not supported (its objects render as any other): "
            + ", ".join(f"'{name}'" for name in sorted(names)) for label, names in found.items() if names]


def _nothing_to_render(meshes) -> str:
    names = lambda items: ", ".join(f"'{name}'" for name in sorted(items))
    hints = []
    if meshes.invalid:
        hints.append(f"skipped as invalid: {names(meshes.invalid)}")
    if meshes.without_faces():
        hints.append(f"without faces: {names(meshes.without_faces())}")
    if not hints:
        hints.append("check 'Disable in Renders' and excluded collections")
    return f"Nothing to render: the scene has no visible object with faces ({'; '.join(hints)})"
