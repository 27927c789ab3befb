#!/usr/bin/python3
"""Untextured scenes against the renderer before texture support (issue 21: "Scenes without
textures render at the same speed as today, within 2% as a same-run ratio on the time-vs-error
scenes").

  /usr/bin/python3 bench/untextured_speed.py --old OLD/build/core/cli/facet \
      [--new build/core/cli/facet] [--scenes cornell_box,glossy,...] [--rounds 7] [--spp 64]

OLD is the `facet` CLI built from the last commit before texture support (0e4ce13: the first
parent of 5fd0991 "Images as rendering data", issue 21's first commit), e.g.
`git archive 0e4ce13 | tar -x -C /tmp/facet-old` and a Release build there. Each scene is
bench/time_error.py's (scenes/<name>.json at that harness's image size), both binaries read the
same file, and for each it prints:

- callgrind: instructions of the render phase, as the difference of two whole-process counts at
  --cg-spp (default 1 and 3 spp, 1 thread, the image at 1/--cg-div of the harness's size per
  axis): scene load, BVH build and image write cancel, so what is left is the cost of the extra
  samples (valgrind --tool=callgrind, "summary" line);
- wall and CPU (user + system) seconds of the whole command at --spp, 1 thread, over --rounds
  rounds, old and new run back to back in each round with the order alternating (ABBA), and the
  median of the per-round ratios new / old (a same-run ratio: drift and load fall on both);
- whether the two images are identical (`facet diff`: RMSE, max relative error).

Prints markdown. The machine is shared: CPU time moves a few percent between neighbouring runs,
wall time tens of percent; the instruction counts are the deterministic measure.
"""
import argparse
import json
import os
import re
import resource
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import time_error  # noqa: E402  (its scene list and image sizes)

DEFAULT_SCENES = ["cornell_box", "glossy", "brushed", "point_plane", "big_mesh"]


def write_scene(name, out, div=1):
    with open(os.path.join(ROOT, "scenes", name + ".json")) as f:
        data = json.load(f)
    w, h = time_error.SCENES[name]["size"]
    data["camera"]["width"], data["camera"]["height"] = w // div, h // div
    path = os.path.join(out, "%s_%d.json" % (name, div))
    with open(path, "w") as f:
        json.dump(data, f, indent=1)
    return path, data.get("render", {}).get("integrator", "path")


def render_cmd(facet, scene, spp, out, integrator):
    return [facet, "render", scene, "--spp", str(spp), "--threads", "1", "--seed", "1",
            "--integrator", integrator, "-q", "-o", out]


