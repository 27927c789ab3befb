"""Benchmarks of the Blender side (not a test; run by hand, numbers in docs/performance.md, "Blender"):
  blender -b --factory-startup --python tests/blender/bench_blender.py -- <cornell json> [reps]
(with the addon installed, e.g. BLENDER_USER_SCRIPTS=build/tests/blender/user_scripts after
`ctest -R blender.install`).
1. Export time per 1M triangles: a 708 x 708 grid (1,002,528 triangles), flat (positions and
   indices only) and smooth with auto smooth (split normals, one vertex per loop); the core's
   build_scene (Embree BVH) on the result.
2. F12 on the imported Cornell box (128 x 128, 256 spp, Facet max_depth 64 = Cycles 63
   bounces, facet_testsupport.cycles_scene's exact conversion and settings), Facet and Cycles
   on the same Blender scene in the same run, interleaved, `reps` repetitions (default 3):
   median wall time of bpy.ops.render.render and the ratio; Facet's Blender-side overhead
   (export + build + pixel upload into the render result, hooks.last_timings) as a share of
   its F12 time.
3. Time to equal error: relative RMSE against a 4096-spp Facet reference over the lower half
   of the image (where the two renderers agree within the noise: test_cycles_cornell.py; the
   upper half has Cycles' ~1% direct-light deficit, which would put a floor under Cycles'
   error) at 16, 64 and 256 spp for both (interleaved, median times); error ~ c / sqrt(t) is
   fitted per renderer, and the time each needs to reach Cycles' 256-spp error is printed with
   the ratio."""
import math
import os
import statistics
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

RES = 128
F12_SPP = 256
LADDER = (16, 64, 256)
REF_SPP = 4096
def export_bench():
    from facet_blender import export, native
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=709, y_subdivisions=709, size=2.0)
    grid = bpy.context.object
    for smooth in (False, True):
        if smooth:
            bpy.ops.object.shade_smooth()
            grid.data.use_auto_smooth = True
        dg = bpy.context.evaluated_depsgraph_get()
        best = 1e9
        for _ in range(3):
            t0 = time.perf_counter()
            data, _ = export.export_scene(dg, mesh_cache={})
            best = min(best, time.perf_counter() - t0)
        tris = sum(len(s["indices"]) for s in data["shapes"] if s["type"] == "mesh")
        t0 = time.perf_counter()
        native.build(data)
        tb = time.perf_counter() - t0
        print("BENCH export %s: %d triangles, export %.3f s (%.3f s per 1M), build_scene %.3f s"
              % ("smooth+auto smooth" if smooth else "flat", tris, best, best * 1e6 / tris, tb))


def f12(scene, engine, spp, path=None):
    """One F12: (wall seconds, image or None, Facet's phase timings)."""
    from facet_blender import hooks
    scene.render.engine = engine
    scene.facet.spp = spp
    scene.cycles.samples = spp
    if path:
        scene.render.filepath = path
    t0 = time.perf_counter()
    bpy.ops.render.render(write_still=bool(path))
    dt = time.perf_counter() - t0
    img = cs.load_exr(path).astype(np.float64) if path else None
    return dt, img, dict(hooks.last_timings) if engine == 'FACET' else {}


def main():
    bt.enable_addon()
    export_bench()
    a = bt.args()
    scene_path = a[0]
    reps = int(a[1]) if len(a) > 1 else 3
    out = "/tmp/facet_bench_blender"
    os.makedirs(out, exist_ok=True)
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.import_scene.facet(filepath=scene_path)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = RES
    scene.facet.max_depth = 64
    cs.convert(scene, exact=True)
    cs.cycles_settings(scene, samples=F12_SPP, max_depth=64)

    # 2. F12, interleaved
    times = {'FACET': [], 'CYCLES': []}
    shares = []
    for r in range(reps):
        for engine in ('FACET', 'CYCLES') if r % 2 == 0 else ('CYCLES', 'FACET'):
            dt, _, tm = f12(scene, engine, F12_SPP)
            times[engine].append(dt)
            if tm:
                shares.append((tm["export_build"] + tm["upload"], tm, dt))
    mf, mc = statistics.median(times['FACET']), statistics.median(times['CYCLES'])
    print("BENCH F12 Cornell box %dx%d, %d spp, %d reps interleaved (median, all):"
          % (RES, RES, F12_SPP, reps))
    print("  | renderer | F12 median (s) | all (s) |")
    print("  | Facet | %.2f | %s |" % (mf, " ".join("%.2f" % t for t in times['FACET'])))
    print("  | Cycles | %.2f | %s |" % (mc, " ".join("%.2f" % t for t in times['CYCLES'])))
    print("  Cycles / Facet F12 time: %.2f" % (mc / mf))
    for over, tm, dt in shares:
        print("  Facet F12 %.2f s: export+build %.4f s, upload %.4f s, session %.2f s; "
              "Blender-side overhead %.4f s = %.2f%% of F12 (wall minus session: %.2f%%)"
              % (dt, tm["export_build"], tm["upload"], tm["render"], over, 100 * over / dt,
                 100 * (dt - tm["render"]) / dt))

    # 3. time to equal error
    _, ref, _ = f12(scene, 'FACET', REF_SPP, os.path.join(out, "ref.exr"))
    lower = slice(RES // 2, RES)

    def rel_rmse(img):
        d = (img[lower] - ref[lower]) / np.maximum(ref[lower], 1e-3)
        return float(np.sqrt(np.mean(d ** 2)))
    pts = {'FACET': {}, 'CYCLES': {}}
    for r in range(reps):
        for spp in LADDER:
            for engine in ('FACET', 'CYCLES') if r % 2 == 0 else ('CYCLES', 'FACET'):
                scene.facet.seed = scene.cycles.seed = 10 + r
                dt, img, _ = f12(scene, engine, spp, os.path.join(out, "%s_%d.exr"
                                                                 % (engine, spp)))
                pts[engine].setdefault(spp, []).append((dt, rel_rmse(img)))
    print("BENCH time to equal error (relative RMSE over the lower half vs Facet %d spp):"
          % REF_SPP)
    print("  | renderer | spp | F12 median (s) | rel. RMSE median |")
    fit = {}
    for engine in ('FACET', 'CYCLES'):
        ts, es = [], []
        for spp in LADDER:
            t = statistics.median(p[0] for p in pts[engine][spp])
            e = statistics.median(p[1] for p in pts[engine][spp])
            ts.append(t)
            es.append(e)
            print("  | %s | %d | %.2f | %.4f |" % (engine.capitalize(), spp, t, e))
        # error = c / sqrt(t): c from the geometric mean of e sqrt(t)
        fit[engine] = math.exp(statistics.mean(math.log(e * math.sqrt(t))
                                               for t, e in zip(ts, es)))
    target = statistics.median(p[1] for p in pts['CYCLES'][LADDER[-1]])
    need = {e: (c / target) ** 2 for e, c in fit.items()}
    print("  to reach rel. RMSE %.4f (Cycles at %d spp): Facet %.2f s, Cycles %.2f s; "
          "Cycles / Facet %.2f" % (target, LADDER[-1], need['FACET'], need['CYCLES'],
                                   need['CYCLES'] / need['FACET']))


bt.run(main)
