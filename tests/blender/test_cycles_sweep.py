"""A diffuse / glossy material sweep against Cycles and against the analytic BRDF.

Ten exact spheres (radius 1, 2 rows of 5) with lambert, mirror (Fresnel none, dielectric 1.5,
Schlick 0.3), ggx and beckmann (alpha 0.05, 0.3, 0.6, Fresnel none); Cycles renders them from
Cycles nodes made by cycles_scene.convert(exact=False): Diffuse BSDF, Glossy Sharp (with a
Fresnel node / Layer Weight chain) and Glossy GGX / Beckmann with roughness sqrt(alpha) (Cycles
squares it), as smooth 256 x 128 UV spheres. Direct lighting only (Facet max_depth 1 = Cycles 0
bounces), 160 x 64.

A. A sun (irradiance E, no environment): every lit pixel is exactly f(wi, wo) E cos(theta_i)
   (a delta light: no light-sampling noise, only the pixel's antialiasing). The analytic image
   averages 8 x 8 points per pixel on the exact spheres, with shadows from the other spheres
   traced exactly. Each renderer is compared with its own model's f:
   - Facet: D G2 F / (4 cos_i cos_o) with the exact height-correlated Smith
     G2 = 1 / (1 + L(i) + L(o)) (GGX L = (sqrt(1 + a^2 tan^2) - 1) / 2; Beckmann
     L = (erf(c) - 1) / 2 + exp(-c^2) / (2 c sqrt(pi)), c = 1 / (a tan));
   - Cycles 3.4: the separable G1(i) G1(o), G1 = 1 / (1 + L) for GGX and Walter et al.'s
     rational approximation for Beckmann ((3.535 c + 2.181 c^2) / (1 + 2.276 c + 2.577 c^2),
     1 for c >= 1.6);
   and Facet against Cycles with the two models' difference subtracted. Then Facet renders
   Cycles' node trees themselves (material source "Shader Nodes": the addon's conversion of
   Diffuse and Glossy GGX / Beckmann nodes) and must match the same analytic image.
B. A constant environment (radiance 1, no sun): lambert and the mirrors, whose models are the
   same in both renderers, Facet against Cycles; the mirrors also against the analytic
   L R F(cos theta) where the reflected ray escapes (pixels whose reflected ray hits another
   sphere are left out), averaged over 24 x 24 points per pixel.
Pixels within one pixel of a discontinuity (sphere silhouettes, shadow edges, the edges of a
mirror's reflections of the other spheres) and (A) with cos(theta_i) < 0.1 are left out: a
discontinuity's sub-pixel position is nearly the same in both seeds of a stratified sampler,
so the seed pair does not measure its error (and Cycles' spheres are polygons there).
Tolerance from the measured noise (two seeds each, cycles_scene.block_z over 8 x 8 blocks):
|z| < 5 everywhere."""
import json
import math
import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support",
                                "python"))
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402

W, H = 160, 64
BLOCK = 8
Z_MAX = 5.0
SUB = 8
SUN_E = 2.0
SUN_DIR = np.array([-0.3, -0.5, -1.0]) / math.sqrt(0.09 + 0.25 + 1.0)  # travel direction
ENV_L = 1.0
MATERIALS = [
    ("lambert", {"model": "lambert", "reflectance": 0.8}),
    ("mirror", {"model": "mirror", "reflectance": 0.9}),
    ("mirror_dielectric", {"model": "mirror", "fresnel": "dielectric", "ior": 1.5}),
    ("mirror_schlick", {"model": "mirror", "fresnel": "schlick", "f0": 0.3}),
    ("ggx_0.05", {"model": "ggx", "alpha": 0.05}),
    ("ggx_0.3", {"model": "ggx", "alpha": 0.3}),
    ("ggx_0.6", {"model": "ggx", "alpha": 0.6}),
    ("beckmann_0.05", {"model": "beckmann", "alpha": 0.05}),
    ("beckmann_0.3", {"model": "beckmann", "alpha": 0.3}),
    ("beckmann_0.6", {"model": "beckmann", "alpha": 0.6}),
]
CENTRES = [[2.5 * (i % 5 - 2), 1.3 if i < 5 else -1.3, 0.0] for i in range(10)]
MIRROR_REGION = (26, 0, 134, 34)  # x0, y0, x1, y1: spheres 1-3 of the top row
CAMERA = {"position": [0, 0, 12], "look_at": [0, 0, 0], "up": [0, 1, 0],
          "fov": math.degrees(2 * math.atan(2.5 / 11.0)), "width": W, "height": H}


