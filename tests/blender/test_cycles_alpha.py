"""Film > Transparent and holdouts: Facet's RGBA render result against Cycles 3.4's (issue 35,
item 3).

Scene (64 x 64, orthographic camera looking straight down, 64 spp, Facet max_depth 3 = Cycles
2 bounces; Film > Transparent on, the world a constant 1.0 that lights the scene and is left
out of the image):
- a Lambertian sphere (0.8) on nothing: its silhouette is alpha between 0 and 1, the
  background alpha 0;
- a cube with Object > Visibility > Holdout over part of the sphere: alpha 0 and colour 0
  there, while it still shades the sphere (it blocks the world's light);
- a plane whose material is Mix Shader(Diffuse 0.5, Holdout) at Fac 0.4: alpha 0.6 and 60% of
  its colour.

Bounds, as the real-scene suite states them (tests/realscenes/test_realscene.py), each for
the premultiplied colour's luminance and for the alpha channel:
- |mean ratio Facet / Cycles - 1| <= 2% (Cycles: the mean of its two seeds);
- block RMSE (8 x 8 blocks' means, Facet seed 1 against Cycles seed 1) <= 3 x the noise
  floor (the same between Cycles seeds 1 and 2).
Ability to fail: Facet with the cube's Holdout off, and Facet with Film > Transparent off,
must each break a bound (printed)."""
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


def build_scene():
    scene = cs.new_scene(RES, (1.0, 1.0, 1.0, 1.0), 1.0, "grey")
    bpy.ops.mesh.primitive_uv_sphere_add(radius=1.0, segments=64, ring_count=32,
                                         location=(0.0, 0.0, 0.0))
    bpy.ops.object.shade_smooth()
    mat = bpy.data.materials.new("white")
    bt.single_shader(mat, "ShaderNodeBsdfDiffuse", {"Color": (0.8, 0.8, 0.8, 1.0),
                                                     "Roughness": 0.0})
    bpy.context.object.data.materials.append(mat)
    bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.7, 0.5, 1.4))
    cube = bpy.context.object
    cube.data.materials.append(mat)
    cube.is_holdout = True
    # A plane half holdout: Mix Shader(Diffuse, Holdout, 0.4).
    bpy.ops.mesh.primitive_plane_add(size=0.9, location=(-1.1, -1.1, 0.5))
    mix = bpy.data.materials.new("mixed")
    mix.use_nodes = True
    nt = mix.node_tree
    for n in list(nt.nodes):
        nt.nodes.remove(n)
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    m = nt.nodes.new("ShaderNodeMixShader")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.5, 0.5, 0.5, 1.0)
    h = nt.nodes.new("ShaderNodeHoldout")
    m.inputs["Fac"].default_value = 0.4
    nt.links.new(d.outputs[0], m.inputs[1])
    nt.links.new(h.outputs[0], m.inputs[2])
    nt.links.new(m.outputs[0], out.inputs["Surface"])
    bpy.context.object.data.materials.append(mix)
    cs.ortho_camera_down(scene, 5.0, 3.4)
    scene.facet.max_depth = 3
    scene.facet.spp = SPP
    cs.cycles_settings(scene, samples=SPP, max_depth=3)
    scene.render.film_transparent = True  # (cycles_settings turns it off)
    return scene, cube


def compare(name, f, c1, mean_c, floors):
    """(colour mean ratio, colour block RMSE / floor, alpha mean ratio, alpha RMSE / floor)."""
    lum_f = cs.luminance(f)
    res = (float(lum_f.mean() / mean_c[0]),
           cs.block_rmse(f, c1, BLOCK) / max(floors[0], 1e-12),
           float(f[:, :, 3].mean() / mean_c[1]),
           cs.block_rmse(f[:, :, 3:4].repeat(3, 2), c1[:, :, 3:4].repeat(3, 2), BLOCK)
           / max(floors[1], 1e-12))
    print("%-22s colour: mean ratio %.4f, block RMSE %.2f x floor; alpha: mean ratio %.4f, "
          "block RMSE %.2f x floor" % ((name,) + res))
    return res


def within(res):
    return (abs(res[0] - 1.0) <= MEAN_TOL and res[1] <= RMSE_FACTOR and
            abs(res[2] - 1.0) <= MEAN_TOL and res[3] <= RMSE_FACTOR)


def main():
    out = bt.args()[0]
    bt.enable_addon()
    scene, cube = build_scene()
    c1 = cs.render_rgba(scene, 'CYCLES', os.path.join(out, "alpha_cycles1.exr"), 1)
    c2 = cs.render_rgba(scene, 'CYCLES', os.path.join(out, "alpha_cycles2.exr"), 2)
    bt.check(c1[0, 0, 3] == 0.0 and c1[RES // 2, RES // 2, 3] == 1.0,
             "Cycles: background alpha 0, sphere centre 1 (%g, %g)"
             % (c1[0, 0, 3], c1[RES // 2, RES // 2, 3]))
    mean_c = (0.5 * (cs.luminance(c1).mean() + cs.luminance(c2).mean()),
              0.5 * (c1[:, :, 3].mean() + c2[:, :, 3].mean()))
    floors = (cs.block_rmse(c1, c2, BLOCK),
              cs.block_rmse(c1[:, :, 3:4].repeat(3, 2), c2[:, :, 3:4].repeat(3, 2), BLOCK))
    print("Cycles: mean luminance %.4f, mean alpha %.4f; floors %.5f, %.5f"
          % (mean_c[0], mean_c[1], floors[0], floors[1]))
    f = cs.render_rgba(scene, 'FACET', os.path.join(out, "alpha_facet1.exr"), 1)
    res = compare("Facet", f, c1, mean_c, floors)
    bt.check(within(res), "Facet's premultiplied colour and alpha match Cycles' (mean within "
             "%g, block RMSE <= %g x floor)" % (MEAN_TOL, RMSE_FACTOR))
    # Where the holdout cube covers the sphere: alpha 0 and black, in both.
    from bpy_extras.object_utils import world_to_camera_view
    p = world_to_camera_view(scene, scene.camera, cube.location)
    x, y = int(p.x * RES), RES - 1 - int(p.y * RES)
    bt.check(f[y, x, 3] == 0.0 and np.all(f[y, x, :3] == 0.0) and c1[y, x, 3] == 0.0,
             "the holdout cube's centre pixel (%d, %d): Facet alpha %g colour %s, Cycles alpha %g"
             % (x, y, f[y, x, 3], f[y, x, :3], c1[y, x, 3]))

    # Controls: each must break a bound.
    cube.is_holdout = False
    f = cs.render_rgba(scene, 'FACET', os.path.join(out, "alpha_facet_noholdout.exr"), 1)
    bt.check(not within(compare("Facet, cube not held out", f, c1, mean_c, floors)),
             "without the cube's Holdout a bound breaks: the test can fail")
    cube.is_holdout = True
    scene.render.film_transparent = False
    f = cs.render_rgba(scene, 'FACET', os.path.join(out, "alpha_facet_opaque.exr"), 1)
    bt.check(not within(compare("Facet, film opaque", f, c1, mean_c, floors)),
             "with Film > Transparent off a bound breaks: the test can fail")


bt.run(main)
