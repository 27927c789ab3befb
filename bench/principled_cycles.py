"""Cycles reference numbers for Facet's `principled` model (docs/principled.md).

A sphere of radius 1 under a constant white environment (background 1) is rendered by Blender
3.4's Cycles for a grid of Principled BSDF parameters; the mean radiance of the pixels whose
centres lie within 0.9 radii of the sphere's centre (orthographic view, so the mask is exact
and the same in Facet) is written, per channel, with its standard error from independent
seeds, to tests/render/principled_cycles.json. tests/render/test_principled_render.cpp renders
the same scene with Facet and compares.

Run (about 2 minutes on 2 cores):
    blender -b --factory-startup --python bench/principled_cycles.py -- \
        tests/render/principled_cycles.json

Cycles settings: no clamping, Filter Glossy 0, caustics on, 64 bounces of every kind, no
adaptive sampling, no denoising; the sphere is an icosphere (7 subdivisions, smooth shading).
"""

import json
import math
import os
import sys
import tempfile

import bpy

SIZE = 48  # pixels per side
SCALE = 2.4  # orthographic scale: the view spans [-1.2, 1.2]^2
MASK_RADIUS = 0.9
SPP = 256
SEEDS = 4
BASE = [0.8, 0.4, 0.2]

# name -> Principled inputs (Facet keys; Blender names by BLENDER_NAMES)
GRID = {}
for r in (0.2, 0.5, 0.9):
    GRID[f"dielectric_r{r}"] = {"base_color": BASE, "roughness": r}
    GRID[f"metal_r{r}"] = {"base_color": BASE, "roughness": r, "metallic": 1.0}
GRID["no_specular"] = {"base_color": BASE, "roughness": 0.5, "specular": 0.0}
GRID["metal_no_specular"] = {"base_color": BASE, "roughness": 0.5, "metallic": 1.0,
                             "specular": 0.0}
GRID["specular_tint"] = {"base_color": BASE, "roughness": 0.3, "specular_tint": 1.0}
GRID["sheen"] = {"base_color": BASE, "roughness": 0.5, "sheen": 1.0, "sheen_tint": 0.5}
GRID["clearcoat_0.03"] = {"base_color": BASE, "roughness": 0.5, "clearcoat": 1.0,
                          "clearcoat_roughness": 0.03}
GRID["clearcoat_0.3"] = {"base_color": BASE, "roughness": 0.5, "clearcoat": 1.0,
                         "clearcoat_roughness": 0.3}
GRID["anisotropic"] = {"base_color": BASE, "roughness": 0.5, "metallic": 1.0,
                       "anisotropic": 0.8}
GRID["transmission_r0.2"] = {"base_color": BASE, "roughness": 0.2, "transmission": 1.0}
GRID["transmission_r0.5"] = {"base_color": BASE, "roughness": 0.5, "transmission": 1.0}
GRID["half_transmission"] = {"base_color": BASE, "roughness": 0.5, "transmission": 0.5,
                             "transmission_roughness": 0.3}

BLENDER_NAMES = {
    "base_color": "Base Color", "roughness": "Roughness", "metallic": "Metallic",
    "specular": "Specular", "specular_tint": "Specular Tint", "sheen": "Sheen",
    "sheen_tint": "Sheen Tint", "clearcoat": "Clearcoat",
    "clearcoat_roughness": "Clearcoat Roughness", "anisotropic": "Anisotropic",
    "transmission": "Transmission", "transmission_roughness": "Transmission Roughness",
    "ior": "IOR",
}


def setup_scene():
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=7, radius=1.0, location=(0, 0, 0))
    sphere = bpy.context.active_object
    bpy.ops.object.shade_smooth()
    cam_data = bpy.data.cameras.new("cam")
    cam_data.type = "ORTHO"
    cam_data.ortho_scale = SCALE
    cam = bpy.data.objects.new("cam", cam_data)
    cam.location = (0, 0, 5)
    cam.rotation_euler = (0, 0, 0)
    scene.collection.objects.link(cam)
    scene.camera = cam
    world = bpy.data.worlds.new("white")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (1, 1, 1, 1)
    bg.inputs["Strength"].default_value = 1.0
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.render.resolution_x = scene.render.resolution_y = SIZE
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    c = scene.cycles
    c.device = "CPU"
    c.samples = SPP
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.caustics_reflective = True
    c.caustics_refractive = True
    for key in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces",
                "volume_bounces", "transparent_max_bounces"):
        setattr(c, key, 64)
    scene.render.threads_mode = "FIXED"
    scene.render.threads = 2
    return scene, sphere


def set_material(sphere, params):
    mat = bpy.data.materials.new("p")
    mat.use_nodes = True
    node = mat.node_tree.nodes["Principled BSDF"]
    for key, value in params.items():
        if isinstance(value, list):
            value = (*value, 1.0)
        node.inputs[BLENDER_NAMES[key]].default_value = value
    sphere.data.materials.clear()
    sphere.data.materials.append(mat)


def masked_mean(path):
    img = bpy.data.images.load(path)
    px = list(img.pixels)
    bpy.data.images.remove(img)
    total = [0.0, 0.0, 0.0]
    n = 0
    for j in range(SIZE):
        for i in range(SIZE):
            x = ((i + 0.5) / SIZE - 0.5) * SCALE
            y = ((j + 0.5) / SIZE - 0.5) * SCALE
            if math.hypot(x, y) >= MASK_RADIUS:
                continue
            k = 4 * (j * SIZE + i)
            for ch in range(3):
                total[ch] += px[k + ch]
            n += 1
    return [t / n for t in total], n


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene, sphere = setup_scene()
    tmp = tempfile.mkdtemp()
    points = []
    for name, params in GRID.items():
        set_material(sphere, params)
        means = []
        for seed in range(SEEDS):
            scene.cycles.seed = seed
            path = os.path.join(tmp, f"{name}_{seed}.exr")
            scene.render.filepath = path
            bpy.ops.render.render(write_still=True)
            m, n = masked_mean(path)
            means.append(m)
        mean = [sum(m[c] for m in means) / SEEDS for c in range(3)]
        se = [math.sqrt(sum((m[c] - mean[c]) ** 2 for m in means) / (SEEDS - 1) / SEEDS)
              for c in range(3)]
        print(f"{name}: mean {mean} se {se} ({n} pixels)", flush=True)
        points.append({"name": name, "params": params, "mean": mean, "se": se})
    result = {
        "generator": "bench/principled_cycles.py",
        "blender": bpy.app.version_string,
        "scene": {"size": SIZE, "ortho_scale": SCALE, "mask_radius": MASK_RADIUS,
                  "sphere": "icosphere, 7 subdivisions, radius 1, smooth", "environment": 1.0,
                  "spp": SPP, "seeds": SEEDS, "max_bounces": 64},
        "points": points,
    }
    with open(out, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")


main()
