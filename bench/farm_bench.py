#!/usr/bin/python3
"""facet-farm against `facet render` on the same scene in the same run, per-task costs, and the
scaling model of the README's farm section.

  PYTHONPATH=build/core/python /usr/bin/python3 bench/farm_bench.py [--spp 16] [--reps 3]

1. Cornell box at 1920x1080: `facet render --threads 2` and `facet-farm render` (local cluster,
   default layout, wall time including the cluster's start and shutdown), alternating, `--reps`
   times; medians and the per-rep ratio; the images must be bit-identical.
2. Local layouts (workers x task threads x render threads per task) at `--layout-spp`.
3. Per-task costs: a no-op Dask task and a 8x8-pixel 1-sample facet task (tasks/s through the
   scheduler), bytes of a task's arguments, of the scene payload and of a result per pixel,
   merge throughput (merge_parts and the exact 128-bit chunk sum).
4. The model for a 4K frame at 4096 spp on 10/100/1000 workers, from the numbers above.
Prints markdown.
"""
import argparse
import json
import os
import pathlib
import pickle
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import facet
import facet.farm as farm

ROOT = pathlib.Path(__file__).resolve().parents[1]
BUILD = pathlib.Path(os.environ.get("FACET_BUILD", ROOT / "build"))
CLI = BUILD / "core" / "cli" / "facet"
FARM = BUILD / "core" / "python" / "facet-farm"


def scene_file(d, width, height, spp):
    s = json.loads((ROOT / "scenes" / "cornell_box.json").read_text())
    s["camera"]["width"], s["camera"]["height"] = width, height
    s["render"]["spp"] = spp
    p = pathlib.Path(d) / f"cornell_{width}x{height}_{spp}.json"
    p.write_text(json.dumps(s))
    return p


def timed(cmd):
    t = time.perf_counter()
    subprocess.run([str(c) for c in cmd], check=True, capture_output=True)
    return time.perf_counter() - t


