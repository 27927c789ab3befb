"""Mix Shader, Add Shader, Normal Map and Bump nodes (facet_blender/materials.py, normals.py,
export.py's tangents) in headless Blender:

1. Conversion: a Mix Shader whose Fac is a constant is the core's `mix` (or, for two BSDFs of
   one linear model, one BSDF with the weighted reflectance), a texture Fac a textured weight,
   an Add Shader the core's `add`, nested mixes nest, normals on both sides are hoisted to the
   combination; a Normal Map (tangent space, Image Texture) is `normal_map` with its Strength
   and the mesh exports Blender's MikkTSpace tangents (equal to calc_tangents()); a Bump of an
   image is `bump` (Invert negates the distance, Strength is its strength); what does not
   convert exactly (object space, a chain of bumps, different normals in a mix) is reported,
   once.
2. Renders against Cycles (box filter 1 px, no denoising, same spp both, orthographic camera
   from above, a sun and a grey world):
   - three smooth spheres: Mix(red Diffuse, white Diffuse) with a Checker Fac, Add(Diffuse,
     Glossy) (an energy gain the core reports), Mix(Diffuse, Glass) at 0.5;
   - a plane and a sphere with Debian assimp-testmodels' RibsNormal.png as a tangent-space
     normal map, and a plane bumped by RoughnessStripes.png.
   Tolerance: the means within 2% and mean |Facet - Cycles| per pixel < 0.02 (mix scene,
   measured 0.0080) and, per object, 0.015 / 0.015 / 0.02 (normals; see render_normals). Both
   renderers estimate the same integral with 64 independent samples per pixel; a glossy or
   glass pixel's noise is up to ~0.1 per renderer at 64 spp, so the mean |difference| over the
   pixels is that noise (~0.005-0.01) plus any real difference. Ability to fail: the same
   Facet render with a constant Fac (0.0394) or without the maps (0.0709, 0.0605, 0.0345)
   differs from Cycles by more than twice as much.
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

SPP = 64
MODELS = "/usr/share/assimp/models/glTF2/ClearCoat-glTF"
NORMAL_PNG = os.path.join(MODELS, "RibsNormal.png")
# A smooth real height field: the ribs image's luminance (its red channel varies smoothly
# across each rib). Sharp steps (RoughnessStripes.png) would compare Cycles' one-pixel
# finite differences with Facet's half-texel ones, a documented difference (FORMAT.md).
HEIGHT_PNG = os.path.join(MODELS, "RibsNormal.png")
new_material = bt.new_material


def node(nt, idname, **inputs):
    n = nt.nodes.new(idname)
    for k, v in inputs.items():
        n.inputs[k].default_value = v
    return n


def diffuse(nt, rgb):
    return node(nt, "ShaderNodeBsdfDiffuse", Color=tuple(rgb) + (1.0,))


def mix(nt, a, b, fac):
    m = nt.nodes.new("ShaderNodeMixShader")
    if isinstance(fac, float):
        m.inputs["Fac"].default_value = fac
    else:
        nt.links.new(fac, m.inputs["Fac"])
    nt.links.new(a.outputs[0], m.inputs[1])
    nt.links.new(b.outputs[0], m.inputs[2])
    return m


def add(nt, a, b):
    m = nt.nodes.new("ShaderNodeAddShader")
    nt.links.new(a.outputs[0], m.inputs[0])
    nt.links.new(b.outputs[0], m.inputs[1])
    return m


def image(nt, path, noncolor=True):
    t = nt.nodes.new("ShaderNodeTexImage")
    t.image = bpy.data.images.load(path, check_existing=True)
    if noncolor:
        t.image.colorspace_settings.name = 'Non-Color'
    return t


def normal_map(nt, bsdf, strength=1.0, space='TANGENT'):
    nm = node(nt, "ShaderNodeNormalMap", Strength=strength)
    nm.space = space
    nt.links.new(image(nt, NORMAL_PNG).outputs["Color"], nm.inputs["Color"])
    nt.links.new(nm.outputs[0], bsdf.inputs["Normal"])
    return nm


def bump(nt, bsdf, distance=0.1, strength=1.0, invert=False):
    b = node(nt, "ShaderNodeBump", Strength=strength, Distance=distance)
    b.invert = invert
    nt.links.new(image(nt, HEIGHT_PNG).outputs["Color"], b.inputs["Height"])
    nt.links.new(b.outputs[0], bsdf.inputs["Normal"])
    return b


def checker(nt):
    c = node(nt, "ShaderNodeTexChecker", Scale=4.0)
    nt.links.new(nt.nodes.new("ShaderNodeTexCoord").outputs["UV"], c.inputs["Vector"])
    return c.outputs["Fac"]


def not_luminance(lines):
    """The report lines but the (expected) note that the colour height image is read through
    Facet's luminance weights (textures.LUMINANCE_NOTE)."""
    return [x for x in lines if "luminance" not in x]


