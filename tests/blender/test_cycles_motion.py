"""Blender's motion blur -> Facet's (issue 37, items 3 and 4), against Cycles 3.4.

Export (no render): Motion Blur on gives the render's "motion_blur" (shutter, position, a
shaped shutter curve as weights), an animated cube's "motion" at its motion steps (Cycles'
2^steps + 1 times over the open shutter), an animated camera's "motion"; a still object gets
none; Motion Blur off gives neither, and the view layer's Motion Blur filter off neither.

Render: the factory cube (scaled 0.5) keyframed to move 1.5 units per frame (x -1.5 at frame
0 to 1.5 at frame 2, linear), rendered at frame 1 with shutter 0.5 centred on it, a grey floor, the factory lamp
and a grey world, 64 x 48, direct light plus one bounce (Facet max_depth 2 = Cycles 1 bounce),
Facet (through the export) against Cycles, two seeds each. Bounds as the other Cycles tests
state them (test_cycles34_lamps.py):
- |mean luminance ratio Facet / Cycles - 1| <= 2% (Cycles: its two seeds' mean);
- block RMSE (8 x 8 blocks' mean luminance, Facet seed 1 against Cycles seed 1) <= 3 x the
  noise floor (the same between Cycles seeds 1 and 2).
Ability to fail: Facet with the export's motion removed (the sharp cube at the frame, what the
addon rendered before) must break a bound, and does (numbers printed). The same for a cube
turning 90 degrees per frame about z (rotation: slerped steps) and for the still cube seen from
a camera moving 1 unit per frame sideways (camera motion), and for the cube's mesh sliding
1.5 units per frame by a shape key while the object stays (deformation motion); the export of
a mesh whose topology changes over the shutter is reported, without deformation steps."""
import os
import sys

import bpy
import numpy as np

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


luminance = cs.luminance


def block_rmse(a, b):
    return cs.block_rmse(a, b, BLOCK)


def moving_scene():
    scene = bt.factory_scene(W, H)
    cube = bpy.data.objects["Cube"]
    cube.scale = (0.5, 0.5, 0.5)
    for frame, x in ((0, -1.5), (2, 1.5)):
        cube.location = (x, 0.0, 0.0)
        cube.keyframe_insert("location", frame=frame)
    linear(cube)
    blur_on(scene)
    grey_floor(-0.5)
    return scene, cube


