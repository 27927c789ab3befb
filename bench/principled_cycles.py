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

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_sphere  # noqa: E402  (the scene and Cycles' settings, shared with multiscatter_cycles.py)
from cycles_sphere import MASK_RADIUS, SCALE, SIZE  # noqa: E402

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

def set_material(sphere, params):
    mat = bpy.data.materials.new("p")
    mat.use_nodes = True
    cycles_sphere.set_inputs(mat.node_tree.nodes["Principled BSDF"], params)
    sphere.data.materials.clear()
    sphere.data.materials.append(mat)


def masked_mean(path):
    total = [0.0, 0.0, 0.0]
    n = 0
    for rho, rgb in cycles_sphere.pixels(path):
        if rho >= MASK_RADIUS:
            continue
        for ch in range(3):
            total[ch] += rgb[ch]
        n += 1
    return [t / n for t in total], n


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    scene, sphere, world = cycles_sphere.setup_scene(SPP)
    cycles_sphere.set_background(world, 1.0)
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
                  "sphere": cycles_sphere.SPHERE, "environment": 1.0,
                  "spp": SPP, "seeds": SEEDS, "max_bounces": 64},
        "points": points,
    }
    with open(out, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")


main()
