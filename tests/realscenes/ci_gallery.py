"""The CI-size gallery of docs/realscenes.md from the CTest run's outputs (plain Python).

    ctest --test-dir build -L realscenes
    /usr/bin/python3 tests/realscenes/ci_gallery.py build/tests/realscenes/out

copies each scene's side-by-side PNG (Facet | Cycles | |difference| x 4, written by
test_realscene.py at the CTest size) to docs/img/realscenes/ci/<name>.png and rewrites the
table between the `realscenes-ci` markers of docs/realscenes.md with the numbers of the run's
realscene_<name>.json files. A scene without outputs (pending, or not run) is listed as such,
never with old numbers.
"""
import json
import os
import shutil
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
sys.path.insert(0, HERE)
import scenes  # noqa: E402

DOC = os.path.join(ROOT, "docs", "realscenes.md")
IMG = os.path.join(ROOT, "docs", "img", "realscenes", "ci")
BEGIN, END = "<!-- realscenes-ci:begin -->", "<!-- realscenes-ci:end -->"


def main(outdir):
    os.makedirs(IMG, exist_ok=True)
    rows = ["| scene | picture (Facet \\| Cycles \\| difference × 4) | mean Facet / Cycles | "
            "Cycles seed 1 / seed 2 | block RMSE / noise floor | report lines | Facet | "
            "Cycles | threshold |", "|---|---|---|---|---|---|---|---|---|"]
    for s in scenes.SCENES:
        js = os.path.join(outdir, "realscene_%s.json" % s.name)
        png = os.path.join(outdir, "realscene_%s.png" % s.name)
        if s.pending or not (os.path.isfile(js) and os.path.isfile(png)):
            why = "pending: %s" % s.pending if s.pending else "not run"
            rows.append("| %s | | | | | | | | %s |" % (s.name, why))
            continue
        with open(js) as f:
            r = json.load(f)
        shutil.copyfile(png, os.path.join(IMG, s.name + ".png"))
        rows.append("| %s (%d × %d, %d spp) | ![%s](img/realscenes/ci/%s.png) | %.4f | %.4f | "
                    "%.2f× | %d | %.1f s | %.1f s | %s |"
                    % (s.name, r["width"], r["height"], r["spp"], s.name, s.name,
                       r["mean_ratio"], r["cycles_seed_ratio"], r["rmse_over_floor"],
                       len(r["report"]), r["facet_seconds"], r["cycles_seconds"],
                       "meets" if r["pass"] else "**misses**"))
    with open(DOC) as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        raise SystemExit("%s: no %s ... %s markers" % (DOC, BEGIN, END))
    head, rest = text.split(BEGIN, 1)
    _, tail = rest.split(END, 1)
    with open(DOC, "w") as f:
        f.write(head + BEGIN + "\n" + "\n".join(rows) + "\n" + END + tail)
    print("wrote %s and %s" % (DOC, IMG))


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit("usage: ci_gallery.py BUILD/tests/realscenes/out")
    main(sys.argv[1])
