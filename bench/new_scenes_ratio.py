#!/usr/bin/python3
"""Equal-error time ratio, Facet against Cycles, on issue 25's textured-asset and glass scenes
(bench/staged_bench.py writes them; time_error/cycles_new_scenes.py builds the Cycles twins).

  /usr/bin/python3 bench/new_scenes_ratio.py [--spp 16,64] [--threads 1] [--out DIR]

Each renderer's noise at a budget is the RMSE between two seeds (1, 2) divided by sqrt(2) (the
seeds' images are independent, so MSE(a - b) = 2 Var); k = noise^2 x CPU seconds, constant for
an unbiased renderer in its 1/N regime (the slope of log MSE against log seconds over the budgets
is printed to check it); the equal-error time ratio is k_facet / k_cycles (bench/
time_error_fit.py's estimator, with the between-seed noise instead of a reference). CPU seconds
(user + system): Facet's whole process (load, BVH, textures included); Cycles' process time
around bpy.ops.render.render() (sync, BVH, sampling; not Blender's start-up). CPU time, not
wall: the machine is shared. Bias between the two renderers is not measured here (their pictures
differ: see the twin's notes). Prints markdown.
"""
import argparse
import math
import os
import re
import resource
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def rmse(facet, a, b):
    out = subprocess.run([facet, "diff", a, b], capture_output=True, text=True).stdout
    return float(re.search(r"RMSE\s+([0-9.eE+-]+)", out).group(1))


def facet_render(facet, scene, spp, seed, threads, out):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([facet, "render", scene, "--spp", str(spp), "--seed", str(seed), "--threads",
                    str(threads), "-o", out], check=True, capture_output=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--spp", default="16,64")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "new_scenes"))
    ap.add_argument("--facet", default=os.path.join(ROOT, "build", "core", "cli", "facet"))
    ap.add_argument("--scenes", default="textured_asset,glass")
    a = ap.parse_args()
    budgets = [int(x) for x in a.spp.split(",")]
    subprocess.run([sys.executable, os.path.join(ROOT, "bench", "staged_bench.py"),
                    "--write-only", "--out", a.out], check=True, capture_output=True)
    print("| scene | renderer | spp | noise (RMSE/sqrt 2) | CPU s | k = noise^2 s |")
    print("|---|---|---|---|---|---|")
    ratios = {}
    for name in a.scenes.split(","):
        scene = os.path.join(a.out, name + ".json")
        ks = {}
        for spp in budgets:
            t = [facet_render(a.facet, scene, spp, s, a.threads,
                              os.path.join(a.out, "fa_%s_%d_%d.exr" % (name, spp, s)))
                 for s in (1, 2)]
            n = rmse(a.facet, *[os.path.join(a.out, "fa_%s_%d_%d.exr" % (name, spp, s))
                                for s in (1, 2)]) / math.sqrt(2)
            ks.setdefault("facet", []).append((spp, n, sum(t) / 2))
        cy = subprocess.run(
            ["blender", "-b", "--factory-startup", "-noaudio", "--python",
             os.path.join(ROOT, "bench", "time_error", "cycles_new_scenes.py"), "--", scene,
             a.out, str(a.threads), a.spp, "1,2"], capture_output=True, text=True)
        rows = [l.split() for l in cy.stdout.splitlines() if l.startswith("CY ")]
        if not rows:
            sys.exit("Cycles failed:\n" + cy.stdout[-3000:] + cy.stderr[-3000:])
        for spp in budgets:
            r = [x for x in rows if int(x[2]) == spp]
            n = rmse(a.facet, r[0][6], r[1][6]) / math.sqrt(2)
            ks.setdefault("cycles", []).append((spp, n, (float(r[0][4]) + float(r[1][4])) / 2))
        for who, pts in ks.items():
            for spp, n, t in pts:
                print("| %s | %s | %d | %.5f | %.2f | %.3g |" % (name, who, spp, n, t, n * n * t))
        k = {w: [n * n * t for _, n, t in p] for w, p in ks.items()}
        slope = {w: (math.log(p[-1][1] ** 2) - math.log(p[0][1] ** 2)) /
                 (math.log(p[-1][2]) - math.log(p[0][2])) if len(p) > 1 else float("nan")
                 for w, p in ks.items()}
        ratios[name] = ([kf / kc for kf, kc in zip(k["facet"], k["cycles"])], slope)
    print()
    print("| scene | k_facet / k_cycles per budget | slope log MSE / log s (facet, cycles) |")
    print("|---|---|---|")
    for name, (r, s) in ratios.items():
        print("| %s | %s | %.2f, %.2f |" % (name, ", ".join("%.3f" % x for x in r), s["facet"],
                                            s["cycles"]))


if __name__ == "__main__":
    main()
