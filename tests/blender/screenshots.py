"""Screenshots for docs/blender.md (not a test; run by hand under Xvfb):
  xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup <default.blend> \\
      --python tests/blender/screenshots.py -- <out dir>
Writes render_properties.png (Render Properties with Facet chosen), engine_menu_full.png (the
window with the Render Engine menu open, listing Facet; docs/blender.md shows its top 500 rows as
engine_menu.png),
material_panel.png (the Facet material panel with its lobe plot) and viewport.png (Rendered
shading)."""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402

OUT = bt.args()[0]
state = {"phase": 0}


def area_of(kind):
    win = bpy.context.window_manager.windows[0]
    return win, next(a for a in win.screen.areas if a.type == kind)


def shot(kind, name):
    win, area = area_of(kind)
    with bpy.context.temp_override(window=win, area=area):
        bpy.ops.screen.screenshot_area(filepath=os.path.join(OUT, name))


def step():
    try:
        ph = state["phase"]
        state["phase"] += 1
        if ph == 0:
            bt.enable_addon()
            scene = bpy.context.scene
            scene.render.engine = 'FACET'
            scene.facet.viewport_spp = 64
            mat = bpy.data.materials["Material"]
            mat.use_nodes = False  # Cycles' Surface panel shrinks to its Use Nodes button
            mat.facet.source = 'FACET'
            mat.facet.model = 'ggx'
            mat.facet.ggx__alpha, mat.facet.ggx__alpha__set = 0.15, True
            mat.facet.ggx__fresnel, mat.facet.ggx__fresnel__set = "conductor", True
            mat.facet.ggx__eta, mat.facet.ggx__eta__set = (0.18, 0.42, 1.37), True
            mat.facet.ggx__k, mat.facet.ggx__k__set = (3.42, 2.35, 1.77), True
            win, area = area_of('PROPERTIES')
            area.spaces[0].context = 'RENDER'
            with bpy.context.temp_override(window=win, area=area):
                bpy.ops.screen.screen_full_area()
            return 1.5
        if ph == 1:
            shot('PROPERTIES', "render_properties.png")
            win, area = area_of('PROPERTIES')
            area.spaces[0].context = 'MATERIAL'
            # collapse Blender's own material panels so the Facet panel shows
            return 1.5
        if ph == 2:
            shot('PROPERTIES', "material_panel.png")
            win, area = area_of('PROPERTIES')
            area.spaces[0].context = 'RENDER'
            return 1.0
        if ph == 3:
            # The Render Engine menu opened over its field (the menu opens at the cursor).
            win, area = area_of('PROPERTIES')
            win.cursor_warp(area.x + int(area.width * 0.7), area.y + area.height - 82)
            with bpy.context.temp_override(window=win, area=area):
                bpy.ops.wm.context_menu_enum(data_path="scene.render.engine")
            return 1.0
        if ph == 4:
            win, area = area_of('PROPERTIES')
            with bpy.context.temp_override(window=win):
                bpy.ops.screen.screenshot(filepath=os.path.join(OUT, "engine_menu_full.png"))
            win.cursor_warp(5, 5)  # far from the menu: it closes
            with bpy.context.temp_override(window=win, area=area):
                bpy.ops.screen.back_to_previous()
            return 1.0
        if ph == 5:
            win, area = area_of('VIEW_3D')
            area.spaces[0].shading.type = 'RENDERED'
            with bpy.context.temp_override(window=win, area=area):
                bpy.ops.screen.screen_full_area()
            return 12.0
        if ph == 6:
            shot('VIEW_3D', "viewport.png")
            os._exit(0)
    except Exception:
        import traceback
        traceback.print_exc()
        os._exit(1)


bpy.app.timers.register(step, first_interval=1.0)
