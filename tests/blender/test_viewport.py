"""The 3D view's Rendered shading under Xvfb (Mesa software OpenGL): Facet's view_update /
view_draw draw a non-empty image, and the image changes after the cube is moved (a screenshot
test) without re-exporting the cube's mesh; with Denoise Viewport on, the image shown once
refinement ends is the denoised one (smoother than the merged halves, same mean), also with a
Viewport Noise Threshold set (set aside while denoising); without denoising that threshold
makes the session adaptive (mean samples per pixel below Viewport Samples); then the material
tab's previews are rendered by Facet. Runs with the UI:
`xvfb-run blender --factory-startup --python test_viewport.py`."""
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402

OUT = bt.args()[0]
steps = []


def view3d():
    for win in bpy.context.window_manager.windows:
        for area in win.screen.areas:
            if area.type == 'VIEW_3D':
                return win, area
    raise RuntimeError("no 3D view")


def screenshot(name):
    win, area = view3d()
    path = os.path.join(OUT, name)
    with bpy.context.temp_override(window=win, area=area):
        bpy.ops.screen.screenshot_area(filepath=path)
    im = bpy.data.images.load(path, check_existing=False)
    w, h = im.size
    px = np.empty(w * h * im.channels, np.float32)
    im.pixels.foreach_get(px)
    bpy.data.images.remove(im)
    return px.reshape(h, w, -1)[:, :, :3]


def wait_images(n_more, timeout=30.0):
    from facet_blender import hooks
    target = hooks.viewport_stats["images"] + n_more
    t0 = time.time()

    def poll():
        if hooks.viewport_stats["images"] >= target and hooks.viewport_stats["draws"] > 0:
            return None
        if time.time() - t0 > timeout:
            return None
        return 0.2
    return poll


state = {}


