#!/usr/bin/python3
"""facet-farm against `facet render` on the same scene in the same run, per-task costs, and the
scaling model of docs/performance.md ("Farm").

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
import resource
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


CPU = []  # CPU seconds (user + system, the command and its waited-for children) per timed()


def timed(cmd):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    subprocess.run([str(c) for c in cmd], check=True, capture_output=True)
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    CPU.append(r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime)
    return wall


def same(a, b):
    return np.array_equal(facet.read_image(str(a)), facet.read_image(str(b)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--layout-spp", type=int, default=4)
    ap.add_argument("--skip-layouts", action="store_true")
    ap.add_argument("--compare-only", action="store_true", help="only part 1")
    args = ap.parse_args()
    farm.quiet_logs()
    tmp = pathlib.Path(tempfile.mkdtemp(prefix="farm-bench-"))
    scene = scene_file(tmp, 1920, 1080, args.spp)
    py = sys.executable

    # 1. Same scene, same run.
    cli_t, farm_t, ratios, cli_c, farm_c, cpu_ratios = [], [], [], [], [], []
    for rep in range(args.reps):
        a = timed([CLI, "render", scene, "--threads", "2", "-o", tmp / "cli.exr"])
        cli_c.append(CPU[-1])
        b = timed([py, FARM, "render", scene, "-o", tmp / "farm.exr"])
        farm_c.append(CPU[-1])
        assert same(tmp / "cli.exr", tmp / "farm.exr"), "farm image differs from facet render"
        cli_t.append(a)
        farm_t.append(b)
        ratios.append(b / a)
        cpu_ratios.append(farm_c[-1] / cli_c[-1])
    print(f"## Cornell box 1920x1080, {args.spp} spp, {args.reps} reps (bit-identical images)\n")
    print("| | median s | all reps s |\n|---|---|---|")
    print(f"| facet render --threads 2 | {statistics.median(cli_t):.2f} | "
          f"{', '.join(f'{t:.2f}' for t in cli_t)} |")
    print(f"| facet-farm (local, default) | {statistics.median(farm_t):.2f} | "
          f"{', '.join(f'{t:.2f}' for t in farm_t)} |")
    print(f"| ratio farm / render (per rep) | {statistics.median(ratios):.3f} | "
          f"{', '.join(f'{r:.3f}' for r in ratios)} |")
    print(f"| CPU s: facet render | {statistics.median(cli_c):.2f} | "
          f"{', '.join(f'{t:.2f}' for t in cli_c)} |")
    print(f"| CPU s: facet-farm | {statistics.median(farm_c):.2f} | "
          f"{', '.join(f'{t:.2f}' for t in farm_c)} |")
    print(f"| CPU ratio farm / render (per rep) | {statistics.median(cpu_ratios):.3f} | "
          f"{', '.join(f'{r:.3f}' for r in cpu_ratios)} |\n")
    # CPU time, not wall x 2: the machine is shared, a worker core is not.
    core_s_per_sample = statistics.median(cli_c) / (1920 * 1080 * args.spp)
    if args.compare_only:
        return

    # 2. Local layouts.
    if not args.skip_layouts:
        small = scene_file(tmp, 1920, 1080, args.layout_spp)
        ref = timed([CLI, "render", small, "--threads", "2", "-o", tmp / "l_cli.exr"])
        print(f"## Local layouts, 1920x1080 at {args.layout_spp} spp "
              f"(facet render: {ref:.2f} s)\n")
        print("| local cluster (--workers x --threads x --task-threads) | wall s | "
              "/ facet render |")
        print("|---|---|---|")
        for w, t, rt in [(0, 2, 1), (0, 1, 2), (1, 2, 1), (2, 1, 1)]:
            s = timed([py, FARM, "render", small, "-o", tmp / "l.exr", "--workers", w,
                       "--threads", t, "--task-threads", rt])
            assert same(tmp / "l.exr", tmp / "l_cli.exr")
            kind = "in-process worker" if w == 0 else f"{w} worker process{'es' * (w > 1)}"
            print(f"| {kind} x {t} x {rt} | {s:.2f} | {s / ref:.3f} |")
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
    tiny = scene_file(tmp, 320, 256, 2)
    payload = farm.load_payload(str(tiny))
    regions, samples = farm.plan_still(320, 256, 2, 2, tile_size=8, sample_chunk=1)
    farm.run_jobs(client, [farm.Job(payload, regions, samples, [])])  # warm the worker's cache
    job = farm.Job(payload, regions, samples, [])
    t = time.perf_counter()
    farm.run_jobs(client, [job])
    tiny_s = (time.perf_counter() - t) / job.tasks
    tiny_tasks = job.tasks
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
    reps = []
    for _ in range(3):  # what facet-farm does: each complete tile resolved and pasted
        job = farm.Job(farm.load_payload(str(scene_file(tmp, 1920, 1080, 2))), [], [(0, 2)], [])
        t = time.perf_counter()
        for p in tile_parts:
            farm._place(job, p)
        reps.append(time.perf_counter() - t)
    place_px_s = 1920 * 1080 / statistics.median(reps)
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

    print("## Per-task costs (local cluster: 1 worker process x 2 threads, TCP on loopback)\n")
    print("| quantity | value |\n|---|---|")
    print(f"| no-op Dask task, client round trip | {noop_s * 1e3:.2f} ms/task "
          f"({1 / noop_s:.0f} tasks/s) |")
    print(f"| facet task of 8x8 px x 1 sample (session, part, pickle, merge) | {tiny_s * 1e3:.2f} ms/task "
          f"({tiny_tasks} tasks; the same pixels in one render: {tiny_render:.3f} s) |")
    print(f"| bytes per task (arguments) | {task_bytes} B |")
    print(f"| scene payload (Cornell box), once per worker | {payload_bytes} B |")
    print(f"| bytes per result pixel (pickled part) | {result_bytes:.1f} B |")
    print(f"| merge_parts, 1920x1080 from 256-px tiles | {merge_px_s / 1e6:.1f} Mpx/s |")
    print(f"| facet-farm's assembly (resolve each tile, paste) | {place_px_s / 1e6:.1f} Mpx/s |")
    print(f"| exact sum of two sample chunks (numpy, 128-bit) | {sum_px_s / 1e6:.1f} Mpx/s |")
    print(f"| render cost (facet render, Cornell, CPU time) | {core_s_per_sample * 1e9:.1f} "
          f"core-ns/sample |\n")

    # 4. The model: 4K at 4096 spp.
    # Per task: the measured facet task (8x8 px, 1 sample: almost all of it is overhead).
    model(core_s_per_sample, max(noop_s, tiny_s), result_bytes, place_px_s, sum_px_s)
    # The same with 1 ms per task: Dask's own figure for a scheduler on a machine of its own
    # (an assumption, not measured here).
    model(core_s_per_sample, 1e-3, result_bytes, place_px_s, sum_px_s,
          label="with 1 ms per task (a dedicated scheduler; assumed)")


def model(c, sched_s, result_bytes, merge_px_s, sum_px_s, bandwidth=125e6,
          label="with the per-task cost measured here"):
    """Frame time on P one-core workers (tiles >= 32 px: Embree packets are 8 px wide) with one scheduler and one client (1 Gbit/s link):
    the work W/P plus a tail of one task, or the client's serial costs when they are longer
    (scheduler per task; results 52 B/px per sample chunk over the link; exact chunk sums and
    the final merge). Picks tile size and sample chunk per P, >= 4 tasks per worker."""
    W, H, SPP = 3840, 2160, 4096
    px = W * H
    work = px * SPP * c

    def cost(P, tile, chunk):
        ntiles = len(farm.tiles(W, H, tile))
        nchunks = -(-SPP // chunk)
        tasks = ntiles * nchunks
        if tasks < 4 * P:
            return None
        sched = tasks * sched_s
        net = px * nchunks * result_bytes / bandwidth
        merge = px * (nchunks - 1) / sum_px_s + px / merge_px_s
        task_s = work / tasks
        compute = work / P + task_s  # the last wave's tail: one task
        serial = sched + net + merge
        total = max(compute, serial) + px / merge_px_s  # the final merge after the last result
        return dict(P=P, tile=tile, chunk=chunk, tasks=tasks, task_s=task_s, sched=sched,
                    net=net, merge=merge, total=total, overhead=total / (work / P) - 1)

    def best(P):
        cands = [cost(P, t, ch) for t in (1024, 512, 256, 128, 64, 32)
                 for ch in (SPP, 2048, 1024, 512, 256, 128, 64, 32)]
        cands = [x for x in cands if x]
        if not cands:
            return None
        # The fewest tasks among the splits within 0.5% of the fastest: the least load on the
        # scheduler, the link and the client for the same frame time.
        fastest = min(x["total"] for x in cands)
        return min((x for x in cands if x["total"] <= 1.005 * fastest), key=lambda x: x["tasks"])

    print(f"## Model: a 4K frame ({W}x{H}) at {SPP} spp = {work / 3600:.0f} core-hours "
          f"({c * 1e9:.0f} core-ns/sample as measured here), one scheduler, 1 Gbit/s client "
          f"link, {label}: {sched_s * 1e3:.1f} ms per task\n")
    print("| workers (1 core) | tile / sample chunk | tasks | s per task | scheduler s | "
          "results over the link s | merge s | frame | overhead vs work/P |")
    print("|---|---|---|---|---|---|---|---|---|")
    for P in (10, 100, 1000):
        b = best(P)
        print(f"| {P} | {b['tile']} px / {b['chunk']} spp | {b['tasks']} | {b['task_s']:.1f} | "
              f"{b['sched']:.1f} | {b['net']:.1f} | {b['merge']:.1f} | "
              f"{b['total'] / 60:.1f} min | {b['overhead'] * 100:.1f}% |")
    P = 10
    while True:
        b = best(P * 2)
        if b is None or b["overhead"] > 0.05:
            break
        P *= 2
    b5 = best(P)
    P2 = P
    while True:
        b = best(P2 * 2)
        if b is None or b["total"] >= best(P2)["total"]:
            break
        P2 *= 2
    print(f"\nOverhead stays <= 5% up to ~{P} workers ({b5['tile']}-px tiles, {b5['chunk']}-spp "
          f"chunks, {b5['tasks']} tasks); the frame stops getting faster at ~{P2} workers "
          f"({best(P2)['total']:.0f} s), where the client's serial costs "
          f"(scheduler + results + merge) equal the work per worker.")


def _noop(i):
    return i


if __name__ == "__main__":
    main()
