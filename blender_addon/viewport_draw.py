"""Drawing the viewport's image with the gpu module (Blender 5.0 removed bgl).

The image (scene-linear floats, from viewport.Display: rows bottom-up and
values already clamped below the half-float maximum, 65504, beyond which
the view turns black) is uploaded as an RGBA16F texture when it changed,
and drawn over the region between bind_display_space_shader and
unbind_display_space_shader, so Blender's colour management (view
transform, look, exposure) applies. Imported only by view_draw: never in
`blender -b`.
"""
from __future__ import annotations

import gpu
from gpu_extras.presets import draw_texture_2d


KEPT = []   # textures of engines freed off the main thread: freed by the next view_update / view_draw


def free_on_main_thread(texture):
    """Keep `texture` alive until free_kept() runs on the main thread (a list
    append is atomic under the GIL)."""
    KEPT.append(texture)


def free_kept():
    """Free the kept textures (main thread: view_update or view_draw, where the GPU module is usable)."""
    while KEPT:
        KEPT.pop()


class Texture:
    """The display image on the GPU, uploaded again only when it changed."""

    def __init__(self):
        self.texture, self.version = None, -1

    def update(self, session):
        with session.lock:
            display = session.display
            if display.version == self.version and self.texture is not None:
                return
            height, width = display.rgba.shape[:2]
            data = gpu.types.Buffer("FLOAT", width * height * 4, display.rgba.reshape(-1))
            self.texture = gpu.types.GPUTexture((width, height), format="RGBA16F", data=data)
            self.version = display.version

    def draw(self, engine, scene, width: int, height: int):
        gpu.state.blend_set("ALPHA_PREMULT")
        engine.bind_display_space_shader(scene)
        draw_texture_2d(self.texture, (0, 0), width, height)
        engine.unbind_display_space_shader()
        gpu.state.blend_set("NONE")


def draw(engine, session, context, depsgraph):
    """view_draw: follow the region's view, then draw the latest image."""
    from .export.camera import CameraError
    from .viewport import view_from_context
    try:
        key, camera, pixel = view_from_context(engine, context, depsgraph)
    except CameraError as exc:        # looking through a camera without a view (zero scale, NaN): say why
        session.message = f"Gridwalk: {exc}"
        engine.update_stats("", session.message)
        return
    session.follow_settings(depsgraph.scene)
    session.set_view(key, camera, pixel)
    session.poll()                           # the latest image, if it changed
    texture = engine.__dict__.setdefault("viewport_texture", Texture())
    texture.update(session)
    texture.draw(engine, depsgraph.scene, context.region.width, context.region.height)
    engine.update_stats("", session.message)
