#!/usr/bin/python3
"""Equal-error time ratios from fits of noise^2 x time (issue 25, part 1).

  /usr/bin/python3 bench/time_error_fit.py    # docs/perf/time_error.csv, _reps.csv -> _fit.md

For an unbiased Monte Carlo renderer the mean squared error falls as 1/N and the time grows as N,
so k = MSE x seconds is a constant of the renderer and the scene once start-up costs are small.
The time one contender needs to reach another's error e is then k / e^2, and the equal-error time
ratio of Facet to Cycles at Cycles' error is k_facet / k_cycles, with no rounding to the ladder's
powers of two (the ladder's "first budget that reaches the level" overstates Facet's time by up
to 2x).

What this reads (written by bench/time_error.py):
- time_error.csv, the ladder: one render per budget. The RMSE of a Facet contender is against
  Facet's reference with the reference's own noise removed (`rmse`); Cycles' is against Cycles'
  own reference, likewise (`rmse_self`), so bias between the two renderers is not counted as
  noise. k is taken at the budgets >= --min-spp (default 256), where start-up is a few percent.
- time_error_reps.csv, the timing rounds: the contenders rendered again at the level, round by
  round interleaved with Cycles; each round gives k_facet / k_cycles from its own pair.

The check that k is constant: the least-squares slope of log MSE against log seconds over the fit
range. An unbiased renderer in its 1/N regime has slope -1. A slope above -0.75 means the error
stops falling with time (an error floor: bias, such as Cycles' clamping or POV-Ray's
radiosity): no ratio is given then, the floor is reported instead. A slope below -1.25 means the
error falls faster than 1/N (a low-discrepancy sampler before its 1/N regime, or start-up time):
the ratio is given and flagged, since it then depends on the level.
"""
import argparse
import csv
import math
import os
import statistics

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SLOPE_FLOOR = -0.75  # above: an error floor, no ratio
SLOPE_FAST = -1.25   # below: faster than 1/N, ratio flagged
REFERENCE = "cycles"


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def noise(row):
    """The contender's RMSE with the reference's noise removed (see the module docstring)."""
    key = "rmse_self" if row["contender"] == REFERENCE and row.get("rmse_self") else "rmse"
    v = row.get(key, "")
    return float(v) if v not in ("", None) else float("nan")


def slope(xs, ys):
    """Least-squares slope of ys on xs (None for fewer than two distinct xs)."""
    if len(xs) < 2:
        return None
    mx, my = statistics.fmean(xs), statistics.fmean(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    if sxx == 0:
        return None
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys)) / sxx


def fit(points):
    """points: [(spp, rmse, seconds)] of one contender on one scene, in the fit range.
    Returns dict(k = median of rmse^2 x seconds, k_min, k_max, slope of log MSE on log seconds,
    n, regime) or None when there is nothing to fit."""
    pts = [(n, e, t) for n, e, t in points if e > 0 and t > 0 and math.isfinite(e)]
    if not pts:
        return None
    ks = [e * e * t for _, e, t in pts]
    s = slope([math.log(t) for _, _, t in pts], [math.log(e * e) for _, e, _ in pts])
    regime = "1/N"
    if s is None:
        regime = "one budget"
    elif s > SLOPE_FLOOR:
        regime = "floor"
    elif s < SLOPE_FAST:
        regime = "faster than 1/N"
    return dict(k=statistics.median(ks), k_min=min(ks), k_max=max(ks), slope=s, n=len(pts),
                regime=regime, floor_rmse=min(e for _, e, _ in pts))


def ladder_fits(rows, min_spp, clock="seconds"):
    """{(scene, contender): fit} over the ladder rows at budgets >= min_spp; clock: the time
    column ("seconds": wall, "cpu_seconds": user + system of all threads)."""
    groups = {}
    for r in rows:
        if not r.get("spp") or not r.get(clock):
            continue
        n = float(r["spp"])
        if n < min_spp:
            continue
        groups.setdefault((r["scene"], r["contender"]), []).append(
            (n, noise(r), float(r[clock])))
    return {key: f for key, pts in groups.items() if (f := fit(sorted(pts))) is not None}


def round_ratios(reps, clock="seconds"):
    """{(scene, contender): [k_contender / k_cycles per round]} from the timing rounds."""
    by = {}
    for r in reps:
        by.setdefault((r["scene"], r["round"]), {})[r["contender"]] = r
    out = {}
    for (scene, _), contenders in sorted(by.items()):
        ref = contenders.get(REFERENCE)
        if ref is None:
            continue
        if not ref.get(clock) or ref[clock] == "nan":
            continue
        k_ref = float(ref["rmse"]) ** 2 * float(ref[clock])
        for name, r in contenders.items():
            if name == REFERENCE or k_ref <= 0 or not r.get(clock):
                continue
            k = float(r["rmse"]) ** 2 * float(r[clock])
            out.setdefault((scene, name), []).append(k / k_ref)
    return out


