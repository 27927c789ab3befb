"""Cycles twins of issue 25's textured-asset and glass scenes (bench/staged_bench.py and
bench/time_error.py write the Facet side), built directly in Blender — the Facet importer does
not import glTF shapes. As a module, `build(data, base, threads)` builds the twin into the
current Blender file (time_error/blender_worker.py's "twin": "direct" load); as a script it
renders at the given budgets and seeds and prints one line per render:
`CY <scene> <spp> <seed> <cpu seconds> <wall seconds> <exr>`.

  blender -b --factory-startup -noaudio --python bench/time_error/cycles_new_scenes.py -- \
      <scene.json> <out dir> <threads> <spp,spp,...> <seed,seed,...>

The twin: the camera (full vertical fov), the HDRI as the World's Environment Texture (Facet's
mapping is Blender's, FORMAT.md), the ground plane as a large quad with a Diffuse BSDF, the
checker disc as a 64-gon with a Diffuse BSDF whose colour is an Image-free checker in UV (same
cells as Facet's checker: 4 per unit of the disc's uv), spheres as smooth 128 x 64 UV spheres,
dielectrics as Glass BSDF (GGX, Roughness = sqrt(alpha), the same IOR), and the glTF file
through Blender's own glTF importer (Debian's importer needs numpy.bool, restored below), its
materials as that importer makes them (Principled BSDF; it also converts the clear coat that
Facet reports and leaves out). The two renderers therefore do not draw the same picture to the
last digit; each is measured against its own noise (RMSE between seeds), which is what the
time-to-error ratio needs.
"""
import json
import math
import os
import sys
import time

import bpy
import numpy
from mathutils import Matrix, Vector

if not hasattr(numpy, "bool"):
    numpy.bool = bool  # Debian's Blender 3.4 glTF importer still uses the removed alias


def look_at(position, target, up):
    f = (Vector(target) - Vector(position)).normalized()
    r = f.cross(Vector(up)).normalized()
    u = r.cross(f)
    m = Matrix.Identity(4)
    for i in range(3):
        m[i][0], m[i][1], m[i][2], m[i][3] = r[i], u[i], -f[i], position[i]
    return m


def material(desc):
    m = bpy.data.materials.new("m")
    m.use_nodes = True
    t = m.node_tree
    t.nodes.remove(t.nodes["Principled BSDF"])
    out = t.nodes["Material Output"]
    if desc["model"] == "dielectric":
        b = t.nodes.new("ShaderNodeBsdfGlass")
        b.distribution = 'GGX'
        b.inputs["IOR"].default_value = desc.get("ior", 1.5)
        b.inputs["Roughness"].default_value = math.sqrt(desc.get("alpha", 0.0))
    else:
        b = t.nodes.new("ShaderNodeBsdfDiffuse")
        r = desc.get("reflectance", 0.5)
        if isinstance(r, dict):
            c = r["checker"]
            ch = t.nodes.new("ShaderNodeTexChecker")
            uv = t.nodes.new("ShaderNodeTexCoord")
            t.links.new(uv.outputs["UV"], ch.inputs["Vector"])
            ch.inputs["Scale"].default_value = c["scale"]
            ch.inputs["Color1"].default_value = list(c["colors"][1]) + [1]
            ch.inputs["Color2"].default_value = list(c["colors"][0]) + [1]
            t.links.new(ch.outputs["Color"], b.inputs["Color"])
        else:
            r = [r] * 3 if not isinstance(r, list) else r
            b.inputs["Color"].default_value = list(r) + [1]
    t.links.new(b.outputs[0], out.inputs["Surface"])
    return m


def build(data, base, threads):
    """The twin of scene `data` (paths relative to `base`) in a new empty Blender file, with the
    comparison settings; returns the scene."""
    bpy.ops.wm.read_homefile(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'

    cam = data["camera"]
    cd = bpy.data.cameras.new("cam")
    cd.sensor_fit = 'VERTICAL'
    cd.angle_y = math.radians(cam["fov"])
    co = bpy.data.objects.new("cam", cd)
    co.matrix_world = look_at(cam["position"], cam["look_at"], cam["up"])
    scene.collection.objects.link(co)
    scene.camera = co
    scene.render.resolution_x, scene.render.resolution_y = cam["width"], cam["height"]
    scene.render.resolution_percentage = 100

    world = bpy.data.worlds.new("w")
    scene.world = world
    world.use_nodes = True
    nt = world.node_tree
    env = nt.nodes.new("ShaderNodeTexEnvironment")
    light = data["lights"][0]
    env.image = bpy.data.images.load(os.path.join(base, light["file"]))
    nt.links.new(env.outputs["Color"], nt.nodes["Background"].inputs["Color"])
    nt.nodes["Background"].inputs["Strength"].default_value = float(light.get("radiance", 1))

    mats = {k: material(v) for k, v in data["materials"].items()}
    for s in data["shapes"]:
        if s["type"] == "gltf":
            bpy.ops.import_scene.gltf(filepath=os.path.join(base, s["file"]))
            continue
        if s["type"] == "sphere":
            bpy.ops.mesh.primitive_uv_sphere_add(segments=128, ring_count=64, radius=s["radius"],
                                                 location=s["center"])
            bpy.ops.object.shade_smooth()
        elif s["type"] == "disc":
            bpy.ops.mesh.primitive_circle_add(vertices=64, radius=s["radius"], fill_type='NGON',
                                              location=s["center"])
        elif s["type"] == "plane":
            bpy.ops.mesh.primitive_plane_add(size=200, location=s["point"])
        o = bpy.context.active_object
        o.data.materials.append(mats[s["material"]])

    c = scene.cycles
    c.device = 'CPU'
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    bounces = int(data["render"].get("max_depth", 8)) - 1
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = bounces
    c.transparent_max_bounces = bounces
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.pixel_filter_type = 'BOX'
    c.filter_width = 1.0
    c.use_auto_tile = False
    scene.render.threads_mode = 'FIXED'
    scene.render.threads = threads
    scene.view_settings.view_transform = 'Standard'
    scene.render.image_settings.file_format = 'OPEN_EXR'
    scene.render.image_settings.color_depth = '32'
    return scene


def main():
    argv = sys.argv[sys.argv.index("--") + 1:]
    scene_path, out_dir, threads = argv[0], argv[1], int(argv[2])
    budgets = [int(x) for x in argv[3].split(",")]
    seeds = [int(x) for x in argv[4].split(",")]
    with open(scene_path) as f:
        data = json.load(f)
    name = os.path.splitext(os.path.basename(scene_path))[0]
    scene = build(data, os.path.dirname(os.path.abspath(scene_path)), threads)
    c = scene.cycles
    os.makedirs(out_dir, exist_ok=True)
    for spp in budgets:
        for seed in seeds:
            c.samples, c.seed = spp, seed
            path = os.path.join(out_dir, "cy_%s_%d_%d.exr" % (name, spp, seed))
            scene.render.filepath = path
            t0, p0 = time.time(), time.process_time()
            bpy.ops.render.render(write_still=True)
            print("CY %s %d %d %.3f %.3f %s" % (name, spp, seed, time.process_time() - p0,
                                               time.time() - t0, path), flush=True)


if __name__ == "__main__":
    main()