def scene_json(out, lighting):
    lights = ([{"type": "directional", "direction": SUN_DIR.tolist(), "irradiance": SUN_E}]
              if lighting == "sun" else [{"type": "environment", "radiance": ENV_L}])
    data = {"format": "facet-scene", "version": 1, "camera": CAMERA,
            "materials": {name: m for name, m in MATERIALS},
            "shapes": [{"type": "sphere", "name": name, "center": c, "radius": 1.0,
                        "material": name} for (name, _), c in zip(MATERIALS, CENTRES)],
            "lights": lights, "render": {"max_depth": 1}}
    path = os.path.join(out, "sweep_%s.json" % lighting)
    with open(path, "w") as f:
        json.dump(data, f)
    return path


# --- the analytic images ---------------------------------------------------------------------

def hit_spheres(o, d):
    """Nearest sphere hit of rays o + t d (d (..., 3) unit): (index (-1: none), t, point)."""
    best_t = np.full(d.shape[:-1], np.inf)
    best_i = np.full(d.shape[:-1], -1)
    for i, c in enumerate(CENTRES):
        oc = o - np.asarray(c)
        b = np.sum(oc * d, axis=-1)
        disc = b * b - (np.sum(oc * oc, axis=-1) - 1.0)
        t = -b - np.sqrt(np.maximum(disc, 0.0))
        ok = (disc > 0) & (t > 1e-6) & (t < best_t)
        best_t = np.where(ok, t, best_t)
        best_i = np.where(ok, i, best_i)
    p = o + np.where(np.isfinite(best_t), best_t, 0.0)[..., None] * d
    return best_i, best_t, p


def lam_ggx(a, cos):
    tan2 = np.maximum(1.0 - cos * cos, 0.0) / (cos * cos)
    return 0.5 * (np.sqrt(1.0 + a * a * tan2) - 1.0)


def lam_beckmann(a, cos):
    from math import erf
    tan = np.sqrt(np.maximum(1.0 - cos * cos, 0.0)) / cos
    c = 1.0 / np.maximum(a * tan, 1e-12)
    verf = np.vectorize(erf)(c)
    return np.where(c > 30, 0.0, 0.5 * (verf - 1.0) + np.exp(-c * c) / (2 * c * math.sqrt(math.pi)))


def g1_beckmann_cycles(a, cos):
    tan = np.sqrt(np.maximum(1.0 - cos * cos, 0.0)) / cos
    c = 1.0 / np.maximum(a * tan, 1e-12)
    return np.where(c < 1.6, (3.535 * c + 2.181 * c * c) / (1 + 2.276 * c + 2.577 * c * c), 1.0)


def brdf(m, n, wi, wo, cycles):
    """f(wi, wo) of description m for unit normals n (..., 3); Cycles' Smith term if cycles."""
    ci = np.sum(n * wi, axis=-1)
    co = np.sum(n * wo, axis=-1)
    if m["model"] == "lambert":
        return np.full(ci.shape, m["reflectance"] / math.pi)
    a = m["alpha"]
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    ch = np.clip(np.sum(n * h, axis=-1), 1e-9, 1.0)
    tan2 = (1.0 - ch * ch) / (ch * ch)
    if m["model"] == "ggx":
        D = a * a / (math.pi * ch ** 4 * (a * a + tan2) ** 2)
        li, lo = lam_ggx(a, ci), lam_ggx(a, co)
        G = 1.0 / ((1 + li) * (1 + lo)) if cycles else 1.0 / (1 + li + lo)
    else:
        D = np.exp(-tan2 / (a * a)) / (math.pi * a * a * ch ** 4)
        if cycles:
            G = g1_beckmann_cycles(a, ci) * g1_beckmann_cycles(a, co)
        else:
            G = 1.0 / (1 + lam_beckmann(a, ci) + lam_beckmann(a, co))
    return D * G / (4 * ci * co)


