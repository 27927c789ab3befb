"""F12 on Blender's default scene (cube, point light, camera; factory startup) with Facet:
the image has the cube lit by the light in the middle and the world's grey around it, the EXR
Blender writes is the engine's image, and the render reports no error."""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def main():
    out_dir = bt.args()[0]
    bt.enable_addon()
    scene = bt.factory_scene(480, 270, spp=8, reload=False)  # 25 % of 1920 x 1080
    path = os.path.join(out_dir, "default_scene.exr")
    img, problems = bt.render(scene, path)
    bt.check(img is not None and img.shape == (270, 480, 3), "rendered 480x270")
    bt.check(np.isfinite(img).all(), "finite pixels")
    centre = img[135 - 10:135 + 10, 240 - 10:240 + 10].mean()
    corner = img[:10, :10].mean(axis=(0, 1))
    # The world of the factory scene is a Background of (0.0509, 0.0509, 0.0509), strength 1.
    bt.check(np.allclose(corner, 0.0509, atol=2e-3), "corner sees the world colour: %s" % corner)
    bt.check(centre > 0.1, "the cube in the middle is lit: %.3f" % centre)
    saved = bt.load_exr(path)
    bt.check(np.array_equal(saved, img), "the saved EXR is the engine's image bit for bit")
    bt.check(not [p for p in problems if "rror" in p], "no errors: %s" % problems)


bt.run(main)
