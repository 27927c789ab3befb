"""The Facet render engine: the class Blender registers. It keeps no render state of its own
and hands each mode to its session: render() (F12, animation frames, material previews) to a
final.FinalSession, view_update()/view_draw() (Rendered shading) to the
viewport.ViewportSession it keeps while the 3D view shows Facet."""
import bpy

from . import final, passes, viewport


class FacetRenderEngine(bpy.types.RenderEngine):
    bl_idname = 'FACET'
    bl_label = 'Facet'
    bl_use_preview = True  # material previews (small, few samples)
    bl_use_shading_nodes_custom = False  # keep Cycles' shader node editor
    bl_use_postprocess = True

    def render(self, depsgraph):
        final.FinalSession(self).render(depsgraph)

    def update_render_passes(self, scene=None, renderlayer=None):
        passes.register_passes(self, scene, renderlayer)

    def view_update(self, context, depsgraph):
        vs = getattr(self, "_viewport", None)
        if vs is None:
            vs = self._viewport = viewport.ViewportSession()
        vs.view_update(self, context, depsgraph)

    def view_draw(self, context, depsgraph):
        vs = getattr(self, "_viewport", None)
        if vs is not None:
            vs.view_draw(self, context, depsgraph)

    def __del__(self):
        # May run twice (Blender 3.4); the worker never holds the engine, so this runs here.
        vs = getattr(self, "_viewport", None)
        if vs is not None:
            self._viewport = None
            vs.stop()


def register():
    bpy.utils.register_class(FacetRenderEngine)


def unregister():
    bpy.utils.unregister_class(FacetRenderEngine)
