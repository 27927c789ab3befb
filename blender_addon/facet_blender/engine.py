"""The Facet render engine: F12 stills and animations rendered by the core.

render() exports the evaluated depsgraph (export.py), builds the scene with the core and runs a
facet RenderSession on this thread; the binding releases the GIL while the core renders, and
calls back (GIL held, on this thread) after each pass of about 0.25 s, where the engine polls
test_break() (Esc: the callback returns False and the session stops within that pass), pushes
the image with update_result and updates progress and stats. No native thread ever holds the
engine object. Errors go to self.report({'ERROR'}) and error_set(): an exception escaping
render() would print a traceback, save a blank image and still exit 0 in `blender -b`.
"""
import time
import traceback

import bpy
import numpy as np

from . import export, native, viewport

# The last final image rendered (float32 (h, w, 3), top row first) and the problems reported,
# for tests and scripts.
last_image = None
last_problems = []
last_cancelled = False
# Seconds of the last F12's phases (for tests/blender/bench_blender.py): export_build (export
# + build_scene + session set-up), render (the session, incl. the pass callbacks), upload
# (the callbacks' and the final image copy into Blender's result), total.
last_timings = {}
preview_count = [0]  # material preview renders so far (tests)
PREVIEW_SPP = 16  # material preview renders: small images, seen while editing

# Tests only: a callable polled with test_break() after each pass (headless Blender has no Esc).
test_break_hook = None


def to_blender_rect(img):
    """float32 (h, w, 3) top row first -> float32 (w*h, 4) RGBA, rows bottom to top (what
    RenderPass.rect.foreach_set takes in one call)."""
    h, w = img.shape[:2]
    rgba = np.empty((h, w, 4), np.float32)
    rgba[:, :, :3] = img[::-1]
    rgba[:, :, 3] = 1.0
    return rgba.reshape(h * w, 4)


def border_rect(rd, width, height):
    """Render > Region (border): (x, y, w, h) in Blender's pixel coordinates (y up); the whole
    image without a border. Facet renders the region (bit for bit the pixels of the full
    render, render.h)."""
    if not rd.use_border:
        return 0, 0, width, height
    x0, x1 = round(rd.border_min_x * width), round(rd.border_max_x * width)
    y0, y1 = round(rd.border_min_y * height), round(rd.border_max_y * height)
    x0, y0 = max(0, min(x0, width - 1)), max(0, min(y0, height - 1))
    x1, y1 = max(x0 + 1, min(x1, width)), max(y0 + 1, min(y1, height))
    return x0, y0, x1 - x0, y1 - y0


class FacetRenderEngine(bpy.types.RenderEngine):
    bl_idname = 'FACET'
    bl_label = 'Facet'
    bl_use_preview = True  # material previews (small, few samples)
    bl_use_shading_nodes_custom = False  # keep Cycles' shader node editor
    bl_use_postprocess = True

    def render(self, depsgraph):
        global last_problems
        last_problems = []
        try:
            self._render(depsgraph)
        except Exception as e:  # every error reaches the user (and makes `blender -b` fail)
            traceback.print_exc()
            msg = "Facet: %s" % e
            last_problems.append(msg)
            self.report({'ERROR'}, msg)
            self.error_set(msg)

    def _render(self, depsgraph):
        global last_image, last_cancelled
        scene = depsgraph.scene
        t0 = time.perf_counter()
        self.update_stats("", "Facet | Exporting scene")
        data, problems = export.export_scene(depsgraph)
        if self.is_preview:
            preview_count[0] += 1
        for p in problems:
            last_problems.append(p)
            if not self.is_preview:  # the preview scene's own materials are not the user's
                self.report({'WARNING'}, "Facet: " + p)
        width, height = data["camera"]["width"], data["camera"]["height"]
        self.update_stats("", "Facet | Building scene")
        fscene, warnings = native.build(data, name="blender")
        for w in warnings:
            last_problems.append(w)
            self.report({'WARNING'}, "Facet: " + w)
        rs = data["render"]
        if self.is_preview:
            rs["spp"] = min(rs["spp"], PREVIEW_SPP)
        threads = scene.render.threads if scene.render.threads_mode == 'FIXED' else 0
        x, y, w, h = border_rect(scene.render, width, height)
        region = None if (w, h) == (width, height) else (x, height - y - h, x + w, height - y)
        session = native.Session(fscene, spp=rs["spp"], threads=threads, seed=rs["seed"],
                                 max_depth=rs["max_depth"], integrator=rs["integrator"],
                                 time_budget=rs.get("time_budget", 0.0), region=region)
        t_export = time.perf_counter() - t0
        # With a border, Blender's render rectangle is the border: result coordinates are
        # relative to it.
        result = self.begin_result(0, 0, w, h)
        layer = result.layers[0]
        combined = layer.passes["Combined"]

        upload = [0.0]

        def on_pass(done, target, elapsed, eta):
            if self.test_break() or (test_break_hook is not None and test_break_hook()):
                return False
            tu = time.perf_counter()
            combined.rect.foreach_set(to_blender_rect(session.image()))
            self.update_result(result)
            upload[0] += time.perf_counter() - tu
            self.update_progress(done / max(1, target))
            self.update_stats("", "Facet | Sample %d/%d | Time %.1f s | Remaining %.1f s"
                              % (done, target, elapsed, eta))
            return True

        tr = time.perf_counter()
        finished = session.render(on_pass)
        t_render = time.perf_counter() - tr
        tu = time.perf_counter()
        img = session.image()
        combined.rect.foreach_set(to_blender_rect(img))
        self.end_result(result)
        upload[0] += time.perf_counter() - tu
        last_timings.clear()
        last_timings.update(export_build=t_export, render=t_render, upload=upload[0],
                            total=time.perf_counter() - t0)
        last_image = img
        last_cancelled = not finished
        self.update_stats("", "Facet | %s in %.2f s (export and build %.2f s)"
                          % ("Done" if finished else "Cancelled",
                             time.perf_counter() - t0, t_export))


    # --- viewport (Rendered shading): viewport.py --------------------------------------------

    def view_update(self, context, depsgraph):
        vs = getattr(self, "_viewport", None)
        if vs is None:
            vs = self._viewport = viewport.ViewportSession()
        try:
            viewport.forget_changed(vs.mesh_cache, depsgraph)
            data, problems = export.export_scene(depsgraph, camera=viewport.view_camera(context),
                                                 mesh_cache=vs.mesh_cache)
            fs = depsgraph.scene.facet
            data["render"]["spp"] = fs.viewport_spp
            vs.update(data)
        except Exception as e:
            traceback.print_exc()
            self.update_stats("", "Facet: %s" % e)

    def view_draw(self, context, depsgraph):
        vs = getattr(self, "_viewport", None)
        if vs is None:
            return
        vs.set_camera(viewport.view_camera(context))
        vs.draw(self, context, depsgraph.scene)

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
