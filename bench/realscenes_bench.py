#!/usr/bin/python3
"""The real-scene suite's longer run: every scene of tests/realscenes/scenes.py (pending ones
too, to show what they still lack) rendered by the Facet engine and by Cycles in headless
Blender at the bench size (Scene.bench: 192 x 144, 256 spp unless --size/--spp), with Facet's
default Power light selection measured beside the suite's Uniform. Writes the side-by-sides to
docs/img/realscenes/<name>.png and the table between the markers of docs/realscenes.md.

    bench/realscenes_bench.py --build build [--size 192x144] [--spp 256] [scene ...]

Needs the addon installed as tests/blender installs it (`ctest --test-dir build -R
blender.install`). Takes ~3 minutes per scene on the 2-core development machine.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "tests", "realscenes"))
import scenes  # noqa: E402

BEGIN, END = "<!-- realscenes:begin -->", "<!-- realscenes:end -->"


def run_profile(build, name, out, profile, size_spp, prefix):
    """test_realscene.py NAME OUT PROFILE [W H SPP] in headless Blender with the addon the build
    installs; returns OUT/PREFIX_NAME.json (the log beside it)."""
    bdir = os.path.join(build, "tests", "blender")
    env = dict(os.environ, BLENDER_USER_SCRIPTS=os.path.join(bdir, "user_scripts"),
               BLENDER_USER_CONFIG=os.path.join(bdir, "user_config"), PYTHONNOUSERSITE="1")
    cmd = ["blender", "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1",
           "--python", os.path.join(ROOT, "tests", "realscenes", "test_realscene.py"), "--",
           name, out, profile] + [str(v) for v in size_spp]
    log = os.path.join(out, "%s_%s.log" % (prefix, name))
    with open(log, "w") as f:
        rc = subprocess.run(cmd, env=env, stdout=f, stderr=subprocess.STDOUT).returncode
    path = os.path.join(out, "%s_%s.json" % (prefix, name))
    if rc != 0 or not os.path.exists(path):
        raise RuntimeError("%s failed (exit %d), see %s" % (name, rc, log))
    with open(path) as f:
        return json.load(f)


def update_summary(summary, names, docs_only, measure, show):
    """The per-scene rows of the JSON list `summary`: as they are (docs_only), or with the scenes
    `names` (every scene of the suite when empty) measured again by measure(name), each row
    printed by show(row) and replacing its old one; written back, in the suite's order."""
    if docs_only:
        with open(summary) as f:
            return json.load(f)
    results = []
    if names and os.path.exists(summary):
        with open(summary) as f:
            results = json.load(f)
    order = [s.name for s in scenes.SCENES if not s.pending]
    for name in names or order:
        r = measure(name)
        show(r)
        results = [x for x in results if x["scene"] != name] + [r]
    results.sort(key=lambda x: order.index(x["scene"]) if x["scene"] in order else 99)
    with open(summary, "w") as f:
        json.dump(results, f, indent=1)
    return results


def write_docs(text, begin, end, draw, image):
    """`text` between the markers `begin` and `end` of docs/realscenes.md, and draw(path) the plot
    docs/img/realscenes/`image`."""
    img = os.path.join(ROOT, "docs", "img", "realscenes")
    os.makedirs(img, exist_ok=True)
    draw(os.path.join(img, image))
    doc = os.path.join(ROOT, "docs", "realscenes.md")
    with open(doc) as f:
        old = f.read()
    i, j = old.index(begin) + len(begin), old.index(end)
    with open(doc, "w") as f:
        f.write(old[:i] + "\n" + text + "\n" + old[j:])


def run(build, name, out, size, spp):
    size_spp = []
    if size or spp:
        w, h, s = scenes.by_name(name).bench
        if size:
            w, h = (int(v) for v in size.split("x"))
        size_spp = [w, h, spp or s]
    return run_profile(build, name, out, "bench", size_spp, "realscene")


def row(r):
    status = ("pending: " + r["pending"]) if r["pending"] else (
        "meets" if r["pass"] else "**misses**")
    power = ""
    if "power_block_rmse" in r:
        power = "%.2f× (%.4f)" % (r["power_block_rmse"] / max(r["noise_floor"], 1e-12),
                                  r["power_mean_ratio"])
    return ("| [%s](img/realscenes/%s.png) | %s | %.4f | %.2f× | %s | %.1f s | %.1f s | %d | %s |"
            % (r["scene"], r["scene"], ", ".join(r["features"]), r["mean_ratio"],
               r["rmse_over_floor"], power, r["facet_seconds"], r["cycles_seconds"],
               len(r["report"]), status))


def table(results):
    lines = ["| scene | exercises | mean Facet / Cycles | block RMSE / noise floor | with Power "
             "selection: RMSE / floor (mean) | Facet | Cycles | report lines | threshold |",
             "|---|---|---|---|---|---|---|---|---|"]
    lines += [row(r) for r in results]
    r0 = results[0]
    lines.append("")
    lines.append("%d x %d pixels, %d spp (Facet and each Cycles seed), measured by "
                 "`bench/realscenes_bench.py` on the shared 2-core development machine; times "
                 "are F12 wall times inside Blender (Cycles: one seed, world importance map "
                 "included)." % (r0["width"], r0["height"], r0["spp"]))
    lines.append("")
    lines.append("The conversion reports, as the engine gave them:")
    lines.append("")
    for r in results:
        lines.append("<details><summary>%s: %d lines</summary>" % (r["scene"], len(r["report"])))
        lines.append("")
        lines += ["- " + p.replace("|", "\\|") for p in r["report"]] or ["(none)"]
        lines.append("")
        lines.append("</details>")
        lines.append("")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--out", default=None, help="work directory (default BUILD/realscenes_bench)")
    ap.add_argument("--size", default=None, help="WxH (default: each scene's bench size)")
    ap.add_argument("--spp", type=int, default=None)
    ap.add_argument("--no-docs", action="store_true", help="do not update docs/")
    ap.add_argument("--docs-only", action="store_true",
                    help="rewrite docs/ from OUT/realscenes_bench.json without rendering")
    ap.add_argument("scenes", nargs="*", help="scene names (default: all)")
    a = ap.parse_args()
    out = a.out or os.path.join(a.build, "realscenes_bench")
    os.makedirs(out, exist_ok=True)
    summary = os.path.join(out, "realscenes_bench.json")
    if a.docs_only:
        with open(summary) as f:
            results = json.load(f)
    else:
        results = []
        for name in a.scenes or [s.name for s in scenes.SCENES]:
            r = run(a.build, name, out, a.size, a.spp)
            print(row(r), flush=True)
            results.append(r)
        with open(summary, "w") as f:
            json.dump(results, f, indent=1)
    if a.no_docs:
        return
    img = os.path.join(ROOT, "docs", "img", "realscenes")
    os.makedirs(img, exist_ok=True)
    for r in results:
        shutil.copyfile(os.path.join(out, r["png"]), os.path.join(img, r["scene"] + ".png"))
    doc = os.path.join(ROOT, "docs", "realscenes.md")
    with open(doc) as f:
        text = f.read()
    i, j = text.index(BEGIN) + len(BEGIN), text.index(END)
    with open(doc, "w") as f:
        f.write(text[:i] + "\n" + table(results) + "\n" + text[j:])


if __name__ == "__main__":
    main()
