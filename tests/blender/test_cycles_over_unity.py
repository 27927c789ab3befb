"""A BSDF Color above 1 against Cycles 3.4 (materials.split_over_unity): Cycles takes a BSDF's
Color as a plain factor, the core's reflectance is at most 1, so the exporter writes the `add`
of ceil(max) copies of Color / n, the same f (it is linear in the colour).

A Diffuse BSDF of Color (1.6, 0.8, 0.4) and a Glossy BSDF (GGX, Roughness 0.4) of Color 1.25
on two spheres over a dark floor under a sun and a grey world, 64 x 48, 64 spp, 3 bounces;
Facet against Cycles, bounds as the other Cycles tests state them (test_cycles_motion.py):
- |mean luminance ratio Facet / Cycles - 1| <= 2% (Cycles: its two seeds' mean);
- block RMSE (8 x 8 blocks' mean luminance, Facet seed 1 against Cycles seed 1) <= 3 x the
  noise floor (the same between Cycles seeds 1 and 2).
Ability to fail: the colours clamped to 1 (what the core's range alone would allow) must break
a bound."""
import os
import sys

import bpy

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

W, H, SPP, MAX_DEPTH = 64, 48, 64, 4
MEAN_TOL, RMSE_FACTOR = 0.02, 3.0


def sphere(name, location, idname, inputs, props=None):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.8, location=location, segments=64,
                                         ring_count=32)
    ob = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    mat = bpy.data.materials.new(name)
    bt.single_shader(mat, idname, inputs, props or {})
    ob.data.materials.append(mat)
    return mat


def scene():
    scene = cs.new_scene(W, (0.3, 0.3, 0.3, 1.0))
    scene.render.resolution_y = H
    sphere("Bright diffuse", (-0.9, 0.0, 0.8), "ShaderNodeBsdfDiffuse",
           {"Color": (1.6, 0.8, 0.4, 1.0)})
    sphere("Bright glossy", (0.9, 0.0, 0.8), "ShaderNodeBsdfGlossy",
           {"Color": (1.25, 1.25, 1.25, 1.0), "Roughness": 0.4}, {"distribution": 'GGX'})
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    floor = bpy.data.materials.new("Floor")
    bt.single_shader(floor, "ShaderNodeBsdfDiffuse", {"Color": (0.2, 0.2, 0.2, 1.0)})
    bpy.context.active_object.data.materials.append(floor)
    cs.add_light(scene, 'SUN', 3.0, (0.0, 0.0, 5.0), rotation=(0.5, 0.3, 0.0),
                 visible_camera=False)
    cd = bpy.data.cameras.new("cam")
    cam = bpy.data.objects.new("cam", cd)
    cam.location, cam.rotation_euler = (0.0, -5.0, 1.6), (1.33, 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    scene.facet.spp, scene.facet.max_depth = SPP, MAX_DEPTH
    cs.cycles_settings(scene, samples=SPP, max_depth=MAX_DEPTH)
    return scene


def main():
    out = bt.args()[0]
    bt.enable_addon()
    sc = scene()

    def render(engine, seed, tag=""):
        return cs.render(sc, engine, os.path.join(out, "over_unity%s_%s_%d.exr"
                                                  % (tag, engine.lower(), seed)), seed)[0]
    f = render('FACET', 1)
    c1, c2 = render('CYCLES', 1), render('CYCLES', 2)
    ratio, rel = cs.compare_to_cycles("over unity", f, c1, c2)
    bt.check(abs(ratio - 1.0) <= MEAN_TOL and rel <= RMSE_FACTOR,
             "Colors above 1: mean ratio %.4f within %g, block RMSE %.2f <= %g x floor"
             % (ratio, MEAN_TOL, rel, RMSE_FACTOR))
    # The control: the colours clamped to 1.
    from facet_blender import materials
    saved = materials.split_over_unity

    def clamped(data, notes):
        key = materials._LINEAR_COLOUR.get(data.get("model"))
        if key and key in data and not materials.is_texture(data[key]):
            return dict(data, **{key: [min(float(c), 1.0) for c in data[key]]})
        return data
    materials.split_over_unity = clamped
    try:
        fc = render('FACET', 1, "_clamped")
    finally:
        materials.split_over_unity = saved
    ratio, rel = cs.compare_to_cycles("clamped", fc, c1, c2)
    bt.check(abs(ratio - 1.0) > MEAN_TOL or rel > RMSE_FACTOR,
             "clamped colours break a bound (mean ratio %.4f, block RMSE %.2f x floor): the "
             "test can fail" % (ratio, rel))


bt.run(main)
