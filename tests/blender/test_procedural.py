"""Procedural textures converted natively (facet_blender/textures.py _procedural -> the core's
noise, voronoi, gradient and white_noise kinds, FORMAT.md "Procedural textures"): no bake.

1. Exported data: each node converts to its kind with its parameters, coordinates and mapping,
   without a report and without a bake (a Brick Texture too).
2. Renders against Cycles: a strip of emission quads (one object, one material per face, the
   object moved and rotated so that Object coordinates differ from world space), one texture
   and coordinate mode per quad, orthographic camera, box filter 1 px, 16 spp in both. A
   quad's radiance is the texture, so a pixel is the texture's mean over the pixel in both
   renderers. Criterion (issue 35): per quad, the mean over its pixels of |Facet - Cycles| <=
   1e-3 of Cycles' range over the quad. The textures vary slowly over a pixel (features of
   several pixels), so 16 jittered samples of the same function differ by far less than that
   where the function is smooth; quads with edges (Voronoi colour, radius) are held to the
   same bound, since their edge pixels are a small fraction.
   Controls that must fail the same criterion: the input's own constant (what the addon
   rendered before: Emission Color's white), and a Noise with Detail 2.2 instead of 2.
"""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

SPP = 16
PX = 96  # pixels per quad side
new_material = bt.new_material


def coords(nt, which, loc=None, rot=None, scale=None):
    tc = nt.nodes.new("ShaderNodeTexCoord")
    out = tc.outputs[which]
    if loc is None:
        return out
    m = nt.nodes.new("ShaderNodeMapping")
    m.inputs["Location"].default_value = loc
    m.inputs["Rotation"].default_value = rot
    m.inputs["Scale"].default_value = scale
    nt.links.new(out, m.inputs["Vector"])
    return m.outputs[0]


def tex(nt, idname, vector=None, props=None, inputs=None):
    t = nt.nodes.new(idname)
    for k, v in (props or {}).items():
        setattr(t, k, v)
    for k, v in (inputs or {}).items():
        next(s for s in t.inputs if s.name == k).default_value = v
    if vector is not None:
        nt.links.new(vector, t.inputs["Vector"])
    return t


def noise(nt, vector=None, dims='3D', detail=2.0, **kw):
    inputs = {"Scale": 3.0, "Detail": detail, "Roughness": 0.5, "Distortion": 0.0, "W": 0.3}
    inputs.update(kw)
    return tex(nt, "ShaderNodeTexNoise", vector, {"noise_dimensions": dims}, inputs)


def voronoi(nt, vector=None, feature='F1', metric='EUCLIDEAN', dims='3D', **kw):
    inputs = {"Scale": 1.8, "Randomness": 1.0, "Smoothness": 0.6, "Exponent": 1.5, "W": 0.4}
    inputs.update(kw)
    return tex(nt, "ShaderNodeTexVoronoi", vector,
               {"voronoi_dimensions": dims, "feature": feature, "distance": metric}, inputs)