def analytic_sun():
    """(Facet's image (H, W), Cycles' image, keep (H, W), sphere index per pixel) of sweep A:
    the two renderers' models."""
    o, d = cs.camera_rays(CAMERA, sub=SUB)
    idx, t, p = hit_spheres(o, d)
    n = p - np.asarray(CENTRES)[np.maximum(idx, 0)]
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    wi = np.broadcast_to(-SUN_DIR, n.shape)
    wo = -d
    ci = np.sum(n * wi, axis=-1)
    shadow_idx = hit_spheres(p + 1e-6 * n, wi)[0]
    lit = (idx >= 0) & (ci > 0) & (shadow_idx < 0)
    vals = []
    for cycles in (False, True):
        val = np.zeros(idx.shape)
        for k, (name, m) in enumerate(MATERIALS):
            if m["model"] == "mirror":
                continue
            sel = (idx == k) & lit
            val[sel] = brdf(m, n[sel], wi[sel], wo[sel], cycles) * SUN_E * ci[sel]
        vals.append(val.mean(axis=-1))
    same = (idx == idx[..., :1]).all(axis=-1) & (lit == lit[..., :1]).all(axis=-1)
    keep = ~dilate(~same) & ((idx[..., 0] < 0) | (ci.min(axis=-1) > 0.1))
    return vals[0], vals[1], keep, idx[..., 0]


def dilate(bad):
    """bad pixels and their 8 neighbours."""
    out = bad.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            out |= np.roll(np.roll(bad, dy, axis=0), dx, axis=1)
    return out


def fresnel(m, cos):
    fr = m.get("fresnel", "none")
    if fr == "none":
        return np.full(cos.shape, m.get("reflectance", 1.0))
    if fr == "schlick":
        return m["f0"] + (1 - m["f0"]) * (1 - cos) ** 5
    eta = m["ior"]  # unpolarised dielectric Fresnel
    g = np.sqrt(eta * eta - 1 + cos * cos)
    return 0.5 * ((g - cos) / (g + cos)) ** 2 * (
        1 + ((cos * (g + cos) - 1) / (cos * (g - cos) + 1)) ** 2)


def analytic_env_mirrors(sub=24):
    """(image (H, W), keep (H, W)) of sweep B's mirror spheres: L F(cos) where the reflected
    ray escapes; keep only pixels entirely on one mirror whose reflections all escape.
    sub x sub points per pixel: at 8 x 8 the quadrature error (up to 4e-4 of the dielectric
    mirror's value, measured against 24 x 24) exceeded Facet's noise there."""
    # Only the region of the top row's spheres 1-3 (the mirrors) is computed this finely.
    x0, y0, x1, y1 = MIRROR_REGION
    o, d = cs.camera_rays(CAMERA, sub=sub, region=MIRROR_REGION)
    idx, t, p = hit_spheres(o, d)
    n = p - np.asarray(CENTRES)[np.maximum(idx, 0)]
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    cos = -np.sum(n * d, axis=-1)
    r = d + 2 * cos[..., None] * n
    escapes = hit_spheres(p + 1e-6 * n, r)[0] < 0
    val = np.zeros(idx.shape)
    mirror = np.zeros(idx.shape, bool)
    for k, (name, m) in enumerate(MATERIALS):
        if m["model"] == "mirror":
            sel = idx == k
            mirror |= sel
            val[sel] = ENV_L * fresnel(m, np.clip(cos[sel], 0, 1))
    same = (idx == idx[..., :1]).all(axis=-1)
    keep = (~dilate(~(same & escapes.all(axis=-1))) & mirror.all(axis=-1)
            & (cos.min(axis=-1) > 0.1))
    full_val, full_keep = np.zeros((H, W)), np.zeros((H, W), bool)
    full_val[y0:y1, x0:x1] = val.mean(axis=-1)
    full_keep[y0:y1, x0:x1] = keep
    return full_val, full_keep


