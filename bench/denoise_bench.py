#!/usr/bin/python3
"""The denoiser (core/render/include/facet/render/denoise.h): MSE against time, with and
without denoising, and the time to denoise a 1920 x 1080 frame. Registered nowhere; run by hand:

    PYTHONPATH=build/core/python /usr/bin/python3 bench/denoise_bench.py \
        [--scenes cornell_box showcase] [--size 320] [--ref-spp 4096] [--threads 2] \
        [--realscenes cubes_4mats] [--plot docs/img/denoise_mse_time.png] [--breakdown]

For each scene (scaled to --size pixels wide), a reference of --ref-spp samples per pixel (its
own MSE, estimated from two halves of it, is printed and is far below every row's), then for
spp in 4 .. 128 the plain render (facet.render) and the denoised one (facet.render with
denoise=True: two half-buffers, the albedo/normal/depth AOVs at the same spp, denoise()): the
wall time of each call and its MSE against the reference. The denoised time includes the AOV
pass and the denoiser. A table in Markdown, the ratio 'plain MSE at 8x spp / denoised MSE at
spp' for the targets, and a log-log plot.

--realscenes adds scenes of the real-scene suite (tests/realscenes/scenes.py) at their bench
size, staged and exported in headless Blender (bench/denoise_realscene.py).

--breakdown instead: where the 16-spp denoised image's error lies, by pixel class (emitter
outlines, the brightest pixels, geometric and texture edges, the rest), with and without the
renderer's feature variances, beside plain 16, 64 and 128 spp (breakdown()).

The 1080p row: facet.denoise on 1920 x 1080 arrays (noise over a checker with edges), the
median of --reps runs, beside the time of numpy's copy of the same five arrays (the peer that
shows how loaded the machine is).
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import facet
from scaled_scene import load

ROOT = pathlib.Path(__file__).resolve().parents[1]
SPPS = (4, 8, 16, 32, 64, 128)


def mse(x, ref, keep=None):
    e = np.mean((x.astype(np.float64) - ref) ** 2, axis=2)
    return float(np.mean(e if keep is None else e[keep]))


def off_emitters(scene, threads):
    """The pixels farther than one pixel from any emitter seen (the emission AOV): the MSE
    without the coverage noise of a light's outline, which both half-buffers share."""
    em = np.asarray(facet.render_aovs(scene, ["emission"], spp=16, threads=threads)["emission"])
    lit = em.max(axis=2) > 0
    grown = lit.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            grown |= np.roll(np.roll(lit, dy, 0), dx, 1)
    return ~grown


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def scene_rows(name, args, scene=None):
    """The rows of one scene: a shipped one by name (scaled to --size), or `scene` (built)."""
    scene = scene if scene is not None else load(name, args.size)
    ref_a = facet.render(scene, spp=args.ref_spp // 2, seed=1000, threads=args.threads)
    ref_b = facet.render(scene, spp=args.ref_spp // 2, seed=2000, threads=args.threads)
    ref = (ref_a.astype(np.float64) + ref_b) / 2
    ref_own = mse(ref_a, ref_b) / 4  # the MSE of the mean of two independent halves
    keep = off_emitters(scene, args.threads)
    rows = []
    for spp in SPPS:
        plain, tp = timed(lambda: facet.render(scene, spp=spp, seed=7, threads=args.threads))
        den, td = timed(lambda: facet.render(scene, spp=spp, seed=7, threads=args.threads,
                                             denoise=True))
        rows.append({"spp": spp, "plain_s": tp, "plain_mse": mse(plain, ref), "denoised_s": td,
                     "denoised_mse": mse(den, ref), "plain_mse_off": mse(plain, ref, keep),
                     "denoised_mse_off": mse(den, ref, keep)})
    return {"scene": name, "size": list(ref.shape[1::-1]), "ref_spp": args.ref_spp,
            "ref_mse": ref_own, "outline_share": float(1 - keep.mean()), "rows": rows}


def pixel_classes(scene, ref, threads):
    """Exclusive pixel classes for the error breakdown, first match wins: 'emitter outline'
    (within one pixel of an emitter seen, off_emitters), 'brightest 1%' (of the reference's
    mean over channels), 'geometric edges' (within one pixel of a depth change above 2% or a
    normal change above 0.2 between 4-neighbours, or of a hit next to a miss), 'texture edges'
    (the same for an albedo change above 0.1 in a channel) and 'smooth' (the rest). Features
    from render_aovs at 64 spp."""
    f = facet.render_aovs(scene, ["albedo", "normal", "depth"], spp=64, seed=5, threads=threads)
    albedo, normal = np.asarray(f["albedo"]), np.asarray(f["normal"])
    z = np.asarray(f["depth"])[..., 0]
    miss = z > 1e9

    def grow(mask):
        out = mask.copy()
        for dy in (-1, 0, 1):
            for dx in (-1, 0, 1):
                out |= np.roll(np.roll(mask, dy, 0), dx, 1)
        return out

    def jumps(diff):
        """Pixels whose lower or right neighbour differs (diff(axis): a boolean per pixel and
        its next one along axis; np.roll wraps, so the last row / column is left out)."""
        m = np.zeros(z.shape, bool)
        for axis in (0, 1):
            d = diff(axis)
            if axis == 0:
                d[-1, :] = False
            else:
                d[:, -1] = False
            m |= d
        return m

    def pair(a, axis):
        return a, np.roll(a, -1, axis)

    def geo(axis):
        z0, z1 = pair(z, axis)
        m0, m1 = pair(miss, axis)
        n0, n1 = pair(normal, axis)
        dz = np.abs(z0 - z1) > 0.02 * np.minimum(z0, z1)
        return (m0 != m1) | (~m0 & ~m1 & (dz | (np.linalg.norm(n0 - n1, axis=2) > 0.2)))

    def tex(axis):
        a0, a1 = pair(albedo, axis)
        return np.abs(a0 - a1).max(axis=2) > 0.1

    lum = ref.mean(axis=2)
    classes = {"emitter outline": ~off_emitters(scene, threads),
               "brightest 1%": lum >= np.quantile(lum, 0.99),
               "geometric edges": grow(jumps(geo)),
               "texture edges": grow(jumps(tex))}
    taken = np.zeros(z.shape, bool)
    out = {}
    for name, m in classes.items():
        out[name] = m & ~taken
        taken |= m
    out["smooth"] = ~taken
    return out


def breakdown(name, args, scene=None):
    """Where the 16-spp denoised image's error is: per pixel class (pixel_classes), the share
    of the pixels and, for the denoised 16-spp image with and without the renderer's feature
    variances and the plain 16, 64 and 128-spp renders, the class's squared error summed and
    divided by the image's pixel count (so the classes add up to the image's MSE)."""
    scene = scene if scene is not None else load(name, args.size)
    ref_a = facet.render(scene, spp=args.ref_spp // 2, seed=1000, threads=args.threads)
    ref_b = facet.render(scene, spp=args.ref_spp // 2, seed=2000, threads=args.threads)
    ref = (ref_a.astype(np.float64) + ref_b) / 2
    spp = 16
    halves = [facet.render(scene, spp=spp, samples=s, seed=7, threads=args.threads)
              for s in ((0, spp // 2), (spp // 2, spp))]
    images = {
        "denoised 16, feature variances": facet.denoise_halves(
            scene, halves[0], halves[1], spp, 7, threads=args.threads),
        "denoised 16, none": facet.denoise_halves(
            scene, halves[0], halves[1], spp, 7, threads=args.threads, feature_variances=False)}
    for n in (16, 64, 128):
        images[f"plain {n}"] = facet.render(scene, spp=n, seed=7, threads=args.threads)
    classes = pixel_classes(scene, ref, args.threads)
    err = {k: np.mean((v.astype(np.float64) - ref) ** 2, axis=2) for k, v in images.items()}
    table = {c: {"pixels": float(m.mean()),
                 **{k: float(e[m].sum() / m.size) for k, e in err.items()}}
             for c, m in classes.items()}
    table["image"] = {"pixels": 1.0, **{k: float(e.mean()) for k, e in err.items()}}
    return {"scene": name, "size": list(ref.shape[1::-1]), "ref_spp": args.ref_spp,
            "ref_mse": mse(ref_a, ref_b) / 4, "breakdown": table}


def print_breakdown(r):
    print(f"\n### {r['scene']} ({r['size'][0]} x {r['size'][1]}), reference {r['ref_spp']} "
          f"spp (its own MSE {r['ref_mse']:.3g}): squared error per class / image pixels\n")
    cols = [k for k in r["breakdown"]["image"] if k != "pixels"]
    print("| class | pixels | " + " | ".join(cols) + " |")
    print("|---|---:|" + "---:|" * len(cols))
    for c, row in r["breakdown"].items():
        print(f"| {c} | {100 * row['pixels']:.1f}% | " +
              " | ".join(f"{row[k]:.3g}" for k in cols) + " |")


def realscene_rows(name, args):
    """A scene of the real-scene suite (tests/realscenes/scenes.py), staged in headless Blender
    at its bench size (Scene.bench) and exported by the addon: bench/denoise_realscene.py runs
    scene_rows there. Needs the addon installed as tests/blender installs it (`ctest
    --test-dir build -R blender.install`)."""
    bdir = os.path.join(args.build, "tests", "blender")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=os.path.join(bdir, "user_scripts"),
               BLENDER_USER_CONFIG=os.path.join(bdir, "user_config"), PYTHONNOUSERSITE="1")
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "rows.json")
        cmd = ["blender", "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
               "--python", str(ROOT / "bench" / "denoise_realscene.py"), "--", name, out,
               str(args.ref_spp), str(args.threads), "breakdown" if args.breakdown else "rows"]
        r = subprocess.run(cmd, env=env, capture_output=True, text=True)
        if r.returncode != 0 or not os.path.exists(out):
            raise RuntimeError("%s failed (exit %d):\n%s" % (name, r.returncode,
                                                             r.stdout[-3000:] + r.stderr[-3000:]))
        return json.loads(pathlib.Path(out).read_text())


def frame_timing(args):
    h, w = 1080, 1920
    rng = np.random.default_rng(3)
    yy, xx = np.mgrid[0:h, 0:w]
    albedo = np.where(((xx // 64 + yy // 64) % 2 == 0)[..., None], 0.8, 0.2).astype(np.float32)
    albedo = np.repeat(albedo, 3, axis=2)
    normal = np.zeros((h, w, 3), np.float32)
    normal[..., 2] = 1
    depth = np.full((h, w, 3), 5.0, np.float32)
    a = (albedo + rng.normal(0, 0.1, albedo.shape)).astype(np.float32)
    b = (albedo + rng.normal(0, 0.1, albedo.shape)).astype(np.float32)
    den, cpy = [], []
    for _ in range(args.reps):
        _, t = timed(lambda: facet.denoise(a, b, albedo, normal, depth, threads=args.threads))
        den.append(t)
        _, t = timed(lambda: [x.copy() for x in (a, b, albedo, normal, depth)])
        cpy.append(t)
    return {"denoise_s": statistics.median(den), "copy_s": statistics.median(cpy),
            "reps": args.reps}


def print_tables(results, frame):
    for r in results:
        print(f"\n### {r['scene']} ({r['size'][0]} x {r['size'][1]}), reference {r['ref_spp']} "
              f"spp (its own MSE {r['ref_mse']:.3g})\n")
        print("| spp | plain s | plain MSE | denoised s | denoised MSE | plain / denoised | "
              "off emitters: plain MSE | denoised MSE |")
        print("|---:|---:|---:|---:|---:|---:|---:|---:|")
        by_spp = {row["spp"]: row for row in r["rows"]}
        for row in r["rows"]:
            print(f"| {row['spp']} | {row['plain_s']:.2f} | {row['plain_mse']:.3g} | "
                  f"{row['denoised_s']:.2f} | {row['denoised_mse']:.3g} | "
                  f"{row['plain_mse'] / row['denoised_mse']:.1f} | "
                  f"{row['plain_mse_off']:.3g} | {row['denoised_mse_off']:.3g} |")
        if 16 in by_spp and 128 in by_spp:
            for label, key in (("", "_mse"), (" off emitters", "_mse_off")):
                r128, r64 = by_spp[128]["plain" + key], by_spp[64]["plain" + key]
                d16 = by_spp[16]["denoised" + key]
                print(f"\n{label}: plain 128 spp / denoised 16 spp = {r128 / d16:.2f} "
                      f"(target >= 1), plain 64 spp / denoised 16 spp = {r64 / d16:.2f}")
        print(f"\npixels within one pixel of an emitter: {100 * r['outline_share']:.2f}%")
    print(f"\n1920 x 1080 denoise: median {frame['denoise_s']:.2f} s over {frame['reps']} runs "
          f"(numpy copy of the inputs: {frame['copy_s']:.3f} s)")


def plot(results, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(results), figsize=(5 * len(results), 4), squeeze=False)
    for ax, r in zip(axes[0], results):
        rows = r["rows"]
        ax.loglog([x["plain_s"] for x in rows], [x["plain_mse"] for x in rows], "o-",
                  label="plain")
        ax.loglog([x["denoised_s"] for x in rows], [x["denoised_mse"] for x in rows], "s-",
                  label="denoised")
        for x in rows:
            ax.annotate(str(x["spp"]), (x["denoised_s"], x["denoised_mse"]), fontsize=7)
            ax.annotate(str(x["spp"]), (x["plain_s"], x["plain_mse"]), fontsize=7)
        ax.set_title(f"{r['scene']} {r['size'][0]}x{r['size'][1]}")
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel("MSE against the reference")
        ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=100)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", nargs="*", default=["cornell_box", "showcase"])
    ap.add_argument("--realscenes", nargs="*", default=[],
                    help="scenes of tests/realscenes/scenes.py, at their bench size")
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--size", type=int, default=320)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--plot", default="")
    ap.add_argument("--json", default="")
    ap.add_argument("--breakdown", action="store_true",
                    help="only the error breakdown of the 16-spp denoised image by pixel class")
    args = ap.parse_args()
    if args.breakdown:
        results = [breakdown(s, args) for s in args.scenes]
        results += [realscene_rows(s, args) for s in args.realscenes]
        for r in results:
            print_breakdown(r)
        if args.json:
            pathlib.Path(args.json).write_text(json.dumps(results, indent=1))
        return 0
    results = [scene_rows(s, args) for s in args.scenes]
    results += [realscene_rows(s, args) for s in args.realscenes]
    frame = frame_timing(args)
    print_tables(results, frame)
    if args.plot:
        plot(results, args.plot)
    if args.json:
        pathlib.Path(args.json).write_text(json.dumps({"scenes": results, "frame": frame},
                                                      indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
