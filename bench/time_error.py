#!/usr/bin/python3
"""Time against error: Facet (standalone, each integrator/sampler/kernel, and inside Blender)
against Blender Cycles, on the benchmark scenes, in one interleaved run (issue 12).

  /usr/bin/python3 bench/time_error.py            # full run (~35 min on 2 cores) -> docs/perf/
  /usr/bin/python3 bench/time_error.py --quick    # smoke run (~3 min) -> out/bench/quick/

For every scene (a copy of scenes/<name>.json at the benchmark's image size) and every
contender, renders with a ladder of budgets (spp, doubling) and records wall time and error
against the scene's reference. The renders of all contenders are interleaved (for each budget,
each contender in turn, the order rotating from budget to budget) so that machine drift falls
on every contender alike.

Contenders: `facet render` (path / direct integrator, Sobol / independent sampler, the kernel
specialised to the scene or the general one), wall time of the whole command (process start,
scene load, BVH build included); Facet inside headless Blender (the addon from the build's zip,
File > Import > Facet scene, F12) and Blender Cycles on the same Blender scene built from Cycles
nodes, both timed around bpy.ops.render.render() inside one long-lived Blender
(time_error/blender_worker.py), so Blender's start-up is not counted.

References (cached in out/bench/ref, keyed by a hash of what makes them; reruns reuse them):
- point_plane: analytic, the pixel-area mean of rho/pi * Phi cos(theta) / (4 pi r^2)
  (Gauss-Legendre 12 x 12 per pixel; the change from 6 x 6 is printed, < 1e-6 relative);
- the others: the mean of two high-spp Facet renders with seeds 101 and 102 (seed 1 is the
  contenders'), so the reference's own noise is known from the pair: Var(ref) per pixel =
  (a - b)^2 / 4, and the error of a render x is reported with it subtracted,
  MSE = mean((x - ref)^2) - mean(Var(ref)) (x is independent of the reference's seeds). That
  reference is checked against the mean of two high-spp Cycles renders (seeds 101, 102) in
  16 x 16-pixel blocks per channel with noise-derived z-scores (reference_check.md).

Metrics (those of `facet diff`, computed here with numpy from the EXRs): RMSE over all pixels
and channels, relative MSE = mean((x - r)^2 / (r^2 + 1e-2)). The error level of the summary is
the RMSE of Cycles' top-budget (1024-spp) render, measured against Cycles' own reference (its
noise, not the conversion differences between the two renderers, which reference_check.md
states); each contender's time to that level is interpolated on its log-log curve of RMSE
against seconds, and the summary gives its ratio to Cycles' time. time_error_fit.md gives the
equal-error ratios from noise² × time fits, and time_error_bias.md each contender's bias apart
from its noise (difference of means with its z-score, blockwise bias maps:
bench/time_error_bias.py).
"""
import argparse
import csv
import hashlib
import json
import math
import os
import resource
import shutil
import subprocess
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HERE = os.path.join(ROOT, "bench", "time_error")
REL_EPS = 1e-2            # facet diff's kRelMseEpsilon (core/render/include/facet/render/diff.h)
REF_SEEDS = (101, 102)    # reference halves; the contenders render with seed 1
SEED = 1
BLOCK = 16                # reference check block size (pixels)

# Scenes: image size, the Facet contenders' and Cycles' budgets (spp), reference spp per half.
SCENES = {
    "cornell_box": dict(size=(128, 128), ladder=[4, 8, 16, 32, 64, 128, 256, 512, 1024],
                        ref_spp=2048, cycles_ref_spp=1024),
    "glossy": dict(size=(128, 128), ladder=[4, 8, 16, 32, 64, 128, 256, 512, 1024],
                   ref_spp=2048, cycles_ref_spp=1024),
    "brushed": dict(size=(128, 128), ladder=[4, 8, 16, 32, 64, 128, 256, 512, 1024],
                    ref_spp=2048, cycles_ref_spp=1024),
    "point_plane": dict(size=(256, 192), ladder=[2, 4, 8, 16, 32, 64, 128, 256, 512, 1024],
                        ref_spp=None, cycles_ref_spp=1024),
    "big_mesh": dict(size=(128, 96), ladder=[4, 8, 16, 32, 64, 128, 256, 512, 1024],
                     ref_spp=2048, cycles_ref_spp=1024),
    # Issue 25's new scenes (issue 21's textured benchmark): the scene of
    # time_error/new_scenes.py (a real glTF asset with three 2048^2 textures, normal map
    # included, under Blender's studio.exr) and scenes/glass.json. Cycles renders the same files
    # through a twin built directly in Blender (time_error/cycles_new_scenes.py; Blender's glTF
    # importer for the asset), so Facet inside Blender, whose importer does not take glTF
    # shapes, is not a contender; nor are the variants that the rounds never time.
    "textured_asset": dict(size=(96, 64), ladder=[32, 64, 128, 256, 512, 1024],
                           ref_spp=2048, cycles_ref_spp=1024, twin="direct",
                           build="textured_asset", only=("facet path sobol", "cycles")),
    "glass": dict(size=(96, 64), ladder=[32, 64, 128, 256, 512, 1024], ref_spp=2048,
                  cycles_ref_spp=1024, twin="direct", only=("facet path sobol", "cycles")),
}
QUICK = dict(size_div=2, ladder=[4, 8, 16, 32, 64], ref_spp=256, cycles_ref_spp=64)


# Budget caps (spp) of the contenders that cannot reach the error level or are biased, to keep
# the full run near 35 min: independent samples converge at MSE ~ spp^-1 (never near Sobol's
# level), direct lighting misses the indirect light on every scene but point_plane.
CAP = {"facet path independent": 512, "facet direct sobol": 256}


def contenders(scene):
    """(name, kind, options): kind 'cli' = `facet render` with these flags; 'blender' = the
    worker with this engine."""
    if scene == "point_plane":   # direct is exact here: its integrators and samplers
        cli = [("facet direct sobol", ["--integrator", "direct", "--sampler", "sobol"]),
               ("facet direct sobol general", ["--integrator", "direct", "--kernel", "general"]),
               ("facet direct independent", ["--integrator", "direct",
                                             "--sampler", "independent"]),
               ("facet path sobol", ["--integrator", "path"])]
    else:
        cli = [("facet path sobol", ["--integrator", "path", "--sampler", "sobol"]),
               ("facet path sobol general", ["--integrator", "path", "--kernel", "general"]),
               ("facet path independent", ["--integrator", "path", "--sampler", "independent"]),
               ("facet direct sobol", ["--integrator", "direct"])]
    pov = [("povray brdf", "pov", None)] if ARGS.povray and scene in POV_SCENES else []
    if ARGS.povray and scene in POV_RAD_SCENES:
        pov.append(("povray radiosity", "povrad", None))
    every = ([(n, "cli", o) for n, o in cli] + pov +
             [("facet in blender", "blender", "FACET"), ("cycles", "blender", "CYCLES")])
    if ARGS.contenders:
        every = [c for c in every if c[0] in ARGS.contenders]
    if "only" in SCENES.get(scene, {}):
        every = [c for c in every if c[0] in SCENES[scene]["only"]]
    return every