def case_export():
    scene, cube = moving_scene()
    data, problems = export(scene_frame_set)
    mb = data["render"].get("motion_blur")
    bt.check(mb is not None and mb["shutter"] == 0.5 and mb["position"] == "center"
             and "curve" not in mb, "motion blur settings: %s" % mb)
    shapes = {s["name"]: s for s in data["shapes"]}
    m = shapes["Cube"].get("motion")
    bt.check(m is not None and len(m) == 3, "the cube's motion: 3 steps (motion_steps 1)")
    xs = [row[0][3] for row in m] if m else []
    bt.check(np.allclose(xs, [-0.375, 0.0, 0.375], atol=1e-5),
             "the steps at frames 0.75, 1, 1.25: x %s" % xs)
    bt.check("motion" not in shapes["Plane"], "the still floor has no motion")
    bt.check(bpy.context.scene.frame_current == 1 and
             abs(bpy.context.scene.frame_subframe) < 1e-6, "the frame is restored")
    bt.check(not [p for p in problems if "otion" in p], "no motion line: %s" % problems)
    # Instances carry no motion: an instance of the moving cube (a collection instance) is
    # named in the report.
    coll = bpy.data.collections.new("Moving")
    coll.objects.link(cube)
    holder = bpy.data.objects.new("Holder", None)
    holder.instance_type = 'COLLECTION'
    holder.instance_collection = coll
    holder.location = (0.0, 3.0, 0.0)
    scene.collection.objects.link(holder)
    problems = export(scene_frame_set)[1]
    bt.check([p for p in problems
              if "'Cube': its instances are rendered without motion blur" in p],
             "the moving cube's instance is reported: %s" % problems)
    bpy.data.objects.remove(holder)
    bpy.data.collections.remove(coll)
    problems = export(scene_frame_set)[1]
    bt.check(not [p for p in problems if "otion" in p], "no motion line again: %s" % problems)
    cube.cycles.motion_steps = 2
    m = {s["name"]: s for s in export(scene_frame_set)[0]["shapes"]}["Cube"]["motion"]
    bt.check(len(m) == 5, "motion_steps 2: 5 steps")
    cube.cycles.use_motion_blur = False
    bt.check("motion" not in {s["name"]: s for s in export(scene_frame_set)[0]["shapes"]}["Cube"],
             "the object's Motion Blur off: no motion")
    cube.cycles.use_motion_blur = True
    # A shaped shutter curve: weights; position End.
    cm = scene.render.motion_blur_shutter_curve
    pts = cm.curves[0].points
    pts[0].location = (0.0, 0.0)
    cm.update()
    scene.cycles.motion_blur_position = 'END'
    data = export(scene_frame_set)[0]
    mb = data["render"]["motion_blur"]
    bt.check(mb["position"] == "end" and len(mb.get("curve", [])) == 256
             and mb["curve"][0] < mb["curve"][-1], "a shaped curve: %s..." % mb.get("curve", [])[:3])
    xs = [row[0][3] for row in {s["name"]: s for s in data["shapes"]}["Cube"]["motion"]]
    bt.check(np.allclose(xs[-1], 0.0, atol=1e-5), "position End: the last step at the frame")
    # Camera motion (Center again: steps at frames 0.75, 1, 1.25).
    scene.cycles.motion_blur_position = 'CENTER'
    cam = scene.camera
    cam.keyframe_insert("location", frame=1)
    cam.location.x += 1.0
    cam.keyframe_insert("location", frame=2)
    scene.frame_set(1)
    data = export(scene_frame_set)[0]
    bt.check(len(data["camera"].get("motion", [])) == 3, "the camera's motion")
    # Off: nothing.
    scene.render.use_motion_blur = False
    data = export(scene_frame_set)[0]
    bt.check("motion_blur" not in data["render"] and "motion" not in data["camera"],
             "Motion Blur off: no settings, no motion")
    scene.render.use_motion_blur = True
    bpy.context.view_layer.use_motion_blur = False
    data = export(scene_frame_set)[0]
    bt.check("motion_blur" not in data["render"], "the view layer's filter off: none")
    # The description builds (the core accepts it).
    from facet_blender import native
    bpy.context.view_layer.use_motion_blur = True
    built, _ = native.build(export(scene_frame_set)[0], name="blender")
    bt.check(built.features().has_motion if hasattr(built, "features") else True,
             "the exported scene builds")


def renders(scene, name, out, engines=('FACET', 'CYCLES')):
    scene.facet.max_depth = MAX_DEPTH
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=MAX_DEPTH)
    scene.render.use_motion_blur = True  # cycles_settings turns it off
    return {e: tuple(cs.render(scene, e, os.path.join(out, "motion_%s_%s_%d.exr"
                                                        % (name, e.lower(), seed)), seed)[0]
                     for seed in (1, 2)) for e in engines}


def compare(name, f, c1, c2):
    return cs.compare_to_cycles(name, f, c1, c2, BLOCK)


