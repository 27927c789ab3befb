"""A scene of scenes/, imported into Blender (File > Import > Facet scene) and rendered with
Facet (F12, the EXR Blender writes), equals `facet render` of the same JSON at the same seed
and spp, bit for bit. Exact because an imported object exports its original description while
Blender's state (matrix, light, camera, resolution) is unchanged since the import (export.py),
and the render session's image is deterministic for given options (render.h)."""
import os
import subprocess
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def main():
    cli, scene_path, out_dir, spp, seed = bt.args()[:5]
    name = os.path.splitext(os.path.basename(scene_path))[0]
    ref_path = os.path.join(out_dir, "%s_cli.exr" % name)
    subprocess.run([cli, "render", scene_path, "--spp", spp, "--seed", seed, "-q",
                    "-o", ref_path], check=True)
    bt.enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    res = bpy.ops.import_scene.facet(filepath=scene_path)
    bt.check(res == {'FINISHED'}, "imported %s" % scene_path)
    scene = bpy.context.scene
    bt.check(scene.render.engine == 'FACET', "engine set to Facet by the import")
    scene.facet.spp = int(spp)
    scene.facet.seed = int(seed)
    path = os.path.join(out_dir, "%s_blender.exr" % name)
    img, problems = bt.render(scene, path)
    bt.check(img is not None, "rendered (problems: %s)" % problems)
    ref = bt.load_exr(ref_path)
    got = bt.load_exr(path)
    bt.check(got.shape == ref.shape, "same size %s" % (ref.shape,))
    diff = np.abs(got.astype(np.float64) - ref)
    bt.check(np.isfinite(got).all() and got.max() > 0.0, "finite, not black")
    bt.check(np.array_equal(got, ref), "bit for bit equal to `facet render` (max diff %.3g at %s)"
             % (diff.max(), np.unravel_index(diff.argmax(), diff.shape)))


bt.run(main)