# (name, builder(nt) -> output socket): one quad each.
QUADS = [
    ("noise3d_generated", lambda nt: noise(nt).outputs["Fac"]),
    ("noise3d_object_mapping_colour",
     lambda nt: noise(nt, coords(nt, "Object", (0.2, -0.1, 0.3), (0.3, 0.2, 0.5),
                                 (1.2, 0.8, 1.0)), Distortion=0.6).outputs["Color"]),
    ("noise4d_uv", lambda nt: noise(nt, coords(nt, "UV"), '4D', detail=3.5).outputs["Fac"]),
    ("noise2d_generated", lambda nt: noise(nt, None, '2D', detail=0.0, Scale=4.0).outputs["Fac"]),
    ("noise1d_w", lambda nt: noise(nt, None, '1D', W=0.7).outputs["Color"]),
    ("gradient_linear_generated",
     lambda nt: tex(nt, "ShaderNodeTexGradient", None, {"gradient_type": 'LINEAR'})
     .outputs["Fac"]),
    ("gradient_spherical_object",
     lambda nt: tex(nt, "ShaderNodeTexGradient",
                    coords(nt, "Object", (-9.75, -0.75, 0.0), (0, 0, 0), (1.5, 1.5, 1.5)),
                    {"gradient_type": 'SPHERICAL'}).outputs["Color"]),
    ("gradient_radial_uv",
     lambda nt: tex(nt, "ShaderNodeTexGradient",
                    coords(nt, "UV", (-0.5, -0.5, 0.0), (0, 0, 0), (1, 1, 1)),
                    {"gradient_type": 'RADIAL'}).outputs["Fac"]),
    ("voronoi_f1_object", lambda nt: voronoi(nt, coords(nt, "Object")).outputs["Distance"]),
    ("voronoi_smooth_f1_manhattan",
     lambda nt: voronoi(nt, None, 'SMOOTH_F1', 'MANHATTAN').outputs["Distance"]),
    ("voronoi_f2_chebychev_uv",
     lambda nt: voronoi(nt, coords(nt, "UV"), 'F2', 'CHEBYCHEV').outputs["Distance"]),
    ("voronoi_f1_minkowski_4d",
     lambda nt: voronoi(nt, coords(nt, "Object"), 'F1', 'MINKOWSKI', '4D')
     .outputs["Distance"]),
    ("voronoi_edge", lambda nt: voronoi(nt, None, 'DISTANCE_TO_EDGE').outputs["Distance"]),
    ("voronoi_f1_colour", lambda nt: voronoi(nt, coords(nt, "Object")).outputs["Color"]),
    ("voronoi_radius", lambda nt: voronoi(nt, None, 'N_SPHERE_RADIUS').outputs["Radius"]),
    ("musgrave_ridged_object",
     lambda nt: tex(nt, "ShaderNodeTexMusgrave", coords(nt, "Object"),
                    {"musgrave_type": 'RIDGED_MULTIFRACTAL'},
                    {"Scale": 1.5, "Detail": 2.5, "Dimension": 1.2, "Lacunarity": 2.0,
                     "Offset": 1.0, "Gain": 1.0}).outputs["Fac"]),
    ("wave_rings_distorted",
     lambda nt: tex(nt, "ShaderNodeTexWave", coords(nt, "Object"),
                    {"wave_type": 'RINGS', "rings_direction": 'SPHERICAL',
                     "wave_profile": 'SIN'},
                    {"Scale": 0.35, "Distortion": 1.5, "Detail": 2.0, "Detail Scale": 1.0,
                     "Detail Roughness": 0.5, "Phase Offset": 0.3}).outputs["Color"]),
    ("magic_generated",
     lambda nt: tex(nt, "ShaderNodeTexMagic", None, {"turbulence_depth": 2},
                    {"Scale": 0.6, "Distortion": 1.0}).outputs["Color"]),
    ("white_noise_1d",
     lambda nt: tex(nt, "ShaderNodeTexWhiteNoise", None, {"noise_dimensions": '1D'},
                    {"W": 0.37}).outputs["Color"]),
]


def strip_scene(builders):
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    n = len(builders)
    verts, faces = [], []
    for i in range(n):
        verts += [(i, 0, 0), (i + 1, 0, 0), (i + 1, 1, 0), (i, 1, 0)]
        faces.append((4 * i, 4 * i + 1, 4 * i + 2, 4 * i + 3))
    me = bpy.data.meshes.new("strip")
    me.from_pydata(verts, [], faces)
    uv = me.uv_layers.new(name="UVMap")
    for i in range(len(me.loops)):
        uv.data[i].uv = [(0, 0), (1, 0), (1, 1), (0, 1)][i % 4]
    ob = bpy.data.objects.new("strip", me)
    # Object space differs from world space: moved, and turned about z by 180 degrees
    # (the strip then runs from x = 2 - n to x = 2 in world space, y from -0.5 to 0.5).
    ob.location = (2.0, 0.5, 0.0)
    ob.rotation_euler = (0.0, 0.0, math.pi)
    scene.collection.objects.link(ob)
    bt.ortho_camera(scene, n, (2.0 - n / 2.0, 0.0, 5.0))
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    for i, (name, build) in enumerate(builders):
        mat, nt, out = new_material("proc_" + name)
        e = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(build(nt), e.inputs["Color"])
        nt.links.new(e.outputs[0], out.inputs["Surface"])
        me.materials.append(mat)
        me.polygons[i].material_index = i
    scene.render.resolution_x, scene.render.resolution_y = PX * n, PX
    scene.render.resolution_percentage = 100
    scene.facet.spp = SPP
    scene.facet.max_depth = 1
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=1)
    return scene, me


