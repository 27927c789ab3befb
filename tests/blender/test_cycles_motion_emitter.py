"""A moving emissive mesh under motion blur (issue 37) -> Facet, against Cycles 3.4.

Export (no render): the emitting cube gets its "motion" and no report line; a point lamp
keyframed to move gets none and no report line either: Cycles 3.4 syncs lamps at the frame only
(blender/object.cpp skips lights at the motion steps), so a lamp renders still in both.

Render: a small emissive cube (0.5 across, Emission strength 8) flying 3 units per frame along
x, 0.25 above a grey diffuse floor, rendered at frame 1 with shutter 0.5 centred on it (a
1.5-unit sweep), no lamp, the factory camera and world, 64 x 48, direct light plus one bounce
(Facet max_depth 2 = Cycles 1 bounce), Facet (through the export) against Cycles, two seeds
each. Bounds as the other Cycles tests state them (test_cycles_motion.py):
- |mean luminance ratio Facet / Cycles - 1| <= 2% (Cycles: its two seeds' mean);
- block RMSE (8 x 8 blocks' mean luminance, Facet seed 1 against Cycles seed 1) <= 3 x the
  noise floor (the same between Cycles seeds 1 and 2).
Ability to fail: Facet with the export's motion removed (the emitter still at the frame) must
break a bound, and does (numbers printed)."""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402
from facet_testsupport.motion_scene import (  # noqa: E402
    blur_on, export, grey_floor, linear, scene_frame_set)

W, H = 64, 48
BLOCK = 8
SPP = 128
MEAN_TOL = 0.02
RMSE_FACTOR = 3.0
MAX_DEPTH = 2



def emitter_scene():
    scene = bt.factory_scene(W, H)
    bpy.data.objects.remove(bpy.data.objects["Light"])
    cube = bpy.data.objects["Cube"]
    cube.scale = (0.25, 0.25, 0.25)
    for frame, x in ((0, -3.0), (2, 3.0)):
        cube.location = (x, 0.0, 0.0)
        cube.keyframe_insert("location", frame=frame)
    linear(cube)
    mat, nt, out = bt.new_material("Glow")
    e = nt.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (1.0, 0.9, 0.7, 1)
    e.inputs["Strength"].default_value = 8.0
    nt.links.new(e.outputs[0], out.inputs["Surface"])
    cube.data.materials.clear()
    cube.data.materials.append(mat)
    blur_on(scene)
    grey_floor(-0.5)
    return scene, cube


def case_export():
    scene, cube = emitter_scene()
    data, problems = export(scene_frame_set)
    shapes = {s["name"]: s for s in data["shapes"]}
    bt.check(len(shapes["Cube"].get("motion", [])) == 3 and shapes["Cube"].get("emission"),
             "the emitting cube moves: %s" % sorted(shapes["Cube"]))
    bt.check(not [p for p in problems if "otion" in p or "emit" in p],
             "no report line for the moving emitter: %s" % problems)
    # A moving lamp stays at the frame, as in Cycles, with no report.
    bpy.ops.object.light_add(type='POINT', location=(0.0, 2.0, 2.0))
    lamp = bpy.context.active_object
    lamp.keyframe_insert("location", frame=0)
    lamp.location.x += 3.0
    lamp.keyframe_insert("location", frame=2)
    linear(lamp)
    scene.frame_set(1)
    data, problems = export(scene_frame_set)
    points = [l for l in data["lights"] if l["type"] == "point"]
    bt.check(len(points) == 1 and "motion" not in points[0]
             and abs(points[0]["position"][0] - 1.5) < 1e-5,
             "the lamp has no motion and sits at the frame's x = 1.5: %s" % points)
    bt.check(not [p for p in problems if "otion" in p or "emit" in p],
             "no report line for the moving lamp: %s" % problems)
    bpy.data.objects.remove(lamp)


def renders(scene, name, out, engines=('FACET', 'CYCLES')):
    scene.facet.max_depth = MAX_DEPTH
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=MAX_DEPTH)
    scene.render.use_motion_blur = True  # cycles_settings turns it off
    return {e: tuple(cs.render(scene, e, os.path.join(out, "motion_emitter_%s_%s_%d.exr"
                                                        % (name, e.lower(), seed)), seed)[0]
                     for seed in (1, 2)) for e in engines}


def case_render(out):
    scene, _ = emitter_scene()
    imgs = renders(scene, "glow", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = cs.compare_to_cycles("moving emitter", imgs['FACET'][0], c1, c2, BLOCK)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the moving emitter: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    # The control: the emitter still at the frame (Facet without the motion).
    from facet_blender import sync_motion
    saved = sync_motion.add_motion
    sync_motion.add_motion = lambda *a, **k: None
    try:
        still = renders(scene, "still", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_motion.add_motion = saved
    ratio, rel = cs.compare_to_cycles("still emitter", still, c1, c2, BLOCK)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "the still emitter breaks a bound (mean ratio %.4f, block RMSE %.2f x floor): the "
             "test can fail" % (ratio, rel))


def main():
    out = bt.args()[0]
    bt.enable_addon()
    case_export()
    case_render(out)


bt.run(main)
