"""An environment map imported into Blender becomes a World that Cycles renders as Facet does.

A Facet scene with only an environment map (a smooth 64 x 32 map, RGB multiplier [1, 2, 0.5])
and a camera looking along +X is imported (importer.py, _environment_world): the World must be
Environment Texture (the map) -> Multiply (the multiplier) -> Background, and the Facet engine
and Cycles (camera rays only, 16 spp) must render the same sky. Tolerance: the map varies by at
most ~10% across a pixel, so the two renderers' filtering (Facet's lookup, Cycles' linear
interpolation, both averaged over the pixel by 16 jittered samples) may differ by a few
tenths of a percent per pixel (measured: 0.29% at most, image means within 1e-5): 1% per pixel
and 0.2% on the image mean. A map read with another orientation (u offset by a quarter turn)
differs by ~50%; the missing multiplier by 2x.
"""
import json
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402


def main():
    out = bt.args()[0]
    bt.enable_addon()
    from facet_blender import native
    w, h = 64, 32
    u = (np.arange(w) + 0.5) / w
    v = (np.arange(h) + 0.5) / h
    uu, vv = np.meshgrid(u, v)
    sky = np.stack([1.0 + 0.5 * np.cos(2 * math.pi * uu), 1.0 + 0.5 * np.sin(2 * math.pi * uu),
                    0.5 + vv], axis=2).astype(np.float32)
    map_path = os.path.join(out, "envmap_world.exr")
    native.facet.write_image(sky, map_path)
    scene_path = os.path.join(out, "envmap_world.json")
    with open(scene_path, "w") as f:
        json.dump({"format": "facet-scene", "version": 1,
                   "camera": {"position": [0, 0, 0], "look_at": [1, 0, 0], "up": [0, 0, 1],
                              "fov": 60, "width": 32, "height": 16},
                   "materials": {}, "shapes": [],
                   "lights": [{"type": "environment", "file": "envmap_world.exr",
                               "radiance": [1.0, 2.0, 0.5]}],
                   "render": {"spp": 16, "max_depth": 1}}, f)
    bpy.ops.wm.read_homefile(use_empty=True)
    bt.check(bpy.ops.import_scene.facet(filepath=scene_path) == {'FINISHED'}, "imported")
    scene = bpy.context.scene
    nodes = scene.world.node_tree.nodes
    tex = [n for n in nodes if n.bl_idname == 'ShaderNodeTexEnvironment']
    bt.check(scene.world.use_nodes and len(tex) == 1
             and os.path.samefile(bpy.path.abspath(tex[0].image.filepath), map_path),
             "the World reads the map through an Environment Texture")
    cs.cycles_settings(scene, samples=16, max_depth=1)
    img = {e: cs.render(scene, e, os.path.join(out, "envmap_world_%s.exr" % e.lower()), 3)[0]
           for e in ('FACET', 'CYCLES')}
    rel = np.abs(img['FACET'] - img['CYCLES']) / np.maximum(img['CYCLES'], 1e-6)
    ratio = img['FACET'].mean(axis=(0, 1)) / img['CYCLES'].mean(axis=(0, 1))
    print("per-pixel relative difference: max %.4f, mean %.4f; mean ratio %s"
          % (rel.max(), rel.mean(), ratio))
    bt.check(rel.max() < 0.01, "Facet and Cycles see the same sky per pixel (max %.4f)"
             % rel.max())
    bt.check(np.all(np.abs(ratio - 1.0) < 0.002), "image means agree to 0.2%% (%s)" % ratio)
    negative_texels(scene, sky, out)


def negative_texels(scene, sky, out):
    """A float map with negative values (Blender's own studio HDRIs have some, down to
    -0.0039) renders from a copy clamped to 0, reported with the count and the minimum; the
    core would refuse the file itself (negative radiance)."""
    from facet_blender import export, native
    neg = sky.copy()
    neg[3, 5, 1] = -0.25
    neg[10, 40, 2] = -0.125
    path = os.path.join(out, "envmap_world_negative.exr")
    native.facet.write_image(neg, path)
    world = bpy.data.worlds.new("negative")  # a user's World (not the imported one)
    world.use_nodes = True
    node = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    node.image = bpy.data.images.load(path)
    world.node_tree.links.new(node.outputs["Color"],
                              world.node_tree.nodes["Background"].inputs["Color"])
    scene.world = world
    data, problems = export.export_scene(bpy.context.evaluated_depsgraph_get())
    env = data["lights"][-1]
    lines = [p for p in problems if "negative colour values" in p]
    print(lines)
    bt.check(len(lines) == 1 and "2 negative colour values (down to -0.25) clamped to 0"
             in lines[0], "the clamp is reported with its count and minimum")
    bt.check(env["file"] != path and np.array_equal(bt.load_exr(env["file"]),
                                                     np.maximum(neg, 0.0)),
             "the map rendered is the file clamped to 0, every other texel unchanged")
    native.build(data, name="negative")  # the core accepts it (it refuses the original)
    print("ok: the clamped map builds")


bt.run(main)