def converted(mat):
    from facet_blender import materials
    return materials.convert(mat)


def conversion():
    # Mix of two Diffuse at a constant Fac: one lambert (linear in the reflectance).
    mat, nt, out = new_material("mix_const")
    nt.links.new(mix(nt, diffuse(nt, (1, 0, 0)), diffuse(nt, (1, 1, 1)), 0.25).outputs[0],
                 out.inputs["Surface"])
    c = converted(mat)
    bt.check(c.data == {"model": "lambert", "reflectance": [1.0, 0.25, 0.25]}
             and c.problems == [], "Mix(red, white, 0.25) -> lambert: %s %s"
             % (c.data, c.problems))
    # A Checker Fac: the core's mix with a textured weight.
    mat, nt, out = new_material("mix_tex")
    nt.links.new(mix(nt, diffuse(nt, (1, 0, 0)), diffuse(nt, (1, 1, 1)), checker(nt))
                 .outputs[0], out.inputs["Surface"])
    c = converted(mat)
    w = c.data.get("weight")
    bt.check(c.data["model"] == "mix" and isinstance(w, dict) and "checker" in w
             and c.data["materials"] == [{"model": "lambert", "reflectance": [1.0, 0.0, 0.0]},
                                         {"model": "lambert", "reflectance": [1.0, 1.0, 1.0]}]
             and c.problems == [] and c.uv_maps == {""},
             "Mix with a Checker Fac -> mix, textured weight: %s %s" % (c.data, c.problems))
    # Add(Diffuse, Glossy) -> add; nested: Mix(Add(...), Glass, 0.5) -> mix of add and glass.
    mat, nt, out = new_material("nested")
    gl = node(nt, "ShaderNodeBsdfGlossy", Roughness=0.5)
    a = add(nt, diffuse(nt, (0.5, 0.5, 0.5)), gl)
    glass = node(nt, "ShaderNodeBsdfGlass", IOR=1.5)
    nt.links.new(mix(nt, a, glass, 0.5).outputs[0], out.inputs["Surface"])
    c = converted(mat)
    kids = c.data.get("materials", [])
    bt.check(c.data["model"] == "mix" and c.data["weight"] == 0.5 and len(kids) == 2
             and kids[0]["model"] == "add"
             and [k["model"] for k in kids[0]["materials"]] == ["lambert", "ggx"]
             and kids[1]["model"] == "dielectric" and c.problems == [],
             "Mix(Add(Diffuse, Glossy), Glass) nests: %s %s" % (c.data, c.problems))

    # Normal Map (tangent, image, Strength 0.5) -> normal_map; Bump inverted -> bump, the
    # distance negated; both on one Principled BSDF (Bump fed by the Normal Map).
    mat, nt, out = new_material("nm_bump")
    p = nt.nodes.new("ShaderNodeBsdfPrincipled")
    b = bump(nt, p, distance=0.25, invert=True)
    nm = normal_map(nt, b, strength=0.5)
    nt.links.new(p.outputs[0], out.inputs["Surface"])
    c = converted(mat)
    n, h = c.data.get("normal_map", {}), c.data.get("bump", {})
    bt.check(n.get("texture") == NORMAL_PNG and n.get("colorspace") == "linear"
             and n.get("strength") == 0.5 and h.get("texture") == HEIGHT_PNG
             and h.get("distance") == -0.25 and h.get("channel") == "luminance"
             and c.tangents and not_luminance(c.problems) == [],
             "Normal Map + inverted Bump -> normal_map, bump: %s %s" % (c.data, c.problems))
    # Bump Strength 0.5 -> strength; Object space reported (once); a chain of bumps.
    nm.space = 'OBJECT'
    b.inputs["Strength"].default_value = 0.5
    c = converted(mat)
    lines = not_luminance(c.problems)
    bt.check("normal_map" not in c.data and c.data.get("bump", {}).get("strength") == 0.5
             and len(lines) == 1 and "Normal Map" in lines[0] and "Object" in lines[0],
             "Bump Strength 0.5 converted, object space reported once: %s %s"
             % (c.data.get("bump"), c.problems))
    b2 = bump(nt, p)  # Principled <- Bump.001 <- Bump <- Normal Map
    nt.links.new(b.outputs[0], b2.inputs["Normal"])
    c = converted(mat)
    bt.check(any("chain of bumps" in x for x in c.problems),
             "a chain of bumps reported: %s" % c.problems)
    # Different normals on the two sides of a mix: the first's, reported on the Mix Shader.
    mat, nt, out = new_material("mix_normals")
    d1, d2 = diffuse(nt, (0.8, 0.8, 0.8)), node(nt, "ShaderNodeBsdfGlossy")
    normal_map(nt, d1)
    nt.links.new(mix(nt, d1, d2, 0.5).outputs[0], out.inputs["Surface"])
    c = converted(mat)
    bt.check(c.data["model"] == "mix" and "normal_map" in c.data
             and all("normal_map" not in k for k in c.data["materials"])
             and len(c.problems) == 1 and "Mix Shader" in c.problems[0]
             and "different normals" in c.problems[0],
             "different normals in a mix: the first's, reported: %s %s"
             % (c.data, c.problems))
    normal_map(nt, d2)  # the same map on both sides: hoisted exactly
    c = converted(mat)
    bt.check("normal_map" in c.data and c.problems == [],
             "the same normal map on both sides: hoisted: %s" % c.problems)