def step():
    try:
        from facet_blender import hooks
        phase = state.get("phase", 0)
        if phase == 0:
            bt.enable_addon()
            scene = bpy.context.scene
            scene.render.engine = 'FACET'
            scene.facet.viewport_spp = 16
            win, area = view3d()
            area.spaces[0].shading.type = 'RENDERED'
            state["t"] = time.time()
            state["phase"] = 1
            return 0.5
        if phase == 1:  # wait for a few passes to be drawn
            vstats = hooks.viewport_stats
            if (vstats["draws"] < 3 or vstats["images"] < 2) and time.time() - state["t"] < 40:
                return 0.3
            bt.check(vstats["draws"] > 0, "view_draw drew Facet images: %s" % vstats)
            time.sleep(1.0)
            state["a"] = screenshot("viewport_a.png")
            a = state["a"]
            bt.check(a.std() > 0.01, "the screenshot is not empty (std %.3f) %s"
                     % (a.std(), hooks.viewport_stats))
            state["restarts"] = hooks.viewport_stats["restarts"]
            state["meshes"] = hooks.export_stats["meshes"]
            bpy.data.objects["Cube"].location.x += 1.5
            state["t"] = time.time()
            state["phase"] = 2
            return 1.0
        if phase == 2:
            if (hooks.viewport_stats["restarts"] <= state["restarts"]
                    and time.time() - state["t"] < 30):
                return 0.3
            bt.check(hooks.viewport_stats["restarts"] > state["restarts"],
                     "moving the cube restarted the render")
            bt.check(hooks.export_stats["meshes"] == state["meshes"],
                     "moving the cube re-exported no mesh (%d before, %d after)"
                     % (state["meshes"], hooks.export_stats["meshes"]))
            time.sleep(3.0)
            state["phase"] = 3
            return 0.5
        if phase == 3:
            b = screenshot("viewport_b.png")
            diff = np.abs(b - state["a"]).mean()
            bt.check(diff > 1e-3, "the image changed after the move (mean diff %.4f)" % diff)
            # A floor under a grey world (Monte Carlo noise, which the point-lit cube alone
            # hardly has at 16 spp), and Denoise Viewport: restarts as two halves.
            bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0.0, 0.0, -1.0))
            bpy.context.view_layer.objects.active = bpy.data.objects["Cube"]  # for the previews
            world = bpy.context.scene.world
            world.use_nodes = True
            world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
            bpy.context.scene.facet.viewport_spp = 8  # 4 per half: keeps the phase short
            bpy.context.scene.facet.viewport_denoise = True
            # A Viewport Noise Threshold is set aside while denoising (the halves are sample
            # ranges, which an adaptive session refuses): the denoised image must still come.
            bpy.context.scene.facet.viewport_adaptive_threshold = 0.1
            state["t"] = time.time()
            state["phase"] = 5
            return 0.5
        if phase == 5:  # Denoise Viewport: wait for the end of refinement
            if hooks.viewport_stats["denoised"] == 0 and time.time() - state["t"] < 60:
                return 0.3
            bt.check(hooks.viewport_stats["denoised"] > 0,
                     "Denoise Viewport published a denoised image: %s" % hooks.viewport_stats)
            merged, den = hooks.viewport_denoised

            def roughness(x):  # mean absolute difference of horizontal neighbours
                return float(np.abs(np.diff(x, axis=1)).mean())
            # The latest image published is the denoised one (means of the same floats,
            # summed in another order: 1e-5 relative).
            latest = hooks.viewport_stats["mean"]
            bt.check(abs(latest - float(den.mean())) <= 1e-5 * abs(latest),
                     "the viewport shows the denoised image (mean %.6g, denoised %.6g)"
                     % (latest, float(den.mean())))
            # 8 spp: the denoiser at least halves the pixel-to-pixel noise (measured 2.7x at
            # 16 spp) and keeps the mean within 2% (its bias is local).
            bt.check(roughness(den) < roughness(merged) / 2,
                     "denoised roughness %.4g < half the merged %.4g"
                     % (roughness(den), roughness(merged)))
            bt.check(abs(den.mean() - merged.mean()) <= 0.02 * merged.mean(),
                     "denoised mean %.4g ~ merged %.4g" % (den.mean(), merged.mean()))
            # Viewport Noise Threshold without denoising: the session stops its tiles early.
            hooks.viewport_stats["mean_spp"] = 0.0
            bpy.context.scene.facet.viewport_denoise = False
            bpy.context.scene.facet.viewport_spp = 32
            bpy.context.scene.update_tag()  # as a click in the panel: the view updates
            state["t"] = time.time()
            state["restarts"] = hooks.viewport_stats["restarts"]
            state["phase"] = 6
            return 0.5
        if phase == 6:  # a whole adaptive session
            if hooks.viewport_stats["mean_spp"] == 0.0 and time.time() - state["t"] < 90:
                return 0.3
            spp = hooks.viewport_stats["mean_spp"]
            # Threshold 0.1 (Min Samples automatic: 16) on the grey-world floor and the cube:
            # the tiles stop before 32 (a session ignoring the threshold takes all 32).
            bt.check(0.0 < spp < 28.0, "Viewport Noise Threshold 0.1: mean %.1f spp of 32 "
                     "(restarts %d -> %s)" % (spp, state["restarts"], hooks.viewport_stats))
            # Material previews (bl_use_preview): show the material tab.
            for area in bpy.context.window.screen.areas:
                if area.type == 'PROPERTIES':
                    area.spaces[0].context = 'MATERIAL'
                    area.tag_redraw()
            state["t"] = time.time()
            state["phase"] = 4
            return 0.5
        if phase == 4:
            from facet_blender import hooks
            if hooks.preview_renders == 0 and time.time() - state["t"] < 30:
                return 0.3
            bt.check(hooks.preview_renders > 0, "Facet rendered material previews (%d)"
                     % hooks.preview_renders)
            from facet_blender import ui
            bt.check(bool(ui._plot) and "Material" in ui._plot[0].keys,
                     "the Facet material panel drew the lobe plot of 'Material'")
            state["t"] = time.time()
            state["phase"] = 7
            return 0.3
        if phase == 7:  # the screenshot and the exit once no preview render is in flight
            if bpy.app.is_job_running('RENDER_PREVIEW') and time.time() - state["t"] < 60:
                return 0.3
            for win in bpy.context.window_manager.windows:
                for area in win.screen.areas:
                    if area.type == 'PROPERTIES':
                        with bpy.context.temp_override(window=win, area=area):
                            bpy.ops.screen.screenshot_area(
                                filepath=os.path.join(OUT, "material_panel.png"))
            print("PASS")
            sys.stdout.flush()
            os._exit(0)
    except Exception:
        import traceback
        traceback.print_exc()
        sys.stdout.flush()
        os._exit(1)


bpy.app.timers.register(step, first_interval=1.0)