# --- the renders -----------------------------------------------------------------------------

def render_pairs(path, out, tag, spp):
    t0 = time.perf_counter()
    bpy.ops.wm.read_homefile(use_empty=True)
    bpy.ops.import_scene.facet(filepath=path)
    scene = bpy.context.scene
    notes = cs.convert(scene, exact=False)
    glossy_notes = [s for s in notes if "Smith" in s]
    bt.check(len(glossy_notes) == 6, "the 6 ggx/beckmann spheres convert with a note on the "
             "Smith term (%d notes)" % len(glossy_notes))
    scene.facet.max_depth = 1
    scene.facet.spp = spp
    cs.cycles_settings(scene, samples=spp, max_depth=1)
    print("%s: import and convert %.1f s" % (tag, time.perf_counter() - t0))
    imgs, secs = {}, {}
    for e in ('FACET', 'CYCLES'):
        r = [cs.render(scene, e, os.path.join(out, "sweep_%s_%s_%d.exr" % (tag, e.lower(), s)),
                       s) for s in (1, 2)]
        imgs[e], secs[e] = (r[0][0], r[1][0]), r[0][1] + r[1][1]
    print("%s: 2 renders each: Facet %.1f s, Cycles %.1f s" % (tag, secs['FACET'], secs['CYCLES']))
    return imgs, scene


def grey(x):
    return np.repeat(x[..., None], 3, axis=2)


def per_sphere(z, idx_pixel):
    """max |z| per sphere: the block's sphere is the most common pixel sphere in it."""
    out = {}
    hb, wb = z.shape[:2]
    for by in range(hb):
        for bx in range(wb):
            blk = idx_pixel[by * BLOCK:(by + 1) * BLOCK, bx * BLOCK:(bx + 1) * BLOCK]
            vals = blk[blk >= 0]
            k = int(np.bincount(vals).argmax()) if vals.size else -1
            out[k] = max(out.get(k, 0.0), float(np.abs(z[by, bx]).max()))
    return out


def report(title, zs, idx_pixel):
    per = per_sphere(zs, idx_pixel)
    print("%s: max |z| per sphere: %s" % (title, ", ".join(
        "%s %.1f" % (MATERIALS[k][0] if k >= 0 else "background", v)
        for k, v in sorted(per.items()))))
    return max(per.values())


