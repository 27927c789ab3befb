"""Instances in the Blender exporter (facet_blender/export.py) -> the core's prototypes and
`instance` shapes, in headless Blender.

The scene: a collection of a smooth textured UV sphere (UVs) and a cube with two material
slots, placed by 6 Empties (Instance Collection; turned, scaled, one mirrored); a cone placed
on the 9 points of a grid by geometry nodes (Instance on Points); two linked duplicates of one
mesh; an emitting quad placed twice by a collection instance; a ground plane placed once.

1. Export counts: each mesh placed more than once is one prototype (sphere, cube with its two
   slots, cone, the duplicates' mesh: 4 prototypes, 5 shapes) with one `instance` per
   placement (6 + 6 + 9 + 2 = 23); the ground stays a mesh; the emitting quad is expanded
   into two meshes and reported (the core's prototypes cannot emit); the prototype arrays are
   those of the expanded export. With instancing off the same scene is all mesh shapes.
2. Image: the instanced export and the expanded one rendered by the core with the same
   settings and seed (the `direct` integrator: camera hits, shading, light samples and shadow
   rays through the instances; 16 spp, 96 x 72). Hits differ only by float round-off (Embree's
   float instance transforms: the core's Instancing tests measure 2e-5 in position), so every
   pixel takes the same samples and agrees to ~1e-6, except where a round-off moves a camera
   hit across an edge. Tolerance: mean |difference| < 1e-4 of the image mean (measured
   8.8e-6), 99.5% of pixels within 1e-3 relative (measured 99.94%). With `path` (4 bounces) a
   round-off at a bounce changes the rest of that path: 1.6% of pixels then differ by sample
   noise (mean |difference| 1.1e-4 of the mean), which is why this compares direct light.
   Ability to fail: the expanded scene with one placement left out (one cone) differs by
   5.5e-3 of the mean, 55x the tolerance (checked here: > 10x).
"""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402

SIZE = (96, 72)
SPP = 16
INTEGRATOR = "direct"


def diffuse(name, rgb, checker=False):
    mat, nt, out = bt.new_material(name)
    d = nt.nodes.new("ShaderNodeBsdfDiffuse")
    d.inputs["Color"].default_value = tuple(rgb) + (1.0,)
    if checker:
        ch = nt.nodes.new("ShaderNodeTexChecker")
        ch.inputs["Color1"].default_value = tuple(rgb) + (1.0,)
        ch.inputs["Color2"].default_value = (0.9, 0.9, 0.9, 1.0)
        ch.inputs["Scale"].default_value = 8.0
        uv = nt.nodes.new("ShaderNodeUVMap")
        nt.links.new(uv.outputs["UV"], ch.inputs["Vector"])
        nt.links.new(ch.outputs["Color"], d.inputs["Color"])
    nt.links.new(d.outputs[0], out.inputs["Surface"])
    return mat


def emitter(name):
    mat, nt, out = bt.new_material(name)
    e = nt.nodes.new("ShaderNodeEmission")
    e.inputs["Strength"].default_value = 2.0
    nt.links.new(e.outputs[0], out.inputs["Surface"])
    return mat


def collection_of(name, objs):
    coll = bpy.data.collections.new(name)
    for ob in objs:
        for c in ob.users_collection:
            c.objects.unlink(ob)
        coll.objects.link(ob)
    return coll


def place(scene, coll, name, loc, rot_z=0.0, scale=(1.0, 1.0, 1.0)):
    e = bpy.data.objects.new(name, None)
    e.instance_type = 'COLLECTION'
    e.instance_collection = coll
    e.location = loc
    e.rotation_euler = (0.0, 0.0, rot_z)
    e.scale = scale
    scene.collection.objects.link(e)
    return e