def tangents_exported():
    """The exported per-corner tangents are Blender's calc_tangents() (a UV sphere)."""
    from facet_blender import export
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    for o in list(bpy.data.objects):
        if o.type != 'CAMERA':
            bpy.data.objects.remove(o)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=16, ring_count=8)
    ob = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    mat, nt, out = new_material("nm")
    d = diffuse(nt, (0.8, 0.8, 0.8))
    normal_map(nt, d)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    ob.data.materials.append(mat)
    data, problems = export.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={})
    s = next(x for x in data["shapes"] if x.get("name") == ob.name)
    me = ob.data
    me.calc_tangents()
    ref = np.array([list(lp.tangent) + [lp.bitangent_sign] for lp in me.loops], np.float32)
    tan = s.get("tangents")
    same = tan is not None and tan.shape == ref.shape and np.array_equal(tan, ref)
    bt.check(same and problems == [],
             "tangents exported per corner, equal to calc_tangents(): %s, max diff %s, %s"
             % (None if tan is None else tan.shape,
                np.abs(tan - ref).max() if tan is not None and tan.shape == ref.shape else "-",
                problems))


def report_grouping():
    """Two objects sharing a material with a report and two instances of it: the render's
    report says each line once, under the material with both objects named and counted; the
    core's build warning about a material joins that material's group."""
    from facet_blender import export, gaps
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    for o in list(bpy.data.objects):
        if o.type != 'CAMERA':
            bpy.data.objects.remove(o)
    mat, nt, out = new_material("shared")
    d1, d2 = diffuse(nt, (0.8, 0.8, 0.8)), node(nt, "ShaderNodeBsdfGlossy")
    nm = node(nt, "ShaderNodeNormalMap")
    nm.space = 'WORLD'
    nt.links.new(nm.outputs[0], d1.inputs["Normal"])
    nt.links.new(add(nt, d1, d2).outputs[0], out.inputs["Surface"])
    for x in (0.0, 3.0):
        bpy.ops.mesh.primitive_uv_sphere_add(location=(x, 0, 0))
        bpy.context.active_object.data.materials.append(mat)
    users = {}
    data, problems = export.export_scene(bpy.context.evaluated_depsgraph_get(),
                                         mesh_cache={}, users=users)
    warning = "blender: /materials/shared: add reflects 1.6 of the light"
    groups = gaps.grouped(problems + problems + [warning, "object 'Sphere': note"], users)
    subjects = [g[0] for g in groups]
    bt.check(subjects == ["material 'shared' (2 objects: Sphere, Sphere.001)",
                          "object 'Sphere'"]
             and len(groups[0][1]) == 2 and "World" in groups[0][1][0]
             and groups[0][1][1] == warning
             and gaps.summary(groups).startswith("3 conversion notes: material 'shared'"),
             "grouped report: each line once, by material with its objects, counted: %s %s"
             % (groups, gaps.summary(groups)))


