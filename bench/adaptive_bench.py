#!/usr/bin/python3
"""Adaptive sampling (render.h, "Adaptive sampling"): equal-error time against the plain render
of the same scene in the same run. Registered nowhere; run by hand:

    PYTHONPATH=build/core/python /usr/bin/python3 bench/adaptive_bench.py \
        [--scenes cornell_box showcase brushed] [--size 320] [--ref-spp 4096] [--threads 2] \
        [--thresholds 0.05 0.02 0.01] [--spp 1024] [--reps 3]

For each scene (scaled to --size pixels wide): a reference of --ref-spp samples per pixel (two
seeds, whose difference gives its own MSE, printed: it must be far below every row's); the plain
render at spp 16 .. 1024 and the adaptive render at each threshold (capped at --spp), the median
wall time of --reps runs of each and its MSE against the reference (the reference's own MSE
subtracted). Each adaptive row reads as an equal-error time ratio: its time over the time the
plain render needs for the same MSE (log time interpolated in log MSE between the plain rows
around it). Below 1, adaptive sampling wins. A Markdown table.
"""
import argparse
import math
import pathlib
import statistics
import time

import numpy as np

import facet
from scaled_scene import load

ROOT = pathlib.Path(__file__).resolve().parents[1]
PLAIN_SPP = (16, 32, 64, 128, 256, 512, 1024)


def timed(args, fn):
    times, out = [], None
    for _ in range(args.reps):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return out, statistics.median(times)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", nargs="+", default=["cornell_box", "showcase", "brushed"])
    ap.add_argument("--size", type=int, default=320)
    ap.add_argument("--ref-spp", type=int, default=4096)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--thresholds", type=float, nargs="+", default=[0.05, 0.02, 0.01])
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--reps", type=int, default=3)
    args = ap.parse_args()
    print("| scene | render | mean spp | time s | MSE | equal-error time vs plain |")
    print("|---|---|---|---|---|---|")
    for name in args.scenes:
        scene = load(name, args.size)
        half = args.ref_spp // 2
        a = facet.render(scene, spp=half, seed=1000, threads=args.threads).astype(np.float64)
        b = facet.render(scene, spp=half, seed=2000, threads=args.threads).astype(np.float64)
        ref = (a + b) / 2
        ref_mse = float(np.mean((a - b) ** 2)) / 4  # MSE of the mean of two halves
        print(f"| {name} | reference {args.ref_spp} spp | | | {ref_mse:.3g} (own) | |")

        def mse(img):
            return float(np.mean((img.astype(np.float64) - ref) ** 2)) - ref_mse

        plain = []
        for spp in PLAIN_SPP:
            img, t = timed(args, lambda: facet.render(scene, spp=spp, seed=7,
                                                      threads=args.threads))
            plain.append((t, mse(img)))
            print(f"| {name} | plain | {spp} | {t:.3f} | {plain[-1][1]:.3g} | |")
        # The plain renders' time at an MSE: log t interpolated linearly in log MSE between the
        # two plain rows around it (their MSE falls monotonically with spp here).
        lt = np.log([p[0] for p in plain])
        lm = np.log([max(p[1], 1e-30) for p in plain])
        for thr in args.thresholds:
            session_stats = {}

            def run():
                s = facet.RenderSession(scene, spp=args.spp, seed=7, threads=args.threads,
                                        adaptive_threshold=thr)
                s.render()
                session_stats["mean"] = s.stats.mean_spp
                return np.asarray(s.image())

            img, t = timed(args, run)
            e = mse(img)
            le = math.log(max(e, 1e-30))
            inside = lm.min() <= le <= lm.max()
            t_plain = math.exp(float(np.interp(le, lm[::-1], lt[::-1])))
            ratio = f"{t / t_plain:.2f}" if inside else "(outside the plain rows)"
            print(f"| {name} | adaptive {thr} | {session_stats['mean']:.1f} | {t:.3f} | {e:.3g} "
                  f"| {ratio} |")


if __name__ == "__main__":
    main()
