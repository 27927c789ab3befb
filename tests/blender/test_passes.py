"""Render passes (facet_blender/passes.py, the core's aov.h) through Blender's compositor:
a Render Layers node's Depth, Normal, Emit and Albedo outputs written by a File Output node,
for Facet and for Cycles (the same scene and compositor).

Scene: a camera 5 above the plane z = 0 (Diffuse 0.6) looking straight down, a smooth UV
sphere (radius 0.8, centre (0.9, 0, 0.8), Diffuse 0.6) and an emitting quad (Emission
(1, 0.5, 0.25) x 2, at z = 0.5).
Checks, on pixels whose 3 x 3 neighbourhood sees one surface (no silhouette in the pixel):
- Depth: perspective camera, the plane: 5 everywhere (the view-axis distance; the distance
  along the ray would be 5 / cos theta, up to 8% more in the corners); Cycles 3.4 the same
  (this is how its Z pass is defined: camera-space z, measured here), |Facet - Cycles| < 1e-3
  (float32 positions of a plane: exact up to rounding).
- Normal: the plane (0, 0, 1); on the sphere the analytic normal (p - c) / r from the
  orthographic render's pixel position within 0.02 (the 64 x 32 UV sphere's interpolated
  normals: their deviation from the sphere is below 0.01 rad; averaging over the pixel adds
  a curvature term below 0.01 at 64 samples); Cycles' Normal pass within 0.02.
- Emit: exactly (2, 1, 0.5) on the quad and 0 elsewhere, as Cycles' Emit pass to 1e-4.
- Albedo: exactly 0.6 on the Lambertian surfaces (cosine sampling makes the estimate
  constant), 0 on the emitter's black material.
- Nothing is computed or registered when the passes are off: the Render Layers node then has
  no Depth output.
"""
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

W, H = 64, 48
SPHERE_C, SPHERE_R = (0.9, 0.0, 0.8), 0.8


def scene_setup():
    bpy.ops.wm.read_homefile(use_factory_startup=True)
    scene = bpy.context.scene
    for ob in list(scene.objects):
        bpy.data.objects.remove(ob)
    cam = bpy.data.cameras.new("cam")
    cob = bpy.data.objects.new("cam", cam)
    cob.location = (0.0, 0.0, 5.0)
    scene.collection.objects.link(cob)
    scene.camera = cob
    mat, nt, out = bt.new_material("grey")
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = (0.6, 0.6, 0.6, 1)
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    bpy.context.active_object.data.materials.append(mat)
    bpy.ops.mesh.primitive_uv_sphere_add(segments=64, ring_count=32, radius=SPHERE_R,
                                         location=SPHERE_C)
    bpy.ops.object.shade_smooth()
    bpy.context.active_object.data.materials.append(mat)
    emat, ent, eout = bt.new_material("glow")
    e = ent.nodes.new("ShaderNodeEmission")
    e.inputs["Color"].default_value = (1.0, 0.5, 0.25, 1)
    e.inputs["Strength"].default_value = 2.0
    ent.links.new(e.outputs[0], eout.inputs["Surface"])
    bpy.ops.mesh.primitive_plane_add(size=0.8, location=(-1.0, 0.3, 0.5))
    bpy.context.active_object.data.materials.append(emat)
    scene.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    scene.render.resolution_x, scene.render.resolution_y = W, H
    scene.render.resolution_percentage = 100
    scene.facet.spp = 16
    scene.facet.max_depth = 2
    cs.cycles_settings(scene, samples=16, seed=1, max_depth=2)
    vl = scene.view_layers[0]
    vl.use_pass_z = vl.use_pass_normal = vl.use_pass_emit = True
    return scene, cob, vl


def compositor(scene, outdir, tag, names):
    """Render Layers -> File Output of `names`; returns {name: path pattern}."""
    scene.use_nodes = True
    scene.render.use_compositing = True
    tree = scene.node_tree
    for n in list(tree.nodes):
        tree.nodes.remove(n)
    rl = tree.nodes.new("CompositorNodeRLayers")
    comp = tree.nodes.new("CompositorNodeComposite")
    tree.links.new(rl.outputs["Image"], comp.inputs["Image"])
    fo = tree.nodes.new("CompositorNodeOutputFile")
    fo.base_path = outdir
    fo.format.file_format = 'OPEN_EXR'
    fo.format.color_depth = '32'
    fo.format.color_mode = 'RGB'
    fo.file_slots.clear()
    paths = {}
    for name in names:
        if name not in rl.outputs:
            raise AssertionError("Render Layers has no '%s' output: %s"
                                 % (name, [o.name for o in rl.outputs]))
        slot = "passes_%s_%s_" % (tag, name)
        fo.file_slots.new(slot)
        tree.links.new(rl.outputs[name], fo.inputs[slot])
        paths[name] = os.path.join(outdir, slot + "%04d.exr" % scene.frame_current)
    return paths


