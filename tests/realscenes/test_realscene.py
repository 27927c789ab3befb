"""One scene of the real-scene suite (scenes.py), Facet engine against Cycles at equal settings.

Run inside Blender: `blender -b --factory-startup --python test_realscene.py -- NAME OUTDIR
[ci|preview|bench|timeerror [WIDTH HEIGHT SPP] | adaptive WIDTH HEIGHT MAX_SPP REF_SPP]`
(tests/realscenes/CMakeLists.txt, bench/realscenes_bench.py, bench/realscenes_time_error.py,
bench/realscenes_adaptive.py).

Equal settings: the same resolution, samples per pixel and bounces (Facet max_depth = Cycles
bounces + 1); Cycles without clamping (Clamp Direct 0, Clamp Indirect 0), Filter Glossy 0, no
denoising, no adaptive sampling, light threshold 0, a 1-pixel box filter
(facet_testsupport.cycles_scene.cycles_settings). No compositing, no sequencer.

Measured per scene (written to OUTDIR/realscene_NAME.json, printed, and drawn in
OUTDIR/realscene_NAME.png: Facet | Cycles | |Facet - Cycles| x 4, one exposure for all three):
- the mean-luminance ratio Facet / Cycles (Rec. 709 luminance of the linear images; Cycles =
  the mean of its two seeds);
- the block RMSE: the root mean square over 8 x 8-pixel blocks of the difference of the
  blocks' mean luminance, Facet (seed 1) against Cycles (seed 1), and the noise floor: the same
  RMSE between Cycles seed 1 and Cycles seed 2;
- the conversion report (every line the Facet engine reported), both renderers' times.

Thresholds (the issue's; a scene's entry may state a documented difference instead):
- |mean ratio - 1| <= 2% (Scene.mean_tol). At the CI size (96 x 72, 32 spp; the glass scene
  128 spp) the image mean's own noise is well below that (the two Cycles seeds' means differ
  by at most 0.45%, glass 1.1% at 32 spp), so 2% is a systematic difference: a lamp in the wrong units, a texture in the wrong colour
  space, a lost Mapping rotation (each 10% or more; see test_textures.py for such cases).
- block RMSE <= 3 x the noise floor (Scene.rmse_factor). If Facet and Cycles converge to the
  same image with the same noise, the expected ratio is 1 (both differences are between two
  independent renders); 3 allows Facet's noise to be up to ~2.8x Cycles' per block (a different
  sampler), while a misplaced shadow, a missing normal map or a wrong roughness moves whole
  blocks by many noise units.
- every report line matches one of the scene's `explained` patterns (each a documented
  difference, see scenes.py); any other line fails the test: no unexplained report entry.
A scene with `pending` set is skipped (exit code 77, CTest SKIP_RETURN_CODE) naming the
missing feature.
"""
import json
import os
import re
import sys

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "support", "python"))
sys.path.insert(0, HERE)
from facet_testsupport import blender_harness as bt  # noqa: E402
from facet_testsupport import cycles_scene as cs  # noqa: E402
import scenes  # noqa: E402

SKIP = 77
BLOCK = 8
LUMA = np.array([0.2126, 0.7152, 0.0722])  # Rec. 709 / sRGB primaries, linear


def luminance(img):
    return img[..., :3] @ LUMA


def block_means(y):
    h, w = y.shape
    h, w = h - h % BLOCK, w - w % BLOCK
    return y[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).mean(axis=(1, 3))


def block_rmse(a, b):
    return float(np.sqrt(np.mean((block_means(luminance(a)) - block_means(luminance(b))) ** 2)))


