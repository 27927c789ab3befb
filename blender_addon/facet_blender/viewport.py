"""Rendered shading in the 3D view: a worker thread renders progressively, view_draw only
uploads the latest finished pass and draws it.

- The engine keeps one ViewportSession while the 3D view shows Facet and forwards its
  view_update and view_draw to it. view_update (main thread) exports the evaluated depsgraph
  and posts it to the worker; view_draw posts the same scene data with a new camera when the
  view or the region size changed (Blender calls only view_draw for zoom, orbit and resize).
  A new post cancels the running session within a pass; the worker builds the new scene (GIL
  released) and renders.
- Viewport Noise Threshold (Render Properties > Facet): adaptive sampling in the viewport,
  apart from the final render's Noise Threshold (as Cycles keeps them); off while denoising.
- Denoise Viewport (Render Properties > Facet): the samples are rendered as two sessions over
  [0, n/2) and [n/2, n), the half-buffers; while the second refines, the image shown is the
  two merged (weighted by their sample counts). Once refinement ends, the core's denoiser
  (denoise_halves, as F12) replaces it. A restart before the end skips the denoiser.
- The worker never touches the engine or any bpy object: it publishes images under a lock.
  view_draw asks for another redraw (tag_redraw) while the render is still refining. stop()
  joins the worker; it is called from the engine's __del__ (which may run twice) and before
  each restart.
"""
import threading
import traceback

import numpy as np

from . import export, hooks, native, pixels, units


def viewport_adaptive(render, fs):
    """The viewport's adaptive sampling in the exported render settings `render`: Viewport
    Noise Threshold (0 = off) with Min Samples automatic, in place of the final render's;
    off with Denoise Viewport (its half-buffers are sample ranges, which an adaptive render
    cannot be split into)."""
    render.pop("adaptive_min_samples", None)
    if fs.viewport_adaptive_threshold > 0.0 and not fs.viewport_denoise:
        render["adaptive_threshold"] = fs.viewport_adaptive_threshold
    else:
        render.pop("adaptive_threshold", None)


def view_camera(context):
    """The 3D view's camera as scene-data camera (FORMAT.md), from the region's matrices."""
    region, rv3d = context.region, context.region_data
    width, height = max(1, region.width), max(1, region.height)
    m = rv3d.view_matrix.inverted()
    pos = [m[i][3] for i in range(3)]
    fwd = [-m[i][2] for i in range(3)]
    up = [m[i][1] for i in range(3)]
    w11 = rv3d.window_matrix[1][1]
    fov = units.fov_from_projection(w11) if rv3d.is_perspective and w11 > 0 else 50.0
    fov = min(max(fov, 1e-3), 179.0)
    return {"position": pos, "look_at": [p + f for p, f in zip(pos, fwd)], "up": up,
            "fov": fov, "width": width, "height": height}


def forget_changed(mesh_cache, depsgraph):
    """Drops the cached mesh arrays of objects whose geometry changed (a moved object keeps its
    arrays: only its matrix is exported again)."""
    import bpy
    for u in depsgraph.updates:
        if not u.is_updated_geometry:
            continue
        idb = getattr(u.id, "original", u.id)
        if isinstance(idb, bpy.types.Object):
            for key in [k for k in mesh_cache if k[0] == idb.name]:
                del mesh_cache[key]  # keys: (name, is_instance, data, uv layer, tangents, colours)
        elif isinstance(idb, (bpy.types.Mesh, bpy.types.Curve, bpy.types.MetaBall,
                              bpy.types.Collection, bpy.types.Scene)):
            mesh_cache.clear()  # shared data, or objects added or removed


