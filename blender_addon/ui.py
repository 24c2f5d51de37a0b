"""Panels: render settings, the object's "Render as sphere" option, lights.

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


class GridwalkPanel:
    COMPAT_ENGINES = {ENGINE}
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES


class GRIDWALK_RENDER_PT_sampling(GridwalkPanel, bpy.types.Panel):
    bl_label = "Sampling"
    bl_context = "render"

    def draw(self, context):
        props = context.scene.gridwalk
        layout = self.layout
        layout.use_property_split = True
        col = layout.column()
        col.prop(props, "aa")
        col.prop(props, "aa_samples", text="Samples")
        if props.aa == "ADAPTIVE":
            col.prop(props, "adaptive_threshold", text="Threshold")
            col.prop(props, "adaptive_depth", text="Depth")
        col.prop(props, "filter", text="Filter")
        if props.filter == "GAUSSIAN":
            col.prop(props, "filter_width", text="Width")
        col.separator()
        col.prop(props, "shadow", text="Shadows")
        sub = col.column()
        sub.active = props.shadow != "HARD"
        sub.prop(props, "shadow_samples", text="Samples")
        col.prop(props, "dof_samples", text="DoF Samples")
        col.prop(props, "glossy_samples", text="Glossy Rays")
        col.prop(props, "max_depth")
        col.prop(props, "min_weight")


class GRIDWALK_RENDER_PT_acceleration(GridwalkPanel, bpy.types.Panel):
    bl_label = "Acceleration"
    bl_context = "render"

    def draw(self, context):
        props = context.scene.gridwalk
        layout = self.layout
        layout.use_property_split = True
        col = layout.column()
        col.prop(props, "accel", text="Method")
        sub = col.column()
        sub.active = props.accel == "GRID"
        sub.prop(props, "grid_density", text="Density M")
        sub.prop(props, "max_cells")
        sub.prop(props, "skip_empty")
        col.prop(props, "mailboxes")


class GRIDWALK_RENDER_PT_performance(GridwalkPanel, bpy.types.Panel):
    bl_label = "Performance"
    bl_context = "render"
    bl_options = {"DEFAULT_CLOSED"}

    def draw(self, context):
        props = context.scene.gridwalk
        layout = self.layout
        layout.use_property_split = True
        col = layout.column()
        col.prop(props, "threads")
        col.prop(props, "tile_size")
        col.prop(props, "seed")
        col.prop(props, "memory_limit")


class GRIDWALK_OBJECT_PT_settings(GridwalkPanel, bpy.types.Panel):
    bl_label = "Gridwalk"
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return super().poll(context) and context.object is not None

    def draw(self, context):
        self.layout.prop(context.object.gridwalk, "render_as_sphere")


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
        if light.type in ("POINT", "SPOT"):
            col.prop(light, "shadow_soft_size", text="Radius")
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


classes = (GRIDWALK_RENDER_PT_sampling, GRIDWALK_RENDER_PT_acceleration,
           GRIDWALK_RENDER_PT_performance, GRIDWALK_OBJECT_PT_settings, GRIDWALK_LIGHT_PT_light)


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
