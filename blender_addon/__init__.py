"""Gridwalk render engine for Blender: registration only.

Installs as a Blender 4.2+ extension (blender_manifest.toml, with the gridwalk
wheel under ./wheels) or, on Blender 3.4 - 4.1, as a legacy add-on (bl_info).
"""

bl_info = {
    "name": "Gridwalk",
    "author": "Gridwalk developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Render > Render Engine > Gridwalk",
    "description": "Grid-accelerated Whitted / distribution ray tracer",
    "category": "Render",
}


def register():
    from . import dependencies, engine, nff_import, properties, ui
    dependencies.add_bundled_wheels()
    from .export import main_thread
    properties.register()
    ui.register()
    engine.register()
    nff_import.register()
    main_thread.register()


def unregister():
    from . import engine, nff_import, properties, ui
    from .export import main_thread
    main_thread.unregister()
    nff_import.unregister()
    engine.unregister()
    ui.unregister()
    properties.unregister()
