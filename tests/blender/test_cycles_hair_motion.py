"""Hair under motion blur (issue 37, items 3 and 4): moving hair -> the curves shapes' motion
steps, against Cycles 3.4.

Export (no render): the hair sphere of test_cycles_hair.py (300 hairs grown from vertices, root
radius 0.04, tip 0.02) keyframed to move 3 units per frame along x (linear), at frame 1 with
shutter 0.5 centred on it and the object's default 3 motion steps: its hair shape gets the
emitter's 3 matrices as its "motion" and no "motion_positions" (the keys read at each step do
not move in the emitter's space), with the object's Deformation on or off; the object's
Motion Blur off, or the
viewport's export (no frame_set): still hair; nothing is reported as rendered without motion
blur. A CURVES object (Add > Curves > Random) moving 1.5
units per frame gets the object's 3 matrices as its shape's "motion" and no deformation steps.
A CURVES object whose points a geometry nodes modifier slides 1.5 units per frame gets
"motion_positions" of 3 steps 0.375 apart, and renders against Cycles within the same bounds
(below).

Render: that moving furry sphere (Diffuse hair, diffuse skin, a sun, a dark world) at 64 x 48,
128 spp, max depth 2 (Cycles 1 bounce), Facet (through the export) against Cycles, two seeds
each; the bounds of the other Cycles tests (test_cycles_motion.py):
- |mean luminance ratio Facet / Cycles - 1| <= 2% (Cycles: its two seeds' mean);
- block RMSE (8 x 8 blocks' mean luminance, Facet seed 1 against Cycles seed 1) <= 3 x the
  noise floor (the same between Cycles seeds 1 and 2).
The same for the deforming CURVES object (Add > Curves > Random in front of the factory cube,
as test_cycles_hair.py's Curves case).
The same for the furry sphere spinning SPIN = 90 degrees about z over the shutter with
Deformation off, seen from above (case_spin): its hair shape carries the emitter's matrices as
its "motion" (points in the emitter's object space, no "motion_positions"), which Facet
interpolates decomposed (the rotation by slerp) as Cycles 3.4 moves particle hair with its
object's transform motion; the control exports the still keys carried by the emitter's
matrices as "motion_positions" (interpolated linearly: the strands cut the chord between
steps) and must break a bound.
Ability to fail (also for the deforming Curves): Facet with the hair's motion steps dropped
(the sphere blurred, its hair sharp at the frame: what the addon rendered before) must break a
bound, and so must Facet with motion blur off altogether (numbers printed)."""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402
from facet_testsupport.motion_scene import (  # noqa: E402
    blur_on, export, linear, scene_frame_set)

W, H = 64, 48
BLOCK = 8
SPP = 128
MEAN_TOL = 0.02
RMSE_FACTOR = 3.0
MAX_DEPTH = 2
SLIDE = 1.5  # the deforming Curves' slide, units per frame
SPIN = 90.0  # the spinning emitter's turn over the shutter, degrees


def diffuse(name, colour):
    mat, nt, out = bt.new_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = colour + (1.0,)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def move(obj, x0=-1.5, x1=1.5):
    """Keyframes `obj` from x0 at frame 0 to x1 at frame 2, linearly (1.5 units per frame)."""
    y, z = obj.location[1], obj.location[2]
    for frame, x in ((0, x0), (2, x1)):
        obj.location = (x, y, z)
        obj.keyframe_insert("location", frame=frame)
    linear(obj)



def fur_scene():
    """The furry sphere "Ball" at the origin (still), its sun and dark world."""
    scene = bt.factory_scene(W, H)
    bpy.data.objects.remove(bpy.data.objects["Cube"])
    bpy.data.objects.remove(bpy.data.objects["Light"])
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0.0, 0.0, 0.0))
    sphere = bpy.context.active_object
    sphere.name = "Ball"
    sphere.data.materials.append(diffuse("Skin", (0.5, 0.5, 0.5)))
    sphere.data.materials.append(diffuse("Fur", (0.8, 0.4, 0.1)))
    # Thicker than cs.add_fur's (root radius 0.04, tip 0.02): the hair's share of the image
    # large enough that sharp hair on the blurred sphere shows beyond the noise (the control).
    cs.add_fur(sphere, 300).particle_system.settings.radius_scale = 0.08
    scene.cycles_curves.shape = 'THICK'
    cs.add_light(scene, 'SUN', 3.0, (0.0, 0.0, 5.0), rotation=(0.6, 0.3, 0.0))
    scene.world.use_nodes = True
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)
    return scene, sphere


