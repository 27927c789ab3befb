"""Object > Visibility > Shadow Catcher: Facet's render result against Cycles 3.4's, with
Film > Transparent on and off (issue 35, item 3).

Scene (64 x 64, orthographic camera looking straight down, 64 spp, Facet max_depth 3 = Cycles
2 bounces): a plane with a Principled BSDF (base colour 0.8, 0.5, 0.4) that is a shadow
catcher, a sphere above it (Diffuse 0.8, 0.3, 0.2), a sun lamp at 30 degrees and a world of
colour (0.2, 0.3, 0.5) that lights the scene too. The plane covers part of the view: the
world is seen directly around it.
- Film > Transparent on: Cycles' Combined is the sphere's colour with alpha, and on the
  catcher no colour and alpha = the shadow (1 - the light the sphere takes from it);
- off: the catcher shows the world behind it darkened by the same shadow.
A second scene, over a transparent film, makes the catcher glossy (Specular 1, Roughness 0.15:
it reflects the sphere) and lights it with a 1 m area lamp instead of the sun (soft shadows).

Bounds, as the real-scene suite states them (tests/realscenes/test_realscene.py): for the
(premultiplied) colour's luminance and, over a transparent film, for the alpha channel,
- |mean ratio Facet / Cycles - 1| <= 2% (Cycles: the mean of its two seeds);
- block RMSE (8 x 8 blocks' means, Facet seed 1 against Cycles seed 1) <= 3 x the noise
  floor (the same between Cycles seeds 1 and 2).
Ability to fail: Facet with the plane's Shadow Catcher off must break a bound in each film
mode (printed).

View Layer > Passes > Shadow Catcher on (the first scene, both film modes): Cycles 3.4 then
writes the Shadow Catcher pass (per channel the light the catcher kept: about 1 on the lit
catcher, less in the shadow, 1 where no catcher is seen) and its Combined pass is no longer
the approximation but the matte: the sphere with its alpha, the catcher colourless with alpha
0 over an opaque film too (checked on Cycles' own render). Facet's pass (luminance) and
Combined (colour and alpha) against Cycles', with the same bounds; with Render Properties >
Facet > Denoise (two half-buffers) Facet's pass is the same, bit for bit. Ability to fail: a pass of
1 everywhere, and Facet's Combined without the pass (the approximation), break a bound."""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

RES = 64
BLOCK = 8
SPP = 64
MEAN_TOL = 0.02
RMSE_FACTOR = 3.0


def build_scene(glossy_area=False):
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = RES
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.2, 0.3, 0.5, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world
    bpy.ops.mesh.primitive_plane_add(size=2.6, location=(0.0, 0.0, 0.0))
    plane = bpy.context.object
    floor = bpy.data.materials.new("floor")
    floor.use_nodes = True
    bsdf = floor.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (0.8, 0.5, 0.4, 1.0)
    if glossy_area:
        bsdf.inputs["Roughness"].default_value = 0.15
        bsdf.inputs["Specular"].default_value = 1.0
    plane.data.materials.append(floor)
    plane.is_shadow_catcher = True
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, segments=64, ring_count=32,
                                         location=(0.3, 0.2, 0.7))
    bpy.ops.object.shade_smooth()
    mat = bpy.data.materials.new("orange")
    bt.single_shader(mat, "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.3, 0.2, 1.0),
                                                     "Roughness": 0.0})
    bpy.context.object.data.materials.append(mat)
    if glossy_area:
        cs.add_light(scene, 'AREA', 150.0, (1.0, 1.2, 2.5), rotation=(-0.4, 0.35, 0.0),
                     visible_camera=False, size=1.0)
    else:
        cs.add_light(scene, 'SUN', 3.0, (0.0, 0.0, 4.0), rotation=(0.5236, 0.0, 0.6),
                     visible_camera=False, angle=0.0)
    cd = bpy.data.cameras.new("cam")
    cd.type = 'ORTHO'
    cd.ortho_scale = 3.4
    cam = bpy.data.objects.new("cam", cd)
    cam.location = (0.0, 0.0, 5.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.facet.max_depth = 3
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=3)
    return scene, plane


def compare(name, f, c1, mean_c, floors, alpha):
    """(colour mean ratio, colour block RMSE / floor[, alpha mean ratio, alpha RMSE / floor])."""
    res = (float(cs.luminance(f).mean() / mean_c[0]),
           cs.block_rmse(f, c1, BLOCK) / max(floors[0], 1e-12))
    if alpha:
        res += (float(f[:, :, 3].mean() / mean_c[1]),
                cs.block_rmse(f[:, :, 3:4].repeat(3, 2), c1[:, :, 3:4].repeat(3, 2), BLOCK)
                / max(floors[1], 1e-12))
        print("%-34s colour: mean ratio %.4f, block RMSE %.2f x floor; alpha: mean ratio "
              "%.4f, block RMSE %.2f x floor" % ((name,) + res))
    else:
        print("%-34s colour: mean ratio %.4f, block RMSE %.2f x floor" % ((name,) + res))
    return res


