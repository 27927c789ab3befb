#!/usr/bin/python3
"""Bias of each time-vs-error contender, apart from its noise (issue 25, section 1).

  PYTHONPATH=build/core/python /usr/bin/python3 bench/time_error_bias.py \
      [--out out/bench/time_error] [--ref out/bench/ref] [--publish docs/perf]

bench/time_error.py calls `write_bias` at the end of a run; run alone, this script reads a
finished run's images (OUT/images/<scene>/<contender>_<spp>.exr) and the cached references
(REF/<scene>_{facet,cycles}_<hash>_{101,102}.exr, the newest pair of each) and writes
time_error_bias.md and one bias map per scene and contender (PUBLISH/bias/).

For a contender's top-budget render x against a reference r (the mean of two high-spp renders
with other seeds), d = x - r per pixel and channel. Pixels are independent estimates (each has
its own sampler seed), so the mean of d over n values has the standard error std(d) / sqrt(n):

- **difference of means**: mean(x) / mean(r) - 1, with z = mean(d) / (std(d) / sqrt(n)) over the
  whole image; |z| > 4 is bias that the render's own noise cannot explain;
- **bias map**: the same z per 16 x 16-pixel block (luminance), drawn red where x is brighter,
  blue where darker, full colour at |z| = 6; the table gives the largest |z| and the share of
  blocks with |z| > 4 (under pure noise about 6e-5 of blocks).

Each contender is measured against its own renderer's reference (Cycles against Cycles', every
Facet contender and POV-Ray against Facet's) — its bias as a Monte Carlo estimator, which is what
turns an equal-error ratio into an error floor — and against the other renderer's reference (the
conversion difference between the renderers, which reference_check.md also states blockwise).
"""
import argparse
import glob
import math
import os
import re
import sys

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLOCK = 16
Z_BIAS = 4.0   # |z| above which a difference is called bias (pure noise: p ~ 6e-5)
Z_FULL = 6.0   # the bias map's colour saturates here
LUM = np.array([0.2126, 0.7152, 0.0722])


def _facet():
    sys.path.insert(0, os.path.join(ROOT, "build", "core", "python"))
    import facet  # noqa: E402
    return facet


