"""Render Properties > Facet > Denoise (final.py, the core's denoise.h): F12 renders two
half-buffers and the features and denoises them. Checks:
- the image equals the core's own facet.render(denoise=True) of the exported scene, bit for bit
  (one implementation: the addon only splits the samples and calls the core);
- it is closer to a 1024-spp reference than the plain render of the same 16 samples (MSE at
  most half: the C++ tests hold the denoiser's own bounds, this checks it is applied);
- with a render region (where a denoiser cannot run: it is not split-invariant) the render is
  not denoised and the report says why;
- View Layer > Passes > Denoising Data (Cycles' toggle): the Render Layers node offers
  Denoising Normal, Denoising Albedo and Denoising Depth, and a File Output node writes the
  core's normal, albedo and depth (render_aovs at the render's spp and seed) into them, to
  1e-6 (EXR float32 round trip of the same floats; a wrong pass or a flipped image differs
  by ~1);
- Noise Threshold (adaptive sampling): F12 equals facet.render of the exported scene (which
  carries the threshold in its render settings) bit for bit, and with Denoise on the render is
  not adaptive and the report says so.
"""
import os
import sys
import tempfile

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def main():
    bt.enable_addon()
    from facet_blender import export, native
    scene = bt.factory_scene(96, 72, spp=16, reload=False)
    # A floor and a grey world: indirect and environment light, the Monte Carlo noise a
    # denoiser is for (the factory scene alone is a point-lit cube whose only error at 16 spp
    # is the antialiasing of its outline).
    bpy.ops.mesh.primitive_plane_add(size=20.0, location=(0.0, 0.0, -1.0))
    scene.world.use_nodes = True
    scene.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.5, 0.5, 0.5, 1)
    scene.facet.seed = 3
    scene.render.threads_mode = 'FIXED'
    scene.render.threads = 2
    plain, _ = bt.render(scene)
    scene.facet.denoise = True
    den, problems = bt.render(scene)
    bt.check(den is not None and den.shape == plain.shape and np.isfinite(den).all(),
             "a denoised image of the render's size (%s)" % problems)
    data, _ = export.export_scene(bpy.context.evaluated_depsgraph_get())
    fscene, _ = native.build(data, name="denoise")
    core = np.asarray(native.facet.render(fscene, spp=16, seed=3, threads=2, denoise=True))
    bt.check(np.array_equal(den, core),
             "F12 with Denoise equals facet.render(denoise=True), bit for bit")
    ref = np.asarray(native.facet.render(fscene, spp=1024, seed=11, threads=2), np.float64)
    m_plain = float(np.mean((plain - ref) ** 2))
    m_den = float(np.mean((den - ref) ** 2))
    bt.check(m_den < m_plain / 2, "denoised MSE %.3g < half the plain MSE %.3g" % (m_den, m_plain))

    # Denoising Data passes through the compositor.
    names = ["Denoising Normal", "Denoising Albedo", "Denoising Depth"]
    scene.use_nodes = True
    tree = scene.node_tree
    for n in list(tree.nodes):
        tree.nodes.remove(n)
    rl = tree.nodes.new("CompositorNodeRLayers")
    bt.check(not any(n in [o.name for o in rl.outputs if o.enabled] for n in names),
             "no Denoising Data outputs while the toggle is off")
    scene.view_layers[0].cycles.denoising_store_passes = True
    bt.check(all(n in [o.name for o in rl.outputs if o.enabled] for n in names),
             "Denoising Data offers %s: %s" % (names, [o.name for o in rl.outputs if o.enabled]))
    comp = tree.nodes.new("CompositorNodeComposite")
    tree.links.new(rl.outputs["Image"], comp.inputs["Image"])
    fo = tree.nodes.new("CompositorNodeOutputFile")
    outdir = tempfile.mkdtemp(prefix="facet_denoise_passes_")
    fo.base_path = outdir
    fo.format.file_format = 'OPEN_EXR'
    fo.format.color_depth = '32'
    fo.format.color_mode = 'RGB'
    fo.file_slots.clear()
    for i, n in enumerate(names):
        fo.file_slots.new("p%d_" % i)
        tree.links.new(rl.outputs[n], fo.inputs["p%d_" % i])
    bt.render(scene)
    got = [bt.load_exr(os.path.join(outdir, "p%d_%04d.exr" % (i, scene.frame_current)))
           for i in range(3)]
    aovs = native.render_aovs(fscene, ["normal", "albedo", "depth"], spp=16, seed=3, threads=2)
    for n, g, want in zip(names, got, (aovs["normal"], aovs["albedo"], aovs["depth"][:, :, :1])):
        err = float(np.max(np.abs(g[:, :, :want.shape[2]] - want)))
        bt.check(err <= 1e-6, "%s equals the core's pass (max difference %.3g)" % (n, err))
    scene.view_layers[0].cycles.denoising_store_passes = False
    scene.use_nodes = False

    rd = scene.render
    rd.use_border = rd.use_crop_to_border = True
    rd.border_min_x, rd.border_max_x = 0.2, 0.7
    rd.border_min_y, rd.border_max_y = 0.3, 0.8
    _, problems = bt.render(scene)
    bt.check(any("Denoise is off for this render: a render region" in p for p in problems),
             "a region render says why it is not denoised (%s)" % problems)

    rd.use_border = False
    scene.facet.adaptive_threshold = 0.05
    scene.facet.adaptive_min_samples = 4
    _, problems = bt.render(scene)
    bt.check(den is not None and any("Noise Threshold (adaptive sampling) is off" in p
                                     for p in problems),
             "Denoise with a Noise Threshold: not adaptive, reported (%s)" % problems)
    scene.facet.denoise = False
    adaptive, problems = bt.render(scene)
    data, _ = export.export_scene(bpy.context.evaluated_depsgraph_get())
    bt.check(abs(data["render"].get("adaptive_threshold", 0) - 0.05) < 1e-7,
             "the threshold is exported in the render settings: %s" % data["render"])
    fscene, _ = native.build(data, name="adaptive")
    session = native.facet.RenderSession(fscene, threads=2)
    session.render()
    bt.check(np.array_equal(adaptive, np.asarray(session.image()))
             and session.stats.mean_spp < 16,
             "F12 with Noise Threshold 0.05 equals the core's adaptive render (mean %.1f spp of "
             "16)" % session.stats.mean_spp)


bt.run(main)
