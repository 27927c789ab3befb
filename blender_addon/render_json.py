"""Renders a Facet JSON scene inside headless Blender with the Facet addon (build.sh):
  BLENDER_USER_SCRIPTS=<dir> blender -b --factory-startup --python blender_addon/render_json.py \\
      -- <facet_blender.zip> <scene.json> <out.exr> <out.png>
Installs the addon from the zip into BLENDER_USER_SCRIPTS, imports the scene (File > Import >
Facet scene), renders it with F12's code path and writes a linear EXR and an sRGB PNG (view
transform Standard, as `facet render` writes PNGs). Fails (exit 1) when the engine reported
an error."""
import os
import sys
import traceback

import addon_utils
import bpy


def main():
    zip_path, scene_path, exr_path, png_path = sys.argv[sys.argv.index("--") + 1:][:4]
    bpy.ops.preferences.addon_install(filepath=zip_path, overwrite=True)
    addon_utils.enable("facet_blender", default_set=True, handle_error=None)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.import_scene.facet(filepath=os.path.abspath(scene_path))
    scene = bpy.context.scene
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    bpy.ops.render.render()  # raises RuntimeError when Facet reported an error
    img = bpy.data.images["Render Result"]
    settings = scene.render.image_settings
    settings.file_format, settings.color_depth, settings.color_mode = 'OPEN_EXR', '32', 'RGB'
    img.save_render(os.path.abspath(exr_path), scene=scene)
    settings.file_format, settings.color_depth, settings.color_mode = 'PNG', '8', 'RGB'
    img.save_render(os.path.abspath(png_path), scene=scene)
    print("render_json: wrote %s and %s" % (exr_path, png_path))


try:
    main()
except Exception:
    traceback.print_exc()
    sys.stdout.flush()
    os._exit(1)