def table(fits, rounds):
    """Markdown table: per scene and contender, k, its spread, the slope, and the equal-error
    ratio to Cycles from the ladder fits and from the timing rounds."""
    lines = ["| scene | contender | budgets | k = MSE·s (median) | k spread | slope log MSE / log s "
             "| equal-error ratio to Cycles (ladder fit) | per-round ratios (median, range) |",
             "|---|---|---:|---:|---:|---:|---:|---|"]
    scenes = []
    for scene, _ in fits:
        if scene not in scenes:
            scenes.append(scene)
    for scene in scenes:
        ref = fits.get((scene, REFERENCE))
        names = sorted((c for s, c in fits if s == scene), key=lambda c: (c == REFERENCE, c))
        for c in names:
            f = fits[(scene, c)]
            spread = "%.2f–%.2f" % (f["k_min"] / f["k"], f["k_max"] / f["k"])
            sl = "—" if f["slope"] is None else "%.2f" % f["slope"]
            if f["regime"] == "floor":
                ratio = "error floor at RMSE %.3g: no ratio" % f["floor_rmse"]
            elif f["regime"] == "one budget":
                ratio = "— (one budget in range: no fit)"
            elif c == REFERENCE:
                ratio = "1 (peer)"
            elif ref is None or ref["regime"] in ("floor", "one budget"):
                ratio = "— (Cycles has no 1/N fit)"
            else:
                ratio = "**%.3g**" % (f["k"] / ref["k"])
                if f["regime"] != "1/N" or ref["regime"] != "1/N":
                    ratio += " (not 1/N: depends on the level)"
            rr = rounds.get((scene, c))
            rtxt = ("%.3g (%.3g–%.3g, %d rounds)" % (statistics.median(rr), min(rr), max(rr),
                                                    len(rr))) if rr else ""
            lines.append("| %s | %s | %d | %.3g | %s | %s | %s | %s |" % (
                scene, c, f["n"], f["k"], spread, sl, ratio, rtxt))
    return "\n".join(lines)


def write_fit(csv_path, reps_path, out_path, min_spp=256):
    """Reads the ladder and the rounds, writes the Markdown table to out_path; returns it."""
    rows = read_csv(csv_path)
    reps = read_csv(reps_path) if os.path.exists(reps_path) else []
    fits = ladder_fits(rows, min_spp)
    rounds = round_ratios(reps)
    cpu_fits = ladder_fits(rows, min_spp, "cpu_seconds")
    text = ("# Equal-error time ratios from noise² × time fits (bench/time_error_fit.py)\n\n"
            "Source: `%s` (ladder, budgets ≥ %g spp) and `%s` (timing rounds). "
            "k = RMSE² × wall seconds; a contender reaches Cycles' error e in k / e² seconds, "
            "so the equal-error ratio is k / k_Cycles. Slope −1 = the 1/N regime the fit "
            "assumes; above %.2f the error has a floor (no ratio), below %.2f it falls faster "
            "than 1/N (ratio flagged).\n\n" % (os.path.basename(csv_path), min_spp,
                                               os.path.basename(reps_path), SLOPE_FLOOR,
                                               SLOPE_FAST)
            + table(fits, rounds) + "\n")
    if cpu_fits:
        # The ladders that recorded CPU seconds (runs since the column was added): the same fit
        # with user + system seconds of all threads, which a loaded machine disturbs far less
        # than wall time (Facet: the whole process; Cycles: Blender's process time around
        # render.render()).
        text += ("\n## The same with CPU seconds\n\nk = RMSE² × CPU seconds (user + system, all "
                 "threads; Facet's whole process, Cycles' render call), for the ladders that "
                 "recorded them; per-round ratios from the rounds' CPU seconds.\n\n"
                 + table(cpu_fits, round_ratios(
                     [r for r in reps if (r["scene"], r["contender"]) in cpu_fits],
                     "cpu_seconds")) + "\n")
    with open(out_path, "w") as f:
        f.write(text)
    return text


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    perf = os.path.join(ROOT, "docs", "perf")
    ap.add_argument("--csv", default=os.path.join(perf, "time_error.csv"))
    ap.add_argument("--reps", default=os.path.join(perf, "time_error_reps.csv"))
    ap.add_argument("--out", default=os.path.join(perf, "time_error_fit.md"))
    ap.add_argument("--min-spp", type=float, default=256)
    args = ap.parse_args()
    print(write_fit(args.csv, args.reps, args.out, args.min_spp))


if __name__ == "__main__":
    main()