def _scene(n):
    """An orthographic camera above x in [0, n], y in [0, 1]; a sun 40 degrees from the
    vertical and a grey world."""
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    bt.ortho_camera(scene, n, (n / 2.0, 0.5, 5.0))
    sun = bpy.data.lights.new("sun", 'SUN')
    sun.energy = 3.0
    sun.angle = 0.0  # a delta sun: Cycles and Facet agree exactly (gaps.SUN_ANGLE_NOTE)
    sob = bpy.data.objects.new("sun", sun)
    sob.rotation_euler = (0.7, 0.2, 0.0)
    scene.collection.objects.link(sob)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.3
    scene.render.resolution_x, scene.render.resolution_y = 32 * n, 32
    scene.render.resolution_percentage = 100
    scene.facet.spp = SPP
    scene.facet.max_depth = 4
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=4)
    return scene


def _sphere(x, mat):
    bpy.ops.mesh.primitive_uv_sphere_add(segments=48, ring_count=24, radius=0.45,
                                         location=(x, 0.5, 0.0))
    ob = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    ob.data.materials.append(mat)
    return ob


def _plane(x, mat):
    bpy.ops.mesh.primitive_plane_add(size=0.95, location=(x, 0.5, 0.0))
    ob = bpy.context.active_object
    ob.data.materials.append(mat)
    return ob


def _compare(scene, outdir, name):
    a, _ = cs.render(scene, 'FACET', os.path.join(outdir, name + "_facet.exr"), seed=1)
    from facet_blender import hooks
    problems = list(hooks.last_problems)
    b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, name + "_cycles.exr"), seed=1)
    d = np.abs(a - b).mean()
    print("%s: means Facet %.4f Cycles %.4f, mean |diff| %.4f" % (name, a.mean(), b.mean(), d))
    return a, b, d, problems


