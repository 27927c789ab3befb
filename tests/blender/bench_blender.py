"""Benchmarks of the Blender side (not a test; run by hand, numbers in the README):
  blender -b --factory-startup --python tests/blender/bench_blender.py -- <facet cli> <cornell json>
1. Export time per 1M triangles: a 708 x 708 grid (1,002,528 triangles), flat (positions and
   indices only) and smooth with auto smooth (split normals, one vertex per loop); the core's
   build_scene (Embree BVH) on the result.
2. F12 on the imported Cornell box with Facet and with Cycles (same Blender scene, same run,
   settings of test_cycles_cornell.py), and the Blender-side share of Facet's F12 (export +
   build against the whole render)."""
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test as bt  # noqa: E402


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


def main():
    bt.enable_addon()
    export_bench()
    cli, scene_path = bt.args()[:2]
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.import_scene.facet(filepath=scene_path)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = 256
    scene.facet.spp = 256
    scene.facet.max_depth = 64
    import facet_blender.engine as eng
    import cycles_scene as cs
    cs.convert(scene, exact=True)
    cs.cycles_settings(scene, samples=256, max_depth=64)
    for engine in ('FACET', 'CYCLES'):
        scene.render.engine = engine
        t0 = time.perf_counter()
        bpy.ops.render.render()
        dt = time.perf_counter() - t0
        print("BENCH F12 %s: Cornell box 256x256, 256 spp, 64 bounces: %.2f s" % (engine, dt))


bt.run(main)
