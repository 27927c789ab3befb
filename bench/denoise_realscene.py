"""A real-scene row of bench/denoise_bench.py, run inside Blender:

    blender -b --factory-startup --python bench/denoise_realscene.py -- \
        NAME OUT.json REF_SPP THREADS [rows | breakdown]

Stages scene NAME of tests/realscenes/scenes.py at its bench size (Scene.bench), with its light
selection and max depth, exports it with the Facet addon, and writes denoise_bench.scene_rows
of the exported scene (JSON) to OUT.json, or denoise_bench.breakdown with "breakdown".
"""
import json
import os
import sys

import bpy

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "support", "python"))
sys.path.insert(0, os.path.join(ROOT, "tests", "realscenes"))
sys.path.insert(0, os.path.join(ROOT, "bench"))
from facet_testsupport import blender_harness as bt  # noqa: E402
import scenes  # noqa: E402


class Args:
    def __init__(self, ref_spp, threads):
        self.ref_spp, self.threads = ref_spp, threads


def main():
    name, out, ref_spp, threads = bt.args()[0], bt.args()[1], int(bt.args()[2]), int(bt.args()[3])
    bt.enable_addon()
    entry = scenes.by_name(name)
    scenes.empty_scene()
    entry.stage(bpy.context.scene)
    scene = bpy.context.scene  # staging may have opened a .blend
    width, height, _ = entry.bench
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.use_border = False
    scene.render.engine = 'FACET'
    scene.facet.max_depth = entry.max_depth
    scene.facet.light_selection = entry.light_selection
    from facet_blender import export, native
    data, _ = export.export_scene(bpy.context.evaluated_depsgraph_get())
    fscene, _ = native.build(data, name=name)
    import denoise_bench  # imports facet: the addon's module, on sys.path once it is enabled
    mode = bt.args()[4] if len(bt.args()) > 4 else "rows"
    run = denoise_bench.breakdown if mode == "breakdown" else denoise_bench.scene_rows
    rows = run(name, Args(ref_spp, threads), scene=fscene)
    with open(out, "w") as f:
        json.dump(rows, f)


bt.run(main)