def main():
    out = bt.args()[0]
    bt.enable_addon()

    # A: the sun
    imgs, scene = render_pairs(scene_json(out, "sun"), out, "sun", 16)
    t0 = time.perf_counter()
    ref_f, ref_c, keep, idx_px = analytic_sun()
    print("analytic sun image: %.1f s" % (time.perf_counter() - t0))
    worst = {}
    z = cs.block_z(imgs['FACET'], imgs['CYCLES'], BLOCK, keep=keep,
                   expected_diff=grey(ref_f - ref_c))[0]
    worst["Facet-Cycles"] = report("sun, Facet - Cycles - (model difference)", z, idx_px)
    for engine, ref in (('FACET', ref_f), ('CYCLES', ref_c)):
        r = grey(ref)
        z = cs.block_z(imgs[engine], (r, r), BLOCK, keep=keep)[0]
        worst[engine] = report("sun, %s - its analytic model" % engine.capitalize(), z, idx_px)
    for k, (name, m) in enumerate(MATERIALS):
        sel = keep & (idx_px == k) & (ref_f > 0)
        if m["model"] in ("ggx", "beckmann") and sel.any():
            mf = (0.5 * (imgs['FACET'][0] + imgs['FACET'][1]))[..., 0][sel].sum()
            mc = (0.5 * (imgs['CYCLES'][0] + imgs['CYCLES'][1]))[..., 0][sel].sum()
            print("  %-14s Facet/Cycles %.4f, predicted by the Smith terms %.4f" % (
                name, mf / mc, ref_f[sel].sum() / ref_c[sel].sum()))
    # A': Facet rendering Cycles' node trees (the addon's node conversion: Diffuse -> lambert,
    # Glossy GGX / Beckmann -> ggx / beckmann with alpha = roughness^2) instead of the Facet
    # materials: the same analytic image (Facet's Smith term).
    for name, m in MATERIALS:
        if m["model"] != "mirror":
            bpy.data.materials[name].facet.source = 'NODES'
    from facet_blender import hooks
    from facet_blender import materials
    conv = materials.convert(bpy.data.materials["ggx_0.3"]).data
    bt.check(conv["model"] == "ggx" and conv["alpha"] != 0.3 and abs(conv["alpha"] - 0.3) < 1e-6,
             "F12 now converts the Glossy node (alpha = float32 roughness^2 = %r)" % conv["alpha"])
    a, b = (cs.render(scene, 'FACET', os.path.join(out, "sweep_sun_facet_nodes_%d.exr" % s),
                      s)[0] for s in (1, 2))
    bt.check(not [p for p in hooks.last_problems if "material" in p],
             "the Diffuse and Glossy nodes convert without a report (%s)" % hooks.last_problems)
    r = grey(ref_f)
    mirrors = np.isin(idx_px, [k for k, (_, m) in enumerate(MATERIALS) if m["model"] == "mirror"])
    z = cs.block_z((a, b), (r, r), BLOCK, keep=keep & ~mirrors)[0]
    worst["Facet from Cycles nodes"] = report("sun, Facet from Cycles' nodes - Facet's model",
                                              z, idx_px)
    for who, v in worst.items():
        bt.check(v < Z_MAX, "sun sweep: %s within the noise (|z| < %g)" % (who, Z_MAX))

    # B: the environment, lambert and mirrors
    imgs = render_pairs(scene_json(out, "env"), out, "env", 64)[0]
    t0 = time.perf_counter()
    ref_m, keep_m = analytic_env_mirrors()
    print("analytic mirror image: %.1f s" % (time.perf_counter() - t0))
    exact_models = np.isin(idx_px, [k for k, (_, m) in enumerate(MATERIALS)
                                    if m["model"] in ("lambert", "mirror")])
    o, d = cs.camera_rays(CAMERA, sub=SUB)
    idx_sub = hit_spheres(o, d)[0]
    inner = (idx_sub == idx_sub[..., :1]).all(axis=-1)
    z = cs.block_z(imgs['FACET'], imgs['CYCLES'], BLOCK, keep=exact_models & inner)[0]
    w1 = report("environment, Facet - Cycles (lambert, mirrors)", z, idx_px)
    r = grey(ref_m)
    print("mirror pixels checked against the analytic value: %d (of %d mirror pixels)"
          % (keep_m.sum(), np.isin(idx_px, [1, 2, 3]).sum()))
    w2 = max(report("environment, %s - analytic mirror" % e.capitalize(),
                    cs.block_z(imgs[e], (r, r), BLOCK, keep=keep_m)[0], idx_px)
             for e in ('FACET', 'CYCLES'))
    bt.check(w1 < Z_MAX, "environment sweep: Facet and Cycles agree on lambert and the mirrors "
             "(|z| < %g)" % Z_MAX)
    bt.check(w2 < Z_MAX, "environment sweep: both mirrors' Fresnel equals the analytic value "
             "(|z| < %g)" % Z_MAX)


bt.run(main)
