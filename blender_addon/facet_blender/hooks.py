"""What the addon records for tests and scripts, and the one hook a test may set.

The addon only writes these values (and polls test_break); nothing in it reads them back, so
they never change what is rendered. This module imports nothing of the addon: every module
may import it. Read them as attributes of the module (`hooks.last_image`): they are rebound,
not updated in place.
"""

# The last final render (F12, animation frame, material preview): its image (float32
# (h, w, 3), top row first; None until one finished), the problems it reported (export
# warnings, build warnings, the error), whether Esc or test_break stopped it, and the seconds
# of its phases: export_build (export + build_scene + session set-up), render (the session,
# including the pass callbacks), upload (the callbacks' and the final image's copies into
# Blender's result), total.
last_image = None
last_problems = []
last_cancelled = False
last_timings = {}
preview_renders = 0  # material preview renders so far

# Tests only: a callable polled after each pass of a final render, beside the engine's
# test_break() (headless Blender has no Esc); returning True cancels the render.
test_break = None

# Counters of the viewport (Rendered shading): view_draw calls that drew an image, images
# published by the worker, sessions started, the mean of the latest image, denoised images
# published (Denoise Viewport) and the mean samples per pixel of the last session that finished
# (below Viewport Samples where adaptive sampling stopped tiles); viewport_denoised: the last (merged halves, denoised) pair.
viewport_stats = {"draws": 0, "images": 0, "restarts": 0, "mean": 0.0, "denoised": 0,
                  "mean_spp": 0.0}
viewport_denoised = None

# Counters of the exporter: meshes converted by sync_mesh.mesh_arrays (the viewport converts
# only the changed ones again).
export_stats = {"meshes": 0}


def final_started(problems):
    """A final render starts; `problems` is the list it will append its reports to."""
    global last_problems
    last_problems = problems


def final_finished(image, cancelled, timings):
    global last_image, last_cancelled, last_timings
    last_image, last_cancelled, last_timings = image, cancelled, dict(timings)


def preview_started():
    global preview_renders
    preview_renders += 1