class ViewportSession:
    def __init__(self):
        self._lock = threading.Lock()
        self._wake = threading.Condition(self._lock)
        self._pending = None   # scene data to render next
        self._quit = False
        self._image = None     # float32 (h, w, 4) rows bottom to top
        self._version = 0
        self._busy = False
        self.data = None       # the last exported scene data (main thread)
        self.denoise = False   # Denoise Viewport at the last view_update (main thread)
        self.mesh_cache = {}   # export.export_scene's arrays per object (main thread)
        self.camera = None
        self.errors = []
        self._texture = None
        self._tex_version = -1
        self._thread = threading.Thread(target=self._run, name="facet-viewport", daemon=True)
        self._thread.start()

    # --- main thread -----------------------------------------------------------------------

    def view_update(self, engine, context, depsgraph):
        """The engine's view_update: exports the changed scene and restarts the render."""
        try:
            forget_changed(self.mesh_cache, depsgraph)
            data, problems = export.export_scene(depsgraph, camera=view_camera(context),
                                                 mesh_cache=self.mesh_cache)
            fs = depsgraph.scene.facet
            data["render"]["spp"] = fs.viewport_spp
            self.denoise = fs.viewport_denoise
            viewport_adaptive(data["render"], fs)
            self.update(data)
        except Exception as e:
            traceback.print_exc()
            engine.update_stats("", "Facet: %s" % e)

    def view_draw(self, engine, context, depsgraph):
        """The engine's view_draw: restarts when the view changed, draws the latest image;
        a render that failed shows its error in the viewport's stats."""
        self.set_camera(view_camera(context))
        self.draw(engine, context, depsgraph.scene)
        errors = self.errors  # the worker replaces the list, never empties it
        if errors:
            engine.update_stats("", "Facet: %s" % errors[-1])

    def update(self, data):
        self.data = data
        self.post()

    def post(self):
        if self.data is None or self.camera is None:
            return
        data = dict(self.data)
        data["camera"] = self.camera
        with self._lock:
            self._pending = (data, self.denoise)
            self._busy = True
            self._wake.notify()

    def set_camera(self, camera):
        """True when the camera changed (and a restart was posted)."""
        if camera == self.camera:
            return False
        self.camera = camera
        self.post()
        return True

    def latest(self):
        with self._lock:
            return self._image, self._version, self._busy

    def stop(self):
        with self._lock:
            self._quit = True
            self._wake.notify()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join()
        self._thread = None

    def draw(self, engine, context, scene):
        import gpu
        from gpu_extras.presets import draw_texture_2d
        img, version, busy = self.latest()
        if img is not None:
            if version != self._tex_version:
                h, w = img.shape[:2]
                buf = gpu.types.Buffer('FLOAT', w * h * 4, img.ravel())
                self._texture = gpu.types.GPUTexture((w, h), format='RGBA16F', data=buf)
                self._tex_version = version
            gpu.state.blend_set('ALPHA_PREMULT')
            engine.bind_display_space_shader(scene)
            draw_texture_2d(self._texture, (0, 0), context.region.width, context.region.height)
            hooks.viewport_stats["draws"] += 1
            engine.unbind_display_space_shader()
            gpu.state.blend_set('NONE')
        if busy:
            engine.tag_redraw()

    # --- worker thread ---------------------------------------------------------------------

    def _run(self):
        while True:
            with self._lock:
                while self._pending is None and not self._quit:
                    self._wake.wait()
                if self._quit:
                    return
                (data, denoise), self._pending = self._pending, None
            hooks.viewport_stats["restarts"] += 1
            try:
                self._render(data, denoise)
                self.errors = []
            except Exception as e:  # shown by view_draw's engine as a report
                traceback.print_exc()
                self.errors.append(str(e))
            with self._lock:
                if self._pending is None:
                    self._busy = False

    def _publish(self, img, data):
        """Makes img (float32 (h, w, 3), top row first) the image view_draw shows; False when
        the render should stop (a newer post, or quit)."""
        rect = pixels.to_blender_rect(img)
        h, w = data["camera"]["height"], data["camera"]["width"]
        with self._lock:
            self._image = rect.reshape(h, w, 4)
            self._version += 1
            hooks.viewport_stats["images"] += 1
            hooks.viewport_stats["mean"] = float(rect[:, :3].mean())
            return self._pending is None and not self._quit

    def _render(self, data, denoise):
        scene, _ = native.build(data, name="viewport")
        rs = data["render"]
        n = rs["spp"]
        denoise = denoise and n >= 2
        ranges = [(0, n // 2), (n // 2, n)] if denoise else [None]
        halves = []
        for r in ranges:
            session = native.Session(scene, spp=n, threads=0, seed=rs["seed"],
                                     max_depth=rs["max_depth"], integrator=rs["integrator"],
                                     samples=r)

            def on_pass(done, target, elapsed, eta, session=session):
                img = session.image()
                if halves:  # the second half: shown merged with the first, by sample counts
                    first = n // 2
                    img = (halves[0] * first + img * done) / (first + done)
                return self._publish(img, data)

            if not session.render(on_pass):
                return  # restarted or stopped: no denoising of a partial image
            hooks.viewport_stats["mean_spp"] = session.mean_spp()
            halves.append(session.image())
        if denoise:
            img = native.denoise_halves(scene, halves[0][:, :, :3], halves[1][:, :, :3], n,
                                        rs["seed"])
            if halves[0].shape[2] == 4:  # Film > Transparent: the alpha is not denoised
                img = np.dstack([img, 0.5 * (halves[0][:, :, 3] + halves[1][:, :, 3])])
            if self._publish(img, data):
                hooks.viewport_stats["denoised"] += 1
                hooks.viewport_denoised = ((halves[0] + halves[1]) / 2, img)
