#!/usr/bin/python3
"""Texture memory bound: a scene with more than 2 GB of texture files rendered within a stated
texture cache (`--texture-memory`), against the same scene unbounded (issue 21; docs/textures.md,
"Texture memory"; numbers in docs/performance.md). Registered nowhere; run by hand:

    /usr/bin/python3 bench/texture_cache_bench.py [--facet build/core/cli/facet]
        [--dir /tmp/facet_texcache_bench] [--count 10] [--size 8192] [--cache 512]
        [--unbounded 16384] [--width 640] [--height 360] [--spp 4] [--threads 2] [--keep]

1. Generates --count RGB 8-bit PNGs of --size^2 texels of uniform noise (noise does not
   compress, so the files are as large as their texels: 10 x 8192^2 x 3 B = 2.01 GB) in --dir,
   once (kept for later runs; never in the repository). Delete them with --clean.
2. The scene: one 1 x 64 floor strip per texture running from the camera to the horizon, each
   texture repeated 8 times along its strip (uv_scale [1, 8]) with the default mipmap filter,
   under a constant environment, path tracing to depth 3: near the camera the finest levels are
   read, far away the coarse ones, and bounces read wherever they land.
3. Renders it with `--texture-memory --cache` (MiB) and with `--texture-memory --unbounded`,
   each under /usr/bin/time -v: wall time, peak RSS, and the texture counters of --stats-json
   (images paged, whole bytes, tile cache peak, hit rate). The two images must be identical bit
   for bit (compared as float arrays from the EXR files). Prints markdown.

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
            Image.fromarray(a, "RGB").save(tmp, compress_level=1)
            tmp.rename(p)
        files.append(p)
    return files


def scene(files, width, height, spp):
    n = len(files)
    shapes = []
    for i, f in enumerate(files):
        x0 = -n / 2 + i
        shapes.append({
            "type": "quad",
            "vertices": [[x0, 0, 4], [x0 + 1, 0, 4], [x0 + 1, 0, -60], [x0, 0, -60]],
            "material": {"model": "lambert",
                         "reflectance": {"texture": str(f), "uv_scale": [1, 8]}}})
    return {"format": "facet-scene", "version": 1,
            "camera": {"position": [0, 0.5, 4.5], "look_at": [0, 0, -10], "fov": 70,
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


def read_exr(p, facet):
    # The renderer's own EXR reader is not exposed; the float pixels through PIL are not
    # either: compare with `facet diff --json` (max rel error 0 and RMSE 0 mean identical).
    r = subprocess.run([str(facet), "diff", str(p[0]), str(p[1]), "--json"],
                       capture_output=True, text=True, check=True)
    return json.loads(r.stdout)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--facet", default=str(ROOT / "build" / "core" / "cli" / "facet"))
    ap.add_argument("--dir", default="/tmp/facet_texcache_bench")
    ap.add_argument("--count", type=int, default=10)
    ap.add_argument("--size", type=int, default=8192)
    ap.add_argument("--cache", type=float, default=512)
    ap.add_argument("--unbounded", type=float, default=16384)
    ap.add_argument("--width", type=int, default=640)
    ap.add_argument("--height", type=int, default=360)
    ap.add_argument("--spp", type=int, default=4)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--skip-unbounded", action="store_true")
    ap.add_argument("--clean", action="store_true", help="delete the generated textures")
    a = ap.parse_args()
    d = pathlib.Path(a.dir)
    if a.clean:
        shutil.rmtree(d, ignore_errors=True)
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
        dj = read_exr((d / "bounded.exr", d / "unbounded.exr"), a.facet)
        same = dj.get("rmse", 1) == 0 and dj.get("max_rel_error", 1) == 0
        print(f"\nbounded vs unbounded image: {'identical' if same else 'DIFFERENT'} ({dj})")


if __name__ == "__main__":
    main()
