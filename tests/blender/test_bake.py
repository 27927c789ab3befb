"""The bake fallback (facet_blender/bake.py) in headless Blender:

1. A Brick Texture (on |Generated coordinates|, a vector the conversion does not express) into
   an Emission's Color, a Brick Texture into a Principled BSDF's Base Color and Roughness, and
   a Brick Fac into an Emission
   and a Glossy Roughness (alpha = Fac^2 exactly): before baking, the export reports each as not
   baked yet (naming material, node and input); Render Properties > Facet > Bake Procedural
   Inputs (facet.bake_inputs) bakes them; the export then uses the baked EXRs (the emission
   texture, the principled base_color texture) and lists what was baked; a second bake finds
   nothing to do (the cache, keyed by the node tree, object and resolution); changing the
   resolution bakes again.
2. An object without a UV map gets a message naming the object and the material.
3. Render: the emission plane seen straight on by an orthographic camera, Facet (baked,
   256 x 256 texels over 64 x 64 pixels) against Cycles (the procedural itself), 16 spp, box
   filter 1 px. The pixel is the texture's mean over the pixel in Cycles and the bilinear
   baked image's in Facet. Tolerance: the means agree within 1% and the mean |difference| per
   pixel < 0.01: the bake samples the texture at texel centres (4 x 4 per pixel) and Facet
   interpolates between them, so they differ only by the texture's variation inside a texel
   (the Brick Texture at Scale 2, of contrast 0.1, is flat inside bricks and steps at their
   edges) and the sampling noise of 16 jittered samples. Measured: means 0.50750 / 0.50514,
   mean |difference| 0.0053 (a Noise Texture at Scale 5, before it converted natively:
   0.0008). A view-transformed bake (Image.save(), found while writing) gave a mean of 0.73
   and a mean |difference| of 0.23.
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

SPP = 16


def noise_material(name, target):
    mat, nt, out = bt.new_material(name)
    # A Brick Texture on |Generated| (Vector Math Absolute: the same point, since Generated
    # coordinates lie in [0, 1]^3, but not an affine chain the conversion expresses), so the
    # bake serves it (the procedural kinds convert natively, test_procedural.py). Low
    # contrast (bricks 0.5 / 0.55, mortar 0.45): the bake's bilinear texels blur its edges.
    noise = nt.nodes.new("ShaderNodeTexBrick")
    tc = nt.nodes.new("ShaderNodeTexCoord")
    vm = nt.nodes.new("ShaderNodeVectorMath")
    vm.operation = 'ABSOLUTE'
    nt.links.new(tc.outputs["Generated"], vm.inputs[0])
    nt.links.new(vm.outputs["Vector"], noise.inputs["Vector"])
    noise.inputs["Scale"].default_value = 2.0
    noise.inputs["Color1"].default_value = (0.5, 0.5, 0.5, 1.0)
    noise.inputs["Color2"].default_value = (0.55, 0.55, 0.55, 1.0)
    noise.inputs["Mortar"].default_value = (0.45, 0.45, 0.45, 1.0)
    if target == "emission":
        sh = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(noise.outputs["Color"], sh.inputs["Color"])
    elif target == "view":  # Layer Weight: view dependent, never baked
        sh = nt.nodes.new("ShaderNodeEmission")
        lw = nt.nodes.new("ShaderNodeLayerWeight")
        nt.links.new(lw.outputs["Facing"], sh.inputs["Color"])
    elif target == "rough":  # Emission = Fac, Glossy Roughness = Fac: alpha must be Fac^2
        em = nt.nodes.new("ShaderNodeEmission")
        nt.links.new(noise.outputs["Fac"], em.inputs["Color"])
        gl = nt.nodes.new("ShaderNodeBsdfGlossy")
        nt.links.new(noise.outputs["Fac"], gl.inputs["Roughness"])
        sh = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(em.outputs[0], sh.inputs[0])
        nt.links.new(gl.outputs[0], sh.inputs[1])
    else:
        sh = nt.nodes.new("ShaderNodeBsdfPrincipled")
        nt.links.new(noise.outputs["Color"], sh.inputs["Base Color"])
        nt.links.new(noise.outputs["Fac"], sh.inputs["Roughness"])
    nt.links.new(sh.outputs[0], out.inputs["Surface"])
    return mat


def plane(name, mat, location, uv=True):
    bpy.ops.mesh.primitive_plane_add(size=2.0, location=location)
    ob = bpy.context.active_object
    ob.name = name
    if not uv:
        while ob.data.uv_layers:
            ob.data.uv_layers.remove(ob.data.uv_layers[0])
    ob.data.materials.append(mat)
    return ob


def export():
    from facet_blender import export as ex
    return ex.export_scene(bpy.context.evaluated_depsgraph_get(), mesh_cache={})


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    from facet_blender import bake, textures
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        if ob.type != 'CAMERA':
            bpy.data.objects.remove(ob)
    scene.render.engine = 'FACET'
    scene.facet.bake_resolution = 256
    # A fresh cache for this test.
    textures.CACHE_DIR = os.path.join(outdir, "bake_cache")
    for f in os.listdir(textures.CACHE_DIR) if os.path.isdir(textures.CACHE_DIR) else []:
        os.remove(os.path.join(textures.CACHE_DIR, f))
    plane("EmPlane", noise_material("noise_emission", "emission"), (0, 0, 0))
    plane("BasePlane", noise_material("noise_base", "base"), (5, 0, 0))
    plane("NoUV", noise_material("noise_nouv", "emission"), (10, 0, 0), uv=False)
    plane("RoughPlane", noise_material("noise_rough", "rough"), (15, 0, 0))
    plane("ViewPlane", noise_material("view", "view"), (20, 0, 0))

    data, problems = export()
    for mat, inp in (("noise_emission", "input 'Color'"), ("noise_base", "input 'Base Color'")):
        bt.check(any("'%s'" % mat in p and "Brick Texture 'Brick Texture'" in p and inp in p
                     and "not baked yet" in p for p in problems),
                 "before baking, %s's %s is reported as not baked yet: %s" % (mat, inp, problems))
    bt.check(any("object 'NoUV' has no UV map" in p and "'noise_nouv'" in p for p in problems),
             "the object without UVs is named with its material: %s" % problems)
    bt.check(any("material 'view': Layer Weight" in p and "depends on the view" in p
                 for p in problems), "a view-dependent subgraph is not baked: %s" % problems)
    bt.check(len(bake.PENDING) == 5, "five bakes pending: %s" % [r.describe()
                                                                  for r in bake.PENDING])

    bt.check(bpy.ops.facet.bake_inputs() == {'FINISHED'}, "Bake Procedural Inputs finished")
    baked = sorted(os.listdir(textures.CACHE_DIR))
    bt.check(len(baked) == 5 and all(f.startswith("bake_") and f.endswith(".exr")
                                     for f in baked), "five EXRs in the cache: %s" % baked)
    data, problems = export()
    mats = dict(data["materials"])
    em_shape = [s for s in data["shapes"] if s.get("name") == "EmPlane"][0]
    em = em_shape["emission"]
    base = mats["noise_base"]["base_color"]
    bt.check(isinstance(em, dict) and os.path.dirname(em["texture"]) == textures.CACHE_DIR
             and em["colorspace"] == "linear" and em_shape["uvs"] is not None,
             "the emission plane renders the baked image over its UVs: %s" % em)
    bt.check(isinstance(base, dict) and base["texture"] != em["texture"]
             and mats["noise_base"]["model"] == "principled"
             and isinstance(mats["noise_base"]["roughness"], dict),
             "Principled Base Color and Roughness -> baked base_color and roughness "
             "textures: %s" % mats["noise_base"])
    bt.check(sum("baked: Brick Texture 'Brick Texture'" in p for p in problems) == 5
             and not any("not baked yet" in p for p in problems),
             "what was baked is reported: %s" % problems)
    bt.check(bpy.ops.facet.bake_inputs() == {'FINISHED'} and bake.PENDING == []
             and sorted(os.listdir(textures.CACHE_DIR)) == baked,
             "a second bake finds everything cached")
    scene.facet.bake_resolution = 128
    export()
    bt.check(len(bake.PENDING) == 5, "a new resolution needs new bakes")
    scene.facet.bake_resolution = 256

    # A roughness bakes squared: alpha = clamp(Fac, 0, 1)^2, a grey texture read in "r";
    # the same plane's Emission bake of Fac gives Fac itself.
    rough = [s for s in data["shapes"] if s.get("name") == "RoughPlane"][0]
    alpha = mats["noise_rough"]["alpha"]
    from facet_blender import native
    fac = np.asarray(native.facet.read_image(rough["emission"]["texture"]))
    alp = np.asarray(native.facet.read_image(alpha["texture"]))
    err = np.abs(alp - np.clip(fac, 0, 1) ** 2).max()
    bt.check(mats["noise_rough"]["model"] == "ggx" and alpha["channel"] == "r"
             and fac.std() > 0.02 and err < 1e-5,
             "Glossy Roughness <- Brick: alpha baked as Fac^2 (max error %.3g), channel r: %s"
             % (err, alpha))
    fscene, warnings = native.build(data)
    bt.check(fscene is not None and warnings == [],
             "the core builds the baked textures (a textured ggx alpha too): %s" % warnings)

    # Render: only the emission plane, filling the orthographic view.
    for name in ("BasePlane", "NoUV", "RoughPlane", "ViewPlane"):
        bpy.data.objects.remove(bpy.data.objects[name])
    cam = scene.camera
    cam.data.type = 'ORTHO'
    cam.data.ortho_scale = 2.0
    cam.location = (0.0, 0.0, 3.0)
    cam.rotation_euler = (0.0, 0.0, 0.0)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    scene.render.resolution_x = scene.render.resolution_y = 64
    scene.render.resolution_percentage = 100
    scene.facet.spp = SPP
    scene.facet.max_depth = 1
    cs.cycles_settings(scene, samples=SPP, seed=1, max_depth=1)
    a, _ = cs.render(scene, 'FACET', os.path.join(outdir, "bake_facet.exr"), seed=1)
    from facet_blender import hooks
    problems = list(hooks.last_problems)
    b, _ = cs.render(scene, 'CYCLES', os.path.join(outdir, "bake_cycles.exr"), seed=1)
    d = np.abs(a - b)
    print("bake: means Facet %.5f Cycles %.5f, mean |diff| %.5f, max %.4f"
          % (a.mean(), b.mean(), d.mean(), d.max()))
    bt.check(b.mean() > 0.2 and abs(a.mean() / b.mean() - 1.0) < 0.01,
             "Facet's mean (baked) within 1%% of Cycles' (procedural): %.5f / %.5f"
             % (a.mean(), b.mean()))
    bt.check(d.mean() < 0.01, "mean |Facet - Cycles| per pixel %.5f < 0.01" % d.mean())
    bt.check(any("baked:" in p for p in problems), "the render lists the bake: %s" % problems)


bt.run(main)
