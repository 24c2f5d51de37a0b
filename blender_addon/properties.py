"""PropertyGroups: render settings (Scene.gridwalk) and object options (Object.gridwalk).

The render settings mirror gridwalk.RenderSettings one to one; settings.py
turns them into a RenderSettings. Enum identifiers are the lower-cased
RenderSettings values in upper case (e.g. "JITTERED" -> "jittered").
"""
import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty

ACCEL_ITEMS = [
    ("GRID", "Uniform Grid", "Amanatides & Woo uniform grid"),
    ("NONE", "None", "Test every primitive (brute force, for comparison)"),
]
AA_ITEMS = [
    ("CENTER", "Pixel Centre", "One ray through each pixel centre"),
    ("JITTERED", "Jittered", "Stratified n x n jittered samples per pixel"),
    ("RANDOM", "Random", "n x n uniformly random samples per pixel"),
    ("ADAPTIVE", "Adaptive", "Whitted's adaptive Monte Carlo supersampling"),
    ("SOBOL", "Sobol", "Owen-scrambled Sobol (low discrepancy) samples"),
]
SHADOW_ITEMS = [
    ("HARD", "Hard", "One shadow ray to each light's centre"),
    ("RANDOM", "Random", "A random point on the light per shadow ray"),
    ("AREA", "Area", "An n x n jittered grid of light positions, shuffled per pixel"),
]
FILTER_ITEMS = [
    ("BOX", "Box", "Box pixel filter"),
    ("GAUSSIAN", "Gaussian", "Gaussian pixel filter"),
]


class GridwalkRenderSettings(bpy.types.PropertyGroup):
    accel: EnumProperty(name="Acceleration", items=ACCEL_ITEMS, default="GRID")
    grid_density: FloatProperty(name="Grid Density (M)", default=2.0, min=0.01, soft_max=16.0,
                                description="Cells per axis factor M of the uniform grid")
    mailboxes: BoolProperty(name="Mailboxes", default=True,
                            description="Skip primitives already tested by the same ray")
    skip_empty: BoolProperty(name="Skip Empty Space", default=True,
                             description="Jump across blocks of empty grid cells")
    max_cells: IntProperty(name="Max Cells", default=1 << 24, min=1, max=2**31 - 1,
                           description="Cap on grid cells; past it the density M is reduced")
    min_weight: FloatProperty(name="Min Path Weight", default=1e-3, min=0.0, max=1.0, precision=4,
                              description="Secondary rays whose path weight falls below this are skipped")
    threads: IntProperty(name="Threads", default=0, min=0, max=1024,
                         description="Worker threads (0 = all cores)")
    tile_size: IntProperty(name="Tile Size", default=32, min=4, max=1024)
    memory_limit: IntProperty(name="Memory Limit (MiB)", default=0, min=0, max=2**31 - 1,
                              description="Refuse to render when the estimated memory exceeds this "
                                          "(0 = 75% of physical memory; GRIDWALK_MEMORY_LIMIT_MB "
                                          "also sets a limit, the lower wins)")
    max_depth: IntProperty(name="Max Depth", default=5, min=1, max=64,
                           description="Ray generations (1 = primary rays only)")
    seed: IntProperty(name="Seed", default=0, min=0)
    aa: EnumProperty(name="Anti-Aliasing", items=AA_ITEMS, default="JITTERED")
    aa_samples: IntProperty(name="AA Samples (n)", default=2, min=1, max=64,
                            description="n: n x n samples per pixel")
    adaptive_threshold: FloatProperty(name="Adaptive Threshold", default=0.05, min=0.0, max=1.0)
    adaptive_depth: IntProperty(name="Adaptive Depth", default=3, min=0, max=6)
    filter: EnumProperty(name="Pixel Filter", items=FILTER_ITEMS, default="BOX")
    filter_width: FloatProperty(name="Filter Width", default=0.5, min=0.01, max=4.0,
                                description="Gaussian standard deviation in pixels")
    shadow: EnumProperty(name="Soft Shadows", items=SHADOW_ITEMS, default="HARD")
    shadow_samples: IntProperty(name="Shadow Samples", default=1, min=1, max=64,
                                description="Random: rays per light; Area: n of the n x n grid")
    dof_samples: IntProperty(name="DoF Samples", default=1, min=1, max=1024,
                             description="Lens samples per pixel sample")
    glossy_samples: IntProperty(name="Glossy Samples", default=1, min=1, max=1024,
                                description="Rays at the first glossy bounce")


class GridwalkObjectSettings(bpy.types.PropertyGroup):
    render_as_sphere: BoolProperty(
        name="Render as Sphere", default=False,
        description="Render this object as one analytic sphere (centre and radius from its "
                    "bounding box and transform) instead of its triangles")


classes = (GridwalkRenderSettings, GridwalkObjectSettings)


def register():
    for cls in classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.gridwalk = PointerProperty(type=GridwalkRenderSettings)
    bpy.types.Object.gridwalk = PointerProperty(type=GridwalkObjectSettings)


def unregister():
    del bpy.types.Object.gridwalk
    del bpy.types.Scene.gridwalk
    for cls in reversed(classes):
        bpy.utils.unregister_class(cls)
