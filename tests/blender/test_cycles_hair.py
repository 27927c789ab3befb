"""Blender hair -> Facet's `curves` shapes (issue 37, items 1 and 4), against Cycles 3.4.

Export (no render): a sphere's particle hair system (300 hairs, 9 keys each at render_step 3)
becomes one curves shape of 300 Catmull-Rom strands of 11 points (ends repeated) with Cycles'
radius (radius_scale / 2 x root_radius at the root, the shape's taper, Close Tip's 0 raised
and reported, times the emitter's scale), its material slot, `flat` with Rounded Ribbons; children: the children only;
hidden from renders or with the view layer's Curves filter off: nothing. A CURVES object
(Add > Curves > Random): its points, radius attribute and matrix; no curves: a line.

Render: 300 hairs (radius 0.02 at the root, shape 0, tip 0.5 of the root) with a Diffuse BSDF
on a diffuse sphere under a sun, 64 x 48, direct light plus one bounce (Facet max_depth 2 =
Cycles 1 bounce), Facet (through the export) against Cycles, two seeds each; bounds as the other
Cycles tests state them (test_cycles_motion.py):
- |mean luminance ratio Facet / Cycles - 1| <= 2% (Cycles: its two seeds' mean);
- block RMSE (8 x 8 blocks' mean luminance, Facet seed 1 against Cycles seed 1) <= 3 x the
  noise floor (the same between Cycles seeds 1 and 2).
The same for the random Curves object (a Diffuse BSDF, the sun). Ability to fail: Facet with
every radius halved must break a bound, in both (numbers printed)."""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

W, H = 64, 48
BLOCK = 8
SPP = 128
MEAN_TOL = 0.02
RMSE_FACTOR = 3.0
MAX_DEPTH = 2


def export(frame_set=None):
    from facet_blender import export as ex
    return ex.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={},
                           frame_set=frame_set)


def diffuse(name, colour):
    mat, nt, out = bt.new_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = colour + (1.0,)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def hair_scene(count=300):
    scene = bt.factory_scene(W, H)
    bpy.data.objects.remove(bpy.data.objects["Cube"])
    bpy.data.objects.remove(bpy.data.objects["Light"])
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, location=(0.0, 0.0, 0.0))
    sphere = bpy.context.active_object
    sphere.name = "Ball"
    sphere.data.materials.append(diffuse("Skin", (0.5, 0.5, 0.5)))
    sphere.data.materials.append(diffuse("Fur", (0.8, 0.4, 0.1)))
    mod = cs.add_fur(sphere, count)
    scene.cycles_curves.shape = 'THICK'  # 3D Curves (the factory setting is Rounded Ribbons)
    cs.add_light(scene, 'SUN', 3.0, (0.0, 0.0, 5.0), rotation=(0.6, 0.3, 0.0))
    scene.world.use_nodes = True
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.05, 0.05, 0.05, 1.0)
    return scene, sphere, mod


