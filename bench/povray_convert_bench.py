#!/usr/bin/python3
"""`brdf_convert_classic on` against the classic render of the same stock scene, same binary,
same run: render time ratio (target <= 1.2) and mean-brightness ratio.

Usage: bench/povray_convert_bench.py [POVRAY_FACET] [--reps N] [--size WxH] [--threads T]
                                     [--scenes REL ...]

Scenes are paths under Debian's povray-examples (/usr/share/doc/povray/examples). The switch
is injected with +HI from a one-line include, as a user would. Each repetition renders both
variants, in alternating order, so that a drift of the machine's speed hits both alike; the
table shows the median wall time (whole process: parse and conversion included) of each and
the median of the per-repetition ratios converted / classic. A Markdown table.
"""
import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

EXAMPLES = "/usr/share/doc/povray/examples"
DEFAULT_SCENES = [
    "advanced/woodbox.pov", "advanced/chess2.pov", "advanced/blocks/stackergold.pov",
    "advanced/balcony/balcony.pov", "incdemo/metals/chromes.pov", "incdemo/finish.pov",
    "textures/finishes/metallicreflection.pov", "lights/shadows.pov", "radiosity/cornell.pov",
    "advanced/wineglass.pov",
]


def run(pov, scene, out, size, threads, header, tmp):
    w, h = size.split("x")
    args = [pov, f"+I{scene}", f"+O{out}", f"+W{w}", f"+H{h}", "-D", "-V", "-GA",
            f"+WT{threads}", f"+L{os.path.dirname(scene)}"]
    if header:
        args.append(f"+HI{header}")
    t0 = time.perf_counter()
    p = subprocess.run(args, cwd=tmp, env=dict(os.environ, HOME=tmp), capture_output=True)
    if p.returncode != 0:
        sys.exit(f"{' '.join(args)} failed:\n{p.stderr.decode()[-2000:]}")
    return time.perf_counter() - t0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("povray", nargs="?", default="build/povray_patch/bin/povray-facet")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--size", default="320x240")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--scenes", nargs="*", default=DEFAULT_SCENES)
    a = ap.parse_args()
    pov = os.path.abspath(a.povray)
    print(f"| scene ({a.size}, {a.threads} threads, {a.reps} reps) | classic s | converted s "
          f"| converted / classic |")
    print("|---|---|---|---|")
    ratios = []
    with tempfile.TemporaryDirectory() as tmp:
        header = os.path.join(tmp, "convert.inc")
        with open(header, "w") as f:
            f.write("global_settings { brdf_convert_classic on }\n")
        for rel in a.scenes:
            scene = os.path.join(EXAMPLES, rel)
            tc, tv, r = [], [], []
            for k in range(a.reps):
                order = (None, header) if k % 2 == 0 else (header, None)
                t = {}
                for hd in order:
                    t[hd] = run(pov, scene, os.path.join(tmp, "o.png"), a.size, a.threads, hd, tmp)
                tc.append(t[None])
                tv.append(t[header])
                r.append(t[header] / t[None])
            ratio = statistics.median(r)
            ratios.append(ratio)
            print(f"| {rel} | {statistics.median(tc):.2f} | {statistics.median(tv):.2f} "
                  f"| {ratio:.2f} |")
    print(f"| median over scenes | | | {statistics.median(ratios):.2f} |")


if __name__ == "__main__":
    main()
