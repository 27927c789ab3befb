"""Blender -> JSON -> Blender: a Blender scene (the factory cube with a Principled material, a
subdivided smooth sphere with two material slots and auto smooth, a linked duplicate, point,
spot, sun and area lights, the world colour) exported to JSON, imported into an empty file and
exported again gives the same scene description; and the re-imported scene renders the same
image as the original Blender scene, bit for bit."""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402


def build_scene():
    scene = bt.factory_scene(200, 120)
    scene.facet.seed = 5
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.7, location=(2.2, 0.5, 0.3))
    sph = bpy.context.object
    sub = sph.modifiers.new("sub", 'SUBSURF')
    # JSON export evaluates the scene as the viewport does (Python has no render-mode
    # depsgraph outside a render), F12 with render settings: make them the same here.
    sub.levels = sub.render_levels = 1
    bpy.ops.object.shade_smooth()
    sph.data.use_auto_smooth = True
    red = bpy.data.materials.new("red")
    red.diffuse_color = (0.8, 0.1, 0.1, 1.0)
    red.use_nodes = False
    gold = bpy.data.materials.new("gold")
    gold.facet.source = 'FACET'
    gold.facet.model = 'ggx'
    gold.facet.ggx__fresnel, gold.facet.ggx__fresnel__set = "schlick", True
    gold.facet.ggx__f0, gold.facet.ggx__f0__set = (1.0, 0.77, 0.34), True
    sph.data.materials.append(red)
    sph.data.materials.append(gold)
    for i, p in enumerate(sph.data.polygons):
        p.material_index = int(p.center.z > 0)
    dup = bpy.data.objects.new("SphereLinked", sph.data)
    dup.location = (-2.2, 0.5, 0.3)
    scene.collection.objects.link(dup)
    for kind, loc, energy in (('SPOT', (0, -3, 4), 800.0), ('SUN', (0, 0, 5), 2.0),
                              ('AREA', (0, 2, 3), 300.0)):
        ld = bpy.data.lights.new(kind, kind)
        ld.energy = energy
        if kind == 'SPOT':
            ld.spot_size, ld.spot_blend = math.radians(50), 0.2
        if kind == 'AREA':
            ld.shape, ld.size, ld.size_y = 'RECTANGLE', 1.0, 0.5
        ob = bpy.data.objects.new(kind, ld)
        ob.location = loc
        ob.rotation_euler = (0.4, 0.1, 0.0)
        if kind == 'AREA':
            ob.scale = (2.0, 1.0, 1.0)  # Cycles scales the lamp's size by the object's axes
            ob.visible_camera = True  # Object > Visibility > Camera (off by default for lamps)
        scene.collection.objects.link(ob)
    return scene


def same(a, b, path="scene"):
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), "%s: keys %s vs %s" % (path, sorted(a), sorted(b))
        for k in a:
            same(a[k], b[k], "%s/%s" % (path, k))
    elif isinstance(a, (list, tuple)) and not isinstance(a, str):
        assert len(a) == len(b), "%s: length %d vs %d" % (path, len(a), len(b))
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, "%s/%d" % (path, i))
    elif isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        assert np.array_equal(np.asarray(a), np.asarray(b)), "%s: arrays differ" % path
    else:
        assert a == b, "%s: %r vs %r" % (path, a, b)


def main():
    out = bt.args()[0]
    bt.enable_addon()
    from facet_blender import native
    build_scene()
    img0, probs0 = bt.render()
    bt.check(img0 is not None and img0.max() > 0.0, "the Blender scene renders (%s)" % probs0)
    a_path, b_path = os.path.join(out, "roundtrip_a.json"), os.path.join(out, "roundtrip_b.json")
    bt.check(bpy.ops.export_scene.facet(filepath=a_path) == {'FINISHED'}, "exported A")
    bpy.ops.wm.read_homefile(use_empty=True)
    bt.check(bpy.ops.import_scene.facet(filepath=a_path) == {'FINISHED'}, "imported A")
    bt.check(bpy.ops.export_scene.facet(filepath=b_path) == {'FINISHED'}, "exported B")
    da, db = native.read_scene(a_path), native.read_scene(b_path)
    # The area lamp is Facet's "area" kind with Blender's power, shape, scaled sizes, frame and
    # camera visibility (export.py, _light_data); the core converts the power to radiance.
    lamp = [lt for lt in da["lights"] if lt["type"] == "area"]
    bt.check(len(lamp) == 1 and lamp[0]["shape"] == "rectangle"
             and abs(lamp[0]["size"] - 2.0) < 1e-6 and abs(lamp[0]["size_y"] - 0.5) < 1e-6
             and lamp[0]["camera_visible"] is True
             and np.allclose(lamp[0]["power"], [300.0] * 3)
             and np.allclose(lamp[0]["position"], (0, 2, 3)), "area lamp exported: %s" % lamp)
    da.pop("description"), db.pop("description")
    same(da, db)
    bt.check(True, "A and B describe the same scene")
    img1, probs1 = bt.render()
    bt.check(img1 is not None and np.array_equal(img0, img1),
             "the re-imported scene renders the original's image bit for bit (max diff %.3g)"
             % (np.abs(img1 - img0).max() if img1 is not None else -1))


bt.run(main)
