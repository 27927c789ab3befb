#!/usr/bin/python3
"""Texture memory bound: a scene with more than 2 GB of texture files rendered within a stated
texture cache (`--texture-memory`), against the same scene unbounded (issue 21; docs/textures.md,
"Texture memory"; numbers in docs/performance.md). Registered nowhere; run by hand:

    /usr/bin/python3 bench/texture_cache_bench.py [--facet build/core/cli/facet]
        [--dir /tmp/facet_texcache_bench] [--count 10] [--size 8192] [--cache 512]
        [--unbounded 16384] [--width 960] [--height 540] [--spp 4] [--threads 2]
        [--baseline OLD_FACET [--reps 5]] [--clean]

1. Generates --count RGB 8-bit PNGs of --size^2 texels of uniform noise (noise does not
   compress, so they are stored uncompressed (zlib level 0) and are as large as their texels:
   10 x 8192^2 x 3 B = 2.01 GB) in --dir,
   once (kept for later runs; never in the repository). Delete them with --clean.
2. The scene: one 4 x 200 floor strip per texture, side by side, running from just below the
   camera (height 0.25) to the horizon, each texture repeated 50 times along its strip
   (uv_scale [1, 50]: 2048 texels per unit) with the default mipmap filter, under a constant
   environment, path tracing to depth 3: near the camera level 1 is read (about 2 texels per
   pixel at the bottom of a 960-pixel-wide image), far away the coarse levels, at the sides
   grazing views of the outer strips, and bounces read wherever they land.
3. Renders it with `--texture-memory --cache` (MiB) and with `--texture-memory --unbounded`,
   each under /usr/bin/time -v: wall time, peak RSS, and the texture counters of --stats-json
   (images paged, whole bytes, tile cache peak, hit rate). The two images must be identical bit
   for bit (`facet diff --json`: largest difference 0; and the EXR files' bytes). Prints
   markdown.

4. With --baseline FACET (a `facet` built from the commit before paging): the fast path, for
   scenes that fit the bound. bench/cornell_textured.json (procedural checkers) and the scene of
   step 2 with --baseline-count textures of --baseline-size^2 (all whole under the default
   bound), each rendered by both binaries alternating --reps times (1 thread, CPU seconds of
   the process: steadier than wall time on a shared machine); medians, the median of the
   per-rep ratios (this / baseline), and whether the images are identical bit for bit.

Disk: a paged image's pyramid is spilled as float texels, 4/3 x 4 B per channel and texel
(10.7 GB for the default set) into $FACET_TEXTURE_CACHE_DIR or $TMPDIR; the unbounded render
needs as much RAM instead.
"""
import argparse
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys

import numpy as np
from PIL import Image

ROOT = pathlib.Path(__file__).resolve().parents[1]

Image.MAX_IMAGE_PIXELS = None


def make_textures(d, count, size):
    d.mkdir(parents=True, exist_ok=True)
    files = []
    for i in range(count):
        p = d / f"noise_{size}_{i}.png"
        if not p.exists():
            rng = np.random.default_rng(1000 + i)
            a = rng.integers(0, 256, size=(size, size, 3), dtype=np.uint8)
            tmp = p.with_suffix(".tmp.png")
            Image.fromarray(a, "RGB").save(tmp, compress_level=0)
            tmp.rename(p)
        files.append(p)
    return files


def scene(files, width, height, spp):
    n = len(files)
    shapes = []
    for i, f in enumerate(files):
        x0 = 4.0 * (i - n / 2)
        shapes.append({
            "type": "quad",
            "vertices": [[x0, 0, 4], [x0 + 4, 0, 4], [x0 + 4, 0, -196], [x0, 0, -196]],
            "material": {"model": "lambert",
                         "reflectance": {"texture": str(f), "uv_scale": [1, 50]}}})
    return {"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0.25, 4.5], "look_at": [0, 0, -10], "fov": 70,
                       "width": width, "height": height},
            "shapes": shapes,
            "lights": [{"type": "environment", "radiance": 1}],
            "render": {"integrator": "path", "spp": spp, "max_depth": 3, "seed": 1}}


def run(facet, scene_path, out, mib, threads):
    stats = out.with_suffix(".json")
    cmd = ["/usr/bin/time", "-v", str(facet), "render", str(scene_path), "-o", str(out),
           "--texture-memory", str(mib), "--threads", str(threads), "-q",
           "--stats-json", str(stats)]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed: {' '.join(cmd)}\n{r.stderr}")
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1))
    m = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): (?:(\d+):)?(\d+):([\d.]+)",
                  r.stderr)
    wall = int(m.group(1) or 0) * 3600 + int(m.group(2)) * 60 + float(m.group(3))
    cpu = sum(float(re.search(rf"{k} time \(seconds\): ([\d.]+)", r.stderr).group(1))
              for k in ("User", "System"))
    s = json.loads(stats.read_text())
    return {"rss_mib": rss / 1024, "wall": wall, "cpu": cpu, "render_s": s["seconds"],
            **s["texture_memory"]}