def exported():
    from facet_blender import materials
    scene, me = strip_scene(QUADS)
    for mat in me.materials:
        c = materials.convert(mat, bpy.data.objects["strip"])
        em = c.emission
        bt.check(isinstance(em, dict) and not c.baked and c.problems == [],
                 "%s converts natively: %s, problems %s" % (mat.name, em, c.problems))
    c = materials.convert(bpy.data.materials["proc_noise3d_object_mapping_colour"])
    em = c.emission
    want = [[1.2 * math.cos(0.5) * math.cos(0.2)]]
    bt.check(em["noise"]["output"] == "color" and em["coordinates"] == "object"
             and abs(em["noise"]["distortion"] - 0.6) < 1e-6
             and abs(em["mapping"]["matrix"][0][0] - want[0][0]) < 1e-6
             and abs(em["mapping"]["matrix"][2][3] - 0.3) < 1e-6,
             "Noise (Object, Mapping) -> %s" % em)
    c = materials.convert(bpy.data.materials["proc_noise3d_generated"])
    bt.check(c.emission["coordinates"] == "generated" and "mapping" not in c.emission
             and c.generated, "unlinked Vector: Generated coordinates: %s" % c.emission)
    # A Brick Texture converts to the core's brick kind (its renders: test_composite.py).
    mat, nt, out = new_material("brick")
    e = nt.nodes.new("ShaderNodeEmission")
    m = nt.nodes.new("ShaderNodeTexBrick")
    nt.links.new(m.outputs["Fac"], e.inputs["Color"])
    nt.links.new(e.outputs[0], out.inputs["Surface"])
    me.materials.append(mat)
    c = materials.convert(mat, bpy.data.objects["strip"])
    bt.check(isinstance(c.emission, dict) and "brick" in c.emission and c.problems == [],
             "Brick converts natively: %s %s" % (c.emission, c.problems))


def rendered(outdir):
    scene, me = strip_scene(QUADS)
    a, _ = cs.render(scene, 'FACET', os.path.join(outdir, "procedural_facet.exr"), seed=1)
    from facet_blender import hooks
    problems = list(hooks.last_problems)
    bt.check(problems == [], "the strip converts without a report: %s" % problems)
    b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, "procedural_cycles.exr"), seed=1)
    # The camera looks down -z at the object turned by 180 degrees: quad i (object x in
    # [i, i + 1]) is image column block n - 1 - i.
    n = len(QUADS)
    failed = []
    for i, (name, _) in enumerate(QUADS):
        k = n - 1 - i
        qa, qb = a[:, PX * k:PX * (k + 1)], b[:, PX * k:PX * (k + 1)]
        rng = max(float(qb.max() - qb.min()), 1e-3)
        d = float(np.abs(qa - qb).mean())
        white = float(np.abs(1.0 - qb).mean())  # the control: the input's own white
        print("%-30s mean |Facet - Cycles| %.3g = %.3g of the range %.3g; control %.3g"
              % (name, d, d / rng, rng, white / rng))
        if not d <= 1e-3 * rng:
            failed.append("%s: %.3g > 1e-3 x range %.3g" % (name, d, rng))
        bt.check(white > 1e-3 * rng, "control %s: the constant fails (%.3g)" % (name, white))
    bt.check(not failed, "quads within 1e-3 of the range: " + "; ".join(failed))
    # Control: Detail 2.2 instead of 2 on the first quad must fail the criterion.
    nt = me.materials[0].node_tree
    next(x for x in nt.nodes if x.bl_idname == 'ShaderNodeTexNoise').inputs["Detail"]\
        .default_value = 2.2
    # (Quad 0 alone: a border render of its block, the last one.)
    k = n - 1
    scene.render.use_border = True
    scene.render.use_crop_to_border = True
    scene.render.border_min_x, scene.render.border_max_x = k / n, 1.0
    scene.render.border_min_y, scene.render.border_max_y = 0.0, 1.0
    c, _ = cs.render(scene, 'FACET', os.path.join(outdir, "procedural_control.exr"), seed=1)
    bt.check(c.shape[1] == PX, "the control renders quad 0 alone (%s)" % (c.shape,))
    qc, qb = c, b[:, PX * k:PX * (k + 1)]
    d = float(np.abs(qc - qb).mean())
    rng = float(qb.max() - qb.min())
    print("control detail 2.2: %.3g of the range" % (d / rng))
    bt.check(d > 1e-3 * rng, "a Detail 2.2 noise fails the criterion (%.3g)" % (d / rng))


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    exported()
    rendered(outdir)


bt.run(main)
