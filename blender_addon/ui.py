"""Panels: render settings, the object's "Render as sphere", Ray Visibility and Shadow Catcher, lights.

Blender's own panels (camera, lens, depth of field, material slots and surface,
world, output, colour management, ...) are shown for GRIDWALK by adding
"GRIDWALK" to their COMPAT_ENGINES on register, and removed on unregister.
"""
import bpy

ENGINE = "GRIDWALK"
# Built-in panels made visible besides every panel that lists BLENDER_RENDER
# (the "generic" panels). Missing names (other Blender versions) are skipped.
EXTRA_BUILTIN_PANELS = (
    "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture",
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface",
    "EEVEE_WORLD_PT_surface",
)
# Generic panels that would duplicate ours.
EXCLUDED_BUILTIN_PANELS = ("DATA_PT_light",)
# The object types whose Ray Visibility and Shadow Catcher the object panel shows.
GEOMETRY_TYPES = ("MESH", "CURVE", "SURFACE", "FONT", "META", "POINTCLOUD", "CURVES", "EMPTY")
RAY_VISIBILITY = (("visible_camera", "Camera"), ("visible_glossy", "Glossy"),
                  ("visible_transmission", "Transmission"), ("visible_shadow", "Shadow"))


class GridwalkPanel:
    COMPAT_ENGINES = {ENGINE}
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


def draw_settings(layout, props, groups):
    """Every setting of the table's `groups`, in table order; a setting that
    does not matter for the others' values (Setting.when) is greyed out."""
    from gridwalk.settings import SCHEMA

    from .properties import blender_settings
    layout.use_property_split = True
    col = layout.column()
    values = {s.name: getattr(props, s.name) for s in blender_settings(SCHEMA)}
    values = {k: v.lower() if isinstance(v, str) else v for k, v in values.items()}
    for setting in blender_settings(SCHEMA):
        if setting.group in groups:
            row = col.row()
            row.active = setting.relevant(values)
            row.prop(props, setting.name)
    return col


class SettingsPanel(GridwalkPanel):
    """A render-properties panel showing the settings table's `groups`."""
    bl_context = "render"
    groups = ()

    def draw(self, context):
        draw_settings(self.layout, context.scene.gridwalk, self.groups)


class GRIDWALK_RENDER_PT_sampling(SettingsPanel, bpy.types.Panel):
    bl_label = "Sampling"
    groups = ("sampling", "lights", "lens")


class GRIDWALK_RENDER_PT_acceleration(SettingsPanel, bpy.types.Panel):
    bl_label = "Acceleration"
    groups = ("acceleration",)


class GRIDWALK_RENDER_PT_performance(SettingsPanel, bpy.types.Panel):
    bl_label = "Performance"
    bl_options = {"DEFAULT_CLOSED"}
    groups = ("performance",)

    def draw(self, context):
        super().draw(context)
        self.layout.prop(context.scene.gridwalk, "memory_limit")
        self.layout.prop(context.scene.gridwalk, "denoising_data")


class GRIDWALK_RENDER_PT_viewport(GridwalkPanel, bpy.types.Panel):
    """Rendered viewport shading: samples, the coarse first pass, Blender's pixel size."""
    bl_label = "Viewport"
    bl_context = "render"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        col = layout.column()
        col.prop(context.scene.gridwalk, "viewport_samples", text="Samples")
        col.prop(context.scene.gridwalk, "viewport_start_pixels")
        col.prop(context.scene.render, "preview_pixel_size", text="Pixel Size")


SETTINGS_PANELS = (GRIDWALK_RENDER_PT_sampling, GRIDWALK_RENDER_PT_acceleration, GRIDWALK_RENDER_PT_performance)