def within(res):
    return all(abs(res[i] - 1.0) <= MEAN_TOL and res[i + 1] <= RMSE_FACTOR
               for i in range(0, len(res), 2))


def film_case(scene, plane, out, transparent, tag=None):
    tag = tag or ("transparent" if transparent else "opaque")
    key = tag.replace(", ", "_").replace(" ", "_")
    scene.render.film_transparent = transparent
    plane.is_shadow_catcher = True
    c1 = cs.render_rgba(scene, 'CYCLES', os.path.join(out, "catcher_%s_cycles1.exr" % key), 1)
    c2 = cs.render_rgba(scene, 'CYCLES', os.path.join(out, "catcher_%s_cycles2.exr" % key), 2)
    mean_c = (0.5 * (cs.luminance(c1).mean() + cs.luminance(c2).mean()),
              0.5 * (c1[:, :, 3].mean() + c2[:, :, 3].mean()))
    floors = (cs.block_rmse(c1, c2, BLOCK),
              cs.block_rmse(c1[:, :, 3:4].repeat(3, 2), c2[:, :, 3:4].repeat(3, 2), BLOCK))
    print("Cycles, film %s: mean luminance %.4f, mean alpha %.4f; floors %.5f, %.5f"
          % (tag, mean_c[0], mean_c[1], floors[0], floors[1]))
    # What Cycles does (the definition the test holds Facet to): over a transparent film the
    # lit catcher has no colour and alpha near 0, the shadow alpha; over an opaque one the
    # lit catcher is the world's colour.
    lit = c1[14, 50]  # the plane far from the sphere and its shadows
    if transparent:
        bt.check(np.all(lit[:3] == 0.0) and lit[3] < 0.05,
                 "Cycles: the lit catcher is transparent and colourless (%s)" % lit)
    else:
        bt.check(np.allclose(lit[:3], (0.2, 0.3, 0.5), rtol=0.05),
                 "Cycles: the lit catcher shows the world over an opaque film (%s)" % lit)
    f = cs.render_rgba(scene, 'FACET', os.path.join(out, "catcher_%s_facet1.exr" % key), 1)
    res = compare("Facet, film %s" % tag, f, c1, mean_c, floors, transparent)
    bt.check(within(res), "film %s: Facet's colour%s match Cycles' (mean within %g, block "
             "RMSE <= %g x floor)" % (tag, " and alpha" if transparent else "", MEAN_TOL,
                                      RMSE_FACTOR))
    # Control: without the flag the plane is an ordinary object, and a bound breaks.
    plane.is_shadow_catcher = False
    f = cs.render_rgba(scene, 'FACET', os.path.join(out, "catcher_%s_facet_off.exr" % key), 1)
    bt.check(not within(compare("Facet, film %s, catcher off" % tag, f, c1, mean_c, floors,
                                transparent)),
             "film %s: without Shadow Catcher a bound breaks: the test can fail" % tag)
    plane.is_shadow_catcher = True


def pass_outputs(scene, out, key, engine):
    """Render Layers' Image (RGBA) and Shadow Catcher outputs written by a File Output node
    (the Render Layers node made with `engine` set, so that it offers the engine's passes);
    returns {output: path}."""
    scene.render.engine = engine
    scene.use_nodes = True
    scene.render.use_compositing = True
    tree = scene.node_tree
    for n in list(tree.nodes):
        tree.nodes.remove(n)
    rl = tree.nodes.new("CompositorNodeRLayers")
    tree.links.new(rl.outputs["Image"], tree.nodes.new("CompositorNodeComposite").inputs[0])
    fo = tree.nodes.new("CompositorNodeOutputFile")
    fo.base_path = out
    fo.format.file_format = 'OPEN_EXR'
    fo.format.color_depth = '32'
    fo.format.color_mode = 'RGBA'
    fo.file_slots.clear()
    paths = {}
    for name in ("Image", "Shadow Catcher"):
        bt.check(name in [o.name for o in rl.outputs if o.enabled],
                 "%s: Render Layers offers %s" % (engine, name))
        slot = "catcher_%s_%s_" % (key, name.replace(" ", "_"))
        fo.file_slots.new(slot)
        tree.links.new(rl.outputs[name], fo.inputs[slot])
        paths[name] = os.path.join(out, slot + "%04d.exr" % scene.frame_current)
        if os.path.exists(paths[name]):
            os.remove(paths[name])
    return paths


def render_with_pass(scene, out, key, engine, seed):
    """(Combined RGBA, Shadow Catcher pass RGB) of F12 with `engine` and `seed`."""
    paths = pass_outputs(scene, out, key, engine)
    cs.render_rgba(scene, engine, os.path.join(out, "catcher_%s_result.exr" % key), seed)
    return cs.load_rgba(paths["Image"]), bt.load_exr(paths["Shadow Catcher"]).astype(np.float64)