def moving_fur_scene():
    scene, sphere = fur_scene()
    move(sphere, -3.0, 3.0)
    blur_on(scene)
    return scene, sphere


def spinning_fur_scene():
    """The furry sphere spinning SPIN degrees about z over the shutter (linear keys, 2 SPIN
    per frame; shutter 0.5 centred on frame 1: 3 steps SPIN / 2 apart) with Deformation off,
    seen from above (the camera 6 units up, looking down z), so that the strands sweep their
    arcs in the image plane."""
    scene, sphere = fur_scene()
    for frame, z in ((0, 0.0), (2, 4.0 * math.radians(SPIN))):
        sphere.rotation_euler = (0.0, 0.0, z)
        sphere.keyframe_insert("rotation_euler", frame=frame)
    linear(sphere)
    sphere.cycles.use_deform_motion = False
    scene.camera.location = (0.0, 0.0, 6.0)
    scene.camera.rotation_euler = (0.0, 0.0, 0.0)
    blur_on(scene)
    return scene, sphere


def hair_of(data):
    hair = [s for s in data["shapes"] if s["type"] == "curves"]
    bt.check(len(hair) == 1, "one curves shape: %s" % [s.get("name") for s in data["shapes"]])
    return hair[0]


def case_export():
    scene, sphere = moving_fur_scene()
    data, problems = export(scene_frame_set)
    h = hair_of(data)
    # Frame 1, shutter 0.5 centred: steps at frames 0.75, 1, 1.25; 3 units per frame.
    ball = [s for s in data["shapes"] if s.get("name") == "Ball"]
    bt.check(ball and len(ball[0].get("motion", ())) == 3, "the emitter moves by its matrices")
    bt.check([round(r[0][3], 6) for r in ball[0]["motion"]] == [-0.75, 0.0, 0.75],
             "its steps: %s" % [r[0][3] for r in ball[0]["motion"]])
    bt.check(not [p for p in problems if "motion blur" in p], "nothing reported: %s" % problems)
    # Deformation on: the keys read at the steps do not move in the emitter's space (the fur
    # is carried rigidly), so the hair moves by the emitter's matrices, no motion_positions.
    bt.check("motion_positions" not in h and h.get("motion") == ball[0]["motion"],
             "Deformation on, rigid fur: the emitter's matrices as the hair's motion: %s"
             % sorted(h))
    # Deformation off: the same (the emitter at the origin at frame 1: object space = world
    # space).
    sphere.cycles.use_deform_motion = False
    data, problems = export(scene_frame_set)
    hd = hair_of(data)
    bt.check("motion_positions" not in hd and hd.get("motion") == ball[0]["motion"],
             "Deformation off: the emitter's matrices as the hair's motion: %s"
             % [r[0][3] for r in hd.get("motion", [])])
    bt.check(np.allclose(hd["points"], h["points"], atol=1e-5), "object space = world space")
    sphere.cycles.use_deform_motion = True
    # The object's Motion Blur off: still hair (as Cycles), nothing reported.
    sphere.cycles.use_motion_blur = False
    data, problems = export(scene_frame_set)
    bt.check("motion_positions" not in hair_of(data), "object Motion Blur off: still hair")
    sphere.cycles.use_motion_blur = True
    # Without frame_set (the viewport's export) nothing moves.
    bt.check("motion_positions" not in hair_of(export()[0]), "viewport: still")
    from facet_blender import native
    native.build(export(scene_frame_set)[0], name="blender")


def case_curves_export():
    scene = bt.factory_scene(W, H)
    bpy.ops.object.curves_random_add(location=(0.0, 0.0, 0.5))
    ob = bpy.context.active_object
    ob.name = "Random"
    move(ob)
    blur_on(scene)
    data, problems = export(scene_frame_set)
    h = hair_of(data)
    m = h.get("motion", [])
    bt.check(len(m) == 3 and [round(r[0][3], 6) for r in m] == [-0.375, 0.0, 0.375],
             "the object's matrices as the shape's motion: %s" % [r[0][3] for r in m])
    bt.check("motion_positions" not in h, "no deformation (the points stay)")
    bt.check(not [p for p in problems if "motion blur" in p], "nothing reported: %s" % problems)
    from facet_blender import native
    native.build(data, name="blender")


