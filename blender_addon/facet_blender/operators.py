"""File > Import / Export > Facet scene (.json), through the core's JSON reader and writer."""
import bpy
from bpy.props import StringProperty
from bpy_extras.io_utils import ExportHelper, ImportHelper

from . import bake, export, importer, native, sync_state, sync_volume


class FACET_OT_import_scene(bpy.types.Operator, ImportHelper):
    """Import a Facet JSON scene (scenes/FORMAT.md)"""
    bl_idname = "import_scene.facet"
    bl_label = "Import Facet Scene"
    bl_options = {'REGISTER', 'UNDO'}
    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def execute(self, context):
        try:
            data = native.read_scene(self.filepath)
        except Exception as e:  # the core's message names the file and JSON pointer
            self.report({'ERROR'}, "Facet: %s" % e)
            return {'CANCELLED'}
        problems = []
        importer.import_scene(context, data, problems=problems)
        for line in problems:
            self.report({'WARNING'}, "Facet: %s" % line)
        if context.scene.render.engine != 'FACET':
            context.scene.render.engine = 'FACET'
        return {'FINISHED'}


class FACET_OT_export_scene(bpy.types.Operator, ExportHelper):
    """Export the scene as a Facet JSON scene, for `facet render`"""
    bl_idname = "export_scene.facet"
    bl_label = "Export Facet Scene"
    filename_ext = ".json"
    filter_glob: StringProperty(default="*.json", options={'HIDDEN'})

    def execute(self, context):
        depsgraph = context.evaluated_depsgraph_get()
        try:
            data, problems = export.export_scene(depsgraph)
            for p in problems:
                self.report({'WARNING'}, "Facet: " + p)
            sync_volume.copy_grids_beside(data, self.filepath)
            native.write_scene(data, self.filepath)
        except Exception as e:
            self.report({'ERROR'}, "Facet: %s" % e)
            return {'CANCELLED'}
        return {'FINISHED'}


class FACET_OT_clear_shape(bpy.types.Operator):
    """Forget the exact imported shape: render the object's Blender mesh instead"""
    bl_idname = "facet.clear_shape"
    bl_label = "Use the Blender Mesh"
    bl_options = {'REGISTER', 'UNDO'}

    def execute(self, context):
        ob = context.object
        for k in ("facet_shape", "facet_state"):
            if k in ob:
                del ob[k]
        return {'FINISHED'}


def _menu_import(self, context):
    self.layout.operator(FACET_OT_import_scene.bl_idname, text="Facet scene (.json)")


def _menu_export(self, context):
    self.layout.operator(FACET_OT_export_scene.bl_idname, text="Facet scene (.json)")


class FACET_OT_bake_inputs(bpy.types.Operator):
    """Bake every material input Facet cannot express (procedural textures, ...) into an image
    over its object's UV map, with Cycles (bake.py); cached until the material changes"""
    bl_idname = "facet.bake_inputs"
    bl_label = "Bake Procedural Inputs"
    bl_options = {'REGISTER'}

    def execute(self, context):
        try:
            export.export_scene(context.evaluated_depsgraph_get())  # collects bake.PENDING
        except sync_state.ExportError:
            pass  # no camera: the materials were still collected
        todo = list(bake.PENDING)
        if not todo:
            self.report({'INFO'}, "Facet: nothing to bake (every input converts or is baked)")
            return {'FINISHED'}
        wm = context.window_manager
        wm.progress_begin(0, len(todo))
        try:
            done = bake.bake_all(context, todo, progress=lambda i, n: wm.progress_update(i))
        finally:
            wm.progress_end()
        bad = 0
        for req, err in done:
            if err is None:
                self.report({'INFO'}, "Facet: baked %s" % req.describe())
            else:
                bad += 1
                self.report({'ERROR'}, "Facet: baking %s failed: %s" % (req.describe(), err))
        bake.PENDING.clear()
        return {'FINISHED'} if bad == 0 else {'CANCELLED'}


_classes = (FACET_OT_import_scene, FACET_OT_export_scene, FACET_OT_clear_shape,
            FACET_OT_bake_inputs)


def register():
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.TOPBAR_MT_file_import.append(_menu_import)
    bpy.types.TOPBAR_MT_file_export.append(_menu_export)


def unregister():
    bpy.types.TOPBAR_MT_file_export.remove(_menu_export)
    bpy.types.TOPBAR_MT_file_import.remove(_menu_import)
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