def _srgb(x):
    x = np.clip(x, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def side_by_side(facet, cycles, path):
    """Facet | Cycles | |difference| x 4, one exposure (the Cycles image's 99th luminance
    percentile to 0.9), sRGB, written as an 8-bit PNG through Blender's image writer."""
    scale = 0.9 / max(np.percentile(luminance(cycles), 99), 1e-6)
    gap = np.ones((facet.shape[0], 2, 3))
    row = np.concatenate([facet * scale, gap, cycles * scale, gap,
                          np.abs(facet - cycles) * scale * 4], axis=1)
    h, w = row.shape[:2]
    rgba = np.ones((h, w, 4), np.float32)
    rgba[..., :3] = _srgb(row)
    img = bpy.data.images.new("side_by_side", w, h, alpha=False)
    img.pixels.foreach_set(rgba[::-1].ravel())
    img.filepath_raw = path
    img.file_format = 'PNG'
    img.save()
    bpy.data.images.remove(img)


def unexplained(problems, patterns):
    return [p for p in problems if not any(re.search(pat, p) for pat in patterns)]


def settings(scene, width, height, spp, max_depth, light_selection):
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = width, height, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.use_border = False
    r.use_compositing = False
    r.use_sequencer = False
    scene.facet.spp = spp
    scene.facet.max_depth = max_depth
    scene.facet.light_selection = light_selection
    cs.cycles_settings(scene, samples=spp, seed=1, max_depth=max_depth)
    if scene.world is not None:
        # Cycles' world importance map (a sampling density only: its resolution changes the
        # noise, not the expected image); at its default 1024 building it takes ~9 s here.
        scene.world.cycles.sample_map_resolution = 256


def noise_sigma(a, b):
    """The per-pixel noise of one render: the RMSE between two seeds' images over every pixel
    and channel, / sqrt(2) (the seeds are independent: MSE(a - b) = 2 Var)."""
    return float(np.sqrt(np.mean((a - b) ** 2) / 2.0))


def timed_render(scene, engine, path, seed):
    """cs.render with the process's CPU seconds (user + system, every render thread)
    around it: the machine is shared, so CPU time is the steadier measure."""
    import resource
    r0 = resource.getrusage(resource.RUSAGE_SELF)
    img, wall = cs.render(scene, engine, path, seed, problems_are_errors=False)
    r1 = resource.getrusage(resource.RUSAGE_SELF)
    return img, wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def time_error(scene, name, out, width, height, spp):
    """Profile `timeerror` (bench/realscenes_time_error.py): each engine at its defaults (Facet's
    light selection left at the panel's default; Cycles unbiased, non-adaptive, as `settings`)
    rendered twice, seeds 1 and 2, interleaved F C F C. Equal-error time ratio
    (t_F / t_C) (sigma_F / sigma_C)^2 (issue 34's measure), by CPU and by wall time (each the
    mean of the two renders: export, sync and BVH included)."""
    scene.facet.property_unset("light_selection")
    base = os.path.join(out, "timeerror_%s" % name)
    runs = {}
    for seed in (1, 2):
        for engine in ('FACET', 'CYCLES'):
            runs[engine, seed] = timed_render(scene, engine,
                                              "%s_%s%d.exr" % (base, engine.lower(), seed), seed)
    res = {"scene": name, "width": width, "height": height, "spp": spp}
    for engine in ('FACET', 'CYCLES'):
        (a, w1, c1), (b, w2, c2) = runs[engine, 1], runs[engine, 2]
        key = engine.lower()
        res[key + "_sigma"] = noise_sigma(a, b)
        res[key + "_wall"] = [w1, w2]
        res[key + "_cpu"] = [c1, c2]
        res[key + "_mean"] = float(0.5 * (luminance(a).mean() + luminance(b).mean()))
    sq = (res["facet_sigma"] / max(res["cycles_sigma"], 1e-30)) ** 2
    for m in ("wall", "cpu"):
        res["ratio_" + m] = sum(res["facet_" + m]) / max(sum(res["cycles_" + m]), 1e-9) * sq
    res["noise_ratio"] = res["facet_sigma"] / max(res["cycles_sigma"], 1e-30)
    res["mean_ratio"] = res["facet_mean"] / max(res["cycles_mean"], 1e-30)
    with open(base + ".json", "w") as f:
        json.dump(res, f, indent=1)
    print("%s: noise Facet/Cycles %.3f, CPU %.1f/%.1f s, equal-error ratio CPU %.3f wall %.3f"
          % (name, res["noise_ratio"], sum(res["facet_cpu"]) / 2, sum(res["cycles_cpu"]) / 2,
             res["ratio_cpu"], res["ratio_wall"]))



def mse(a, b):
    """Mean squared difference over every pixel and channel."""
    return float(np.mean((a - b) ** 2))


# Profile `adaptive`: the noise thresholds swept (Cycles' default is 0.01).
CYCLES_THRESHOLDS = (0.1, 0.03, 0.01)
FACET_THRESHOLDS = (0.03, 0.01)  # then halved (or tripled) until Cycles' MSE at 0.01 is bracketed
REFERENCE_SEED = 101


def adaptive(scene, name, out, width, height, max_spp, ref_spp):
    """Profile `adaptive` (bench/realscenes_adaptive.py): both engines with adaptive sampling on,
    Min Samples 0 (automatic), Samples = max_spp the cap, each at its defaults otherwise (Facet's
    light selection left at the panel's default; Cycles unbiased: Clamp 0, Filter Glossy 0, the
    suite's bounces), seed 1; Cycles at CYCLES_THRESHOLDS, Facet from FACET_THRESHOLDS on until
    its points bracket Cycles' MSE at 0.01 (halving down to 0.00125 while the MSE falls,
    tripling up to 0.3). The reference is the mean of a non-adaptive Facet and a non-adaptive Cycles render at ref_spp
    (seed REFERENCE_SEED): neither engine's own small systematic difference favours it. Its own
    error is estimated from its halves: MSE(ref_F, ref_C) / 4 (the halves' noise and, if any,
    their difference of means, each entering the reference by half). Every render records
    MSE against the reference, CPU seconds (user + system of this process around the render)
    and wall seconds."""
    from facet_blender import export as ex
    scene.facet.property_unset("light_selection")
    base = os.path.join(out, "adaptive_%s" % name)
    res = {"scene": name, "width": width, "height": height, "max_spp": max_spp,
           "ref_spp": ref_spp, "cycles": [], "facet": []}
    c = scene.cycles
    c.use_adaptive_sampling = False
    scene.facet.adaptive_threshold = 0.0
    c.samples = scene.facet.spp = ref_spp
    ref = {}
    for engine in ('FACET', 'CYCLES'):
        img, wall, cpu = timed_render(scene, engine, "%s_ref_%s.exr" % (base, engine.lower()),
                                      REFERENCE_SEED)
        ref[engine] = img
        res["ref_%s_cpu" % engine.lower()] = cpu
        res["ref_%s_mean" % engine.lower()] = float(luminance(img).mean())
    reference = 0.5 * (ref['FACET'] + ref['CYCLES'])
    res["ref_mse"] = mse(ref['FACET'], ref['CYCLES']) / 4.0
    res["mean_ratio"] = res["ref_facet_mean"] / max(res["ref_cycles_mean"], 1e-30)

    def point(engine, t):
        if engine == 'CYCLES':
            c.use_adaptive_sampling = True
            c.adaptive_threshold, c.adaptive_min_samples, c.samples = t, 0, max_spp
        else:
            fs = scene.facet
            fs.adaptive_threshold, fs.adaptive_min_samples, fs.spp = t, 0, max_spp
            rs = ex.export_render_settings(scene)  # what the engine renders with
            if (rs.get("adaptive_threshold") != fs.adaptive_threshold
                    or rs.get("adaptive_min_samples") != 0 or rs["spp"] != max_spp):
                raise RuntimeError("Facet's adaptive settings are not exported as set: %s" % rs)
        img, wall, cpu = timed_render(scene, engine, "%s_%s_%g.exr" % (base, engine.lower(), t),
                                      1)
        p = {"threshold": t, "cpu": cpu, "wall": wall, "mse": mse(img, reference),
             "mean": float(luminance(img).mean())}
        res[engine.lower()].append(p)
        print("%s %s threshold %g: MSE %.4g, CPU %.2f s, wall %.2f s"
              % (name, engine, t, p["mse"], cpu, wall), flush=True)
        return p

    for t in CYCLES_THRESHOLDS:
        point('CYCLES', t)
    target = res["cycles"][-1]["mse"]
    for t in FACET_THRESHOLDS:
        point('FACET', t)
    while min(p["mse"] for p in res["facet"]) > target:
        t = min(p["threshold"] for p in res["facet"]) / 2
        best = min(p["mse"] for p in res["facet"])
        if t < 0.00125 or point('FACET', t)["mse"] > 0.999 * best:
            break  # (no gain: every tile at the cap, Samples)
    while max(p["mse"] for p in res["facet"]) < target:
        t = max(p["threshold"] for p in res["facet"]) * 3
        if t > 0.3:
            break
        point('FACET', t)
    with open(base + ".json", "w") as f:
        json.dump(res, f, indent=1)


def main():
    name, out = bt.args()[0], bt.args()[1]
    profile = bt.args()[2] if len(bt.args()) > 2 else "ci"
    entry = scenes.by_name(name)
    if entry.pending and profile == "ci":
        print("SKIPPED: scene '%s' needs %s, not on this branch yet" % (name, entry.pending))
        sys.stdout.flush()
        os._exit(SKIP)
    bt.enable_addon()
    scenes.empty_scene()
    entry.stage(bpy.context.scene)
    scene = bpy.context.scene  # staging may have opened a .blend
    # Profiles: ci (the CTest size, checked), preview (the CTest size, pending scenes too, not
    # checked), bench (bench/realscenes_bench.py: larger, not checked, with Power selection too).
    width, height, spp = entry.bench if profile in ("bench", "timeerror", "adaptive") else entry.ci
    if len(bt.args()) > 5:  # explicit width height spp (bench/realscenes_bench.py --size/--spp)
        width, height, spp = (int(v) for v in bt.args()[3:6])
    settings(scene, width, height, spp, entry.max_depth, entry.light_selection)
    if profile == "timeerror":
        return time_error(scene, name, out, width, height, spp)
    if profile == "adaptive":  # W H MAX_SPP REF_SPP (bench/realscenes_adaptive.py)
        return adaptive(scene, name, out, width, height, spp, int(bt.args()[6]))
    base = os.path.join(out, "realscene_%s" % name)
    from facet_blender import hooks
    facet, t_facet = cs.render(scene, 'FACET', base + "_facet.exr", 1,
                                 problems_are_errors=False)
    problems = list(hooks.last_problems)
    c1, t_cycles = cs.render(scene, 'CYCLES', base + "_cycles1.exr", 1)
    c2, _ = cs.render(scene, 'CYCLES', base + "_cycles2.exr", 2)
    mean_c = 0.5 * (luminance(c1).mean() + luminance(c2).mean())
    ratio = float(luminance(facet).mean() / max(mean_c, 1e-12))
    seed_ratio = float(luminance(c1).mean() / max(luminance(c2).mean(), 1e-12))
    rmse = block_rmse(facet, c1)
    floor = block_rmse(c1, c2)
    bad = unexplained(problems, entry.explained)
    extra = {}
    if profile != "ci" and entry.light_selection != "power":
        # What Facet's default light selection gives (same mean, more noise: scenes.py).
        scene.facet.light_selection = "power"
        fp, t_power = cs.render(scene, 'FACET', base + "_facet_power.exr", 1,
                                problems_are_errors=False)
        extra = {"power_mean_ratio": float(luminance(fp).mean() / max(mean_c, 1e-12)),
                 "power_block_rmse": block_rmse(fp, c1), "power_facet_seconds": t_power}
    side_by_side(facet, c1, base + ".png")
    result = {"scene": name, "asset": entry.asset, "features": list(entry.features),
              "pending": entry.pending, "width": width, "height": height, "spp": spp,
              "max_depth": entry.max_depth, "mean_ratio": ratio, "cycles_seed_ratio": seed_ratio,
              "block_rmse": rmse, "noise_floor": floor,
              "rmse_over_floor": rmse / max(floor, 1e-12), "mean_tol": entry.mean_tol,
              "rmse_factor": entry.rmse_factor, "known": entry.known,
              "facet_seconds": t_facet, "cycles_seconds": t_cycles,
              "facet_phases": dict(hooks.last_timings), "report": problems,
              "unexplained": bad, "png": os.path.basename(base + ".png"),
              "light_selection": entry.light_selection, **extra}
    result["pass"] = (abs(ratio - 1) <= entry.mean_tol
                      and rmse <= entry.rmse_factor * floor and not bad)
    with open(base + ".json", "w") as f:
        json.dump(result, f, indent=1)
    print("report (%d lines):" % len(problems))
    for p in problems:
        print("  " + p)
    print("%s: mean ratio %.4f (Cycles seeds %.4f), block RMSE %.5f, noise floor %.5f "
          "(%.2fx), Facet %.2f s, Cycles %.2f s"
          % (name, ratio, seed_ratio, rmse, floor, rmse / max(floor, 1e-12), t_facet, t_cycles))
    if profile != "ci":
        return
    bt.check(not bad, "no unexplained report entry (%s)" % bad)
    bt.check(abs(ratio - 1) <= entry.mean_tol, "mean luminance within %.1f%% of Cycles (%.4f)"
             % (100 * entry.mean_tol, ratio))
    bt.check(rmse <= entry.rmse_factor * floor, "block RMSE %.5f <= %g x noise floor %.5f"
             % (rmse, entry.rmse_factor, floor))


bt.run(main)