def renders(scene, name, out, engines=('FACET', 'CYCLES')):
    scene.facet.max_depth = MAX_DEPTH
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=MAX_DEPTH)
    scene.render.use_motion_blur = True  # cycles_settings turns it off
    return {e: tuple(cs.render(scene, e, os.path.join(out, "hairmotion_%s_%s_%d.exr"
                                                        % (name, e.lower(), seed)), seed)[0]
                     for seed in (1, 2)) for e in engines}


def compare(name, f, c1, c2):
    return cs.compare_to_cycles(name, f, c1, c2, BLOCK)


def case_render(out):
    scene, sphere = moving_fur_scene()
    imgs = renders(scene, "fur", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = compare("moving", imgs['FACET'][0], c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the moving furry sphere: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    from facet_blender import sync_motion
    # Control 1: the hair's motion dropped (sharp hair on the blurred sphere): neither the
    # emitter's matrices nor motion steps.
    saved = sync_motion._add_hair_deformation, sync_motion._carry_hair
    sync_motion._add_hair_deformation = lambda *a, **k: None
    sync_motion._carry_hair = lambda *a, **k: False
    try:
        sharp = renders(scene, "sharp_hair", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_motion._add_hair_deformation, sync_motion._carry_hair = saved
    ratio, rel = compare("still hair", sharp, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "sharp hair breaks a bound (mean ratio %.4f, block RMSE %.2f x floor): the test "
             "can fail" % (ratio, rel))
    # Control 2: motion blur off in Facet only.
    saved = sync_motion.settings
    sync_motion.settings = lambda *a, **k: None
    try:
        still = renders(scene, "no_blur", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_motion.settings = saved
    ratio, rel = compare("no blur", still, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "no motion blur breaks a bound (mean ratio %.4f, block RMSE %.2f x floor)"
             % (ratio, rel))


def chord_export(shape, step_mats):
    """The linear export that sync_motion._carry_hair replaces: the points carried by the
    emitter's matrices (M_step p, p in its object space) as motion_positions (in the space its
    transform places), which the core interpolates linearly: a spinning emitter's strands cut
    the chord between steps."""
    p = np.array(shape["points"]).reshape(-1, 3)
    inv = np.linalg.inv(np.array(shape["transform"]))
    rel = [inv @ np.array(m) for m in step_mats]
    shape["motion_positions"] = [[float(v) for v in (p @ r[:3, :3].T + r[:3, 3]).ravel()]
                                 for r in rel]


def case_spin(out):
    """The furry sphere spinning SPIN degrees over the shutter, Deformation off: its hair
    shape gets the emitter's 3 matrices as its motion (no motion_positions), its points in the
    emitter's object space (placed by its transform where the still export puts them); against
    Cycles within the bounds; the chord export (chord_export) must break one."""
    scene, sphere = spinning_fur_scene()
    data, problems = export(scene_frame_set)
    h = hair_of(data)
    ball = [s for s in data["shapes"] if s.get("name") == "Ball"][0]
    m = h.get("motion", [])
    bt.check(len(m) == 3 and m == ball.get("motion") and "motion_positions" not in h,
             "the spinning emitter's matrices as the hair's motion, no motion_positions: %s"
             % sorted(h))
    angles = [math.degrees(math.atan2(r[1][0], r[0][0])) % 360.0 for r in m]
    bt.check(np.allclose(np.diff(angles), SPIN / 2.0, atol=1e-3), "steps %s" % angles)
    sphere.cycles.use_motion_blur = False
    still = hair_of(export(scene_frame_set)[0])
    sphere.cycles.use_motion_blur = True
    bt.check(still.get("transform") == h["transform"] and "motion" not in still,
             "still hair: placed by the frame's matrix, no motion")
    bt.check(np.allclose(h["points"], still["points"], atol=1e-6),
             "the same object-space points: off by %g"
             % np.abs(np.array(h["points"]) - np.array(still["points"])).max())
    bt.check(not [p for p in problems if "motion blur" in p], "nothing reported: %s" % problems)
    imgs = renders(scene, "spin", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = compare("spinning", imgs['FACET'][0], c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the spinning furry sphere: mean ratio %.4f within %g, block RMSE %.2f <= %g x "
             "floor" % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    from facet_blender import sync_motion
    saved = sync_motion._carry_hair
    sync_motion._carry_hair = chord_export
    try:
        chord = renders(scene, "spin_chord", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_motion._carry_hair = saved
    ratio, rel = compare("chord", chord, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "the chord export breaks a bound (mean ratio %.4f, block RMSE %.2f x floor): the "
             "test can fail" % (ratio, rel))
    # Deformation on: the keys read at each step, carried into the emitter's space there,
    # do not move in it (a rigid spin), so the export is the same motion without
    # motion_positions; Cycles' images serve (its object-space keys are the same at every
    # step, so its deformation motion is none).
    sphere.cycles.use_deform_motion = True
    data, problems = export(scene_frame_set)
    h = hair_of(data)
    bt.check(h.get("motion") == m and "motion_positions" not in h,
             "Deformation on, rigid spin: the emitter's matrices, no motion_positions: %s"
             % sorted(h))
    f_on = renders(scene, "spin_deform", out, engines=('FACET',))['FACET'][0]
    sphere.cycles.use_deform_motion = False
    ratio, rel = compare("spin, deform on", f_on, c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "Deformation on: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))


def wave_modifier(ob, speed):
    """A geometry nodes modifier moving every point of `ob` by speed (frame - 1) along x: the
    points deform over the shutter (the object itself stays)."""
    ng = bpy.data.node_groups.new("Slide", 'GeometryNodeTree')
    ng.inputs.new('NodeSocketGeometry', "Geometry")
    ng.outputs.new('NodeSocketGeometry', "Geometry")
    gin, gout = ng.nodes.new('NodeGroupInput'), ng.nodes.new('NodeGroupOutput')
    sp = ng.nodes.new('GeometryNodeSetPosition')
    t = ng.nodes.new('GeometryNodeInputSceneTime')
    ma = ng.nodes.new('ShaderNodeMath')
    ma.operation = 'MULTIPLY_ADD'
    ma.inputs[1].default_value = speed
    ma.inputs[2].default_value = -speed
    comb = ng.nodes.new('ShaderNodeCombineXYZ')
    ng.links.new(t.outputs['Frame'], ma.inputs[0])
    ng.links.new(ma.outputs[0], comb.inputs['X'])
    ng.links.new(comb.outputs[0], sp.inputs['Offset'])
    ng.links.new(gin.outputs[0], sp.inputs['Geometry'])
    ng.links.new(sp.outputs[0], gout.inputs[0])
    mod = ob.modifiers.new("Slide", 'NODES')
    mod.node_group = ng
    return mod


def case_curves_deform_render(out):
    """Blender 3.4's random hair curves (Add > Curves > Random: 500 curves, root radius 0.02)
    in the scene of test_cycles_hair.py's Curves case (the factory cube behind them, a sun),
    their points slid SLIDE units per frame along x by a geometry nodes modifier, under
    motion blur (shutter 0.5 centred, 3 steps), against Cycles: the export gives the shape
    motion_positions (3 steps SLIDE / 4 apart in x); the control drops them (sharp curves)."""
    scene = bt.factory_scene(W, H)
    bpy.ops.object.curves_random_add(location=(0.0, 0.0, 0.5))
    ob = bpy.context.active_object
    ob.name = "Sliding"
    ob.data.materials.append(diffuse("Strand", (0.2, 0.6, 0.3)))
    wave_modifier(ob, SLIDE)
    scene.cycles_curves.shape = 'THICK'
    cs.add_light(scene, 'SUN', 3.0, (0.0, 0.0, 5.0), rotation=(0.6, 0.3, 0.0))
    scene.camera.location = (0.0, -3.0, 1.0)
    scene.camera.rotation_euler = (1.35, 0.0, 0.0)
    blur_on(scene)
    data, problems = export(scene_frame_set)
    h = hair_of(data)
    mp = h.get("motion_positions", [])
    dx = [np.mean(np.array(st).reshape(-1, 3)[:, 0]) for st in mp]
    bt.check(len(mp) == 3 and np.allclose(np.diff(dx), SLIDE / 4.0, atol=1e-4),
             "the deforming Curves' points per step: %s" % dx)
    imgs = renders(scene, "curves_slide", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = compare("deforming curves", imgs['FACET'][0], c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the deforming Curves object: mean ratio %.4f within %g, block RMSE %.2f <= %g x "
             "floor" % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    from facet_blender import sync_motion
    saved = sync_motion._add_hair_deformation
    sync_motion._add_hair_deformation = lambda *a, **k: None
    try:
        sharp = renders(scene, "curves_sharp", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_motion._add_hair_deformation = saved
    ratio, rel = compare("sharp curves", sharp, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "sharp curves break a bound (mean ratio %.4f, block RMSE %.2f x floor): the test "
             "can fail" % (ratio, rel))


def main():
    out = bt.args()[0]
    bt.enable_addon()
    case_export()
    case_curves_export()
    case_spin(out)
    case_render(out)
    case_curves_deform_render(out)


bt.run(main)
