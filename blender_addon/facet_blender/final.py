"""The final render: F12 stills, animation frames and material previews.

FinalSession.render() exports the evaluated depsgraph (export.py), builds the scene with the
core and runs a facet RenderSession on the calling thread; the binding releases the GIL while
the core renders, and calls back (GIL held, on this thread) after each pass of about 0.25 s,
where the session polls the engine's test_break() (Esc: the callback returns False and the
session stops within that pass), pushes the image with update_result (not in a headless
`blender -b` render, where no one sees it: the image is pushed once, at the end) and updates
progress and stats. No native thread ever holds the engine object. Errors go to report({'ERROR'}) and
error_set(): an exception escaping RenderEngine.render() would print a traceback, save a blank
image and still exit 0 in `blender -b`.
"""
import time
import traceback

import bpy
import numpy as np

from . import export, gaps, hooks, native, passes, pixels

PREVIEW_SPP = 16  # material preview renders: small images, seen while editing


class FinalSession:
    """One final render of `engine` (a bpy.types.RenderEngine), for one render() call."""

    def __init__(self, engine):
        self.engine = engine
        self.problems = []

    def render(self, depsgraph):
        hooks.final_started(self.problems)
        try:
            self._render(depsgraph)
        except Exception as e:  # every error reaches the user (and makes `blender -b` fail)
            traceback.print_exc()
            msg = "Facet: %s" % e
            self.problems.append(msg)
            self.engine.report({'ERROR'}, msg)
            self.engine.error_set(msg)

    def _report(self, engine, problems, warnings, users, lamp_line=None):
        """One report per render: each line once, grouped by material (with the objects using
        it) and object, after a count (gaps.grouped, gaps.summary); the preview scene's own
        materials are not the user's."""
        groups = gaps.grouped(list(problems) + list(warnings), users)
        for _, lines in groups:
            self.problems.extend(lines)
        if not engine.is_preview and lamp_line:  # what is in use, not a gap: INFO
            engine.report({'INFO'}, "Facet: " + lamp_line)
        if groups and not engine.is_preview:
            engine.report({'WARNING'}, "Facet: " + gaps.summary(groups))
            for subject, lines in groups:
                for line in lines:
                    engine.report({'WARNING'}, "Facet: [%s] %s" % (subject, line))

    def _render(self, depsgraph):
        engine = self.engine
        scene = depsgraph.scene
        t0 = time.perf_counter()
        engine.update_stats("", "Facet | Exporting scene")
        users = {}
        data, problems = export.export_scene(depsgraph, users=users,
                                             frame_set=None if engine.is_preview else
                                             engine.frame_set)
        if engine.is_preview:
            hooks.preview_started()
        width, height = data["camera"]["width"], data["camera"]["height"]
        engine.update_stats("", "Facet | Building scene")
        warnings = []
        try:
            fscene, warnings = native.build(data, name="blender")
        finally:  # the conversion's report also when the build fails
            self._report(engine, problems, warnings, users, gaps.lamp_model_line(data["lights"]))
        rs = data["render"]
        if engine.is_preview:
            rs["spp"] = min(rs["spp"], PREVIEW_SPP)
        threads = scene.render.threads if scene.render.threads_mode == 'FIXED' else 0
        x, y, w, h = pixels.border_rect(scene.render, width, height)
        region = None if (w, h) == (width, height) else pixels.core_region(x, y, w, h, height)
        denoise = self._denoise_plan(engine, scene, rs, region)
        # View Layer > Passes > Shadow Catcher: the pass, and Cycles' Combined with it.
        catcher_pass = not engine.is_preview and passes.shadow_catcher_pass(depsgraph.view_layer)
        # Denoising renders the samples in two halves [0, n/2) and [n/2, n): the half-buffers.
        ranges = [(0, rs["spp"] // 2), (rs["spp"] // 2, rs["spp"])] if denoise else [None]
        # The Depth pass from the render's own camera samples (one session; passes.write).
        depth_pass = (not denoise and not engine.is_preview
                      and passes.wants_depth(depsgraph.view_layer))
        sessions = [native.Session(fscene, spp=rs["spp"], threads=threads, seed=rs["seed"],
                                   max_depth=rs["max_depth"], integrator=rs["integrator"],
                                   time_budget=rs.get("time_budget", 0.0), region=region,
                                   light_selection=scene.facet.light_selection, samples=r,
                                   adaptive_threshold=0.0 if denoise else None,
                                   shadow_catcher_pass=catcher_pass, depth_pass=depth_pass)
                    for r in ranges]
        t_export = time.perf_counter() - t0
        # With a border, Blender's render rectangle is the border: result coordinates are
        # relative to it.
        result = engine.begin_result(0, 0, w, h)
        combined = result.layers[0].passes["Combined"]

        upload = [0.0]
        current = [0]
        # Headless: the passes' images would go to a display nobody has (at 1-sample passes,
        # 1.4 ms each on a 192 x 144 image: 2% of the render's CPU time).
        headless = bpy.app.background

        def on_pass(done, target, elapsed, eta):
            if engine.test_break() or (hooks.test_break is not None and hooks.test_break()):
                return False
            if not headless:
                tu = time.perf_counter()
                combined.rect.foreach_set(pixels.to_blender_rect(sessions[current[0]].image()))
                engine.update_result(result)
                upload[0] += time.perf_counter() - tu
            share = (current[0] + done / max(1, target)) / len(sessions)
            engine.update_progress(share)
            engine.update_stats("", "Facet | %sSample %d/%d | Time %.1f s | Remaining %.1f s"
                                % ("Half %d/2 | " % (current[0] + 1) if denoise else "",
                                   done, target, elapsed, eta))
            return True

        tr = time.perf_counter()
        finished = True
        for i, session in enumerate(sessions):
            current[0] = i
            finished = finished and session.render(on_pass)
        t_render = time.perf_counter() - tr
        tu = time.perf_counter()
        img = sessions[0].image()
        if denoise and finished:
            engine.update_stats("", "Facet | Denoising")
            img = self._denoised(fscene, sessions, rs, threads)
        combined.rect.foreach_set(pixels.to_blender_rect(img))
        if finished and not engine.is_preview:
            # The view layer's other passes (passes.py): only those enabled, each computed once.
            crop = region or (0, 0, width, height)
            written = passes.write(result, fscene, depsgraph.view_layer, min(rs["spp"], 64),
                                   rs["seed"], threads, crop,
                                   depth=sessions[0].depth() if depth_pass else None)
            if catcher_pass:  # of the whole render: the two halves' merged sums
                passes.write_shadow_catcher(
                    result, sessions[0].shadow_catcher_pass() if len(sessions) == 1 else
                    native.merged_shadow_catcher_pass([s.part() for s in sessions]))
                written.append(passes.SHADOW_CATCHER[0])
            if written:
                engine.update_stats("", "Facet | Passes %s" % ", ".join(written))
        engine.end_result(result)
        upload[0] += time.perf_counter() - tu
        hooks.final_finished(img, not finished,
                             dict(export_build=t_export, render=t_render, upload=upload[0],
                                  total=time.perf_counter() - t0))
        engine.update_stats("", "Facet | %s in %.2f s (export and build %.2f s)"
                            % ("Done" if finished else "Cancelled",
                               time.perf_counter() - t0, t_export))

    def _denoise_plan(self, engine, scene, rs, region):
        """Whether this render is denoised: Render Properties > Facet > Denoise, for final
        renders of the whole image at a fixed sample count (a denoiser is not split-invariant:
        it needs both halves of every pixel's samples); otherwise reported, never dropped."""
        if not scene.facet.denoise or engine.is_preview:
            return False
        why = ("a render region (Render > Region) is set" if region is not None else
               "a time budget is set" if rs.get("time_budget", 0.0) > 0 else
               "it needs at least 2 samples per pixel" if rs["spp"] < 2 else
               None)
        if why is None and rs.get("adaptive_threshold", 0.0) > 0:
            # The denoiser's half-buffers are sample ranges; an adaptive render has none.
            msg = ("Noise Threshold (adaptive sampling) is off for this render: Denoise renders "
                   "two half-buffers of fixed sample counts")
            self.problems.append(msg)
            engine.report({'WARNING'}, "Facet: " + msg)
        if why:
            msg = "Denoise is off for this render: %s" % why
            self.problems.append(msg)
            engine.report({'WARNING'}, "Facet: " + msg)
            return False
        return True

    @staticmethod
    def _denoised(fscene, sessions, rs, threads):
        """The denoised image (facet/render/denoise.h) of the two half sessions, with the
        features at the render's spp and seed (as `facet render --denoise`)."""
        a, b = sessions[0].image(), sessions[1].image()
        out = native.denoise_halves(fscene, a[:, :, :3], b[:, :, :3], rs["spp"], rs["seed"],
                                    threads=threads)
        if a.shape[2] == 4:  # alpha: the mean of the halves (the denoiser reads colour only)
            out = np.dstack([out, 0.5 * (a[:, :, 3] + b[:, :, 3])]).astype(np.float32)
        return out