# POV-Ray (povray-facet, the `brdf` finish, the SDL of `facet export-pov`): only where the
# exported SDL renders the same picture. export-pov writes what `facet render --integrator
# direct` computes; that is the full solution only on point_plane (a point light over a plane
# that cannot see itself). Its budgets: adaptive antialiasing (+AM2) with threshold 0, so every
# pixel is subdivided to the full depth r (+R): (2^r + 1)^2 jittered samples per pixel, corners
# shared with the neighbours, ~4^r new samples per pixel; spp = 4^r is used as its budget.
POV_SCENES = ("point_plane",)

# POV-Ray's radiosity (`facet export-pov --radiosity C,E,R`) where the exported emitters and
# Lambert finishes are exact and only the indirect light is approximated: the Cornell box. Its
# budget is a quality ladder, one rung per ladder step: (radiosity count, error_bound,
# recursion_limit, antialiasing n (1: none, one ray through the pixel centre; else +AM1 +A0.0
# +R n +J: an n x n jittered grid inside the pixel plus its centre, spp = n^2 + 1, which is a
# box filter as Facet's; +AM2's corner samples are shared with the neighbours and put the
# emitter's 17-unit edge into the wrong pixels), export-pov --area-grid N (N x N light cells)).
# Radiosity interpolates a cache of irradiance samples, so its error does not fall as a Monte
# Carlo estimate's would: each rung tightens every source of bias together (sample density,
# rays per sample, bounces, pixel-centre vs pixel-area, the light quadrature). Cost grows
# steeply with count and 1/error_bound (timings in docs/performance.md, "POV-Ray as a
# contender"), so the ladder stops where one render takes a few minutes.
POV_RAD_SCENES = ("cornell_box",)
POV_RAD_LADDER = [
    (50, 1.0, 4, 1, 8),
    (100, 0.6, 6, 2, 8),
    (200, 0.4, 8, 3, 8),
    (200, 0.4, 12, 4, 8),
    (300, 0.3, 16, 5, 8),
]


def run_pov(pov_path, spp, out, aa_grid=None):
    """povray-facet on an exported scene; 32-bit float EXR (+FE32, povray-facet's patch: stock
    3.7 writes half floats, which floors the error at the half rounding). Antialiasing: +AM2
    to depth log4(spp), or with aa_grid n, +AM1 with an n x n grid (1: none)."""
    if aa_grid is None:
        aa = ["+AM2", "+A0.0", "+R%d" % int(round(math.log(spp, 4))), "+J"]
    else:
        aa = ["+AM1", "+A0.0", "+R%d" % aa_grid, "+J"] if aa_grid > 1 else ["-A"]
    cmd = [ARGS.povray, "+I" + pov_path, "+O" + out, "+FE32", "+W%d" % CUR["size"][0],
           "+H%d" % CUR["size"][1]] + aa + ["-D", "-UA", "+WT%d" % ARGS.threads, "-GA"]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - t0


def rad_budget(rung):
    count, eb, rl, n, grid = rung
    return "count %d, error_bound %g, recursion_limit %d, %s, area-grid %d" % (
        count, eb, rl, "AA +AM1 +R%d" % n if n > 1 else "no AA", grid)


def run_pov_rad(scene_path, rung, out):
    """One rung of POV-Ray's radiosity ladder: export (timed: it is part of the contender's
    cost, ~0.01 s) and render."""
    count, eb, rl, n, grid = rung
    pov = out[:-4] + ".pov"
    t0 = time.perf_counter()
    subprocess.run([ARGS.facet, "export-pov", scene_path, "-o", pov, "--area-grid", str(grid),
                    "--radiosity", "%d,%g,%d" % (count, eb, rl)], check=True)
    t = time.perf_counter() - t0
    return t + run_pov(pov, 0, out, aa_grid=n)


# --- images and metrics -------------------------------------------------------------------------
_facet = None


def read(path):
    global _facet
    if _facet is None:
        sys.path.insert(0, os.path.join(ARGS.build, "core", "python"))
        import facet
        _facet = facet
    return _facet.read_image(path).astype(np.float64)


def metrics(x, ref, ref_var):
    """RMSE and relative MSE of x against ref, raw and with the reference's noise (per-pixel
    variance ref_var) subtracted."""
    d2 = (x - ref) ** 2
    w = 1.0 / (ref * ref + REL_EPS)
    mse, rel = d2.mean(), (d2 * w).mean()
    mse_c, rel_c = mse - ref_var.mean(), rel - (ref_var * w).mean()
    return dict(rmse_raw=math.sqrt(mse), relmse_raw=rel,
                rmse=math.sqrt(max(mse_c, 0.0)), relmse=max(rel_c, 0.0))


# --- scenes and references ----------------------------------------------------------------------
def digest(*parts):
    h = hashlib.sha256()
    for p in parts:
        h.update(p if isinstance(p, bytes) else str(p).encode())
    return h.hexdigest()[:16]


def file_digest(path):
    with open(path, "rb") as f:
        return digest(f.read())


def bench_scene(name, cfg):
    """scenes/<name>.json (or the scene time_error/new_scenes.py builds) at the benchmark's
    size, written into the run's scene directory."""
    if cfg.get("build"):
        sys.path.insert(0, HERE)
        import new_scenes
        data = getattr(new_scenes, cfg["build"])(os.path.join(ARGS.out_root, "assets"))
    else:
        with open(os.path.join(ROOT, "scenes", name + ".json")) as f:
            data = json.load(f)
    data["camera"]["width"], data["camera"]["height"] = cfg["size"]
    path = os.path.join(ARGS.out, "scenes", name + ".json")
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    return path, data


# CPU seconds (user + system, all threads) of the last render that run_cli or the Blender worker
# timed. On a machine shared with other work, wall time moves tens of percent between
# neighbouring renders while CPU time moves a few percent: the timing rounds report both.
LAST_CPU = [0.0]


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run_cli(scene_path, spp, seed, opts, out):
    cmd = [ARGS.facet, "render", scene_path, "--spp", str(spp), "--seed", str(seed),
           "--threads", str(ARGS.threads), "-q", "-o", out] + list(opts)
    c0 = children_cpu()
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True)
    sec = time.perf_counter() - t0
    LAST_CPU[0] = children_cpu() - c0
    return sec


def point_plane_reference(data, order):
    """Pixel-area means of the analytic radiance of point_plane.json (FORMAT.md's camera, the
    plane y = 0, Lambert rho, one point light): L = rho/pi * Phi cos(theta) / (4 pi r^2)."""
    cam = data["camera"]
    w, h = cam["width"], cam["height"]
    pos, look, up = (np.array(cam[k], float) for k in ("position", "look_at", "up"))
    f = (look - pos) / np.linalg.norm(look - pos)
    r = np.cross(f, up)
    r /= np.linalg.norm(r)
    u = np.cross(r, f)
    tan_y = math.tan(math.radians(cam["fov"]) / 2)
    tan_x = tan_y * w / h
    (plane,), (light,) = data["shapes"], data["lights"]
    assert plane["type"] == "plane" and plane["normal"] == [0, 1, 0] and plane["point"] == [0, 0, 0]
    rho, phi, lp = plane["material"]["reflectance"], light["power"], np.array(light["position"])
    g, gw = np.polynomial.legendre.leggauss(order)
    g, gw = 0.5 * (g + 1), 0.5 * gw                       # on [0, 1]
    xs = (np.arange(w)[:, None] + g[None, :]).ravel()     # film x of every node, per column
    ys = (np.arange(h)[:, None] + g[None, :]).ravel()
    sx = (2 * xs / w - 1) * tan_x
    sy = (1 - 2 * ys / h) * tan_y
    d = f[None, None, :] + sx[None, :, None] * r + sy[:, None, None] * u   # (H*o, W*o, 3)
    t = -pos[1] / d[..., 1]                               # hit y = 0 (the camera looks down)
    p = pos + t[..., None] * d
    to_light = lp - p
    dist2 = (to_light ** 2).sum(-1)
    cos_t = to_light[..., 1] / np.sqrt(dist2)
    L = rho / math.pi * phi * cos_t / (4 * math.pi * dist2)
    L = L.reshape(h, order, w, order)
    img = np.einsum("iajb,a,b->ij", L, gw, gw)
    return np.repeat(img[..., None], 3, axis=2)


