#!/usr/bin/python3
"""Texture filtering: lookup cost and image error of closest / linear / mipmap (issue 21).
Registered nowhere; run by hand:

    /usr/bin/python3 bench/texture_bench.py [--facet build/core/cli/facet] [--reps 5]
        [--ref-spp 2048] [--size 256x128] [--threads 2]

The scene: a 1024^2 checker of 1-texel checks (an 8-bit PNG, 0 and 255), repeated 16 times over
a 400 x 400 Lambertian quad running to the horizon under a constant environment of radiance 1
with max_depth 1. Every path sample then returns the texture's reflectance at the camera hit
exactly (cosine sampling: f cos / pdf = rho), so the image error is the texture filtering's
alone, not Monte Carlo noise.

1. Cost: the render time of the same 1-spp image (--spp-cost samples, default 16, to time more
   than start-up) with each filter, the median of --reps alternating runs; ratios to `closest`
   from the same run (a shared machine moves absolute times; the ratios hold).
2. Error: RMSE (and mean) at 1 spp against a supersampled reference: the mean of two renders of
   --ref-spp samples per pixel each (different seeds; 2 x 2048 = 4096 spp by default), with
   `closest`, i.e. the pixel-box integral of the piecewise-constant texture. The reference's
   own noise is reported as the RMSE between the two halves divided by 2.
"""
import argparse
import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

FILTERS = ("closest", "linear", "mipmap")


def scene_json(filt, width, height):
    return {
        "format": "facet-scene", "version": 1,
        "camera": {"position": [0, 1, 0], "look_at": [0, 0.6, -10], "fov": 40,
                   "width": width, "height": height},
        "shapes": [{"type": "quad",
                    "vertices": [[-200, 0, 10], [200, 0, 10], [200, 0, -390], [-200, 0, -390]],
                    "material": {"model": "lambert",
                                 "reflectance": {"texture": "checker.png", "colorspace": "linear",
                                                 "filter": filt, "uv_scale": [16, 16]}}}],
        "lights": [{"type": "environment", "radiance": 1}],
        "render": {"max_depth": 1, "integrator": "path"},
    }


def read_exr(facet, path, tmp):
    """Pixels of an EXR as float64 (h, w, c), converted to PFM with `facet convert`."""
    pfm = os.path.join(tmp, "x.pfm")
    subprocess.run([facet, "convert", path, "-o", pfm], check=True)
    with open(pfm, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        data = np.frombuffer(f.read(), dtype="<f4" if scale < 0 else ">f4")
    c = 3 if kind == b"PF" else 1
    return data.reshape(h, w, c)[::-1].astype(np.float64)  # PFM rows are bottom-up


def render(args, tmp, filt, spp, seed, out):
    sc = os.path.join(tmp, f"scene_{filt}.json")
    with open(sc, "w") as f:
        json.dump(scene_json(filt, *args.size), f)
    stats = os.path.join(tmp, "stats.json")
    subprocess.run([args.facet, "render", sc, "--spp", str(spp), "--seed", str(seed),
                    "--threads", str(args.threads), "--quiet", "-o", out,
                    "--stats-json", stats], check=True)
    with open(stats) as f:
        return json.load(f)["seconds"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--facet", default="build/core/cli/facet")
    ap.add_argument("--reps", type=int, default=5)
    ap.add_argument("--ref-spp", type=int, default=2048)
    ap.add_argument("--spp-cost", type=int, default=16)
    ap.add_argument("--size", default="256x128")
    ap.add_argument("--threads", type=int, default=2)
    args = ap.parse_args()
    args.size = tuple(int(v) for v in args.size.split("x"))
    with tempfile.TemporaryDirectory() as tmp:
        n = 1024
        checks = ((np.arange(n)[:, None] + np.arange(n)[None, :]) % 2 * 255).astype(np.uint8)
        Image.fromarray(checks, "L").save(os.path.join(tmp, "checker.png"))

        times = {f: [] for f in FILTERS}
        for _ in range(args.reps):
            for f in FILTERS:
                times[f].append(render(args, tmp, f, args.spp_cost, 1,
                                       os.path.join(tmp, "t.exr")))
        med = {f: statistics.median(times[f]) for f in FILTERS}

        ref_a, ref_b = os.path.join(tmp, "ref_a.exr"), os.path.join(tmp, "ref_b.exr")
        render(args, tmp, "closest", args.ref_spp, 11, ref_a)
        render(args, tmp, "closest", args.ref_spp, 12, ref_b)
        ra, rb = read_exr(args.facet, ref_a, tmp), read_exr(args.facet, ref_b, tmp)
        ref = 0.5 * (ra + rb)
        ref_noise = np.sqrt(np.mean((ra - rb) ** 2)) / np.sqrt(2) / np.sqrt(2)

        w, h = args.size
        print(f"texture_bench: {w}x{h}, 1024^2 1-texel checker x16 to the horizon, "
              f"reference {2 * args.ref_spp} spp closest (its RMSE noise ~{ref_noise:.4f})")
        print(f"{'filter':8} {'time (s, ' + str(args.spp_cost) + ' spp)':>20} {'ratio':>7} "
              f"{'RMSE 1 spp':>11} {'mean 1 spp':>11} {'mean ref':>9}")
        for f in FILTERS:
            out = os.path.join(tmp, f"{f}.exr")
            render(args, tmp, f, 1, 1, out)
            img = read_exr(args.facet, out, tmp)
            rmse = np.sqrt(np.mean((img - ref) ** 2))
            print(f"{f:8} {med[f]:20.3f} {med[f] / med['closest']:7.3f} {rmse:11.4f} "
                  f"{img.mean():11.4f} {ref.mean():9.4f}")


if __name__ == "__main__":
    sys.exit(main())
