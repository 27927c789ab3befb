"""Render > Region (border render): Facet renders only the region (a RenderSession region),
and its pixels are bit for bit those of the full render (render.h's guarantee); with Crop to
Render Region the EXR Blender writes is exactly the region, without it the region sits in
place in the full frame."""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def main():
    out = bt.args()[0]
    bt.enable_addon()
    scene = bt.factory_scene(160, 90, reload=False)
    full, _ = bt.render(scene)
    rd = scene.render
    rd.use_border = rd.use_crop_to_border = True
    rd.border_min_x, rd.border_max_x = 0.2, 0.7
    rd.border_min_y, rd.border_max_y = 0.3, 0.8
    path = os.path.join(out, "border.exr")
    part, problems = bt.render(scene, path)
    from facet_blender.pixels import border_rect
    x, y, w, h = border_rect(rd, 160, 90)
    bt.check(part is not None and part.shape == (h, w, 3),
             "rendered the %dx%d region at (%d, %d) (%s)" % (w, h, x, y, problems))
    crop = full[90 - y - h:90 - y, x:x + w]
    bt.check(np.array_equal(part, crop), "the region's pixels equal the full render's, bit for bit")
    saved = bt.load_exr(path)
    bt.check(saved.shape == part.shape and np.array_equal(saved, part),
             "the cropped EXR Blender wrote is the region")
    rd.use_crop_to_border = False
    path = os.path.join(out, "border_uncropped.exr")
    bt.render(scene, path)
    saved = bt.load_exr(path)
    inside = saved[90 - y - h:90 - y, x:x + w]
    outside = saved.copy()
    outside[90 - y - h:90 - y, x:x + w] = 0.0
    bt.check(saved.shape == full.shape and np.array_equal(inside, crop) and not outside.any(),
             "uncropped: the region in place in the full frame, nothing outside it")


bt.run(main)