def facet_reference(name, scene_path, cfg):
    """The mean of two Facet path renders (seeds 101, 102) and its per-pixel variance."""
    key = digest(file_digest(scene_path), file_digest(ARGS.facet), cfg["ref_spp"], REF_SEEDS)
    paths = [os.path.join(ARGS.ref, "%s_facet_%s_%d.exr" % (name, key, s)) for s in REF_SEEDS]
    for p, s in zip(paths, REF_SEEDS):
        if not os.path.exists(p):
            tmp = p + ".tmp.exr"
            t = run_cli(scene_path, cfg["ref_spp"], s, ["--integrator", "path"], tmp)
            os.replace(tmp, p)
            log("  reference %s seed %d, %d spp: %.1f s" % (name, s, cfg["ref_spp"], t))
        else:
            log("  reference %s seed %d: cached %s" % (name, s, os.path.basename(p)))
    a, b = read(paths[0]), read(paths[1])
    return 0.5 * (a + b), 0.25 * (a - b) ** 2, (a, b)


# --- Blender worker -----------------------------------------------------------------------------
class Blender:
    def __init__(self):
        env = dict(os.environ, BLENDER_USER_SCRIPTS=os.path.join(ARGS.out_root, "blender_user"),
                   BLENDER_USER_CONFIG=os.path.join(ARGS.out_root, "blender_config"),
                   PYTHONNOUSERSITE="1")
        self.log = open(os.path.join(ARGS.out, "blender.log"), "w")
        self.p = subprocess.Popen(
            [ARGS.blender, "-b", "--factory-startup", "-noaudio", "--python",
             os.path.join(HERE, "blender_worker.py"), "--", ARGS.addon_zip],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=self.log, text=True, env=env)
        self.info = self._reply()

    def _reply(self):
        for line in self.p.stdout:
            if line.startswith("TE_REPLY "):
                r = json.loads(line[len("TE_REPLY "):])
                if "error" in r:
                    raise RuntimeError("blender worker: " + r["error"])
                return r
            self.log.write(line)
        raise RuntimeError("the Blender worker exited (see %s)" % self.log.name)

    def call(self, **req):
        self.p.stdin.write(json.dumps(req) + "\n")
        self.p.stdin.flush()
        return self._reply()

    def close(self):
        try:
            self.call(cmd="quit")
        except Exception:
            pass
        self.p.wait(timeout=60)


def blender_load(blender, cfg, scene_path):
    """Loads the scene into the worker: through the Facet importer and cycles_twin, or for the
    scenes with twin="direct" through cycles_new_scenes."""
    extra = {"twin": cfg["twin"]} if cfg.get("twin") else {}
    return blender.call(cmd="load", scene=scene_path, threads=ARGS.threads, **extra)


def cycles_reference(name, scene_path, cfg, blender):
    key = digest(file_digest(scene_path), file_digest(os.path.join(HERE, "cycles_twin.py")),
                 file_digest(os.path.join(HERE, "cycles_new_scenes.py")),
                 file_digest(os.path.join(ROOT, "tests", "support", "python", "facet_testsupport",
                                          "cycles_scene.py")),
                 blender.info.get("blender"), cfg["cycles_ref_spp"], REF_SEEDS)
    paths = [os.path.join(ARGS.ref, "%s_cycles_%s_%d.exr" % (name, key, s)) for s in REF_SEEDS]
    for p, s in zip(paths, REF_SEEDS):
        if not os.path.exists(p):
            tmp = p + ".tmp.exr"
            r = blender.call(cmd="render", engine="CYCLES", spp=cfg["cycles_ref_spp"], seed=s,
                             out=tmp)
            os.replace(tmp, p)
            log("  Cycles reference %s seed %d, %d spp: %.1f s"
                % (name, s, cfg["cycles_ref_spp"], r["seconds"]))
        else:
            log("  Cycles reference %s seed %d: cached" % (name, s))
    a, b = read(paths[0]), read(paths[1])
    return 0.5 * (a + b), 0.25 * (a - b) ** 2


def block_check(name, ref, ref_var, cref, cref_var):
    """Facet's reference against Cycles' in BLOCK x BLOCK blocks per channel: z = difference of
    the block means / sqrt(sum of both block means' variances from the seed pairs)."""
    h, w, c = ref.shape
    bh, bw = h // BLOCK, w // BLOCK
    crop = (slice(0, bh * BLOCK), slice(0, bw * BLOCK))

    def bmean(x):
        return x[crop].reshape(bh, BLOCK, bw, BLOCK, c).mean(axis=(1, 3))
    n = BLOCK * BLOCK
    # Noiseless blocks (the environment seen directly) differ by float rounding only: a floor
    # of 1e-6 relative (float32 storage, as facet_testsupport.cycles_scene's block_z).
    floor = (1e-6 * np.maximum(np.abs(bmean(ref)), np.abs(bmean(cref)))) ** 2
    z = (bmean(ref) - bmean(cref)) / np.sqrt(np.maximum(
        (bmean(ref_var) + bmean(cref_var)) / n + floor, 1e-30))
    rel = (bmean(ref) - bmean(cref)) / np.maximum(np.abs(bmean(cref)), 1e-6)
    ratio = [float(ref[..., k].mean() / max(cref[..., k].mean(), 1e-30)) for k in range(c)]
    lines = ["### %s" % name, "",
             "Facet reference / Cycles reference, image mean per channel: %.4f %.4f %.4f"
             % tuple(ratio),
             "", "%d blocks of %d x %d px x %d channels: max |z| %.1f, %.0f%% with |z| < 3, "
             "%d with |z| >= 5." % (bh * bw, BLOCK, BLOCK, c, np.abs(z).max(),
                                    100.0 * (np.abs(z) < 3).mean(), int((np.abs(z) >= 5).sum())),
             "", "Max |z| per block over the channels (row = block row from the top), and in "
             "brackets the largest relative difference of the block means:", "", "```"]
    zmax = np.abs(z).max(axis=2)
    rmax = np.take_along_axis(rel, np.abs(z).argmax(axis=2)[..., None], axis=2)[..., 0]
    for i in range(bh):
        lines.append(" ".join("%5.1f(%+5.1f%%)" % (zmax[i, j], 100 * rmax[i, j])
                              for j in range(bw)))
    lines += ["```", ""]
    return lines, dict(max_abs_z=float(np.abs(z).max()), blocks_z_ge_5=int((np.abs(z) >= 5).sum()),
                       mean_ratio=ratio)


