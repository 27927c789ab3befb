"""Cycles 3.4 reference numbers for Multiscatter GGX (docs/principled.md, "Multiscatter GGX").

Blender 3.4's Multiscatter GGX is Heitz et al. 2016's stochastic random walk on the microsurface
(intern/cycles/kernel/closure/bsdf_microfacet_multi.h), for the Glossy, Anisotropic, Glass and
Principled BSDF nodes. Facet's `principled` option `"distribution": "multi_ggx"` and the other
models' `energy_compensation` restore the same energy deterministically (Kulla & Conty 2017);
these renders decide how close the two are. Each point is rendered with the distribution
Multiscatter GGX and with GGX, in two scenes:

- "env": a sphere of radius 1 under a constant white environment (background 1), orthographic
  view, as bench/principled_cycles.py. A convex sphere sees only the environment, so a pixel is
  the directional albedo at its view direction: a white rough metal (metallic 1, base colour
  1: F = 1) must reflect everything with a multiple-scattering model (the white furnace).
- "sun": the same sphere lit only by a sun lamp behind the camera (strength 1, angle 0, black
  world): a pixel at distance rho from the centre is f(w, w) cos(theta) with cos(theta) =
  sqrt(1 - rho^2), the lobe's back-scattering (its shape, not only its energy).

For each render the mean of the pixels whose centres lie within 0.9 radii of the centre and a
radial profile (mean per ring of pixel centres, edges RINGS) are written, per channel, with the
standard error over independent seeds, to tests/render/multiscatter_cycles.json.

Run (about 15 minutes on 2 idle cores):
    blender -b --factory-startup -noaudio --python bench/multiscatter_cycles.py -- \
        tests/render/multiscatter_cycles.json

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
import cycles_sphere  # noqa: E402  (the scene and Cycles' settings, shared with principled_cycles.py)
from cycles_sphere import MASK_RADIUS, SCALE, SIZE  # noqa: E402

RINGS = [0.0, 0.3, 0.5, 0.65, 0.8, 0.9]
SPP = 256
SEEDS = 4
WHITE = [1.0, 1.0, 1.0]
BASE = [0.8, 0.4, 0.2]
DISTRIBUTIONS = ("MULTI_GGX", "GGX")

# name -> (scene, node type, inputs by Facet key); each is rendered with both DISTRIBUTIONS.
GRID = {}
for r in (0.2, 0.5, 0.8, 1.0):
    GRID[f"metal_white_r{r}"] = ("env", "principled",
                                 {"base_color": WHITE, "metallic": 1.0, "roughness": r})
    GRID[f"dielectric_r{r}"] = ("env", "principled", {"base_color": BASE, "roughness": r})
for r in (0.5, 1.0):
    GRID[f"metal_color_r{r}"] = ("env", "principled",
                                 {"base_color": BASE, "metallic": 1.0, "roughness": r})
    GRID[f"glossy_white_r{r}"] = ("env", "glossy", {"color": WHITE, "roughness": r})
    GRID[f"glass_white_r{r}"] = ("env", "glass", {"color": WHITE, "roughness": r, "ior": 1.45})
    GRID[f"transmission_r{r}"] = ("env", "principled",
                                  {"base_color": WHITE, "transmission": 1.0, "roughness": r})
GRID["anisotropic_white_r0.5"] = ("env", "principled", {"base_color": WHITE, "metallic": 1.0,
                                                        "roughness": 0.5, "anisotropic": 0.8})
for r in (0.5, 1.0):
    GRID[f"sun_metal_white_r{r}"] = ("sun", "principled",
                                     {"base_color": WHITE, "metallic": 1.0, "roughness": r})
GRID["sun_metal_color_r0.5"] = ("sun", "principled",
                                {"base_color": BASE, "metallic": 1.0, "roughness": 0.5})
GRID["sun_glossy_white_r0.5"] = ("sun", "glossy", {"color": WHITE, "roughness": 0.5})

NODES = {"principled": "ShaderNodeBsdfPrincipled", "glossy": "ShaderNodeBsdfGlossy",
         "glass": "ShaderNodeBsdfGlass"}
def setup_scene():
    """The shared sphere scene plus a sun lamp (not yet linked: set_lighting links it)."""
    scene, sphere, world = cycles_sphere.setup_scene(SPP)
    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 1.0  # irradiance normal to the sun's direction
    sun_data.angle = 0.0
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = (0, 0, 0)  # shines along -z: from behind the camera
    return scene, sphere, sun, world


def set_lighting(scene, sun, world, kind):
    if kind == "env":
        cycles_sphere.set_background(world, 1.0)
        if sun.name in scene.collection.objects:
            scene.collection.objects.unlink(sun)
    else:
        cycles_sphere.set_background(world, 0.0)
        if sun.name not in scene.collection.objects:
            scene.collection.objects.link(sun)


def set_material(sphere, node_kind, params, distribution):
    mat = bpy.data.materials.new("m")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    for n in list(nodes):
        if n.bl_idname != "ShaderNodeOutputMaterial":
            nodes.remove(n)
    node = nodes.new(NODES[node_kind])
    node.distribution = distribution
    cycles_sphere.set_inputs(node, params)
    out = nodes["Material Output"]
    mat.node_tree.links.new(node.outputs[0], out.inputs["Surface"])
    sphere.data.materials.clear()
    sphere.data.materials.append(mat)


def statistics(path):
    """Mean over the mask and per ring, per channel."""
    mask = [0.0] * 3
    n_mask = 0
    rings = [[0.0] * 3 for _ in RINGS[1:]]
    n_rings = [0] * (len(RINGS) - 1)
    for rho, rgb in cycles_sphere.pixels(path):
        if rho < MASK_RADIUS:
            for ch in range(3):
                mask[ch] += rgb[ch]
            n_mask += 1
        for b in range(len(RINGS) - 1):
            if RINGS[b] <= rho < RINGS[b + 1]:
                for ch in range(3):
                    rings[b][ch] += rgb[ch]
                n_rings[b] += 1
    return ([m / n_mask for m in mask],
            [[v / n for v in ring] for ring, n in zip(rings, n_rings)])


def mean_se(values):
    """values: list over seeds of equal-shaped nested lists -> (mean, se) of the same shape."""
    if isinstance(values[0], list):
        pairs = [mean_se([v[k] for v in values]) for k in range(len(values[0]))]
        return [p[0] for p in pairs], [p[1] for p in pairs]
    n = len(values)
    m = sum(values) / n
    return m, math.sqrt(sum((v - m) ** 2 for v in values) / (n - 1) / n)


def main():
    out = sys.argv[sys.argv.index("--") + 1]
    only = sys.argv[sys.argv.index("--") + 2:]  # optional point names
    scene, sphere, sun, world = setup_scene()
    tmp = tempfile.mkdtemp()
    points = []
    for name, (kind, node_kind, params) in GRID.items():
        if only and name not in only:
            continue
        set_lighting(scene, sun, world, kind)
        for dist in DISTRIBUTIONS:
            set_material(sphere, node_kind, params, dist)
            means, rings = [], []
            for seed in range(SEEDS):
                scene.cycles.seed = seed
                path = os.path.join(tmp, f"{name}_{dist}_{seed}.exr")
                scene.render.filepath = path
                bpy.ops.render.render(write_still=True)
                m, r = statistics(path)
                means.append(m)
                rings.append(r)
            mean, se = mean_se(means)
            ring, ring_se = mean_se(rings)
            print(f"{name} {dist}: mean {mean} se {se}", flush=True)
            points.append({"name": name, "scene": kind, "node": node_kind,
                           "distribution": dist, "params": params, "mean": mean, "se": se,
                           "rings": ring, "rings_se": ring_se})
            with open(out, "w") as f:  # after every point: a partial run keeps its numbers
                json.dump({
                    "generator": "bench/multiscatter_cycles.py",
                    "blender": bpy.app.version_string,
                    "scene": {"size": SIZE, "ortho_scale": SCALE, "mask_radius": MASK_RADIUS,
                              "rings": RINGS,
                              "sphere": cycles_sphere.SPHERE,
                              "environment": 1.0, "sun": {"strength": 1.0, "angle": 0.0,
                                                          "direction": [0, 0, -1]},
                              "spp": SPP, "seeds": SEEDS, "max_bounces": 64},
                    "points": points,
                }, f, indent=1)
                f.write("\n")


main()
