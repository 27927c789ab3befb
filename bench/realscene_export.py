"""Exports scene NAME of tests/realscenes/scenes.py as a Facet JSON scene, as the time-vs-error
benchmark renders it (bench/realscenes_time_error.py: WIDTH x HEIGHT pixels, SPP samples, the
suite's max depth, Facet's default light selection), for profiling `facet render` on it (see
docs/curves.md, "What a hair sample costs"). Run inside Blender with the addon the build
installs (ctest -R blender.install):

    BLENDER_USER_SCRIPTS=build/tests/blender/user_scripts \\
    BLENDER_USER_CONFIG=build/tests/blender/user_config \\
    blender -b --factory-startup --python bench/realscene_export.py -- \\
        NAME OUT.json [WIDTH HEIGHT SPP]

(default: the scene's bench size, Scene.bench). Prints the export's seconds and its report.
"""
import os
import sys
import time

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "support", "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "realscenes"))
from facet_testsupport import blender_harness as bt  # noqa: E402
import scenes  # noqa: E402


def main():
    name, out = bt.args()[0], bt.args()[1]
    bt.enable_addon()
    entry = scenes.by_name(name)
    scenes.empty_scene()
    entry.stage(bpy.context.scene)
    scene = bpy.context.scene  # staging may have opened a .blend
    width, height, spp = entry.bench
    if len(bt.args()) > 4:
        width, height, spp = (int(v) for v in bt.args()[2:5])
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    scene.render.engine = 'FACET'
    scene.facet.spp = spp
    scene.facet.max_depth = entry.max_depth
    scene.facet.property_unset("light_selection")  # the panel's default, as the benchmark
    from facet_blender import export, native
    t0 = time.perf_counter()
    data, problems = export.export_scene(bpy.context.evaluated_depsgraph_get())
    print("%s: exported in %.3f s; %d report lines" % (name, time.perf_counter() - t0,
                                                        len(problems)))
    for p in problems:
        print("  " + p)
    native.write_scene(data, out)


bt.run(main)