def build_scene():
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = 'FACET'
    scene.render.resolution_x, scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    world = bpy.data.worlds.new("sky")
    world.use_nodes = False
    world.color = (0.3, 0.35, 0.4)
    scene.world = world
    # the collection: a smooth textured sphere and a two-slot cube
    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0, 0, 0.5), segments=24,
                                         ring_count=12)
    sph = bpy.context.object
    bpy.ops.object.shade_smooth()
    sph.data.materials.append(diffuse("checker", (0.8, 0.2, 0.1), checker=True))
    bpy.ops.mesh.primitive_cube_add(size=0.4, location=(0.6, 0, 0.2))
    cube = bpy.context.object
    cube.data.materials.append(diffuse("blue", (0.1, 0.2, 0.8)))
    cube.data.materials.append(diffuse("green", (0.1, 0.7, 0.2)))
    idx = np.zeros(len(cube.data.polygons), np.int32)
    idx[::2] = 1
    cube.data.polygons.foreach_set("material_index", idx)
    coll = collection_of("group", [sph, cube])
    for i in range(6):
        s = 0.8 + 0.1 * i
        scale = (-s, s, s) if i == 4 else (s, s, s)  # one mirrored placement
        place(scene, coll, "group %d" % i, ((i % 3 - 1) * 2.0, (i // 3) * 2.0, 0.0),
              math.radians(35 * i), scale)
    # geometry nodes: a cone on each point of a 3 x 3 grid
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=2, y_subdivisions=2, size=4.0,
                                    location=(0.0, -3.0, 0.0))
    grid = bpy.context.object
    grid.name = "cone field"
    grid.data.materials.append(diffuse("cone", (0.7, 0.7, 0.2)))
    ng = bpy.data.node_groups.new("cones", 'GeometryNodeTree')
    ng.inputs.new('NodeSocketGeometry', "Geometry")
    ng.outputs.new('NodeSocketGeometry', "Geometry")
    gi, go = ng.nodes.new('NodeGroupInput'), ng.nodes.new('NodeGroupOutput')
    iop = ng.nodes.new('GeometryNodeInstanceOnPoints')
    cone = ng.nodes.new('GeometryNodeMeshCone')
    cone.inputs["Radius Top"].default_value = 0.0
    cone.inputs["Radius Bottom"].default_value = 0.3
    cone.inputs["Depth"].default_value = 0.8
    setmat = ng.nodes.new('GeometryNodeSetMaterial')
    setmat.inputs["Material"].default_value = bpy.data.materials["cone"]
    ng.links.new(cone.outputs["Mesh"], setmat.inputs["Geometry"])
    ng.links.new(gi.outputs[0], iop.inputs["Points"])
    ng.links.new(setmat.outputs[0], iop.inputs["Instance"])
    ng.links.new(iop.outputs[0], go.inputs[0])
    grid.modifiers.new("cones", 'NODES').node_group = ng
    # linked duplicates
    bpy.ops.mesh.primitive_ico_sphere_add(radius=0.4, location=(3.5, 0.0, 0.4))
    dup = bpy.context.object
    dup.name = "dup A"
    dup.data.materials.append(diffuse("grey", (0.6, 0.6, 0.6)))
    dup2 = bpy.data.objects.new("dup B", dup.data)
    dup2.location = (3.5, 1.5, 0.6)
    dup2.rotation_euler = (0.3, 0.0, 0.5)
    scene.collection.objects.link(dup2)
    # an emitting quad placed twice
    bpy.ops.mesh.primitive_plane_add(size=0.6, location=(0.0, 0.0, 2.5))
    lamp = bpy.context.object
    lamp.rotation_euler = (math.pi, 0.0, 0.0)  # facing down
    lamp.data.materials.append(emitter("glow"))
    lcoll = collection_of("lamps", [lamp])
    place(scene, lcoll, "lamp 0", (-1.5, 0.0, 0.0))
    place(scene, lcoll, "lamp 1", (1.5, 1.0, 0.0))
    # the ground, placed once
    bpy.ops.mesh.primitive_plane_add(size=20.0)
    bpy.context.object.name = "ground"
    bpy.context.object.data.materials.append(diffuse("ground", (0.5, 0.5, 0.5)))
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", 'SUN'))
    sun.data.energy = 3.0
    sun.data.angle = 0.0
    sun.rotation_euler = (math.radians(40), 0.0, math.radians(30))
    scene.collection.objects.link(sun)
    cam = bpy.data.objects.new("cam", bpy.data.cameras.new("cam"))
    cam.location = (0.0, -10.0, 7.0)
    cam.rotation_euler = (math.radians(58), 0.0, 0.0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    return scene


def kinds(data):
    out = {}
    for s in data["shapes"]:
        out[s["type"]] = out.get(s["type"], 0) + 1
    return out


def render(data):
    from facet_blender import native
    data = dict(data)
    data["render"] = dict(data["render"], spp=SPP, seed=3, integrator=INTEGRATOR, max_depth=4)
    fscene, warnings = native.build(data)
    s = native.Session(fscene, spp=SPP, seed=3, max_depth=4, integrator=INTEGRATOR, threads=2)
    s.render(lambda *a: True)
    return s.image().astype(np.float64), warnings


def main():
    bt.enable_addon()
    from facet_blender import export
    build_scene()
    dg = bpy.context.evaluated_depsgraph_get()
    inst, p_inst = export.export_scene(dg, mesh_cache={})
    flat, p_flat = export.export_scene(dg, mesh_cache={}, instancing=False)
    protos = inst.get("prototypes", {})
    print("instanced: %s, prototypes %s; expanded: %s" % (
        kinds(inst), {k: len(v) for k, v in protos.items()}, kinds(flat)))
    print("reports:", p_inst)
    bt.check(len(protos) == 4 and sum(len(v) for v in protos.values()) == 5,
             "4 prototypes (sphere, two-slot cube, cone, duplicates' mesh), 5 shapes")
    bt.check(kinds(inst) == {"instance": 23, "mesh": 3},
             "23 instances; the ground and the 2 expanded emitters are meshes (%s)"
             % kinds(inst))
    bt.check("flattened" not in "".join(p_flat) and "prototypes" not in flat,
             "instancing off: no prototypes")
    bt.check(kinds(flat) == {"mesh": 1 + 6 * 3 + 9 + 2 + 2},
             "instancing off: every placement a mesh shape per slot (%s)" % kinds(flat))
    emit = [p for p in p_inst if "placed 2 times and emits light" in p]
    bt.check(len(emit) == 1 and "Plane" in emit[0], "the emitting quad is expanded and reported")
    bt.check(not any("empty mesh" in p for p in p_inst), "no empty-mesh report (%s)" % p_inst)
    sph = next(v for k, v in protos.items() if k.startswith("Sphere"))[0]
    bt.check(sph.get("uvs") is not None and sph.get("normals") is not None,
             "the textured smooth sphere's prototype has its UVs and normals")
    flat_sph = next(s for s in flat["shapes"] if s["name"].startswith("Sphere"))
    bt.check(np.array_equal(sph["positions"], flat_sph["positions"]) and
             np.array_equal(sph["uvs"], flat_sph["uvs"]),
             "the prototype's arrays are the expanded meshes'")
    img_i, w_i = render(inst)
    img_f, w_f = render(flat)
    mean = img_f.mean()
    d = np.abs(img_i - img_f)
    rel = d / np.maximum(img_f, 1e-3)
    print("instanced vs expanded: image mean %.5f, mean |diff| %.3g, max %.3g, pixels within "
          "1e-3 relative %.4f" % (mean, d.mean(), d.max(), (rel.max(axis=2) <= 1e-3).mean()))
    bt.check(d.mean() < 1e-4 * mean, "mean |instanced - expanded| %.3g < 1e-4 x mean"
             % d.mean())
    bt.check((rel.max(axis=2) <= 1e-3).mean() >= 0.995, "99.5% of pixels within 1e-3")
    # ability to fail: one cone fewer in the expanded scene
    cone_idx = [i for i, s in enumerate(flat["shapes"]) if s["name"].startswith("cone field")]
    fewer = dict(flat, shapes=[s for i, s in enumerate(flat["shapes"]) if i != cone_idx[4]])
    img_x, _ = render(fewer)
    dx = np.abs(img_x - img_f).mean()
    print("one cone left out: mean |diff| %.3g" % dx)
    bt.check(dx > 10 * 1e-4 * mean, "a missing placement would fail the test (%.3g)" % dx)


bt.run(main)