def case_export():
    scene, sphere, mod = hair_scene()
    data, problems = export()
    hair = [s for s in data["shapes"] if s["type"] == "curves"]
    bt.check(len(hair) == 1, "one curves shape: %s" % [s.get("name") for s in data["shapes"]])
    h = hair[0]
    # (The viewport's depsgraph: Display Steps 3, so 9 keys, as a render's Render Steps 3.)
    bt.check(len(h["counts"]) == 300 and set(h["counts"]) == {11},
             "300 strands of 9 keys plus the repeated ends: %s" % sorted(set(h["counts"])))
    bt.check(h["basis"] == "catmull_rom" and h["profile"] == "round", "Cycles' 3D curves")
    r = np.array(h["radius"]).reshape(300, 11)
    bt.check(np.allclose(r[:, 0], 0.02) and np.allclose(r[:, -1], 0.01),
             "radius 0.02 at the root, 0.01 at the tip: %s %s" % (r[0, 0], r[0, -1]))
    keys = np.array(h["points"]).reshape(300, 11, 3)[0, 1:-1]
    along = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(keys, axis=0), axis=1))])
    bt.check(np.allclose(r[0, 1:-1], 0.02 - 0.01 * along / along[-1], atol=1e-6),
             "shape 0: linear in the length along the strand (Cycles' shaperadius): %s" % r[0])
    mats = dict(data["materials"])
    bt.check(h["material"] in mats and mats[h["material"]]["model"] == "lambert",
             "the system's material slot (Fur): %s" % h["material"])
    pts = np.array(h["points"]).reshape(-1, 3)
    roots = pts[0::11]
    # (cs.add_fur grows hairs from the UV sphere's vertices, at radius 1 up to float
    # rounding.)
    bt.check(np.allclose(np.linalg.norm(roots, axis=1), 1.0, atol=1e-5),
             "roots on the sphere's vertices: |root| in [%.4f, %.4f]"
             % (np.linalg.norm(roots, axis=1).min(), np.linalg.norm(roots, axis=1).max()))
    tips = pts[10::11]
    lengths = np.linalg.norm(tips - roots, axis=1)
    bt.check(np.allclose(lengths, lengths.mean(), rtol=0.02) and 0.3 < lengths.mean() < 0.7,
             "straight strands of one length (Hair Length 0.6): %.4f to %.4f"
             % (lengths.min(), lengths.max()))
    bt.check(not [p for p in problems if "Ball" in p], "nothing reported: %s" % problems)
    # Close Tip: the tip's 0 is raised and reported.
    mod.particle_system.settings.use_close_tip = True
    data, problems = export()
    h = [s for s in data["shapes"] if s["type"] == "curves"][0]
    bt.check(min(h["radius"]) > 0.0, "radii > 0")
    bt.check([p for p in problems if "radius 0 (Close Tip" in p], "Close Tip reported: %s"
             % problems)
    mod.particle_system.settings.use_close_tip = False
    # The emitter's scale scales the radius (Cycles' Hair::apply_transform: the cube root of the
    # matrix's |det|): at scale 0.5 the root radius is 0.01.
    sphere.scale = (0.5, 0.5, 0.5)
    h = [s for s in export()[0]["shapes"] if s["type"] == "curves"][0]
    r = np.array(h["radius"]).reshape(300, 11)
    bt.check(np.allclose(r[:, 0], 0.01) and np.allclose(r[:, -1], 0.005),
             "scale 0.5: radius 0.01 at the root, 0.005 at the tip: %s %s" % (r[0, 0], r[0, -1]))
    sphere.scale = (1.0, 1.0, 1.0)
    # The hair of a moving emitter under motion blur moves with it (the emitter's matrices:
    # test_cycles_hair_motion.py), and nothing is reported.
    scene.render.use_motion_blur = True
    sphere.location = (0.0, 0.0, 0.0)
    sphere.keyframe_insert("location", frame=1)
    sphere.location = (0.5, 0.0, 0.0)
    sphere.keyframe_insert("location", frame=2)
    scene.frame_set(1)
    data, problems = export(lambda f, sub: scene.frame_set(f, subframe=sub))
    h = [s for s in data["shapes"] if s["type"] == "curves"][0]
    bt.check(len(h.get("motion", ())) == 3 and "motion_positions" not in h and
             not [p for p in problems if "without motion blur" in p],
             "a moving emitter's hair: its 3 matrices, no line: %s %s" % (sorted(h), problems))
    sphere.animation_data_clear()
    sphere.location = (0.0, 0.0, 0.0)
    scene.render.use_motion_blur = False
    # Ribbons.
    scene.cycles_curves.shape = 'RIBBONS'
    h = [s for s in export()[0]["shapes"] if s["type"] == "curves"][0]
    bt.check(h["profile"] == "flat", "Rounded Ribbons: flat")
    scene.cycles_curves.shape = 'THICK'
    # Children: the children only (10 each).
    st = mod.particle_system.settings
    st.child_type = 'INTERPOLATED'
    st.child_nbr = st.rendered_child_count = 10
    h = [s for s in export()[0]["shapes"] if s["type"] == "curves"][0]
    bt.check(len(h["counts"]) == 3000, "children only: %d strands" % len(h["counts"]))
    st.child_type = 'NONE'
    # Hidden from renders, or the view layer's Curves filter off: no hair, no line.
    mod.show_render = False
    data, problems = export()
    bt.check(not [s for s in data["shapes"] if s["type"] == "curves"], "hidden: no hair")
    mod.show_render = True
    bpy.context.view_layer.use_strand = False
    data, problems = export()
    bt.check(not [s for s in data["shapes"] if s["type"] == "curves"] and
             not [p for p in problems if "hair" in p], "Curves filter off: no hair, no line")
    bpy.context.view_layer.use_strand = True
    # The exported scene builds.
    from facet_blender import native
    native.build(export()[0], name="blender")
    # A second hair system: Cycles numbers the strands of both in one sequence, so the second
    # shape's strands carry the random values of indices 300..349 (strand_random); the first's
    # are their own indices' (no key).
    cs.add_fur(sphere, 50)
    hair = [s for s in export()[0]["shapes"] if s["type"] == "curves"]
    bt.check(len(hair) == 2 and "strand_random" not in hair[0]
             and np.allclose(hair[1].get("strand_random", []),
                             native.curve_random(np.arange(300, 350)), atol=0.0),
             "a second system's strands continue Cycles' numbering: %s"
             % [sorted(h) for h in hair])
    sphere.modifiers.remove(sphere.modifiers[-1])