def render_mix(outdir):
    scene = _scene(3)
    mat, nt, out = new_material("mix_checker")
    fac = checker(nt)
    m = mix(nt, diffuse(nt, (0.8, 0.05, 0.05)), diffuse(nt, (0.9, 0.9, 0.9)), fac)
    nt.links.new(m.outputs[0], out.inputs["Surface"])
    _sphere(0.5, mat)
    mat2, nt2, out2 = new_material("add")
    nt2.links.new(add(nt2, diffuse(nt2, (0.6, 0.6, 0.6)),
                      node(nt2, "ShaderNodeBsdfGlossy", Roughness=0.3,
                           Color=(0.8, 0.8, 0.8, 1))).outputs[0], out2.inputs["Surface"])
    _sphere(1.5, mat2)
    mat3, nt3, out3 = new_material("mix_glass")
    nt3.links.new(mix(nt3, diffuse(nt3, (0.2, 0.5, 0.8)),
                      node(nt3, "ShaderNodeBsdfGlass", IOR=1.45), 0.5).outputs[0],
                  out3.inputs["Surface"])
    _sphere(2.5, mat3)
    a, b, d, problems = _compare(scene, outdir, "shadernodes_mix")
    gain = [p for p in problems if "add reflects" in p]
    bt.check(len(gain) == 1 and len(problems) == 1,
             "the Add's energy gain reported as the core does, nothing else: %s" % problems)
    bt.check(abs(a.mean() / b.mean() - 1.0) < 0.02 and d < 0.02,
             "mix/add/glass spheres: means %.4f / %.4f within 2%%, mean |diff| %.4f < 0.02"
             % (a.mean(), b.mean(), d))
    # Ability to fail: a constant Fac 0.5 instead of the checker.
    nt.links.remove(m.inputs["Fac"].links[0])
    m.inputs["Fac"].default_value = 0.5
    a2, _ = cs.render(scene, 'FACET', os.path.join(outdir, "shadernodes_mix_flat.exr"), seed=1)
    d2 = np.abs(a2 - b).mean()
    bt.check(d2 > 2.0 * d,
             "without the textured Fac the difference grows: %.4f (vs %.4f)" % (d2, d))


def render_units(outdir):
    """The model units Velvet and Translucent against Cycles: a velvet sphere (Sigma 0.3), a
    translucent sphere and a translucent pane lit by the sun from above and the grey world (the
    pane shows what it transmits from below). Means within 2% and mean |diff| < 0.02, as the
    mix spheres (the same two-seed noise); with plain Diffuse BSDFs in their place the
    difference must grow more than twofold (ability to fail)."""
    scene = _scene(3)
    mat, nt, out = new_material("velvet")
    v = node(nt, "ShaderNodeBsdfVelvet", Sigma=0.3, Color=(0.8, 0.6, 0.4, 1))
    nt.links.new(v.outputs[0], out.inputs["Surface"])
    _sphere(0.5, mat)
    mat2, nt2, out2 = new_material("translucent")
    t = node(nt2, "ShaderNodeBsdfTranslucent", Color=(0.3, 0.8, 0.5, 1))
    nt2.links.new(t.outputs[0], out2.inputs["Surface"])
    _sphere(1.5, mat2)
    _plane(2.5, mat2)
    a, b, d, problems = _compare(scene, outdir, "shadernodes_units")
    bt.check(not problems, "velvet and translucent convert without a note: %s" % problems)
    bt.check(abs(a.mean() / b.mean() - 1.0) < 0.02 and d < 0.02,
             "velvet/translucent: means %.4f / %.4f within 2%%, mean |diff| %.4f < 0.02"
             % (a.mean(), b.mean(), d))
    for tree, n in ((nt, v), (nt2, t)):
        dn = diffuse(tree, tuple(n.inputs["Color"].default_value)[:3])
        tree.links.new(dn.outputs[0], (out if tree is nt else out2).inputs["Surface"])
    a2, _ = cs.render(scene, 'FACET', os.path.join(outdir, "shadernodes_units_diffuse.exr"),
                      seed=1)
    d2 = np.abs(a2 - b).mean()
    bt.check(d2 > 2.0 * d, "as Diffuse BSDFs the difference grows: %.4f (vs %.4f)" % (d2, d))