def bias(x, ref):
    """Difference of means and blockwise z-scores of image x against reference ref (h, w, 3)."""
    d = x - ref
    n = d.size
    sd = d.std()
    z = d.mean() / (sd / math.sqrt(n)) if sd > 0 else 0.0
    dl = (d * LUM).sum(axis=2)
    h, w = dl.shape[0] // BLOCK * BLOCK, dl.shape[1] // BLOCK * BLOCK
    blocks = dl[:h, :w].reshape(h // BLOCK, BLOCK, w // BLOCK, BLOCK).swapaxes(1, 2)
    blocks = blocks.reshape(h // BLOCK, w // BLOCK, BLOCK * BLOCK)
    bse = blocks.std(axis=2) / BLOCK  # standard error of a block's mean: BLOCK^2 pixels
    bz = np.divide(blocks.mean(axis=2), bse, out=np.zeros_like(bse), where=bse > 0)
    return dict(mean_rel=float(x.mean() / ref.mean() - 1.0), z=float(z), block_z=bz,
                max_block_z=float(np.abs(bz).max()) if bz.size else 0.0,
                biased_blocks=float((np.abs(bz) > Z_BIAS).mean()) if bz.size else 0.0)


def bias_map(block_z, size):
    """An RGB picture of block z-scores at the image's size (white: 0, red: +, blue: -)."""
    t = np.clip(block_z / Z_FULL, -1.0, 1.0)
    rgb = np.ones(block_z.shape + (3,))
    rgb[..., 1] = 1.0 - np.abs(t)
    rgb[..., 0] = np.where(t < 0, 1.0 + t, 1.0)
    rgb[..., 2] = np.where(t > 0, 1.0 - t, 1.0)
    img = np.ones((size[0], size[1], 3))
    big = np.repeat(np.repeat(rgb, BLOCK, axis=0), BLOCK, axis=1)
    img[:big.shape[0], :big.shape[1]] = big
    return img.astype(np.float32)


def newest_pair(ref_dir, scene, renderer):
    """The mean of the newest reference pair of scene by renderer, or None."""
    files = glob.glob(os.path.join(ref_dir, "%s_%s_*_101.exr" % (scene, renderer)))
    files = [f for f in files if os.path.exists(f[:-8] + "_102.exr")]
    if not files:
        return None
    a = max(files, key=os.path.getmtime)
    read = _facet().read_image
    return 0.5 * (read(a).astype(np.float64) + read(a[:-8] + "_102.exr").astype(np.float64))


def top_budget_images(img_dir):
    """{contender file stem: path of its largest-spp ladder render}."""
    top = {}
    for f in glob.glob(os.path.join(img_dir, "*.exr")):
        m = re.fullmatch(r"(.+)_(\d+)\.exr", os.path.basename(f))
        if not m or m.group(1).startswith(("rep", "trial")):
            continue
        name, spp = m.group(1), int(m.group(2))
        if name not in top or spp > top[name][0]:
            top[name] = (spp, f)
    return top


def write_bias(out_dir, ref_dir, publish):
    facet = _facet()
    maps = os.path.join(publish, "bias")
    os.makedirs(maps, exist_ok=True)
    lines = ["# Bias apart from noise (bench/time_error_bias.py)", "",
             "Top-budget render of each contender: difference of image means against its own "
             "renderer's reference and against the other renderer's, with z = mean(d) / "
             "(std(d)/sqrt(n)); blockwise (16x16, luminance) the largest |z| and the share of "
             "blocks with |z| > %g (pure noise: ~6e-5). Maps: red brighter, blue darker than "
             "the own reference, full at |z| = %g." % (Z_BIAS, Z_FULL), "",
             "| scene | contender | spp | vs own reference: mean diff (z) | max block \\|z\\| | "
             "blocks \\|z\\| > 4 | vs the other renderer's reference: mean diff (z) | map |",
             "|---|---|---:|---|---:|---:|---|---|"]
    for img_dir in sorted(glob.glob(os.path.join(out_dir, "images", "*"))):
        scene = os.path.basename(img_dir)
        refs = {r: newest_pair(ref_dir, scene, r) for r in ("facet", "cycles")}
        for name, (spp, path) in sorted(top_budget_images(img_dir).items()):
            own_r = "cycles" if name == "cycles" else "facet"
            other_r = "facet" if own_r == "cycles" else "cycles"
            if refs[own_r] is None:
                continue
            x = facet.read_image(path).astype(np.float64)
            if x.shape != refs[own_r].shape:
                continue
            own = bias(x, refs[own_r])
            png = "%s_%s.png" % (scene, name)
            facet.write_image(bias_map(own["block_z"], x.shape[:2]), os.path.join(maps, png))
            other = "—"
            if refs[other_r] is not None and refs[other_r].shape == x.shape:
                b = bias(x, refs[other_r])
                other = "%+.2f%% (%.0f)" % (100 * b["mean_rel"], b["z"])
            lines.append("| %s | %s | %d | %+.3f%% (%.1f) | %.1f | %.4f | %s | [map](bias/%s) |"
                         % (scene, name.replace("_", " "), spp, 100 * own["mean_rel"], own["z"],
                            own["max_block_z"], own["biased_blocks"], other, png))
    path = os.path.join(publish, "time_error_bias.md")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "time_error"))
    ap.add_argument("--ref", default=os.path.join(ROOT, "out", "bench", "ref"))
    ap.add_argument("--publish", default=os.path.join(ROOT, "docs", "perf"))
    a = ap.parse_args()
    print(write_bias(a.out, a.ref, a.publish))


if __name__ == "__main__":
    main()