def case_render(out):
    scene, cube = moving_scene()
    imgs = renders(scene, "cube", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = compare("moving", imgs['FACET'][0], c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the moving cube: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    # The control: the sharp cube (Facet without the motion, as before this conversion).
    from facet_blender import sync_motion
    saved = sync_motion.add_motion
    sync_motion.add_motion = lambda *a, **k: None
    try:
        sharp = renders(scene, "sharp", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_motion.add_motion = saved
    ratio, rel = compare("sharp", sharp, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "the sharp cube breaks a bound (mean ratio %.4f, block RMSE %.2f x floor): the "
             "test can fail" % (ratio, rel))


def case_rotate_and_camera(out):
    """A cube turning 90 degrees per frame about z (a 45 degree sweep over the shutter:
    slerped steps in both renderers), then the still cube seen from a camera moving 1 unit
    per frame sideways: the same bounds and the same sharp control."""
    from facet_blender import sync_motion
    scene, cube = moving_scene()
    cube.animation_data_clear()
    cube.location = (0.0, 0.0, 0.0)
    cube.scale = (1.0, 0.4, 0.4)
    for frame, angle in ((0, -90.0), (2, 90.0)):
        cube.rotation_euler = (0.0, 0.0, angle * 3.141592653589793 / 180.0)
        cube.keyframe_insert("rotation_euler", frame=frame)
    linear(cube)
    cam = scene.camera
    cases = [("rotating", None)]

    def camera_moves():
        cube.animation_data_clear()
        cube.rotation_euler = (0.0, 0.0, 0.3)
        x0 = cam.location.x
        for frame, dx in ((0, -1.0), (2, 1.0)):
            cam.location.x = x0 + dx
            cam.keyframe_insert("location", frame=frame)
        linear(cam)
    cases.append(("camera", camera_moves))
    for name, setup in cases:
        if setup is not None:
            setup()
        scene.frame_set(1)
        imgs = renders(scene, name, out)
        c1, c2 = imgs['CYCLES']
        ratio, rel = compare(name, imgs['FACET'][0], c1, c2)
        bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
                 "%s: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
                 % (name, ratio, MEAN_TOL, rel, RMSE_FACTOR))
        saved = sync_motion.add_motion
        sync_motion.add_motion = lambda *a, **k: None
        try:
            sharp = renders(scene, name + "_sharp", out, engines=('FACET',))['FACET'][0]
        finally:
            sync_motion.add_motion = saved
        ratio, rel = compare(name + "/sharp", sharp, c1, c2)
        bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
                 "%s without motion breaks a bound (mean ratio %.4f, block RMSE %.2f x floor)"
                 % (name, ratio, rel))


def deforming_scene():
    """The moving cube's scene with the cube still and its mesh sliding instead: a shape key
    moving every vertex 6 units along object x (1.5 world units per frame at scale 0.5, as the
    moving cube), keyed 0 at frame 0 to 1 at frame 2, linear; the object at x -1.5, so that
    at frame 1 the cube is where the moving cube is."""
    scene, cube = moving_scene()
    cube.animation_data_clear()
    cube.location = (-1.5, 0.0, 0.0)
    cube.shape_key_add(name="Basis")
    key = cube.shape_key_add(name="Slide")
    for v in key.data:
        v.co.x += 6.0
    for frame, value in ((0, 0.0), (2, 1.0)):
        key.value = value
        key.keyframe_insert("value", frame=frame)
    for fc in cube.data.shape_keys.animation_data.action.fcurves:
        for kp in fc.keyframe_points:
            kp.interpolation = 'LINEAR'
    scene.frame_set(1)
    return scene, cube


def case_deform_export():
    """Deformation motion: the sliding mesh gets "motion_positions" at its 3 steps (no
    "motion": the object does not move) with the shape key's values 0.375, 0.5, 0.625; the
    object's Deformation off gives none; a mesh whose topology changes over the shutter (a
    Build modifier adding faces) gets none and a report line naming it."""
    scene, cube = deforming_scene()
    data, problems = export(scene_frame_set)
    shape = {s["name"]: s for s in data["shapes"]}["Cube"]
    steps = shape.get("motion_positions")
    bt.check(steps is not None and len(steps) == 3 and "motion" not in shape,
             "the sliding cube: 3 deformation steps, no transform motion")
    if steps is not None:
        base = np.asarray(shape["positions"], np.float64)
        dx = [float(np.mean(np.asarray(st, np.float64)[:, 0] - base[:, 0])) for st in steps]
        # At frame 1 the key is 0.5 (base = +3); the steps at 0.375, 0.5, 0.625: -0.75, 0, 0.75.
        bt.check(np.allclose(dx, [-0.75, 0.0, 0.75], atol=1e-4), "the steps' offsets: %s" % dx)
    bt.check(not [p for p in problems if "otion" in p or "topology" in p],
             "no motion line: %s" % problems)
    from facet_blender import native
    built, _ = native.build(data, name="blender")  # the core accepts the steps
    bt.check(built is not None, "the deforming export builds")
    cube.cycles.use_deform_motion = False
    shape = {s["name"]: s for s in export(scene_frame_set)[0]["shapes"]}["Cube"]
    bt.check("motion_positions" not in shape, "Deformation off: no deformation steps")
    cube.cycles.use_deform_motion = True
    # A smooth mesh: its normals per step too (a new factory scene).
    scene, box = twisting_scene(smooth=True)
    shape = {s["name"]: s for s in export(scene_frame_set)[0]["shapes"]}["Twist"]
    bt.check(len(shape.get("motion_positions", [])) == 3 and
             len(shape.get("motion_normals", [])) == 3 and shape.get("normals") is not None,
             "the smooth twisting box: deformation steps with normals")
    # Topology that changes over the shutter: a Build modifier over frames 0 to 2.
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2, radius=0.4, location=(0.0, 1.5, 0.0))
    ico = bpy.context.active_object
    ico.name = "Growing"
    build = ico.modifiers.new("Build", 'BUILD')
    build.frame_start = 0.0
    build.frame_duration = 2.0
    scene.frame_set(1)
    data, problems = export(scene_frame_set)
    grow = {s["name"]: s for s in data["shapes"]}["Growing"]
    lines = [p for p in problems if "'Growing'" in p and "topology" in p]
    bt.check("motion_positions" not in grow and len(lines) == 1,
             "changing topology: no steps, one line: %s" % lines)
    bpy.data.objects.remove(ico)


