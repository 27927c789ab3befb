"""Facet against Cycles (which nobody here wrote) on the Cornell box (scenes/cornell_box.json,
imported into Blender; 128 x 128). Cycles renders the same Blender scene from Cycles nodes:
Diffuse BSDF with each material's reflectance, an Emission shader (strength 1) on the light
quad; box pixel filter 1 px, no clamping, no denoising, adaptive sampling off, light threshold
0, fixed seeds, 64 bounces (Facet: max_depth 64), 32-bit EXR.

Tolerance from the measured noise of both: each renderer renders twice (seeds 1 and 2), the
per-pixel variance of one render is estimated as (A - B)^2 / 2, and the mean of the two renders
is compared over 8 x 8 blocks of 16 x 16 pixels per channel: z = (facet - cycles) / sqrt(var),
var the sum of both renderers' block-mean variances. The test requires |z| < 5 for all 192
block-channels (a false failure has probability ~1e-4 with normal errors) and prints the
image-mean ratio per channel. Known difference, below the noise here: Cycles' mesh lights emit
from both sides, Facet's area lights from the front only (FORMAT.md); the back of the light
faces the ceiling 0.1 mm away.

Found difference beyond the noise: the pixels the light's edges cross (the light is 17.2 times
brighter than its surroundings, so a sub-pixel shift of an edge is far above the noise, and the
seed-to-seed noise of a straight edge's coverage is tiny with stratified samples). They are
left out of the block test and decided analytically instead: the light's near and far edges
project (FORMAT.md's camera) to film rows y = 15.8934 and 20.3556 at 128 x 128, so rows 15
and 20 are covered 0.1066 and 0.3556. Facet's measured coverage matches (within 0.005 = about
one sample of 256); Cycles' is printed (0.119 and 0.352 here: its light edges sit ~0.01 px
higher)."""
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import blender_test as bt  # noqa: E402

SPP = 256
RES = 128
BLOCK = 16
Z_MAX = 5.0


def cycles_materials():
    """Cycles node trees equivalent to the imported Facet materials (lambert reflectance)."""
    for mat in bpy.data.materials:
        fs = mat.facet
        rho = getattr(fs, "lambert__reflectance")
        bt.single_shader(mat, "ShaderNodeBsdfDiffuse",
                         {"Color": (rho[0], rho[1], rho[2], 1.0), "Roughness": 0.0})
    import json
    light = next(o for o in bpy.data.objects if "facet_shape" in o
                 and any(json.loads(o["facet_shape"]).get("emission") or []))
    em = json.loads(light["facet_shape"])["emission"]
    mat = bpy.data.materials.new("light (Cycles)")
    bt.single_shader(mat, "ShaderNodeEmission",
                     {"Color": (em[0], em[1], em[2], 1.0), "Strength": 1.0})
    light.data.materials.append(mat)


def cycles_settings(scene):
    c = scene.cycles
    c.device = 'CPU'
    c.samples = SPP
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.max_bounces = c.diffuse_bounces = 64
    c.glossy_bounces = c.transmission_bounces = c.volume_bounces = c.transparent_max_bounces = 64
    c.caustics_reflective = c.caustics_refractive = True
    c.blur_glossy = 0.0
    c.pixel_filter_type = 'BOX'
    c.filter_width = 1.0
    c.use_animated_seed = False
    c.film_exposure = 1.0
    scene.render.film_transparent = False


def render_with(engine, seed, out):
    scene = bpy.context.scene
    scene.render.engine = engine
    if engine == 'CYCLES':
        scene.cycles.seed = seed
    else:
        scene.facet.seed = seed
    path = os.path.join(out, "cornell_%s_%d.exr" % (engine.lower(), seed))
    t0 = time.perf_counter()
    bt.render(scene, path)
    dt = time.perf_counter() - t0
    return bt.load_exr(path).astype(np.float64), dt


def block_means(img):
    h, w, c = img.shape
    return img.reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, c).mean(axis=(1, 3))