class GRIDWALK_OBJECT_PT_settings(GridwalkPanel, bpy.types.Panel):
    bl_label = "Gridwalk"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.object is not None

    def draw(self, context):
        layout, ob = self.layout, context.object
        layout.prop(ob.gridwalk, "render_as_sphere")
        # (Blender's own Visibility panel shows these for Cycles and EEVEE only; GRIDWALK renders them)
        if ob.type in GEOMETRY_TYPES:
            layout.use_property_split = True
            col = layout.column(heading="Ray Visibility")
            for prop, text in RAY_VISIBILITY:
                if hasattr(ob, prop):
                    col.prop(ob, prop, text=text, toggle=False)
            if hasattr(ob, "is_shadow_catcher"):
                layout.column(heading="Mask").prop(ob, "is_shadow_catcher", toggle=False)


class GRIDWALK_LIGHT_PT_light(GridwalkPanel, bpy.types.Panel):
    bl_label = "Light"
    bl_context = "data"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.light is not None

    def draw(self, context):
        light = context.light
        layout = self.layout
        layout.row().prop(light, "type", expand=True)
        layout.use_property_split = True
        col = layout.column()
        col.prop(light, "color")
        col.prop(light, "energy")
        for name in ("exposure", "normalize"):
            if hasattr(light, name):
                col.prop(light, name)
        col.prop(light, "use_shadow", text="Cast Shadow")
        if light.type in ("POINT", "SPOT"):
            col.prop(light, "shadow_soft_size", text="Radius")
            if hasattr(light, "use_soft_falloff"):   # (Blender 4.0+)
                col.prop(light, "use_soft_falloff")
        if light.type == "SPOT":
            col.prop(light, "spot_size")
            col.prop(light, "spot_blend")
        elif light.type == "SUN":
            col.prop(light, "angle")
        elif light.type == "AREA":
            col.prop(light, "shape")
            if light.shape in ("SQUARE", "DISK"):
                col.prop(light, "size")
            else:
                col.prop(light, "size", text="Size X")
                col.prop(light, "size_y", text="Y")


class GRIDWALK_CAMERA_PT_panorama(GridwalkPanel, bpy.types.Panel):
    """A Panoramic camera's type and the settings of that type (export/camera.py's
    PANORAMAS), which Blender's Lens panel draws for Cycles only."""
    bl_label = "Panorama"
    bl_context = "data"
    bl_parent_id = "DATA_PT_lens"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.camera is not None and context.camera.type == "PANO"

    def draw(self, context):
        from .export.camera import PANORAMAS, panorama_settings
        holder = panorama_settings(context.camera)
        layout = self.layout
        layout.use_property_split = True
        if holder is None:
            layout.label(text="Enable the Cycles add-on to set up panoramas (Blender 3.x keeps them there)",
                         icon="ERROR")
            return
        col = layout.column()
        col.prop(holder, "panorama_type")
        if holder.panorama_type not in PANORAMAS:
            col.label(text="Gridwalk does not render this panorama type", icon="ERROR")
            return
        sub = None
        for name in PANORAMAS[holder.panorama_type][1]:
            if name.endswith(("_min", "_k0")) or sub is None:   # (a range, or the coefficients, kept together)
                sub = col.column(align=True)
            sub.prop(holder, name)


classes = (GRIDWALK_RENDER_PT_sampling, GRIDWALK_RENDER_PT_viewport, GRIDWALK_RENDER_PT_acceleration,
           GRIDWALK_RENDER_PT_performance, GRIDWALK_OBJECT_PT_settings, GRIDWALK_LIGHT_PT_light,
           GRIDWALK_CAMERA_PT_panorama)


def builtin_panels():
    """The built-in panel classes GRIDWALK shares."""
    panels = []
    for name in dir(bpy.types):
        cls = getattr(bpy.types, name, None)
        engines = getattr(cls, "COMPAT_ENGINES", None)
        if not isinstance(engines, set) or name in EXCLUDED_BUILTIN_PANELS:
            continue
        if "BLENDER_RENDER" in engines or name in EXTRA_BUILTIN_PANELS:
            panels.append(cls)
    return panels


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    for panel in builtin_panels():
        panel.COMPAT_ENGINES.add(ENGINE)


def unregister():
    for panel in builtin_panels():
        panel.COMPAT_ENGINES.discard(ENGINE)
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