def twisting_scene(smooth=False):
    """A non-rigid deformation: a box (1 x 0.4 x 0.4, each edge cut in 5; flat shaded, or
    `smooth`) twisted about x by a Simple Deform modifier whose angle is keyed -360 degrees at
    frame 0 to 360 at frame 2 (linear): at frame 1 untwisted, over the shutter from -90 to 90
    degrees end to end."""
    scene, cube = moving_scene()
    bpy.data.objects.remove(cube)
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, 0.0))
    box = bpy.context.active_object
    box.name = "Twist"
    box.scale = (1.0, 0.4, 0.4)
    bpy.ops.object.mode_set(mode='EDIT')
    bpy.ops.mesh.subdivide(number_cuts=4)
    bpy.ops.object.mode_set(mode='OBJECT')
    if smooth:
        bpy.ops.object.shade_smooth()
    mod = box.modifiers.new("Twist", 'SIMPLE_DEFORM')
    mod.deform_method = 'TWIST'
    mod.deform_axis = 'X'
    for frame, deg in ((0, -360.0), (2, 360.0)):
        mod.angle = deg * 3.141592653589793 / 180.0
        box.keyframe_insert('modifiers["Twist"].angle', frame=frame)
    linear(box)
    scene.frame_set(1)
    return scene, box


def case_deform_render(out):
    """The sliding mesh and the twisting box against Cycles' deformation blur, with the same
    bounds as the moving cube, and each without its deformation steps as the control that must
    fail."""
    from facet_blender import sync_motion
    for name, make in (("deform", deforming_scene), ("twist", twisting_scene)):
        scene, _ = make()
        imgs = renders(scene, name, out)
        c1, c2 = imgs['CYCLES']
        ratio, rel = compare(name, imgs['FACET'][0], c1, c2)
        bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
                 "%s: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
                 % (name, ratio, MEAN_TOL, rel, RMSE_FACTOR))
        saved = sync_motion.add_motion
        sync_motion.add_motion = lambda *a, **k: None
        try:
            sharp = renders(scene, name + "_sharp", out, engines=('FACET',))['FACET'][0]
        finally:
            sync_motion.add_motion = saved
        ratio, rel = compare(name + "/sharp", sharp, c1, c2)
        bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
                 "%s without its deformation steps breaks a bound (mean ratio %.4f, block "
                 "RMSE %.2f x floor): the test can fail" % (name, ratio, rel))


def main():
    out = bt.args()[0]
    bt.enable_addon()
    case_export()
    case_deform_export()
    case_render(out)
    case_rotate_and_camera(out)
    case_deform_render(out)


bt.run(main)