def main():
    cli, scene_path, out = bt.args()[:3]
    bt.enable_addon()
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.import_scene.facet(filepath=scene_path)
    scene = bpy.context.scene
    scene.render.resolution_x = scene.render.resolution_y = RES
    scene.facet.spp = SPP
    scene.facet.max_depth = 64
    cycles_materials()
    cycles_settings(scene)
    imgs, times = {}, {}
    for engine in ('FACET', 'CYCLES'):
        a, ta = render_with(engine, 1, out)
        b, tb = render_with(engine, 2, out)
        imgs[engine] = (a, b)
        times[engine] = ta + tb
    # Pixels partly covered by the light (decided analytically below) are left out.
    light = 17.1969
    edge = np.zeros(imgs['FACET'][0].shape[:2], bool)
    for a, b in imgs.values():
        for img in (a, b):
            edge |= (img[..., 0] > 1.0) & (img[..., 0] < light - 0.5)
    keep = (~edge)[..., None].astype(np.float64)
    h, w, c = imgs['FACET'][0].shape

    def block_sum(x):
        return x.reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK, c).sum(axis=(1, 3))
    n = block_sum(np.broadcast_to(keep, (h, w, c)).copy())
    var_blocks = 0.0
    means = {}
    for engine, (a, b) in imgs.items():
        # variance of one render per pixel ~ (a - b)^2 / 2; of the mean of two: half that;
        # of a block mean of n pixels: the sum over the block / n^2.
        var_blocks = var_blocks + block_sum(0.25 * (a - b) ** 2 * keep) / n ** 2
        means[engine] = block_sum(0.5 * (a + b) * keep) / n
    z = (means['FACET'] - means['CYCLES']) / np.sqrt(np.maximum(var_blocks, 1e-30))
    print("left out %d light-edge pixels of %d" % (edge.sum(), edge.size))
    # The light's edge rows, analytically: film y = (1 - s_y / tan_y) h / 2 (FORMAT.md).
    import math
    tan_y = math.tan(math.radians(39.307648) / 2)
    coverage = {}
    for z_edge, top in ((227.0, True), (332.0, False)):
        y = (1.0 - (548.7 - 273.0) / (z_edge + 800.0) / tan_y) * RES / 2
        row = int(y)
        exact = (row + 1 - y) if top else (y - row)
        cols = slice(58, 70)  # inside the light's columns (53..74)
        out_row = row - 1 if top else row + 1
        for engine, (a, b) in imgs.items():
            m = 0.5 * (a + b)
            bg = m[out_row, cols, 0].mean()
            cov = (m[row, cols, 0].mean() - bg) / (light - bg)
            coverage.setdefault(engine, []).append(cov)
        print("light edge row %d: exact coverage %.4f, Facet %.4f, Cycles %.4f"
              % (row, exact, coverage['FACET'][-1], coverage['CYCLES'][-1]))
        bt.check(abs(coverage['FACET'][-1] - exact) < 0.005,
                 "Facet's light edge in row %d is where the camera model puts it" % row)
    ratio = [float(0.5 * (imgs['FACET'][0] + imgs['FACET'][1])[..., k].mean()
                   / (0.5 * (imgs['CYCLES'][0] + imgs['CYCLES'][1])[..., k].mean()))
             for k in range(3)]
    print("Facet/Cycles image-mean ratio per channel: %.4f %.4f %.4f" % tuple(ratio))
    print("max |z| over %d block-channels: %.2f (mean z %.2f); time Facet %.2f s, Cycles %.2f s"
          " (2 renders each, %d spp, %dx%d)" % (z.size, np.abs(z).max(), z.mean(),
                                               times['FACET'], times['CYCLES'], SPP, RES, RES))
    bt.check(np.abs(z).max() < Z_MAX, "Facet and Cycles agree within the noise (|z| < %g)" % Z_MAX)


bt.run(main)