def render_transparent(outdir):
    """Transparent BSDFs against Cycles, as the core's opacity: a leaf cut-out (Mix Shader of a
    Transparent and a Diffuse by a Checker Fac) and a plane of Mix(Transparent Color 0.5,
    Diffuse, 0.4) over a red floor, seen from above. Means within 2% and mean |diff| < 0.02;
    with the transparent planes opaque (Diffuse alone) the difference must grow more than
    twofold (ability to fail)."""
    scene = _scene(2)
    floor = bpy.ops.mesh.primitive_plane_add(size=4.0, location=(1.0, 0.5, -0.5))
    floor = bpy.context.active_object
    mf, ntf, outf = new_material("floor")
    ntf.links.new(diffuse(ntf, (0.8, 0.1, 0.1)).outputs[0], outf.inputs["Surface"])
    floor.data.materials.append(mf)
    mat, nt, out = new_material("leaf")
    leaf_d = diffuse(nt, (0.1, 0.6, 0.1))
    m = mix(nt, node(nt, "ShaderNodeBsdfTransparent"), leaf_d, checker(nt))
    nt.links.new(m.outputs[0], out.inputs["Surface"])
    _plane(0.5, mat)
    mat2, nt2, out2 = new_material("veil")
    veil_d = diffuse(nt2, (0.7, 0.7, 0.9))
    m2 = mix(nt2, node(nt2, "ShaderNodeBsdfTransparent", Color=(0.5, 0.5, 0.5, 1)), veil_d, 0.4)
    nt2.links.new(m2.outputs[0], out2.inputs["Surface"])
    _plane(1.5, mat2)
    from facet_blender import materials
    c = materials.convert(mat)
    bt.check(c.data.get("opacity", {}).get("checker") is not None and not c.problems,
             "leaf: the diffuse with the Checker as its opacity: %s %s" % (c.data, c.problems))
    c2 = materials.convert(mat2)
    bt.check(abs(c2.data.get("opacity", 0) - 0.7) < 1e-6 and c2.data["model"] == "mix"
             and abs(c2.data["weight"] - 0.4 / 0.7) < 1e-6,
             "veil: opacity 1 - 0.6 x 0.5, mix(black, diffuse, 0.4 / 0.7): %s" % c2.data)
    a, b, d, problems = _compare(scene, outdir, "shadernodes_transparent")
    bt.check(not problems, "transparent mixes convert without a note: %s" % problems)
    bt.check(abs(a.mean() / b.mean() - 1.0) < 0.02 and d < 0.02,
             "transparent: means %.4f / %.4f within 2%%, mean |diff| %.4f < 0.02"
             % (a.mean(), b.mean(), d))
    nt.links.new(leaf_d.outputs[0], out.inputs["Surface"])
    nt2.links.new(veil_d.outputs[0], out2.inputs["Surface"])
    a2, _ = cs.render(scene, 'FACET', os.path.join(outdir, "shadernodes_opaque.exr"), seed=1)
    d2 = np.abs(a2 - b).mean()
    bt.check(d2 > 2.0 * d, "opaque planes differ more: %.4f (vs %.4f)" % (d2, d))