# --- the run ------------------------------------------------------------------------------------
def log(msg):
    print(msg, flush=True)
    with open(os.path.join(ARGS.out, "run.log"), "a") as f:
        f.write(msg + "\n")


def time_to_error(points, target):
    """Seconds at which the log-log curve (seconds, rmse), in budget order, first reaches the
    target RMSE; (seconds, flag): flag '' interpolated, '<=' reached at the first point,
    '>' never reached (the last time)."""
    pts = [(t, e) for t, e in points if e > 0]
    if not pts:
        return float("nan"), "?"
    if pts[0][1] <= target:
        return pts[0][0], "<="
    for (t0, e0), (t1, e1) in zip(pts, pts[1:]):
        if e1 <= target < e0:
            a = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(t0) + a * (math.log(t1) - math.log(t0))), ""
    return pts[-1][0], ">"


def run_scene(name, cfg, blender, rows, summary, checks):
    scene_path, data = bench_scene(name, cfg)
    log("== %s (%dx%d)" % (name, cfg["size"][0], cfg["size"][1]))
    if blender:
        r = blender_load(blender, cfg, scene_path)
        for note in r.get("notes", []):
            log("  cycles twin: " + note)
    if cfg["ref_spp"] is None:
        ref = point_plane_reference(data, 12)
        coarse = point_plane_reference(data, 6)
        log("  analytic reference: Gauss-Legendre 12x12 vs 6x6 per pixel, max relative change "
            "%.2g" % (np.abs(ref - coarse) / ref).max())
        ref_var = np.zeros_like(ref)
        REF_MEAN[name] = float(ref.mean())
    else:
        ref, ref_var, _ = facet_reference(name, scene_path, cfg)
    cref = None
    if blender:
        cref, cref_var = cycles_reference(name, scene_path, cfg, blender)
        if cfg["ref_spp"] is not None:
            lines, info = block_check(name, ref, ref_var, cref, cref_var)
        else:
            m = metrics(cref, ref, np.zeros_like(ref))
            info = dict(mean_ratio=[float(ref[..., k].mean() / cref[..., k].mean())
                                    for k in range(3)], max_abs_z=float("nan"))
            lines = ["### %s" % name, "", "Analytic reference; Cycles' reference (2 x %d spp) "
                     "against it: RMSE %.3g (raw, Cycles' noise included), analytic / Cycles "
                     "image mean %.4f %.4f %.4f." % ((cfg["cycles_ref_spp"], m["rmse_raw"])
                                                     + tuple(info["mean_ratio"])), ""]
        checks.append(lines)
        for line in lines[2:3]:
            log("  " + line)
    conts = [c for c in contenders(name) if blender or c[1] != "blender"]
    imgdir = os.path.join(ARGS.out, "images", name)
    os.makedirs(imgdir, exist_ok=True)
    CUR["size"] = cfg["size"]
    pov_path = None
    if any(c[1] == "pov" for c in conts):
        pov_path = os.path.join(imgdir, name + ".pov")
        subprocess.run([ARGS.facet, "export-pov", scene_path, "-o", pov_path], check=True)
    curves = {c[0]: [] for c in conts}
    for k, spp in enumerate(cfg["ladder"]):
        order = conts[k % len(conts):] + conts[:k % len(conts)]
        for cname, kind, opt in order:
            if name != "point_plane" and spp > CAP.get(cname, spp) and not ARGS.quick:
                continue
            if kind == "pov" and abs(math.log(spp, 4) - round(math.log(spp, 4))) > 1e-9:
                continue
            if kind == "povrad" and k >= len(POV_RAD_LADDER[:ARGS.pov_rungs]):
                continue
            out = os.path.join(imgdir, "%s_%d.exr" % (cname.replace(" ", "_"), spp))
            budget, row_spp = "", spp
            LAST_CPU[0] = float("nan")
            if kind == "cli":
                sec = run_cli(scene_path, spp, SEED, opt, out)
            elif kind == "pov":
                sec = run_pov(pov_path, spp, out)
            elif kind == "povrad":
                rung = POV_RAD_LADDER[k]
                out = os.path.join(imgdir, "%s_rung%d.exr" % (cname.replace(" ", "_"), k))
                sec = run_pov_rad(scene_path, rung, out)
                row_spp = rung[3] ** 2 + 1 if rung[3] > 1 else 1
                budget = rad_budget(rung)
            else:
                r = blender.call(cmd="render", engine=opt, spp=spp, seed=SEED, out=out,
                                 integrator=data.get("render", {}).get("integrator", "path"))
                sec = r["seconds"]
                LAST_CPU[0] = r.get("cpu_seconds", float("nan"))
            x = read(out)
            m = metrics(x, ref, ref_var)
            row = dict(scene=name, contender=cname, spp=row_spp, seconds=round(sec, 4),
                       cpu_seconds=("" if math.isnan(LAST_CPU[0]) else round(LAST_CPU[0], 4)),
                       rmse=m["rmse"], relmse=m["relmse"], rmse_raw=m["rmse_raw"],
                       relmse_raw=m["relmse_raw"], rmse_self="", budget=budget)
            if cname == "cycles" and cref is not None:
                row["rmse_self"] = metrics(x, cref, cref_var)["rmse"]
            rows.append(row)
            curves[cname].append((sec, m["rmse"], row["rmse_self"]))
            log("  %-28s %5d spp %8.2f s  RMSE %.4g  relMSE %.4g%s%s"
                % (cname, row_spp, sec, m["rmse"], m["relmse"],
                   "  (vs Cycles ref %.4g)" % row["rmse_self"] if row["rmse_self"] != "" else "",
                   "  (%s; image mean / reference %.4f)" % (budget, x.mean() / ref.mean())
                   if budget else ""))
        write_csv(rows)
    # The error level: Cycles' top-budget render against Cycles' own reference (its noise);
    # without Blender, the top budget of `facet path sobol` / `facet direct sobol`.
    if not blender and ARGS.level_csv:
        # Cycles' curve of an earlier run (--level-csv): its top budget's noise is the level,
        # its times the base (measured in that run, under that run's load).
        with open(ARGS.level_csv) as f:
            cyc = [r for r in csv.DictReader(f)
                   if r["scene"] == name and r["contender"] == "cycles" and r["rmse_self"]]
        if not cyc:
            sys.exit("time_error: --level-csv %s has no Cycles rows for %s" % (ARGS.level_csv,
                                                                             name))
        curves["cycles"] = [(float(r["seconds"]), float(r["rmse"]), float(r["rmse_self"]))
                            for r in cyc]
        for r in cyc:
            rows.append(dict({k: r.get(k, "") for k in CSV_FIELDS},
                             budget="from %s" % os.path.relpath(ARGS.level_csv, ROOT)))
        write_csv(rows)
        log("  error level from %s: Cycles %s spp RMSE %s" % (ARGS.level_csv, cyc[-1]["spp"],
                                                             cyc[-1]["rmse_self"]))
    if "cycles" in curves and curves["cycles"] and curves["cycles"][-1][2] != "":
        target = curves["cycles"][-1][2]
        base = "cycles"
        base_time, _ = time_to_error([(t, s) for t, _, s in curves["cycles"]], target)
    else:
        base = conts[0][0]
        target = curves[base][-1][1]
        base_time = curves[base][-1][0]
    TARGETS[name] = target
    for cname in curves:
        pts = [(t, e) for t, e, _ in curves[cname]]
        if cname == "cycles":
            pts = [(t, s) for t, _, s in curves[cname]]
        t, flag = time_to_error(pts, target)
        summary.append(dict(scene=name, contender=cname, target_rmse=target, seconds=t, flag=flag,
                            ratio=t / base_time, base=base))
    return curves