def callgrind_ir(cmd, out_file):
    subprocess.run(["valgrind", "--tool=callgrind", "--callgrind-out-file=" + out_file] + cmd,
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(out_file) as f:
        for line in f:
            if line.startswith("summary:") or line.startswith("totals:"):
                return int(line.split()[1])
    raise RuntimeError("no summary in " + out_file)


def timed(cmd):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def diff(facet, a, b):
    out = subprocess.run([facet, "diff", a, b], capture_output=True, text=True).stdout
    rmse = re.search(r"RMSE\s+([0-9.eE+-]+)", out)
    mre = re.search(r"max rel(?:ative)? error\s+([0-9.eE+-]+)", out, re.I)
    return (float(rmse.group(1)) if rmse else float("nan"),
            float(mre.group(1)) if mre else float("nan"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--old", required=True, help="facet CLI of the commit before textures")
    ap.add_argument("--new", default=os.path.join(ROOT, "build", "core", "cli", "facet"))
    ap.add_argument("--scenes", default=",".join(DEFAULT_SCENES))
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--spp", type=int, default=64, help="budget of the timed runs")
    ap.add_argument("--cg-spp", default="1,3", help="the two budgets of the callgrind difference")
    ap.add_argument("--cg-div", type=int, default=2, help="callgrind renders at the harness's "
                    "image size / this per axis (a small render)")
    ap.add_argument("--no-callgrind", action="store_true")
    ap.add_argument("--cg-scenes", default=None, help="callgrind only these scenes (default: "
                    "all of --scenes; big_mesh's BVH build of 1 M triangles takes minutes under "
                    "callgrind)")
    ap.add_argument("--no-timing", action="store_true")
    ap.add_argument("--out", default=os.path.join(ROOT, "out", "bench", "untextured_speed"))
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    lo, hi = (int(x) for x in a.cg_spp.split(","))
    names = [s for s in a.scenes.split(",") if s]
    bins = {"old": a.old, "new": a.new}
    rows = []
    for name in names:
        scene, integ = write_scene(name, a.out)
        cg_scene, _ = write_scene(name, a.out, a.cg_div)
        row = {"scene": name, "size": "%dx%d" % time_error.SCENES[name]["size"]}
        if not a.no_callgrind and (a.cg_scenes is None or name in a.cg_scenes.split(",")):
            ir = {}
            for who, exe in bins.items():
                for spp in (lo, hi):
                    ir[who, spp] = callgrind_ir(
                        render_cmd(exe, cg_scene, spp, os.path.join(a.out, "cg_%s_%s_%d.exr" % (
                            name, who, spp)), integ),
                        os.path.join(a.out, "callgrind.%s.%s.%d" % (name, who, spp)))
            row["ir_old"] = ir["old", hi] - ir["old", lo]
            row["ir_new"] = ir["new", hi] - ir["new", lo]
            row["ir_total"] = (ir["old", hi], ir["new", hi])
            row["same_cg"] = diff(a.new, os.path.join(a.out, "cg_%s_old_%d.exr" % (name, hi)),
                                  os.path.join(a.out, "cg_%s_new_%d.exr" % (name, hi)))
            print("%s: render-phase instructions (%d - %d spp) old %d, new %d: %.4f"
                  % (name, hi, lo, row["ir_old"], row["ir_new"], row["ir_new"] / row["ir_old"]),
                  file=sys.stderr, flush=True)
        if not a.no_timing:
            t = {"old": [], "new": []}
            ratios_wall, ratios_cpu = [], []
            for k in range(a.rounds):
                order = ["old", "new"] if k % 2 == 0 else ["new", "old"]
                this = {}
                for who in order:
                    this[who] = timed(render_cmd(bins[who], scene, a.spp, os.path.join(
                        a.out, "t_%s_%s.exr" % (name, who)), integ))
                    t[who].append(this[who])
                ratios_wall.append(this["new"][0] / this["old"][0])
                ratios_cpu.append(this["new"][1] / this["old"][1])
            row["wall"] = {w: statistics.median(x[0] for x in v) for w, v in t.items()}
            row["cpu"] = {w: statistics.median(x[1] for x in v) for w, v in t.items()}
            row["r_wall"] = (statistics.median(ratios_wall), min(ratios_wall), max(ratios_wall))
            row["r_cpu"] = (statistics.median(ratios_cpu), min(ratios_cpu), max(ratios_cpu))
            row["same_t"] = diff(a.new, os.path.join(a.out, "t_%s_old.exr" % name),
                                 os.path.join(a.out, "t_%s_new.exr" % name))
            print("%s: CPU ratio %.4f (%.4f-%.4f), wall %.4f" % (
                name, *row["r_cpu"], row["r_wall"][0]), file=sys.stderr, flush=True)
        rows.append(row)
    print("| scene | size | render-phase instructions old → new (%d − %d spp, 1 thread, 1/%d "
          "size) | "
          "ratio | CPU s old / new (median, %d spp, 1 thread) | per-round CPU ratio new/old "
          "(median, range of %d) | per-round wall ratio (median, range) | images |"
          % (hi, lo, a.cg_div, a.spp, a.rounds))
    print("|---|---|---|---:|---|---|---|---|")
    for r in rows:
        cg = ("%.1f M → %.1f M | **%+.2f%%**" % (r["ir_old"] / 1e6, r["ir_new"] / 1e6,
                                               100 * (r["ir_new"] / r["ir_old"] - 1))
              if "ir_old" in r else "— | —")
        tm = ("%.2f / %.2f | **%.4f** (%.4f–%.4f) | %.4f (%.4f–%.4f)" % (
            r["cpu"]["old"], r["cpu"]["new"], *r["r_cpu"], *r["r_wall"])
            if "cpu" in r else "— | — | —")
        same = r.get("same_t") or r.get("same_cg")
        img = ("identical" if same[0] == 0 else "RMSE %.3g, max rel %.3g" % same)
        print("| %s | %s | %s | %s | %s |" % (r["scene"], r["size"], cg, tm, img))


if __name__ == "__main__":
    main()
