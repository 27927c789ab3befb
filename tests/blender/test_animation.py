"""Animation render (bpy.ops.render.render(animation=True), what `blender -b -a` and
Ctrl-F12 run): the default cube moves between frames 1 and 2; each frame is rendered by Facet
(Blender makes a fresh engine per frame) and written, and the frames differ where the cube
moved."""
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
    cube = bpy.data.objects["Cube"]
    cube.location = (0, 0, 0)
    cube.keyframe_insert("location", frame=1)
    cube.location = (0, 1.5, 0)
    cube.keyframe_insert("location", frame=2)
    scene.frame_start, scene.frame_end = 1, 2
    scene.render.filepath = os.path.join(out, "anim_")
    scene.render.image_settings.file_format = 'OPEN_EXR'
    scene.render.image_settings.color_depth = '32'
    scene.render.image_settings.color_mode = 'RGB'
    bpy.ops.render.render(animation=True)
    frames = [os.path.join(out, "anim_%04d.exr" % f) for f in (1, 2)]
    bt.check(all(os.path.exists(f) for f in frames), "both frames written")
    a, b = (bt.load_exr(f) for f in frames)
    bt.check(a.max() > 0.1 and b.max() > 0.1, "both frames lit")
    bt.check(np.abs(a - b).max() > 0.1, "the cube moved between the frames")


bt.run(main)
