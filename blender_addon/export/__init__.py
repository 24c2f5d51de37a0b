"""Export an evaluated Blender depsgraph to gridwalk.Scene keyword arguments.

One module per datablock kind: meshes (and instances), lights, camera,
materials, world. Nothing here touches bpy.context: everything comes from the
depsgraph, so it works inside RenderEngine.render().
"""
from __future__ import annotations

from .camera import CameraError, convert_camera
from .lights import light_from_instance
from .materials import MaterialTable
from .meshes import MeshCollector
from .world import background_color


class ExportError(ValueError):
    """The scene cannot be rendered; the message is meant for the user."""


def export_scene(depsgraph) -> tuple[dict, list[str]]:
    """(scene_kwargs, warnings): `gridwalk.Scene(**scene_kwargs)` builds the scene.

    Raises ExportError with a user-facing message when there is no camera or
    nothing to render.
    """
    scene = depsgraph.scene_eval if hasattr(depsgraph, "scene_eval") else depsgraph.scene
    warnings: list[str] = []
    try:
        camera = convert_camera(scene.camera, scene.render, scene.unit_settings.scale_length)
    except CameraError as exc:
        raise ExportError(str(exc)) from None
    if scene.render.use_border:
        warnings.append("Render region (border) is not supported: rendering the full frame")
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
        raise ExportError("Nothing to render: the scene has no visible mesh objects "
                          "(check 'Disable in Renders' and excluded collections)")
    if not lights:
        warnings.append("The scene has no lights: only emissive materials will be visible")
    kwargs.update(materials=materials.materials, lights=lights, camera=camera,
                  background=background_color(scene.world, warnings))
    warnings.extend(materials.warnings())
    warnings.extend(meshes.warnings())
    return kwargs, warnings