def render_passes(scene, outdir, engine, tag, names):
    paths = compositor(scene, outdir, tag, names)
    for p in paths.values():
        if os.path.exists(p):
            os.remove(p)
    cs.render(scene, engine, os.path.join(outdir, "passes_%s.exr" % tag), seed=1)
    return {k: bt.load_exr(p) for k, p in paths.items()}


def interior(mask):
    """Pixels whose 3 x 3 neighbourhood is all in mask."""
    m = mask.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            m &= np.roll(np.roll(mask, dy, 0), dx, 1)
    m[0, :] = m[-1, :] = m[:, 0] = m[:, -1] = False
    return m


def main():
    bt.enable_addon()
    outdir = bt.args()[0]
    scene, cob, vl = scene_setup()

    # Passes off: not registered (the compositor has no such output).
    vl.use_pass_z = vl.use_pass_normal = vl.use_pass_emit = False
    scene.render.engine = 'FACET'
    scene.use_nodes = True
    rl = scene.node_tree.nodes.new("CompositorNodeRLayers")
    bt.check("Depth" not in [o.name for o in rl.outputs if o.enabled],
             "no Depth output when the pass is off")
    vl.use_pass_z = vl.use_pass_normal = vl.use_pass_emit = True
    vl.facet.use_pass_albedo = True
    bt.check("Albedo" in [o.name for o in rl.outputs if o.enabled],
             "the Albedo toggle re-queries the passes: the Render Layers node offers it")

    names = ["Depth", "Normal", "Emit", "Albedo"]
    f = render_passes(scene, outdir, 'FACET', "facet_persp", names)
    c = render_passes(scene, outdir, 'CYCLES', "cycles_persp", names[:3])

    depth = f["Depth"][..., 0]
    plane = interior(np.abs(f["Normal"][..., 2] - 1.0) < 1e-6)
    plane &= interior(np.abs(f["Emit"]).max(axis=2) == 0)
    # The plane's pixels far from the sphere (its normal is exactly (0, 0, 1) there).
    bt.check(plane.sum() > 500 and np.abs(depth[plane] - 5.0).max() < 1e-4,
             "Facet Depth of the plane = 5 (view axis): max error %.2g over %d pixels"
             % (np.abs(depth[plane] - 5.0).max(), plane.sum()))
    cd = c["Depth"][..., 0]
    print("Cycles depth of the plane: min %.5f max %.5f" % (cd[plane].min(), cd[plane].max()))
    bt.check(np.abs(cd[plane] - depth[plane]).max() < 1e-3,
             "Cycles 3.4's Z pass is the view-axis depth too: max |Facet - Cycles| %.2g"
             % np.abs(cd[plane] - depth[plane]).max())
    glow = interior(np.abs(f["Emit"] - np.array([2.0, 1.0, 0.5])).max(axis=2) < 1e-6)
    bt.check(glow.sum() > 20 and np.abs(c["Emit"][glow] - f["Emit"][glow]).max() < 1e-4
             and np.abs(c["Emit"][plane]).max() < 1e-6,
             "Emit (2, 1, 0.5) on the quad, 0 on the plane, as Cycles: %d pixels" % glow.sum())
    alb = f["Albedo"]
    bt.check(np.abs(alb[plane] - 0.6).max() < 1e-5 and np.abs(alb[glow]).max() < 1e-6,
             "Albedo 0.6 on the Lambertian plane, 0 on the emitter: max error %.2g"
             % np.abs(alb[plane] - 0.6).max())
    nd = np.abs(c["Normal"] - f["Normal"]).max(axis=2)
    same = interior(np.linalg.norm(f["Normal"], axis=2) > 0.999)
    bt.check(np.percentile(nd[same], 99) < 0.02,
             "Normal pass as Cycles': 99th percentile of the difference %.3g"
             % np.percentile(nd[same], 99))

    # Orthographic, 4 x 3 scene units: the sphere's normals against (p - c) / r.
    cob.data.type = 'ORTHO'
    cob.data.ortho_scale = 4.0
    f = render_passes(scene, outdir, 'FACET', "facet_ortho", ["Depth", "Normal"])
    ys, xs = np.mgrid[0:H, 0:W]
    px = (xs + 0.5 - W / 2.0) * 4.0 / W
    py = (H / 2.0 - ys - 0.5) * 4.0 / W
    rx, ry = (px - SPHERE_C[0]) / SPHERE_R, (py - SPHERE_C[1]) / SPHERE_R
    inside = interior(rx * rx + ry * ry < 0.8)
    nz = np.sqrt(np.clip(1.0 - rx * rx - ry * ry, 0.0, 1.0))
    ref = np.stack([rx, ry, nz], axis=2)
    err = np.abs(f["Normal"] - ref).max(axis=2)[inside]
    dz = np.abs(f["Depth"][..., 0] - (5.0 - SPHERE_C[2] - SPHERE_R * nz))[inside]
    bt.check(inside.sum() > 100 and err.max() < 0.02 and dz.max() < 0.02,
             "sphere normals (p - c) / r within %.3g, depth within %.3g (%d pixels)"
             % (err.max(), dz.max(), inside.sum()))


bt.run(main)