CSV_FIELDS = ["scene", "contender", "spp", "seconds", "rmse", "relmse", "rmse_raw", "relmse_raw",
              "rmse_self", "budget", "cpu_seconds"]


def write_csv(rows):
    with open(os.path.join(ARGS.publish, "time_error.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, CSV_FIELDS)
        w.writeheader()
        for r in KEPT["csv"] + rows:
            w.writerow({k: ("%.6g" % r.get(k, "") if isinstance(r.get(k, ""), float)
                            else r.get(k, "")) for k in CSV_FIELDS})


def plot(all_curves, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    n = len(all_curves)
    cols = min(n, 3)
    rws = (n + cols - 1) // cols
    fig, axes = plt.subplots(rws, cols, figsize=(4.2 * cols, 3.4 * rws), squeeze=False)
    styles = {"facet path sobol": ("C0", "-"), "facet direct sobol": ("C0", ":"),
              "facet path sobol general": ("C2", "--"), "facet direct sobol general": ("C2", "--"),
              "facet path independent": ("C4", "-."), "facet direct independent": ("C4", "-."),
              "facet path sobol ": ("C0", "-"), "facet in blender": ("C1", "-"),
              "cycles": ("C3", "-"), "povray brdf": ("C8", "-"),
              "povray radiosity": ("C6", "-")}
    for ax, (name, curves) in zip(axes.ravel(), all_curves.items()):
        for cname, pts in curves.items():
            color, ls = styles.get(cname, ("C5", "-"))
            if name == "point_plane" and cname == "facet path sobol":
                color, ls = "C9", ":"
            t = [p[0] for p in pts]
            e = [p[2] if cname == "cycles" and p[2] != "" else p[1] for p in pts]
            ax.loglog(t, e, color=color, ls=ls, marker=".", label=cname)
            if cname == "cycles" and all(p[2] != "" for p in pts):
                ax.loglog(t, [p[1] for p in pts], color=color, ls=":", lw=0.8,
                          label="cycles vs Facet ref")
        if name in TARGETS:
            ax.axhline(TARGETS[name], color="0.5", lw=0.8, ls="--")
        ax.set_title(name, fontsize=10)
        ax.set_xlabel("seconds (2 threads)", fontsize=8)
        ax.set_ylabel("RMSE", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, which="both", lw=0.3)
    for ax in axes.ravel()[n:]:
        ax.axis("off")
    handles = {}
    for ax in axes.ravel()[:n]:
        for h, lab in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(lab, h)
    if n < rws * cols:
        axes.ravel()[-1].legend(list(handles.values()), list(handles.keys()), loc="center",
                                fontsize=8, frameon=False)
    else:
        fig.legend(list(handles.values()), list(handles.keys()), loc="upper center",
                   bbox_to_anchor=(0.5, 0.0), fontsize=7, ncol=4, frameon=False)
    fig.tight_layout()
    fig.savefig(path, dpi=80, bbox_inches="tight")
    plt.close(fig)


def replot():
    curves = {}
    with open(os.path.join(ARGS.publish, "time_error.csv")) as f:
        for r in csv.DictReader(f):
            self_e = float(r["rmse_self"]) if r["rmse_self"] else ""
            curves.setdefault(r["scene"], {}).setdefault(r["contender"], []).append(
                (float(r["seconds"]), float(r["rmse"]), self_e))
    for name, c in curves.items():
        if "cycles" in c and c["cycles"][-1][2] != "":
            TARGETS[name] = c["cycles"][-1][2]
    plot(curves, os.path.join(ARGS.publish, "time_error.png"))


# --- repeated timings at the budget that reaches the error level --------------------------------
MAX_EXTRAPOLATION = 8.0  # x the top budget: the timing rounds measure the error there again


def spp_to_error(pts, target):
    """The budget (spp) at which the log-log curve [(spp, rmse)] first reaches target; beyond
    the ladder, the last segment's slope extended up to MAX_EXTRAPOLATION x the top budget
    (the timing rounds then measure the error at that budget). None if out of reach."""
    pts = [(n, e) for n, e in pts if e > 0]
    if pts and pts[0][1] <= target:
        return float(pts[0][0])
    for (n0, e0), (n1, e1) in zip(pts, pts[1:]):
        if e1 <= target < e0:
            a = (math.log(target) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(n0) + a * (math.log(n1) - math.log(n0)))
    if len(pts) >= 2:
        (n0, e0), (n1, e1) = pts[-2], pts[-1]
        slope = (math.log(e1) - math.log(e0)) / (math.log(n1) - math.log(n0))
        if slope < 0:
            n = n1 * math.exp((math.log(target) - math.log(e1)) / slope)
            if n <= MAX_EXTRAPOLATION * n1:
                return n
    return None


def render_measured(name, scene_path, cname, kind, opt, spp, data, ref, ref_var, cref, cref_var,
                    blender, tag):
    """One render of a contender at spp for the timing phase: (wall seconds, CPU seconds, RMSE
    against the contender's reference; Cycles against its own)."""
    imgdir = os.path.join(ARGS.out, "images", name)
    os.makedirs(imgdir, exist_ok=True)
    out = os.path.join(imgdir, "%s_%s.exr" % (tag, cname.replace(" ", "_")))
    if kind == "cli":
        sec = run_cli(scene_path, spp, SEED, opt, out)
        cpu = LAST_CPU[0]
    else:
        r = blender.call(cmd="render", engine=opt, spp=spp, seed=SEED, out=out,
                         integrator=data.get("render", {}).get("integrator", "path"))
        sec, cpu = r["seconds"], r.get("cpu_seconds", float("nan"))
    x = read(out)
    e = metrics(x, cref, cref_var)["rmse"] if cname == "cycles" else \
        metrics(x, ref, ref_var)["rmse"]
    return sec, cpu, e


def timing_phase(names, rows, blender, reps):
    """Timing noise on a shared machine is tens of percent per render, and the error against
    spp is deterministic (fixed seeds): so each contender that reaches the error level is
    rendered `reps` more times at the budget that reaches it (the log-log interpolation rounded
    up when one trial render there, measured, reaches the level, else the first ladder budget
    that did; Cycles at its top budget), interleaved round by round with Cycles, and the ratio is taken of the medians (and
    the median of the per-round ratios). The error of these renders is measured again (the
    ladder's time to the level interpolates on the log-log curve; these rounds measure)."""
    out_rows, lines = [], []
    for name in names:
        cfg = CFG[name]
        scene_path, data = bench_scene(name, cfg)
        srows = [r for r in rows if r["scene"] == name]
        cyc = [r for r in srows if r["contender"] == "cycles"]
        if not cyc or cyc[-1]["rmse_self"] == "":
            continue
        target = float(cyc[-1]["rmse_self"])
        if cfg["ref_spp"] is None:
            ref, ref_var = point_plane_reference(data, 12), None
            ref_var = np.zeros_like(ref)
        else:
            ref, ref_var, _ = facet_reference(name, scene_path, cfg)
        cref, cref_var = cycles_reference(name, scene_path, cfg, blender)
        blender_load(blender, cfg, scene_path)
        jobs = []
        extrapolated = False
        main = "facet direct sobol" if name == "point_plane" else "facet path sobol"
        for cname, kind, opt in contenders(name):
            pts = [(int(r["spp"]), float(r["rmse"])) for r in srows if r["contender"] == cname]
            if cname == "cycles":
                jobs.append((cname, kind, opt, int(cyc[-1]["spp"])))
                continue
            if kind in ("pov", "povrad") or "independent" in cname or \
                    (cname == "facet direct sobol" and name != "point_plane") or \
                    (ARGS.reps_contenders and cname not in ARGS.reps_contenders.split(",")):
                continue
            n = spp_to_error(pts, target)
            if n is None:
                continue
            reached = [b for b, e in pts if e <= target]
            if reached:
                # Within the ladder: the budget interpolated on the log-log curve when one
                # render there, measured, reaches the level; otherwise the first ladder budget
                # that reached it. (Sobol points are stratified at powers of two; between them
                # the error need not be on the log-log line: point_plane 2.3e-6 at 48 spp,
                # 6.3e-7 at 64 — such a trial fails and the ladder budget is used.)
                budget = min(reached)
                trial = int(math.ceil(n))
                if trial < budget:
                    _, _, e = render_measured(name, scene_path, cname, kind, opt, trial, data,
                                              ref, ref_var, cref, cref_var, blender, "trial")
                    log("  trial %-28s %5d spp  RMSE %.4g (level %.4g): %s" % (
                        cname, trial, e, target, "used" if e <= target else
                        "not reached, %d spp from the ladder" % budget))
                    if e <= target:
                        budget = trial
                jobs.append((cname, kind, opt, budget))
            elif n <= 2 * pts[-1][0] or cname == main:
                # Beyond it: the extrapolated budget (its error is measured and shown); beyond
                # twice the top budget only for the main contender, in one round (long renders).
                jobs.append((cname, kind, opt, int(math.ceil(n))))
                extrapolated = extrapolated or n > 2 * pts[-1][0]
        times = {j[0]: [] for j in jobs}
        cpus = {}
        errs = {}
        if extrapolated:
            jobs = [j for j in jobs if j[0] in (main, "cycles")]
        nrounds = 1 if extrapolated else reps
        log("== %s: %d timing rounds at the error level RMSE %.4g: %s" % (
            name, nrounds, target, ", ".join("%s %d spp" % (j[0], j[3]) for j in jobs)))
        rounds = []
        for k in range(nrounds):
            order = jobs[k % len(jobs):] + jobs[:k % len(jobs)]
            this = {}
            for cname, kind, opt, spp in order:
                sec, cpu, e = render_measured(name, scene_path, cname, kind, opt, spp, data, ref,
                                              ref_var, cref, cref_var, blender, "rep")
                errs[cname] = e
                times[cname].append(sec)
                cpus.setdefault(cname, []).append(cpu)
                this[cname] = sec
                this[cname + " cpu"] = cpu
                out_rows.append(dict(scene=name, contender=cname, round=k, spp=spp,
                                     seconds=round(sec, 4), cpu_seconds=round(cpu, 4), rmse=e))
                log("  round %d %-28s %5d spp %8.2f s (CPU %8.2f s)  RMSE %.4g"
                    % (k, cname, spp, sec, cpu, e))
            rounds.append(this)
        tc = float(np.median(times["cycles"]))
        goal = 1 / 3 if name == "cornell_box" else 1 / 2
        for cname, kind, opt, spp in jobs:
            t = float(np.median(times[cname]))
            per_round = float(np.median([r[cname] / r["cycles"] for r in rounds]))
            cpu_ratio = float(np.median(cpus[cname])) / float(np.median(cpus["cycles"]))
            verdict = ""
            if cname == main:
                verdict = "≤ %s: %s" % ("1/3" if goal < 0.4 else "1/2",
                                        "met" if per_round <= goal else "**not met**")
            lines.append("| %s | %s | %d | %.4g | %s | %.2f s | %.3f | %.3f | %s | %.3f | %s |" % (
                name, cname, spp, errs[cname], " ".join("%.2f" % v for v in times[cname]), t,
                t / tc, per_round, " ".join("%.2f" % v for v in cpus[cname]), cpu_ratio,
                verdict))
    mode = "a" if ARGS.reps_append or ARGS.merge else "w"
    with open(os.path.join(ARGS.publish, "time_error_reps.csv"),
              "w" if ARGS.merge else mode, newline="") as f:
        w = csv.DictWriter(f, ["scene", "contender", "round", "spp", "seconds", "cpu_seconds",
                               "rmse"])
        if mode == "w" or ARGS.merge:
            w.writeheader()
        for r in KEPT["reps"] + out_rows:
            w.writerow({k: ("%.6g" % v if isinstance(v, float) else v) for k, v in r.items()})
    head = ["| scene | contender | spp reaching the level | RMSE there | seconds per round | "
            "median | ratio of medians to Cycles | median per-round ratio | CPU seconds per "
            "round | ratio of CPU medians | target (wall, per round) |",
            "|---|---|---:|---:|---|---:|---:|---:|---|---:|---|"]
    text = "\n".join(["## Time to Cycles' top-budget error, %d interleaved rounds (%s)"
                       % (reps, ", ".join(names)), "", "Run of %s UTC, load average at the end "
                       "%.1f." % (time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                                  os.getloadavg()[0]), ""] + head + lines)
    with open(os.path.join(ARGS.publish, "time_error_ratios.md"), mode) as f:
        f.write(("\n" if mode == "a" else "") + text + "\n")
    log(text)


def RUN_META_KEEP():
    """The first paragraph of the published summary (the run it describes)."""
    try:
        with open(os.path.join(ARGS.publish, "time_error_summary.md")) as f:
            return f.read().split("\n\n")[1]
    except (OSError, IndexError):
        return ""


def resummarize(names, blender):
    """The summary again from the published CSV and the cached references (no rendering)."""
    rows = read_rows()
    summary, checks = [], []
    for name in names:
        cfg = CFG[name]
        scene_path, data = bench_scene(name, cfg)
        srows = [r for r in rows if r["scene"] == name]
        if not srows:
            continue
        if cfg["ref_spp"] is None:
            ref = point_plane_reference(data, 12)
            cref, _ = cycles_reference(name, scene_path, cfg, blender)
            m = metrics(cref, ref, np.zeros_like(ref))
            ratio = [float(ref[..., k].mean() / cref[..., k].mean()) for k in range(3)]
            checks.append(["### %s" % name, "", "Analytic reference; Cycles' reference (2 x %d "
                           "spp) against it: RMSE %.3g (raw, Cycles' noise included), analytic / "
                           "Cycles image mean %.5f %.5f %.5f." % ((cfg["cycles_ref_spp"],
                                                                   m["rmse_raw"]) + tuple(ratio)),
                           ""])
        else:
            ref, ref_var, _ = facet_reference(name, scene_path, cfg)
            cref, cref_var = cycles_reference(name, scene_path, cfg, blender)
            checks.append(block_check(name, ref, ref_var, cref, cref_var)[0])
        cyc = [r for r in srows if r["contender"] == "cycles"]
        target = float(cyc[-1]["rmse_self"])
        base_time, _ = time_to_error([(float(r["seconds"]), float(r["rmse_self"])) for r in cyc],
                                     target)
        for cname, _, _ in contenders(name):
            pts = [(float(r["seconds"]), float(r["rmse_self"] if cname == "cycles" else r["rmse"]))
                   for r in srows if r["contender"] == cname]
            if not pts:
                continue
            t, flag = time_to_error(pts, target)
            summary.append(dict(scene=name, contender=cname, target_rmse=target, seconds=t,
                                flag=flag, ratio=t / base_time, base="cycles"))
    return summary, checks


def read_rows():
    with open(os.path.join(ARGS.publish, "time_error.csv")) as f:
        return list(csv.DictReader(f))


def write_summary(summary, checks, path, meta):
    title = "# Time against error (bench/time_error.py)"
    if ARGS.merge:
        title = "## Scenes %s (a --merge run, appended)" % ", ".join(sorted(CFG))
    lines = [title, "", meta, "",
             "Ladder: one render per budget, the time to the level interpolated on the log-log "
             "curve; the timing rounds (time_error_ratios.md) measure it again, repeated, and "
             "decide the targets.", "",
             "| scene | contender | time to the error level | ratio to %s | target (ladder) |"
             % ("Cycles" if any(s["base"] == "cycles" for s in summary) else "the base"),
             "|---|---|---:|---:|---|"]
    for s in summary:
        mark = {"": "", "<=": "≤ ", ">": "> ", "?": "? "}[s["flag"]]
        ratio = "%s%.2f" % ({"": "", "<=": "≤ ", ">": "> ", "?": ""}[s["flag"]], s["ratio"])
        goal = 1 / 3 if s["scene"] == "cornell_box" else 1 / 2
        if s["contender"] in ("facet path sobol", "facet direct sobol") and s["base"] == "cycles" \
                and (s["scene"] == "point_plane") == (s["contender"] == "facet direct sobol"):
            ok = "met" if s["ratio"] <= goal and s["flag"] != ">" else "**not met**"
            target = "≤ %s: %s" % ("1/3" if goal < 0.4 else "1/2", ok)
        else:
            target = ""
        lines.append("| %s (RMSE %.4g) | %s | %s%.2f s | %s | %s |"
                     % (s["scene"], s["target_rmse"], s["contender"], mark, s["seconds"], ratio,
                        target))
    lines += ["", "%s Reference check: Facet's reference against Cycles'"
              % ("###" if ARGS.merge else "##"), ""]
    for c in checks:
        lines += c
    with open(path, "w") as f:
        f.write(KEPT["summary"] + "\n".join(lines) + "\n")


def main():
    global ARGS
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="smoke run: small images, short ladders")
    ap.add_argument("--scenes", default=",".join(SCENES), help="comma-separated subset")
    ap.add_argument("--no-blender", action="store_true", help="Facet standalone only")
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--blender", default=shutil.which("blender") or "blender")
    ap.add_argument("--facet", default=None, help="the facet CLI (default <build>/core/cli/facet)")
    ap.add_argument("--povray", default=None, help="povray-facet binary: adds POV-Ray (brdf "
                    "finish, facet export-pov) where the SDL can express the scene (default: "
                    "<build>/povray_patch/bin/povray-facet when it is built, except with --quick)")
    ap.add_argument("--no-povray", action="store_true", help="leave POV-Ray out even where it "
                    "is built")
    ap.add_argument("--contenders", default="", help="comma-separated: run only these "
                    "contenders (e.g. 'facet path sobol,povray radiosity')")
    ap.add_argument("--level-csv", default=None, help="with --no-blender: take Cycles' curve "
                    "and error level from this CSV of an earlier run (e.g. docs/perf/"
                    "time_error.csv) instead of rendering Cycles")
    ap.add_argument("--pov-rungs", type=int, default=len(POV_RAD_LADDER), help="POV-Ray "
                    "radiosity: run only the first N rungs of its quality ladder (1-%d)"
                    % len(POV_RAD_LADDER))
    ap.add_argument("--reps", type=int, default=3, help="timing rounds at the error level "
                    "after the ladders (0: none)")
    ap.add_argument("--reps-only", action="store_true", help="only the timing rounds, from the "
                    "published CSV of an earlier run")
    ap.add_argument("--reps-contenders", default="", help="comma-separated: only these Facet "
                    "contenders in the timing rounds (Cycles always)")
    ap.add_argument("--reps-append", action="store_true", help="append to the timing tables")
    ap.add_argument("--resummarize", action="store_true", help="only rewrite the summary "
                    "from the published CSV and the cached references")
    ap.add_argument("--replot", action="store_true", help="only redraw the plot from the "
                    "published CSV (no rendering)")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--merge", action="store_true", help="keep the published results of the "
                    "scenes not in --scenes: their CSV and timing-round rows stay, the summary "
                    "and the rounds' table gain this run's sections, the plot and the fit cover "
                    "all (e.g. --scenes textured_asset,glass --merge)")
    ap.add_argument("--check", action="store_true", help="smoke test (CTest): exit 1 unless "
                    "every Sobol Facet contender's error falls with the budget and point_plane's "
                    "converges to the analytic reference")
    ap.add_argument("--out", default=None, help="run directory (default out/bench/time_error or "
                    "out/bench/quick)")
    ap.add_argument("--publish", default=None, help="where the CSV, summary and plot go "
                    "(default docs/perf; --quick: the run directory)")
    ARGS = ap.parse_args()
    known = {c for s in SCENES for c in ("facet path sobol", "facet path sobol general",
                                          "facet path independent", "facet direct sobol",
                                          "facet direct sobol general",
                                          "facet direct independent", "povray brdf",
                                          "povray radiosity", "facet in blender", "cycles")}
    ARGS.contenders = [c.strip() for c in ARGS.contenders.split(",") if c.strip()]
    if ARGS.no_povray:
        ARGS.povray = None
    elif ARGS.povray is None and not ARGS.quick:
        # The full run is the one command that reproduces every table: POV-Ray joins whenever
        # the patched binary is built (build.sh builds it).
        built = os.path.join(ARGS.build, "povray_patch", "bin", "povray-facet")
        ARGS.povray = built if os.access(built, os.X_OK) else None
    for c in ARGS.contenders:
        if c not in known:
            ap.error("--contenders: unknown contender %r (have %s)" % (c, ", ".join(sorted(known))))
    if not 1 <= ARGS.pov_rungs <= len(POV_RAD_LADDER):
        ap.error("--pov-rungs: must be in [1, %d] (got %d)" % (len(POV_RAD_LADDER), ARGS.pov_rungs))
    if ARGS.level_csv and not ARGS.no_blender:
        ap.error("--level-csv: only with --no-blender (with Blender, Cycles is rendered)")
    if ARGS.level_csv and not os.path.exists(ARGS.level_csv):
        ap.error("--level-csv: no such file: %s" % ARGS.level_csv)
    if any(c.startswith("povray") for c in ARGS.contenders) and not ARGS.povray:
        ap.error("--contenders: POV-Ray contenders need --povray <povray-facet>")
    ARGS.out_root = (os.path.dirname(os.path.abspath(ARGS.out)) if ARGS.out
                     else os.path.join(ROOT, "out", "bench"))
    ARGS.out = ARGS.out or os.path.join(ARGS.out_root, "quick" if ARGS.quick else "time_error")
    ARGS.ref = os.path.join(ARGS.out_root, "ref")
    ARGS.publish = ARGS.publish or (ARGS.out if ARGS.quick else os.path.join(ROOT, "docs", "perf"))
    ARGS.facet = ARGS.facet or os.path.join(ARGS.build, "core", "cli", "facet")
    ARGS.addon_zip = os.path.join(ARGS.build, "blender_addon", "facet_blender.zip")
    for d in (ARGS.out, ARGS.ref, ARGS.publish):
        os.makedirs(d, exist_ok=True)
    if ARGS.replot:
        return replot()
    open(os.path.join(ARGS.out, "run.log"), "w").close()
    names = [s for s in ARGS.scenes.split(",") if s]
    for s in names:
        if s not in SCENES:
            sys.exit("time_error: unknown scene %r (have %s)" % (s, ", ".join(SCENES)))
    if ARGS.merge:
        if ARGS.reps_only or ARGS.resummarize or ARGS.quick:
            ap.error("--merge: only for a run that renders (not --reps-only, --resummarize, "
                     "--quick)")
        for key, fname in (("csv", "time_error.csv"), ("reps", "time_error_reps.csv")):
            path = os.path.join(ARGS.publish, fname)
            if os.path.exists(path):
                with open(path) as f:
                    KEPT[key] = [r for r in csv.DictReader(f) if r["scene"] not in names]
        path = os.path.join(ARGS.publish, "time_error_summary.md")
        if os.path.exists(path):
            with open(path) as f:
                KEPT["summary"] = f.read().rstrip("\n") + "\n\n"
    blender = None
    if not ARGS.no_blender:
        if not os.path.exists(ARGS.addon_zip):
            sys.exit("time_error: %s missing (configure with -DFACET_BUILD_BLENDER=ON and build)"
                     % ARGS.addon_zip)
        blender = Blender()
    t_start = time.time()
    load0 = os.getloadavg()
    rows, summary, checks, all_curves = [], [], [], {}
    try:
        for name in names:
            cfg = dict(SCENES[name])
            if ARGS.quick:
                cfg["size"] = tuple(v // QUICK["size_div"] for v in cfg["size"])
                cfg["ladder"] = QUICK["ladder"]
                cfg["ref_spp"] = cfg["ref_spp"] and QUICK["ref_spp"]
                cfg["cycles_ref_spp"] = QUICK["cycles_ref_spp"]
            CFG[name] = cfg
            if not (ARGS.reps_only or ARGS.resummarize):
                all_curves[name] = run_scene(name, cfg, blender, rows, summary, checks)
                if ARGS.merge:
                    replot()
                else:
                    plot(all_curves, os.path.join(ARGS.publish, "time_error.png"))
        if ARGS.resummarize:
            summary, checks = resummarize(names, blender)
            write_summary(summary, checks, os.path.join(ARGS.publish, "time_error_summary.md"),
                          RUN_META_KEEP())
            return
        if blender and ARGS.reps > 0 and not ARGS.quick:
            if not ARGS.reps_only:
                # The ladders' summary now, so that it exists even if the rounds are cut short.
                write_summary(summary, checks,
                              os.path.join(ARGS.publish, "time_error_summary.md"),
                              run_meta(t_start, load0) + " (Written before the timing rounds.)")
            timing_phase(names, read_rows(), blender, ARGS.reps)
    finally:
        if blender:
            blender.close()
    if ARGS.reps_only:
        return
    meta = run_meta(t_start, load0)
    write_summary(summary, checks, os.path.join(ARGS.publish, "time_error_summary.md"), meta)
    # The equal-error ratios from noise^2 x time fits (issue 25): from the published tables.
    import time_error_fit
    time_error_fit.write_fit(os.path.join(ARGS.publish, "time_error.csv"),
                             os.path.join(ARGS.publish, "time_error_reps.csv"),
                             os.path.join(ARGS.publish, "time_error_fit.md"))
    # Bias apart from noise (issue 25): difference of means and blockwise maps per contender.
    import time_error_bias
    log("  bias: " + time_error_bias.write_bias(ARGS.out, ARGS.ref, ARGS.publish))
    log(meta)
    for s in summary:
        log("  %-12s %-28s %s%.2f s  ratio %.3f" % (s["scene"], s["contender"], s["flag"],
                                                     s["seconds"], s["ratio"]))
    if ARGS.check:
        sys.exit(check(rows))


def run_meta(t_start, load0):
    """The summary's first paragraph: when, how long, the machine's load."""
    meta = ("Run of %s: %.0f min, %d threads, load average %.1f at the start and %.1f at the end "
            "(2-core machine shared with other work). Error level per scene: the RMSE of Cycles' "
            "top-budget render against Cycles' own reference." %
            (time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime(t_start)),
             (time.time() - t_start) / 60, ARGS.threads, load0[0], os.getloadavg()[0]))
    if ARGS.level_csv:
        meta += (" Cycles was not rendered in this run: its curve and level are those of %s "
                 "(another run, another machine load), so ratios to Cycles' time compare "
                 "across runs; ratios between this run's contenders are same-run."
                 % os.path.relpath(os.path.abspath(ARGS.level_csv), ROOT))
    return meta


def check(rows):
    """The smoke test's conditions; returns the exit code. Sobol Facet renders must lose at
    least 3/4 of their RMSE from the first budget to the last (4 -> 64 spp in --quick; measured
    1.2e-4 -> 1.3e-6 on point_plane), and point_plane's direct renders must reach
    1e-4 of the image mean against the analytic reference (measured ~1e-5 at 64 spp; a reference
    off by a fraction of a pixel or by a radiometric factor stays far above it)."""
    bad = []
    for name in sorted({r["scene"] for r in rows}):
        for cname in ("facet path sobol", "facet direct sobol"):
            rs = [r for r in rows if r["scene"] == name and r["contender"] == cname]
            if not rs or (name != "point_plane" and cname == "facet direct sobol"):
                continue
            first, last = rs[0]["rmse"], rs[-1]["rmse"]
            ok = last < 0.25 * first
            print("check: %s %s RMSE %.3g at %d spp -> %.3g at %d spp: %s"
                  % (name, cname, first, rs[0]["spp"], last, rs[-1]["spp"], "ok" if ok else "FAIL"))
            if not ok:
                bad.append((name, cname))
            if name == "point_plane":
                mean = REF_MEAN[name]
                ok = last < 1e-4 * mean
                print("check: point_plane %s RMSE %.3g < 1e-4 x image mean %.3g: %s"
                      % (cname, last, mean, "ok" if ok else "FAIL"))
                if not ok:
                    bad.append((name, cname + " vs analytic"))
    return 1 if bad else 0


ARGS = None
CFG = {}
# --merge: the published rows and summary of the scenes this run does not render
KEPT = {"csv": [], "reps": [], "summary": ""}
REF_MEAN = {}
CUR = {}
TARGETS = {}
if __name__ == "__main__":
    main()