def render_normals(outdir):
    """Per region (x thirds: the normal-mapped plane, the normal-mapped sphere, the bumped
    plane) the mean |Facet - Cycles| must stay below 0.015 (maps) and 0.02 (bump), and the
    same Facet render without the maps must differ from Cycles by more than twice as much in
    every region. Measured 0.0052, 0.0103, 0.0139; without the maps 0.0709, 0.0605, 0.0345.
    The bump has Distance 0.2 and Strength 0.5 (the core's bump strength, exact per
    BumpMap.LinearHeightRampGivesTheAnalyticTilt).
    The normal-mapped plane shows the noise floor (~0.005); the bump adds the step
    difference: the 512-texel ribs are minified 16x, and Cycles differentiates the height over
    one pixel (its ray differentials) where Facet takes half a texel (FORMAT.md, Bump maps)."""
    scene = _scene(3)
    mat, nt, out = new_material("ribs")
    dn = diffuse(nt, (0.8, 0.8, 0.8))
    nm = normal_map(nt, dn)
    nt.links.new(dn.outputs[0], out.inputs["Surface"])
    _plane(0.5, mat)
    _sphere(1.5, mat)
    mat2, nt2, out2 = new_material("bumped")
    db = diffuse(nt2, (0.8, 0.8, 0.8))
    bmp = bump(nt2, db, distance=0.2, strength=0.5)
    nt2.links.new(db.outputs[0], out2.inputs["Surface"])
    _plane(2.5, mat2)
    a, b, d, problems = _compare(scene, outdir, "shadernodes_normals")
    bt.check(not any("Normal" in p or "Bump" in p for p in not_luminance(problems)),
             "normal map and bump convert without a report: %s" % problems)

    def regions(x, y):
        return [float(np.abs(x - y)[:, 32 * i:32 * i + 32].mean()) for i in range(3)]

    dr = regions(a, b)
    bt.check(abs(a.mean() / b.mean() - 1.0) < 0.02 and max(dr[:2]) < 0.015 and dr[2] < 0.02,
             "normal-mapped plane and sphere, bumped plane: means %.4f / %.4f within 2%%, "
             "mean |diff| per region %s < 0.015, 0.015, 0.02" % (a.mean(), b.mean(),
                                                    ["%.4f" % x for x in dr]))
    nt.links.remove(nm.outputs[0].links[0])
    nt2.links.remove(bmp.outputs[0].links[0])
    a2, _ = cs.render(scene, 'FACET', os.path.join(outdir, "shadernodes_flat.exr"), seed=1)
    d2 = regions(a2, b)
    bt.check(all(x2 > 2.0 * x for x, x2 in zip(dr, d2)),
             "without the maps every region differs more: %s (vs %s)"
             % (["%.4f" % x for x in d2], ["%.4f" % x for x in dr]))


def render_view_factor(outdir):
    """The classic pre-Principled materials: Mix Shader(Diffuse, Glossy) by a Fresnel node
    (IOR 1.45), by a Layer Weight's Fresnel (Blend 0.3) and by its Facing (Blend 0.6), one
    sphere each, against Cycles: converted with no note, means within 2% and mean |diff| <
    0.02 (the mix spheres' bounds); with the Fac cut to its default constant 0.5 the difference
    must grow more than twofold (ability to fail)."""
    scene = _scene(3)
    mixes = []
    for x, (idname, out_name, inp, value) in enumerate((
            ("ShaderNodeFresnel", "Fac", "IOR", 1.45),
            ("ShaderNodeLayerWeight", "Fresnel", "Blend", 0.3),
            ("ShaderNodeLayerWeight", "Facing", "Blend", 0.6))):
        mat, nt, out = new_material("view_%s_%s" % (idname[10:].lower(), out_name.lower()))
        f = node(nt, idname, **{inp: value})
        m = mix(nt, diffuse(nt, (0.7, 0.25, 0.1)),
                node(nt, "ShaderNodeBsdfGlossy", Roughness=0.2, Color=(0.9, 0.9, 0.9, 1)), 0.5)
        nt.links.new(f.outputs[out_name], m.inputs["Fac"])
        nt.links.new(m.outputs[0], out.inputs["Surface"])
        _sphere(x + 0.5, mat)
        mixes.append((nt, m))
    a, b, d, problems = _compare(scene, outdir, "shadernodes_view")
    bt.check(not problems, "Fresnel / Layer Weight factors convert without a note: %s" % problems)
    bt.check(abs(a.mean() / b.mean() - 1.0) < 0.02 and d < 0.02,
             "view factors: means %.4f / %.4f within 2%%, mean |diff| %.4f < 0.02"
             % (a.mean(), b.mean(), d))
    for nt, m in mixes:
        nt.links.remove(m.inputs["Fac"].links[0])
    a2, _ = cs.render(scene, 'FACET', os.path.join(outdir, "shadernodes_view_flat.exr"), seed=1)
    d2 = np.abs(a2 - b).mean()
    bt.check(d2 > 2.0 * d, "with a constant Fac the difference grows: %.4f (vs %.4f)" % (d2, d))


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    conversion()
    tangents_exported()
    report_grouping()
    render_mix(outdir)
    render_units(outdir)
    render_transparent(outdir)
    render_view_factor(outdir)
    render_normals(outdir)


bt.run(main)
