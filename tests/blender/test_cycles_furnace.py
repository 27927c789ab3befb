"""The analytic multi-bounce check for Facet and Cycles: white furnaces.

A closed enclosure whose inside emits Le and reflects rho (Lambert) has radiance Le (1 + rho +
... + rho^(n)) everywhere after n bounces, whatever its shape: Le / (1 - rho) in the limit. Two
enclosures, imported from Facet scenes and converted by cycles_scene.convert:
scenes/furnace.json (a sphere, Le 0.5, rho 0.8; Cycles renders a 256 x 128 UV sphere, which as a
closed polyhedron has the same exact answer) and a box (12 triangles, exact for both). 32 x 32,
64 spp, Facet max_depth 65 = Cycles 64 bounces (0.5 * 0.8^66 / 0.2 = 1.0e-6 short of 2.5: the
expected value includes it). Seeds 1 and 2; the noise of the image mean is estimated from the
two seeds' per-pixel differences (pixels independent). Both renderers must agree with the
analytic value within |z| < 5 (the script prints each ratio and z). So multi-bounce diffuse transport and one-sided mesh emission agree in both renderers;
the Cornell box's upper-half difference is direct light (test_cycles_cornell.py)."""
import json
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

RES = 32
SPP = 64
DEPTH = 65
Z_MAX = 5.0
LE, RHO = 0.5, 0.8


def box_scene(out):
    data = {"format": "facet-scene", "version": 1,
            "camera": {"position": [0.1, 0.2, 0.3], "look_at": [0, 0, -1], "up": [0, 1, 0],
                       "fov": 60, "width": RES, "height": RES},
            "shapes": [{"type": "box", "min": [-1, -1, -1], "max": [1, 1, 1],
                        "flip_normals": True, "emission": LE,
                        "material": {"model": "lambert", "reflectance": RHO}}]}
    path = os.path.join(out, "furnace_box.json")
    with open(path, "w") as f:
        json.dump(data, f)
    return path


def main():
    scene_dir, out = bt.args()[:2]
    bt.enable_addon()
    expected = LE * sum(RHO ** k for k in range(DEPTH + 1))
    for name, path in (("sphere", os.path.join(scene_dir, "furnace.json")),
                       ("box", box_scene(out))):
        bpy.ops.wm.read_homefile(use_empty=True)
        bpy.ops.import_scene.facet(filepath=path)
        scene = bpy.context.scene
        scene.render.resolution_x = scene.render.resolution_y = RES
        cs.convert(scene, exact=True)
        scene.facet.max_depth = DEPTH
        scene.facet.spp = SPP
        cs.cycles_settings(scene, samples=SPP, max_depth=DEPTH)
        for engine in ('FACET', 'CYCLES'):
            a, b = (cs.render(scene, engine, os.path.join(
                out, "furnace_%s_%s_%d.exr" % (name, engine.lower(), seed)), seed)[0]
                for seed in (1, 2))
            mean = 0.5 * (a + b).mean()
            # variance of one pixel ~ (a - b)^2 / 2; of the mean of 2 N pixel values: / (2 N)
            sigma = np.sqrt(((a - b) ** 2 / 2).mean() / (2 * a.size))
            z = (mean - expected) / sigma
            print("furnace %-6s %-6s mean %.5f, analytic %.5f, ratio %.5f, z %.1f"
                  % (name, engine, mean, expected, mean / expected, z))
            bt.check(abs(z) < Z_MAX, "%s's %s furnace equals Le (1 + rho + ... + rho^%d) "
                     "within the noise (|z| < %g)" % (engine.capitalize(), name, DEPTH, Z_MAX))


bt.run(main)
