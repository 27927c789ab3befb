"""bench/time_error_fit.py on synthetic ladders whose answers are known: the equal-error ratio
of two 1/N renderers, an error floor, and the per-round ratios."""
import math
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "bench"))
import time_error_fit as tef  # noqa: E402


def ladder(scene, contender, k, sec_per_spp, floor=0.0, budgets=(64, 128, 256, 512, 1024)):
    """Rows of a renderer with MSE = k / seconds + floor^2 (seconds = sec_per_spp x spp)."""
    rows = []
    for n in budgets:
        t = sec_per_spp * n
        e = math.sqrt(k / t + floor * floor)
        rows.append(dict(scene=scene, contender=contender, spp=str(n), seconds=str(t),
                         rmse=str(e), rmse_self=str(e) if contender == "cycles" else ""))
    return rows


def test_equal_error_ratio_of_two_unbiased_renderers():
    # Facet reaches Cycles' 1024-spp error in k_f / e^2 s; Cycles took k_c / e^2 s: the ratio
    # is k_f / k_c = 0.28 exactly (up to float formatting), whatever the budgets.
    rows = ladder("cornell", "cycles", 3.0e-5, 0.015) + ladder("cornell", "facet", 0.84e-5, 0.006)
    fits = tef.ladder_fits(rows, 256)
    f, c = fits[("cornell", "facet")], fits[("cornell", "cycles")]
    assert f["n"] == 3 and c["n"] == 3  # 256, 512, 1024
    assert abs(f["slope"] + 1.0) < 1e-9 and f["regime"] == "1/N"
    assert abs(f["k"] / c["k"] - 0.28) < 1e-12
    assert "**0.28**" in tef.table(fits, {})


def test_an_error_floor_gets_no_ratio():
    # A biased renderer: the error stops at 0.01 however long it runs (slope of log MSE on
    # log seconds near 0, far above -0.75).
    rows = ladder("s", "cycles", 1e-5, 0.01) + ladder("s", "biased", 1e-7, 0.01, floor=0.01)
    fits = tef.ladder_fits(rows, 256)
    assert fits[("s", "biased")]["regime"] == "floor"
    text = tef.table(fits, {})
    assert "error floor at RMSE 0.01" in text and "no ratio" in text


def test_faster_than_one_over_n_is_flagged():
    rows = ladder("s", "cycles", 1e-5, 0.01)
    for n in (256, 512, 1024):  # MSE ~ N^-2: a low-discrepancy sampler on a smooth integrand
        rows.append(dict(scene="s", contender="qmc", spp=str(n), seconds=str(0.01 * n),
                         rmse=str(1.0 / n), rmse_self=""))
    fits = tef.ladder_fits(rows, 256)
    assert fits[("s", "qmc")]["regime"] == "faster than 1/N"
    assert "depends on the level" in tef.table(fits, {})


def test_round_ratios_pair_each_round_with_its_cycles_render():
    reps = []
    for rnd, (tf, tc) in enumerate([(6.0, 15.0), (7.0, 14.0), (8.0, 20.0)]):
        reps.append(dict(scene="c", contender="facet", round=str(rnd), spp="1024",
                         seconds=str(tf), rmse="0.0013"))
        reps.append(dict(scene="c", contender="cycles", round=str(rnd), spp="1024",
                         seconds=str(tc), rmse="0.0015"))
    r = tef.round_ratios(reps)[("c", "facet")]
    expect = [(0.0013 ** 2 * tf) / (0.0015 ** 2 * tc) for tf, tc in [(6, 15), (7, 14), (8, 20)]]
    assert len(r) == 3 and all(abs(a - b) < 1e-12 for a, b in zip(r, expect))