def case_curves_object():
    scene = bt.factory_scene(W, H)
    cv = bpy.data.hair_curves.new("Strands")
    ob = bpy.data.objects.new("Strands", cv)
    scene.collection.objects.link(ob)
    data, problems = export()
    bt.check([p for p in problems if "'Strands': hair curves with no curves" in p],
             "empty Curves reported: %s" % problems)
    bpy.data.objects.remove(ob)
    # Blender 3.4's Add > Curves > Random: 500 curves of 8 points with a radius attribute.
    bpy.ops.object.curves_random_add(location=(0.0, 0.0, 0.5))
    ob = bpy.context.active_object
    ob.name = "Random"
    cv = ob.data
    bpy.context.view_layer.update()
    data, problems = export()
    s = [x for x in data["shapes"] if x["type"] == "curves"]
    n = len(cv.curves)
    sizes = np.array([c.points_length for c in cv.curves])
    bt.check(len(s) == 1 and s[0]["counts"] == list(sizes + 2),
             "%d strands, ends repeated: %s" % (n, s[0]["counts"][:4] if s else s))
    pos = np.array([p.position[:] for p in cv.points])
    rad = np.array([p.radius for p in cv.points])
    got = np.array(s[0]["points"]).reshape(-1, 3)
    first = np.concatenate([[0], np.cumsum(sizes + 2)[:-1]])
    bt.check(np.allclose(got[first + 1], pos[np.concatenate([[0], np.cumsum(sizes)[:-1]])],
                         atol=1e-6), "the control points (object space)")
    bt.check(np.allclose(np.array(s[0]["radius"])[first + 1],
                         rad[np.concatenate([[0], np.cumsum(sizes)[:-1]])], atol=1e-7),
             "the radius attribute")
    bt.check(abs(s[0]["transform"][2][3] - 0.5) < 1e-9, "the object's matrix")
    # Its tips have radius 0: raised and reported.
    mine = [p for p in problems if "'Random'" in p]
    zero = int((rad <= 0.0).sum())
    bt.check(len(mine) == 1 and ("%d keys of radius 0" % zero) in mine[0],
             "only the zero radii reported (%d): %s" % (zero, mine))
    from facet_blender import native
    native.build(data, name="blender")
    return scene, ob


def renders(scene, name, out, engines=('FACET', 'CYCLES')):
    scene.facet.max_depth = MAX_DEPTH
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=MAX_DEPTH)
    return {e: tuple(cs.render(scene, e, os.path.join(out, "hair_%s_%s_%d.exr"
                                                        % (name, e.lower(), seed)), seed)[0]
                     for seed in (1, 2)) for e in engines}


def compare(name, f, c1, c2):
    return cs.compare_to_cycles(name, f, c1, c2, BLOCK)


def case_render(out):
    scene, sphere, mod = hair_scene()
    imgs = renders(scene, "fur", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = compare("fur", imgs['FACET'][0], c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the furry sphere: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    # The control: every hair radius halved in the export.
    from facet_blender import sync_hair
    saved = sync_hair.shape_radius
    sync_hair.shape_radius = lambda *a: 0.5 * saved(*a)
    try:
        thin = renders(scene, "thin", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_hair.shape_radius = saved
    ratio, rel = compare("thin", thin, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "halved radii break a bound (mean ratio %.4f, block RMSE %.2f x floor): the test "
             "can fail" % (ratio, rel))


def case_curves_render(out):
    """Blender 3.4's random hair curves with a Diffuse BSDF under a sun against Cycles; the
    control: radii halved."""
    scene, ob = case_curves_object()
    scene.cycles_curves.shape = 'THICK'
    ob.data.materials.append(diffuse("Strand", (0.2, 0.6, 0.3)))
    cs.add_light(scene, 'SUN', 3.0, (0.0, 0.0, 5.0), rotation=(0.6, 0.3, 0.0))
    scene.camera.location = (0.0, -3.0, 1.0)
    scene.camera.rotation_euler = (1.35, 0.0, 0.0)
    imgs = renders(scene, "random", out)
    c1, c2 = imgs['CYCLES']
    ratio, rel = compare("curves", imgs['FACET'][0], c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "the Curves object: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    from facet_blender import sync_hair
    saved = sync_hair._positive
    sync_hair._positive = lambda r, *a: 0.5 * saved(r, *a)
    try:
        thin = renders(scene, "random_thin", out, engines=('FACET',))['FACET'][0]
    finally:
        sync_hair._positive = saved
    ratio, rel = compare("thin", thin, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "halved radii break a bound (mean ratio %.4f, block RMSE %.2f x floor)"
             % (ratio, rel))


def main():
    out = bt.args()[0]
    bt.enable_addon()
    case_export()
    case_curves_render(out)
    case_render(out)


bt.run(main)