def compare_images(a, b, facet):
    """`facet diff --json` of two renders: identical when the largest difference is 0."""
    r = subprocess.run([str(facet), "diff", str(a), str(b), "--json"],
                       capture_output=True, text=True, check=True)
    return json.loads(r.stdout)


def cpu_seconds(cmd):
    r = subprocess.run(["/usr/bin/time", "-f", "%U %S"] + [str(c) for c in cmd],
                       capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"failed: {' '.join(map(str, cmd))}\n{r.stderr}")
    u, s = r.stderr.strip().splitlines()[-1].split()
    return float(u) + float(s)


def fast_path(a, d):
    """Step 4: this build against --baseline on scenes that fit the bound."""
    import statistics
    files = make_textures(d / "small", a.baseline_count, a.baseline_size)
    small = d / "small" / "scene.json"
    small.write_text(json.dumps(scene(files, 320, 180, 4)))
    cases = [("cornell_textured 256^2 region, 16 spp", ROOT / "bench" / "cornell_textured.json",
              ["--spp", "16", "--region", "128,128,384,384"]),
             (f"{a.baseline_count} x {a.baseline_size}^2 PNG floor, 320x180, 4 spp", small, [])]
    print("\n| scene | baseline CPU s (median) | this CPU s (median) | median ratio | identical |")
    print("|---|---|---|---|---|")
    for name, path, extra in cases:
        t_base, t_this, ratios = [], [], []
        for rep in range(a.reps):
            outs = []
            for tag, exe in (("base", a.baseline), ("this", a.facet)):
                out = d / f"fast_{tag}.exr"
                t = cpu_seconds([exe, "render", path, "-o", out, "--threads", "1", "-q"] + extra)
                (t_base if tag == "base" else t_this).append(t)
                outs.append(out)
            ratios.append(t_this[-1] / t_base[-1])
        same = compare_images(outs[0], outs[1], a.facet)["max_abs"] == 0
        print(f"| {name} | {statistics.median(t_base):.3f} | {statistics.median(t_this):.3f} "
              f"| {statistics.median(ratios):.4f} | {'yes' if same else 'NO'} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--facet", default=str(ROOT / "build" / "core" / "cli" / "facet"))
    ap.add_argument("--dir", default="/tmp/facet_texcache_bench")
    ap.add_argument("--count", type=int, default=10)
    ap.add_argument("--size", type=int, default=8192)
    ap.add_argument("--cache", type=float, default=512)
    ap.add_argument("--unbounded", type=float, default=16384)
    ap.add_argument("--width", type=int, default=960)
    ap.add_argument("--height", type=int, default=540)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--skip-unbounded", action="store_true")
    ap.add_argument("--baseline", help="a facet binary without paging: step 4 only")
    ap.add_argument("--baseline-count", type=int, default=4)
    ap.add_argument("--baseline-size", type=int, default=2048)
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--clean", action="store_true", help="delete the generated textures")
    a = ap.parse_args()
    d = pathlib.Path(a.dir)
    if a.clean:
        shutil.rmtree(d, ignore_errors=True)
        return
    if a.baseline:
        fast_path(a, d)
        return
    files = make_textures(d, a.count, a.size)
    total = sum(f.stat().st_size for f in files)
    sp = d / "scene.json"
    sp.write_text(json.dumps(scene(files, a.width, a.height, a.spp)))
    runs = {"bounded": run(a.facet, sp, d / "bounded.exr", a.cache, a.threads)}
    if not a.skip_unbounded:
        runs["unbounded"] = run(a.facet, sp, d / "unbounded.exr", a.unbounded, a.threads)
    print(f"{a.count} x {a.size}^2 RGB 8-bit PNG, {total / 1e9:.2f} GB of files "
          f"({total / 2**30:.2f} GiB); {a.width}x{a.height}, {a.spp} spp, path depth 3, "
          f"{a.threads} threads\n")
    print("| --texture-memory | paged images | whole MiB | tile peak MiB | peak texels MiB "
          "| hit rate | misses | evictions | peak RSS MiB | wall s | CPU s | render s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for name, r in runs.items():
        mib = a.cache if name == "bounded" else a.unbounded
        print(f"| {mib:g} MiB ({name}) | {r['paged_images']} | {r['whole_bytes'] / 2**20:.0f} "
              f"| {r['tile_peak'] / 2**20:.1f} | {r['peak_bytes'] / 2**20:.1f} "
              f"| {r['hit_rate']:.5f} | {r['misses']} | {r.get('evictions', 0)} "
              f"| {r['rss_mib']:.0f} | {r['wall']:.1f} | {r['cpu']:.1f} | {r['render_s']:.2f} |")
    if "unbounded" in runs:
        dj = compare_images(d / "bounded.exr", d / "unbounded.exr", a.facet)
        same = dj["max_abs"] == 0 and dj["nonfinite_pixels"] == 0
        same_bytes = (d / "bounded.exr").read_bytes() == (d / "unbounded.exr").read_bytes()
        print(f"\nbounded vs unbounded image: {'identical' if same else 'DIFFERENT'} "
              f"(max |difference| {dj['max_abs']}, RMSE {dj['rmse']}; EXR files "
              f"{'byte-identical' if same_bytes else 'differ in bytes'})")

if __name__ == "__main__":
    main()
