"""PropertyGroups: render settings (Scene.gridwalk) and object options (Object.gridwalk).

The render settings are built from the core's settings table
(gridwalk.settings.SCHEMA, declared once in core/src/settings.h): one
Blender property per setting, with the table's label, help, default, limits
and choices. Enum identifiers are the choices' ids in upper case
("jittered" -> "JITTERED"). Where Blender starts from another default, the
table says so and why (Setting.host_default). The settings of the "host"
group come from Blender itself (the render border becomes `region`).

memory_limit (the host's memory policy) and the viewport's options
(viewport_samples, viewport_start_pixels) are the add-on's own settings, not
render settings of the core.
"""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

# Blender's IntProperty holds a signed 32-bit integer: wider limits are clamped to it.
INT_MIN, INT_MAX = -2**31, 2**31 - 1
HOST_GROUP = "host"


def blender_settings(schema):
    """The table's settings that Blender shows (all but the host group's)."""
    return [s for s in schema if s.group != HOST_GROUP]


def blender_default(setting):
    return setting.host_default if setting.host_default is not None else setting.default


def changed(self, context):
    """A render or viewport setting changed: tag the scene, so that a rendered
    viewport follows (Blender does not update the depsgraph, nor redraw the
    3D view, when an add-on's property changes)."""
    self.id_data.update_tag()


def make_property(setting):
    """The bpy property for one row of the settings table."""
    default = blender_default(setting)
    common = dict(name=setting.label, description=setting.describe(), update=changed)
    if setting.kind == "bool":
        return BoolProperty(default=default, **common)
    if setting.kind == "enum":
        items = [(cid.upper(), label, text) for cid, label, text in setting.choices]
        return EnumProperty(items=items, default=default.upper(), **common)
    if setting.kind == "int":
        return IntProperty(default=default, min=int(max(setting.min, INT_MIN)), max=int(min(setting.max, INT_MAX)),
                           **common)
    limits = dict(min=setting.min) | ({} if setting.max == float("inf") else dict(max=setting.max))
    return FloatProperty(default=default, precision=4, **limits, **common)


class GridwalkObjectSettings(bpy.types.PropertyGroup):
    render_as_sphere: BoolProperty(
        name="Render as Sphere", default=False,
        description="Render this object as one analytic sphere (centre and radius from its "
                    "bounding box and transform) instead of its triangles")


ADDON_PROPERTIES = {
    "memory_limit": IntProperty(name="Memory Limit (MiB)", default=0, min=0, max=INT_MAX,
                                description="Refuse to render when the estimated memory exceeds this "
                                            "(0 = 75% of physical memory; GRIDWALK_MEMORY_LIMIT_MB "
                                            "also sets a limit, the lower wins)"),
    "denoising_data": BoolProperty(name="Denoising Data", default=False,
                                   description="Write the Denoising Albedo and Denoising Normal passes "
                                               "(Cycles' names) for the compositor's Denoise node"),
    "viewport_samples": IntProperty(name="Viewport Samples", default=16, min=1, max=4096, update=changed,
                                    description="Rendered viewport shading: full-resolution passes of one random "
                                                "camera sample per pixel, averaged; refining stops after these"),
    "viewport_start_pixels": IntProperty(name="Start Pixel Size", default=8, min=1, max=64, update=changed,
                                         description="Rendered viewport shading: the first, coarse pass renders "
                                                     "blocks of this many pixels (times the Pixel Size), so the "
                                                     "view answers at once; 1 skips it"),
}


def viewport_options(scene) -> tuple[int, int, bool]:
    """(samples, start pixel size, opaque) of the scene's rendered viewport."""
    props = scene.gridwalk
    return int(props.viewport_samples), int(props.viewport_start_pixels), not scene.render.film_transparent

classes = []


def register():
    from gridwalk.settings import SCHEMA

    annotations = {s.name: make_property(s) for s in blender_settings(SCHEMA)}
    annotations.update(ADDON_PROPERTIES)
    render_settings = type("GridwalkRenderSettings", (bpy.types.PropertyGroup,), {"__annotations__": annotations})
    classes[:] = [render_settings, GridwalkObjectSettings]
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.gridwalk = PointerProperty(type=render_settings)
    bpy.types.Object.gridwalk = PointerProperty(type=GridwalkObjectSettings)


def unregister():
    del bpy.types.Object.gridwalk
    del bpy.types.Scene.gridwalk
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
    classes.clear()