def pass_case(scene, plane, out, transparent):
    tag = "pass, film %s" % ("transparent" if transparent else "opaque")
    key = tag.replace(", ", "_").replace(" ", "_")
    scene.render.film_transparent = transparent
    plane.is_shadow_catcher = True
    scene.view_layers[0].cycles.use_pass_shadow_catcher = True
    c1, p1 = render_with_pass(scene, out, key + "_cycles1", 'CYCLES', 1)
    c2, p2 = render_with_pass(scene, out, key + "_cycles2", 'CYCLES', 2)
    # Cycles' definition: the lit catcher colourless and transparent in both film modes, its
    # pass near 1; a shadow in the pass; 1 in the pass where no catcher is seen (a corner).
    lit = c1[14, 50]
    bt.check(np.all(lit == 0.0) and abs(p1[14, 50].mean() - 1.0) < 0.1 and
             p1[0, 0].tolist() == [1.0, 1.0, 1.0] and cs.luminance(p1).min() < 0.5,
             "Cycles, %s: Combined 0 on the lit catcher (%s), pass about 1 there (%s), 1 off "
             "the catcher (%s), a shadow below 0.5 (%.3f)" % (tag, lit, p1[14, 50], p1[0, 0],
                                                        cs.luminance(p1).min()))
    mean_c = (0.5 * (cs.luminance(c1).mean() + cs.luminance(c2).mean()),
              0.5 * (c1[:, :, 3].mean() + c2[:, :, 3].mean()))
    floors = (cs.block_rmse(c1, c2, BLOCK),
              cs.block_rmse(c1[:, :, 3:4].repeat(3, 2), c2[:, :, 3:4].repeat(3, 2), BLOCK))
    mean_p = 0.5 * (cs.luminance(p1).mean() + cs.luminance(p2).mean())
    floor_p = cs.block_rmse(p1, p2, BLOCK)
    print("Cycles, %s: mean luminance %.4f, mean alpha %.4f, mean pass %.4f; floors %.5f, "
          "%.5f, %.5f" % (tag, mean_c[0], mean_c[1], mean_p, floors[0], floors[1], floor_p))

    def pass_res(name, p):
        res = (float(cs.luminance(p).mean() / mean_p), cs.block_rmse(p, p1, BLOCK) / floor_p)
        print("%-34s pass: mean ratio %.4f, block RMSE %.2f x floor" % ((name,) + res))
        return res
    f, fp = render_with_pass(scene, out, key + "_facet1", 'FACET', 1)
    bt.check(within(pass_res("Facet, " + tag, fp)),
             "%s: Facet's Shadow Catcher pass matches Cycles' (mean within %g, block RMSE <= "
             "%g x floor)" % (tag, MEAN_TOL, RMSE_FACTOR))
    bt.check(within(compare("Facet, %s, Combined" % tag, f, c1, mean_c, floors, True)),
             "%s: Facet's Combined (colour and alpha) matches Cycles' with the pass" % tag)
    if not transparent:
        # With Denoise the pass comes from the two half-buffers' merged sums: the same pass.
        scene.facet.denoise = True
        _, fd = render_with_pass(scene, out, key + "_facet_denoise", 'FACET', 1)
        scene.facet.denoise = False
        bt.check(np.array_equal(fd, fp), "%s: with Denoise, the pass of the merged half-buffers "
                 "is the same, bit for bit (max difference %g)" % (tag, np.abs(fd - fp).max()))
    # Controls: a pass of 1 everywhere; the approximate Combined (the pass off).
    bt.check(not within(pass_res("pass of 1, " + tag, np.ones_like(fp))),
             "%s: a pass of 1 everywhere breaks a bound: the test can fail" % tag)
    scene.view_layers[0].cycles.use_pass_shadow_catcher = False
    f = cs.render_rgba(scene, 'FACET', os.path.join(out, "catcher_%s_facet_off.exr" % key), 1)
    bt.check(not within(compare("Facet, %s, pass off" % tag, f, c1, mean_c, floors, True)),
             "%s: Facet's Combined without the pass breaks a bound: the test can fail" % tag)
    scene.use_nodes = False


def main():
    out = bt.args()[0]
    bt.enable_addon()
    scene, plane = build_scene()
    from facet_blender import export as ex
    data, problems = ex.export_scene(bpy.context.evaluated_depsgraph_get())
    bt.check([s.get("shadow_catcher", False) for s in data["shapes"]].count(True) == 1
             and not [p for p in problems if "Shadow Catcher" in p],
             "the plane is exported as a shadow catcher, without a report line: %s" % problems)
    film_case(scene, plane, out, True)
    film_case(scene, plane, out, False)
    pass_case(scene, plane, out, False)
    pass_case(scene, plane, out, True)
    scene, plane = build_scene(glossy_area=True)
    film_case(scene, plane, out, True, "transparent, glossy, area lamp")


bt.run(main)
