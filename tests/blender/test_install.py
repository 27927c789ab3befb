"""The addon installs from the zip (Preferences > Add-ons > Install...) and registers: the
engine is listed as "Facet", the material properties carry the core's model table."""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def main():
    zip_path = bt.args()[0]
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    bt.enable_addon()
    import facet
    import facet_blender
    engines = {e.bl_idname: e.bl_label for e in bpy.types.RenderEngine.__subclasses__()}
    bt.check(engines.get("FACET") == "Facet", "engine FACET listed as 'Facet'")
    scene = bpy.context.scene
    scene.render.engine = 'FACET'
    bt.check(scene.render.engine == 'FACET', "Facet selectable as the render engine")
    names = [m.name for m in facet.models()]
    items = [i.identifier for i in bpy.types.Material.bl_rna.properties["facet"].fixed_type
             .properties["model"].enum_items]
    bt.check(items == names, "material models are the core's table: %s" % names)
    bt.check(os.path.dirname(facet.__file__).startswith(os.path.dirname(facet_blender.__file__)),
             "the native module is the zip's (%s)" % facet.__file__)
    bt.check(bpy.types.RENDER_PT_format.COMPAT_ENGINES >= {"FACET"}, "usual panels visible")
    bt.check("FACET" not in bpy.types.CYCLES_RENDER_PT_sampling.COMPAT_ENGINES
             and "FACET" not in bpy.types.CYCLES_RENDER_PT_light_paths.COMPAT_ENGINES,
             "Cycles' own render settings stay hidden for Facet")
    bt.check("FACET" not in bpy.types.RENDER_PT_eevee_sampling.COMPAT_ENGINES,
             "Eevee's panels stay hidden for Facet")
    bt.check(hasattr(bpy.types, "FACET_PT_material_surface")
             and hasattr(bpy.types, "FACET_PT_material_preview"),
             "Facet's node surface and preview panels registered")


bt.run(main)