def same(a, b):
    return np.array_equal(facet.read_image(str(a)), facet.read_image(str(b)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--layout-spp", type=int, default=4)
    ap.add_argument("--skip-layouts", action="store_true")
    args = ap.parse_args()
    farm.quiet_logs()
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="farm-bench-"))
    scene = scene_file(tmp, 1920, 1080, args.spp)
    py = sys.executable

    # 1. Same scene, same run.
    cli_t, farm_t, ratios = [], [], []
    for rep in range(args.reps):
        a = timed([CLI, "render", scene, "--threads", "2", "-o", tmp / "cli.exr"])
        b = timed([py, FARM, "render", scene, "-o", tmp / "farm.exr"])
        assert same(tmp / "cli.exr", tmp / "farm.exr"), "farm image differs from facet render"
        cli_t.append(a)
        farm_t.append(b)
        ratios.append(b / a)
    print(f"## Cornell box 1920x1080, {args.spp} spp, {args.reps} reps (bit-identical images)\n")
    print("| | median s | all reps s |\n|---|---|---|")
    print(f"| facet render --threads 2 | {statistics.median(cli_t):.2f} | "
          f"{', '.join(f'{t:.2f}' for t in cli_t)} |")
    print(f"| facet-farm (local, default) | {statistics.median(farm_t):.2f} | "
          f"{', '.join(f'{t:.2f}' for t in farm_t)} |")
    print(f"| ratio farm / render (per rep) | {statistics.median(ratios):.3f} | "
          f"{', '.join(f'{r:.3f}' for r in ratios)} |\n")
    core_s_per_sample = statistics.median(cli_t) * 2 / (1920 * 1080 * args.spp)

    # 2. Local layouts.
    if not args.skip_layouts:
        small = scene_file(tmp, 1920, 1080, args.layout_spp)
        ref = timed([CLI, "render", small, "--threads", "2", "-o", tmp / "l_cli.exr"])
        print(f"## Local layouts, 1920x1080 at {args.layout_spp} spp "
              f"(facet render: {ref:.2f} s)\n")
        print("| workers x task threads x render threads | wall s | / facet render |")
        print("|---|---|---|")
        for w, t, rt in [(1, 2, 1), (2, 1, 1), (1, 1, 2)]:
            s = timed([py, FARM, "render", small, "-o", tmp / "l.exr", "--workers", w,
                       "--threads", t, "--task-threads", rt])
            assert same(tmp / "l.exr", tmp / "l_cli.exr")
            print(f"| {w} x {t} x {rt} | {s:.2f} | {s / ref:.3f} |")
        print()

    # 3. Per-task costs on a local cluster.
    cluster = farm.local_cluster(1, 2)
    client = farm.connect(cluster)
    client.wait_for_workers(1)
    n = 2000
    futs = client.map(lambda i: i, range(n), pure=False)  # warm-up
    client.gather(futs)
    t = time.perf_counter()
    futs = client.map(_noop, range(n), pure=False)
    client.gather(futs)
    noop_s = (time.perf_counter() - t) / n
    del futs
    tiny = scene_file(tmp, 400, 320, 1)
    payload = farm.load_payload(str(tiny))
    regions, samples = farm.plan_still(400, 320, 1, 2, tile_size=8)
    job = farm.Job(payload, regions, samples, [])
    farm.run_jobs(client, [farm.Job(payload, regions[:50], samples, [])])  # warm the scene cache
    t = time.perf_counter()
    farm.run_jobs(client, [job])
    tiny_s = (time.perf_counter() - t) / job.tasks
    t = time.perf_counter()
    facet.render(facet.load_scene(str(tiny)), threads=2)
    tiny_render = time.perf_counter() - t
    client.close()
    cluster.close()

    big = facet.load_scene(str(scene_file(tmp, 1920, 1080, 2)))
    tile_parts = []
    for r in farm.tiles(1920, 1080, 256):
        s = facet.RenderSession(big, region=r, spp=2, samples=(0, 2), threads=2)
        s.render()
        tile_parts.append(s.part())
    part = tile_parts[0]
    result_bytes = len(pickle.dumps(part, protocol=5)) / (256 * 256)
    task_bytes = len(pickle.dumps((farm.render_piece, "facet-scene-key", (0, 0, 256, 256),
                                   (0, 16), 1), protocol=5))
    payload_bytes = len(pickle.dumps(farm.load_payload(str(scene)), protocol=5))
    reps = []
    for _ in range(3):
        t = time.perf_counter()
        facet.merge_parts(tile_parts)
        reps.append(time.perf_counter() - t)
    merge_px_s = 1920 * 1080 / statistics.median(reps)
    halves = []
    for r in farm.tiles(1920, 1080, 256)[:8]:
        for sr in [(0, 1), (1, 2)]:
            s = facet.RenderSession(big, region=r, spp=2, samples=sr, threads=2)
            s.render()
            halves.append(s.part())
    t = time.perf_counter()
    for k in range(0, len(halves), 2):
        farm._sum_parts(halves[k:k + 2])
    sum_px_s = 8 * 256 * 256 / (time.perf_counter() - t)

    print("## Per-task costs (local cluster, 1 worker x 2 threads)\n")
    print("| quantity | value |\n|---|---|")
    print(f"| no-op Dask task, client round trip | {noop_s * 1e3:.2f} ms/task "
          f"({1 / noop_s:.0f} tasks/s) |")
    print(f"| facet task of 8x8 px x 1 spp (session, part, pickle) | {tiny_s * 1e3:.2f} ms/task "
          f"({job.tasks} tasks; the same pixels in one render: {tiny_render:.3f} s) |")
    print(f"| bytes per task (arguments) | {task_bytes} B |")
    print(f"| scene payload (Cornell box), once per worker | {payload_bytes} B |")
    print(f"| bytes per result pixel (pickled part) | {result_bytes:.1f} B |")
    print(f"| merge_parts, 1920x1080 from 256-px tiles | {merge_px_s / 1e6:.1f} Mpx/s |")
    print(f"| exact sum of two sample chunks (numpy, 128-bit) | {sum_px_s / 1e6:.1f} Mpx/s |")
    print(f"| render cost (facet render, Cornell) | {core_s_per_sample * 1e9:.1f} "
          f"core-ns/sample |\n")

    # 4. The model: 4K at 4096 spp.
    W, H, SPP = 3840, 2160, 4096
    work = W * H * SPP * core_s_per_sample  # core-seconds
    bandwidth = 125e6  # client NIC: 1 Gbit/s
    per_task_sched = noop_s  # serial scheduler + client cost per task
    print(f"## Model: 4K ({W}x{H}) at {SPP} spp = {work / 3600:.1f} core-hours "
          f"({core_s_per_sample * 1e9:.1f} core-ns/sample); client link 1 Gbit/s\n")
    print("| workers (1 core each) | tile / chunk | tasks | work/worker s | serial (sched + "
          "results + merge) s | frame s | efficiency |\n|---|---|---|---|---|---|---|")
    for P in (10, 100, 1000):
        best = None
        for tile in (512, 256, 128, 64, 32):
            for chunk in (SPP, 1024, 256, 64, 16):
                ntiles = len(farm.tiles(W, H, tile))
                nchunks = -(-SPP // chunk)
                tasks = ntiles * nchunks
                if tasks < 4 * P:  # load balance: >= 4 tasks per worker
                    continue
                per_worker = work / P
                results = W * H * nchunks * result_bytes / bandwidth
                merge = W * H / merge_px_s + W * H * (nchunks - 1) / sum_px_s
                serial = tasks * per_task_sched + results + merge
                # serial costs overlap with the work, except the last wave's results and merge
                total = max(per_worker, serial) + W * H / merge_px_s
                eff = work / P / total
                cand = (total, tile, chunk, tasks, per_worker, serial, eff)
                if best is None or total < best[0]:
                    best = cand
        total, tile, chunk, tasks, per_worker, serial, eff = best
        print(f"| {P} | {tile} px / {chunk} spp | {tasks} | {per_worker:.0f} | {serial:.1f} | "
              f"{total:.0f} | {eff * 100:.1f}% |")
    # Where it stops scaling: serial client costs equal the per-worker work.
    tile, chunk = 64, 64
    tasks = len(farm.tiles(W, H, tile)) * (SPP // chunk)
    serial = (tasks * per_task_sched + W * H * (SPP // chunk) * result_bytes / bandwidth +
              W * H * (SPP // chunk) / sum_px_s)
    print(f"\nOne scheduler/client saturates when work/P falls to its serial cost: with "
          f"{tile}-px tiles x {chunk}-spp chunks ({tasks} tasks, {serial:.0f} s serial) at "
          f"P = {work / serial:.0f} workers.")


def _noop(i):
    return i


if __name__ == "__main__":
    main()
