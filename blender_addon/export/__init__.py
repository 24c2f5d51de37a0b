"""Export an evaluated Blender depsgraph to gridwalk.Scene keyword arguments.

One module per datablock kind: meshes (and instances), lights, camera,
materials, world. Nothing here touches bpy.context: everything comes from the
depsgraph, so it works inside RenderEngine.render().
"""
from __future__ import annotations

from .camera import CameraError, convert_camera, render_region, resolution
from .lights import light_from_instance
from .materials import MaterialTable
from .meshes import MeshCollector, count_geometry
from .world import background_color

__all__ = ["CameraError", "ExportError", "count_geometry", "export_scene", "render_region", "resolution"]


class ExportError(ValueError):
    """The scene cannot be rendered; the message is meant for the user.

    `warnings` holds what the export found before it gave up (for example the
    objects it skipped), so that the report can show why nothing was left.
    """

    def __init__(self, message: str, warnings: list[str] | None = None):
        super().__init__(message)
        self.warnings = list(warnings or [])


def export_scene(depsgraph) -> tuple[dict, list[str]]:
    """(scene_kwargs, warnings): `gridwalk.Scene(**scene_kwargs)` builds the scene.

    Raises ExportError with a user-facing message when there is no camera or
    nothing to render. Invalid objects (NaN transforms, ...) are skipped with
    a warning naming them.
    """
    scene = depsgraph.scene_eval if hasattr(depsgraph, "scene_eval") else depsgraph.scene
    warnings: list[str] = []
    try:
        camera = convert_camera(scene.camera, scene.render, scene.unit_settings.scale_length)
    except CameraError as exc:
        raise ExportError(str(exc)) from None
    materials = MaterialTable()
    meshes = MeshCollector(materials)
    lights = []
    for inst in depsgraph.object_instances:
        if inst.object.type == "LIGHT":
            light = light_from_instance(inst, warnings)
            if light is not None:
                lights.append(light)
        else:
            meshes.add_instance(inst)
    kwargs = meshes.arrays()
    if len(kwargs["triangles"]) == 0 and len(kwargs["sphere_radii"]) == 0:
        raise ExportError(_nothing_to_render(meshes), warnings + meshes.warnings())
    if not lights:
        warnings.append("The scene has no lights: only emissive materials will be visible")
    kwargs.update(materials=materials.materials, lights=lights, camera=camera,
                  background=background_color(scene.world, warnings))
    warnings.extend(materials.warnings())
    warnings.extend(meshes.warnings())
    return kwargs, warnings


def _nothing_to_render(meshes) -> str:
    names = lambda items: ", ".join(f"'{name}'" for name in sorted(items))
    hints = []
    if meshes.invalid:
        hints.append(f"skipped as invalid: {names(meshes.invalid)}")
    if meshes.faceless:
        hints.append(f"without faces: {names(meshes.faceless)}")
    if not hints:
        hints.append("check 'Disable in Renders' and excluded collections")
    return f"Nothing to render: the scene has no visible object with faces ({'; '.join(hints)})"
